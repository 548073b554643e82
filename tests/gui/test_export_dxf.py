"""File > Export DXF (Ctrl+E): Geneva drives and rolling levers written off the GUI thread through
the fake dialog service, read back with ezdxf; failures are messages and the document is kept."""
from __future__ import annotations

import threading

import ezdxf
import pytest
from PySide6.QtGui import QKeySequence

from mechsketch import resources
from mechsketch.core import load_scene
from mechsketch.core.analyses import geneva_geometry
from mechsketch.gui.export_worker import ExportTask

from app_fakes import shell  # noqa: F401 - fixture


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
    ("geneva_z6", {"wheel", "locking_disc", "crank_arm", "roller", "centre_marks"}),
    ("rolling_lever_press", {"FRAME_PROFILE", "LEVER", "SLIDER_PROFILE"}),
])
def test_export_writes_a_dxf_in_millimetres_off_the_gui_thread(shell, qtbot, tmp_path, monkeypatch, name, layers):
    parts = shell()
    parts.window.actions[f"example:{name}"].trigger()
    c = parts.controller
    before = c.scene
    threads = []
    if name.startswith("geneva"):
        real = geneva_geometry.geometry
        monkeypatch.setattr(geneva_geometry, "geometry", lambda el: threads.append(threading.current_thread()) or real(el))
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
    if threads:
        assert all(t is not threading.main_thread() for t in threads)
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


def test_nothing_to_export_says_so_without_asking(shell):
    parts = shell()                                    # the four-bar: a linkage only
    assert parts.window.export_dxf() is False
    assert not parts.dialogs.questions
    assert "Geneva drives and rolling levers" in parts.window.statusBar().currentMessage()


def test_cancelling_the_file_dialog_exports_nothing(shell):
    parts = shell()
    parts.window.actions["example:rolling_lever_inclined"].trigger()
    parts.dialogs.save_names.append(None)
    assert parts.window.export_dxf() is False and not parts.window.exporter.busy
    assert parts.dialogs.questions[-1][1].endswith("inclined.dxf")
