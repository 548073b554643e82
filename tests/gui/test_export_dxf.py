"""File > Export DXF (Ctrl+E) and Export SVG: every element type's checked parts written off the
GUI thread through the fake dialog service (the export dialog's request included), read back with
ezdxf and the SVG reader; failures are messages and the document is kept."""
from __future__ import annotations

import threading

import ezdxf
import pytest
from PySide6.QtGui import QKeySequence

from mechsketch import resources
from mechsketch.core import load_scene
from mechsketch.core.analyses.parts import build as parts_build
from mechsketch.core.analyses.parts.build import PartOptions
from mechsketch.gui.export_dialog import DIALOG_VOCABULARY, ExportDialog, ExportRequest
from mechsketch.gui.export_worker import ExportTask

from app_fakes import shell  # noqa: F401 - fixture


def _readback():
    """tests/core/parts_readback.py (the readers the core export tests use)."""
    import importlib.util
    from pathlib import Path

    spec = importlib.util.spec_from_file_location("parts_readback", Path(__file__).parents[1] / "core" / "parts_readback.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _export(parts, qtbot, path) -> None:
    parts.dialogs.save_names.append(str(path))
    parts.window.actions["export_dxf"].trigger()
    qtbot.waitUntil(lambda: not parts.window.exporter.busy, timeout=10000)


def test_the_action_is_in_the_file_menu_with_ctrl_e(shell):
    w = shell().window
    action = w.actions["export_dxf"]
    assert action.shortcut() == QKeySequence("Ctrl+E")
    file_menu = w.menuBar().actions()[0].menu()
    assert action in file_menu.actions()


@pytest.mark.parametrize("name, layers", [
    ("geneva_z6", {"wheel", "locking_disc", "crank_arm", "roller"}),
    ("rolling_lever_press", {"frame", "frame_pivots", "lever", "slider"}),
    ("sixbar_moving_guide", {"ground", "crank", "coupler", "rocker", "rocker_guide_Q", "rod2", "block"}),
])
def test_export_writes_a_dxf_in_millimetres_off_the_gui_thread(shell, qtbot, tmp_path, monkeypatch, name, layers):
    parts = shell()
    parts.window.actions[f"example:{name}"].trigger()
    c = parts.controller
    before = c.scene
    threads = []
    real = parts_build.element_parts
    monkeypatch.setattr(parts_build, "element_parts",
                        lambda *a, **k: threads.append(threading.current_thread()) or real(*a, **k))
    target = tmp_path / "drawing"                    # no suffix: .dxf is added
    _export(parts, qtbot, target)
    path = tmp_path / "drawing.dxf"
    doc = ezdxf.readfile(path)
    assert doc.header["$INSUNITS"] == 4
    assert layers <= {layer.dxf.name for layer in doc.layers}
    assert not any(ly.dxf.name.startswith("NOTES_") for ly in doc.layers) and not doc.modelspace().query("TEXT")
    assert not doc.audit().has_errors
    title, report = parts.dialogs.infos[-1]
    assert title == "DXF exported" and str(path) in report
    assert str(path) in parts.window.statusBar().currentMessage()
    assert c.scene is before and not c.is_dirty and not parts.dialogs.errors
    assert threads and all(t is not threading.main_thread() for t in threads)
    assert not parts.window.export_status.isVisible()


def test_export_to_an_unwritable_path_shows_the_error_and_keeps_the_document(shell, qtbot, tmp_path):
    parts = shell()
    parts.window.actions["example:geneva_z4"].trigger()
    c = parts.controller
    parts.window.properties.fields["slots"].setText("5")
    parts.window.properties.fields["slots"].editingFinished.emit()   # an unsaved edit to keep
    assert c.scene.element("indexer").slots == 5 and c.is_dirty
    edited = c.scene
    _export(parts, qtbot, tmp_path / "no such folder" / "wheel.dxf")
    title, text, _ = parts.dialogs.errors[-1]
    assert title == "Export DXF" and "cannot write" in text and "no such folder" in text
    assert "cannot write" in parts.window.statusBar().currentMessage()
    assert c.scene is edited and c.is_dirty and c.undo_stack.count() == 1
    assert not (tmp_path / "no such folder").exists()


def test_cancel_before_the_write_writes_nothing(qtbot, tmp_path):
    el = load_scene(resources.example_path("geneva_z6")).elements[0]
    task = ExportTask(el, str(tmp_path / "w.dxf"))
    got = {}
    task.signals.cancelled.connect(lambda m: got.setdefault("cancelled", m))
    task.signals.finished.connect(lambda m: got.setdefault("finished", m))
    task.cancel()
    task.run()                                         # synchronously: the stage check sees Cancel
    assert "nothing was written" in got["cancelled"] and "finished" not in got
    assert not (tmp_path / "w.dxf").exists()


def test_a_linkage_exports_its_plates_as_svg_with_the_dialogs_options(shell, qtbot, tmp_path):
    parts = shell()                                    # the four-bar: a linkage only
    parts.dialogs.export_requests.append(
        lambda eid, fmt: ExportRequest(eid, fmt, "apart", ("crank", "coupler"), False, "bulge",
                                       PartOptions(tolerance=0.01, min_web=2.0)))
    parts.dialogs.save_names.append(str(tmp_path / "plates"))
    parts.window.actions["export_svg"].trigger()
    qtbot.waitUntil(lambda: not parts.window.exporter.busy, timeout=20000)
    _, got = _readback().svg_parts(tmp_path / "plates.svg")
    assert set(got) == {"crank", "coupler"} and all(p.is_valid for p in got.values())
    title, report = parts.dialogs.infos[-1]
    assert title == "SVG exported" and "thinnest web" in report and "minimum 2 mm" in report
    assert parts.dialogs.export_choices["fourbar"] == ("ground", "crank", "coupler", "rocker")


def test_a_part_thinner_than_the_minimum_web_is_refused_with_what_to_change(shell, qtbot, tmp_path):
    parts = shell()
    parts.window.actions["example:geneva_z6"].trigger()
    parts.dialogs.export_requests.append(lambda eid, fmt: ExportRequest(
        eid, fmt, options=PartOptions(min_web=5.0, vocabulary=DIALOG_VOCABULARY)))
    _export(parts, qtbot, tmp_path / "w.dxf")
    title, text, _ = parts.dialogs.errors[-1]
    assert title == "Export DXF" and "below the minimum web 5 mm" in text and "change" in text
    assert "the dialog's Minimum web or drawing.min_web" in text and "--" not in text  # no CLI flag in the app
    assert not (tmp_path / "w.dxf").exists()


def test_the_export_dialog_builds_the_request(qtbot):
    dlg = ExportDialog("Export DXF", {"a": ("p", "q"), "b": ("r",)}, "b", "dxf", {"a": 1.0, "b": 2.5},
                       kinds={"a": "linkage", "b": "geneva"}, sizes={"boss_radius": 7.5})
    qtbot.addWidget(dlg)
    assert dlg.element.currentText() == "b" and dlg.min_web.value() == 2.5 and "all: r" in dlg.parts.placeholderText()
    # a Geneva drive takes no plate sizes, no depth, no curve tolerance: those fields are off
    assert not any(w.isEnabled() for w in (dlg.boss_radius, dlg.bore_diameter, dlg.link_width, dlg.frame,
                                           dlg.depth, dlg.tolerance, dlg.fasteners, dlg.base_plate))
    assert dlg.bore_key.isEnabled()          # a Geneva drive's wheel and crank bores take a key
    assert dlg.request().options.boss_radius is None
    dlg.element.setCurrentText("a")
    assert dlg.boss_radius.isEnabled() and not dlg.depth.isEnabled() and dlg.boss_radius.value() == 7.5
    qtbot.keyClicks(dlg.parts, "q, p")
    dlg.layout_box.setCurrentText("assembled")
    dlg.arcs.setCurrentIndex(dlg.arcs.findData("entities"))
    assert "older CAM" in dlg.arcs.currentText() and "older CAM" in dlg.readers.text()
    dlg.split.setChecked(True)
    dlg.annotate.setChecked(True)
    dlg.kerf.setValue(0.2)
    dlg.bore_diameter.setValue(4.0)
    req = dlg.request()
    assert req == ExportRequest("a", "dxf", "assembled", ("q", "p"), True, "entities",
                                PartOptions(tolerance=0.001, min_web=1.0, boss_radius=7.5, bore_diameter=4.0,
                                            vocabulary=DIALOG_VOCABULARY), True, 0.2)


def test_the_dialogs_annotations_and_kerf_reach_the_file_and_its_messages_name_its_fields(shell, qtbot, tmp_path):
    parts = shell()                                    # the four-bar, with its coupler point E
    parts.dialogs.export_requests.append(lambda eid, fmt: ExportRequest(
        eid, fmt, "apart", None, False, "bulge", PartOptions(vocabulary=DIALOG_VOCABULARY), True, 0.3))
    _export(parts, qtbot, tmp_path / "fb.dxf")
    doc = ezdxf.readfile(tmp_path / "fb.dxf")
    layers = {e.dxf.layer for e in doc.modelspace()}
    assert {"NOTES_LABELS", "NOTES_TRACE_E"} <= layers and doc.modelspace().query("TEXT")
    title, report = parts.dialogs.infos[-1]
    assert "kerf 0.3 mm" in report and "tool paths" in report and "--" not in report
    parts.dialogs.export_requests.append(lambda eid, fmt: ExportRequest(
        eid, fmt, options=PartOptions(boss_radius=5.0, bore_diameter=9.0, vocabulary=DIALOG_VOCABULARY)))
    _export(parts, qtbot, tmp_path / "thin.dxf")
    title, text, _ = parts.dialogs.errors[-1]
    assert "the dialog's Boss radius" in text and "--" not in text and not (tmp_path / "thin.dxf").exists()


def test_cancelling_the_export_dialog_exports_nothing(shell):
    parts = shell()
    parts.dialogs.export_requests.append(lambda eid, fmt: None)
    assert parts.window.export_dxf() is False and not parts.window.exporter.busy


def test_cancelling_the_file_dialog_exports_nothing(shell):
    parts = shell()
    parts.window.actions["example:rolling_lever_inclined"].trigger()
    parts.dialogs.save_names.append(None)
    assert parts.window.export_dxf() is False and not parts.window.exporter.busy
    assert parts.dialogs.questions[-1][1].endswith("inclined.dxf")


def test_the_dialogs_fasteners_base_plate_and_bore_key_reach_the_parts(qtbot):
    """Issue 23 item 5 in the dialog: the rolling lever's fasteners and base plate, a linkage's
    bore key; each only where it applies (a rolling lever takes no bore key)."""
    dlg = ExportDialog("Export DXF", {"r": ("frame",), "l": ("crank",)}, "r", "dxf", {"r": 1.0, "l": 1.0},
                       kinds={"r": "rolling_lever", "l": "linkage"})
    qtbot.addWidget(dlg)
    assert dlg.fasteners.isEnabled() and dlg.base_plate.isEnabled() and not dlg.bore_key.isEnabled()
    dlg.fasteners.setValue(5.0)
    dlg.base_plate.setChecked(True)
    opts = dlg.request().options
    assert (opts.fasteners, opts.base_plate, opts.bore_key) == (5.0, True, None)
    dlg.element.setCurrentText("l")       # a linkage takes fasteners (guide plates) and a base plate too
    assert dlg.fasteners.isEnabled() and dlg.base_plate.isEnabled() and dlg.bore_key.isEnabled()
    dlg.fasteners.setValue(0.0)
    dlg.base_plate.setChecked(False)
    dlg.bore_key.setCurrentIndex(dlg.bore_key.findData("flat"))
    opts = dlg.request().options
    assert (opts.fasteners, opts.base_plate, opts.bore_key) == (None, False, "flat")
    scene = load_scene(resources.example_path("fourbar_crank_rocker"))
    keyed = parts_build.element_parts(scene.elements[0], opts)
    crank = next(p for p in keyed.parts if p.name == scene.elements[0].driver.link)
    assert any(h.kinds and h.kinds[0] == "flat" for h in crank.holes)
