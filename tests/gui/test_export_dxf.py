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
    ("geneva_z6", {"wheel", "locking_disc", "crank_arm", "roller", "LABELS"}),
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
    dlg = ExportDialog("Export DXF", {"a": ("p", "q"), "b": ("r",)}, "b", "dxf", {"a": 1.0, "b": 2.5})
    qtbot.addWidget(dlg)
    assert dlg.element.currentText() == "b" and dlg.min_web.value() == 2.5 and "all: r" in dlg.parts.placeholderText()
    dlg.element.setCurrentText("a")
    qtbot.keyClicks(dlg.parts, "q, p")
    dlg.layout_box.setCurrentText("assembled")
    dlg.arcs.setCurrentText("entities")
    dlg.split.setChecked(True)
    req = dlg.request()
    assert req == ExportRequest("a", "dxf", "assembled", ("q", "p"), True, "entities",
                                PartOptions(tolerance=0.001, min_web=1.0, vocabulary=DIALOG_VOCABULARY))


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
