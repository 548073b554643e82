"""Clipboard and files (issue 24 item 10), driven with the keys: Ctrl+C / Ctrl+V / Ctrl+D copy,
paste and duplicate elements — and selected joints of a linkage as a new linkage — within a
window and between windows, as scene JSON on the clipboard; a field being edited keeps its own
Ctrl+C; recent files show their path on hover."""
from __future__ import annotations

import json

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtGui import QCursor, QGuiApplication, QHelpEvent
from PySide6.QtWidgets import QApplication, QToolTip

from mechsketch.core import loads_scene
from mechsketch.core.model.transform import extent
from mechsketch.gui.clipboard import MIME
from mechsketch.resources import example_path

from app_fakes import shell  # noqa: F401 - fixture


def keys(qtbot, w, key, mods=Qt.KeyboardModifier.ControlModifier) -> None:
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow, timeout=20000)
    w.canvas.setFocus()
    qtbot.keyClick(w.canvas, key, mods)


def clipboard_scene():
    data = QGuiApplication.clipboard().mimeData()
    assert data.hasFormat(MIME)
    return loads_scene(bytes(data.data(MIME)).decode())


def test_copy_and_paste_a_drive_at_the_pointer_as_one_undo_step(shell, qtbot):
    parts = shell(example_path("geneva_z6"))
    w, c = parts.window, parts.controller
    (drive,) = c.scene.elements
    c.set_selection([(drive.id, "element", drive.id)])
    keys(qtbot, w, Qt.Key.Key_C)
    assert clipboard_scene().elements == (drive,)
    assert json.loads(QGuiApplication.clipboard().text())["format"] == "mechsketch.scene"   # text too
    spot = w.canvas.viewport().rect().center() + QPoint(60, -40)
    QCursor.setPos(w.canvas.viewport().mapToGlobal(spot))
    keys(qtbot, w, Qt.Key.Key_V)
    assert len(c.scene.elements) == 2 and c.undo_stack.count() == 1
    pasted = c.scene.elements[1]
    assert pasted.id != drive.id and pasted.type == "geneva"
    assert c.selection == [(pasted.id, "element", pasted.id)]
    target = w.canvas.mapToScene(spot)
    dx = pasted.crank_center[0] - drive.crank_center[0]
    dy = pasted.crank_center[1] - drive.crank_center[1]
    x0, y0, x1, y1 = extent(pasted)
    assert ((x0 + x1) / 2, (y0 + y1) / 2) == pytest.approx((target.x(), target.y()), abs=1e-9)
    assert (pasted.slots, pasted.center_distance) == (drive.slots, drive.center_distance) and (dx, dy) != (0, 0)
    c.undo_stack.undo()
    assert c.scene.elements == (drive,)


def test_paste_in_another_window(shell, qtbot):
    first = shell(example_path("rolling_lever_press"))
    (lever,) = first.controller.scene.elements
    first.controller.set_selection([(lever.id, "element", lever.id)])
    keys(qtbot, first.window, Qt.Key.Key_C)
    second = shell()
    QCursor.setPos(QPoint(-100, -100))                    # not over the canvas: beside where it was
    shift = second.window.clipboard_commands._offset()    # 24 px at the zoom of the paste (the view
    keys(qtbot, second.window, Qt.Key.Key_V)              # then shows the new element: zoom may change)
    ids = second.controller.scene.ids
    assert ids == ("fourbar", lever.id)
    got = second.controller.scene.element(lever.id)
    assert got.lever_circle.radius == lever.lever_circle.radius and got.pin != lever.pin
    assert got.pin == pytest.approx((lever.pin[0] + shift, lever.pin[1] - shift), abs=1e-9)


def test_duplicate_a_whole_linkage_picked_by_its_joints_leaves_the_clipboard_alone(shell, qtbot):
    parts = shell()
    w, c = parts.window, parts.controller
    QGuiApplication.clipboard().setText("kept")
    lk = c.scene.element("fourbar")
    c.set_selection([("fourbar", "joint", j) for j in lk.joint_ids])
    QCursor.setPos(QPoint(-100, -100))
    keys(qtbot, w, Qt.Key.Key_D)
    assert c.scene.ids == ("fourbar", "fourbar2") and c.undo_stack.count() == 1
    copy = c.scene.element("fourbar2")
    d = w.clipboard_commands._offset()
    for a, b in zip(lk.joints, copy.joints):
        assert b.at == pytest.approx((a.at[0] + d, a.at[1] - d), abs=1e-9)
    assert (copy.links, copy.driver) == (lk.links, lk.driver)
    assert QGuiApplication.clipboard().text() == "kept"
    res = c.result("fourbar2")
    assert res.error is None and res.solution.valid.all()      # it solves as the original


def test_selected_joints_copy_as_a_new_linkage(shell, qtbot):
    parts = shell(example_path("fourbar_loaded"))
    w, c = parts.window, parts.controller
    lk = c.scene.elements[0]
    c.set_selection([(lk.id, "joint", "A"), (lk.id, "joint", "B"), (lk.id, "joint", "D")])
    keys(qtbot, w, Qt.Key.Key_C)
    (part,) = clipboard_scene().elements
    assert part.joint_ids == ("A", "B", "D")
    assert {k.id: k.joints for k in part.links} == {"ground": ("A", "D"), "crank": ("A", "B")}
    assert part.driver == lk.driver                             # the crank was kept
    assert [m.link for m in part.masses] == ["crank"]
    assert all(getattr(ld, "link", "crank") == "crank" for ld in part.loads)
    QCursor.setPos(QPoint(-100, -100))
    keys(qtbot, w, Qt.Key.Key_V)
    new = c.scene.elements[-1]
    assert new.id == f"{lk.id}2" and c.result(new.id).error is None   # a crank on its frame: it turns
    c.set_selection([(lk.id, "joint", "C")])                  # no frame joint: refused, said why
    keys(qtbot, w, Qt.Key.Key_C)
    assert "pick a ground pivot too" in w.statusBar().currentMessage()


def test_pasting_what_is_not_a_scene_changes_nothing(shell, qtbot):
    parts = shell()
    w, c = parts.window, parts.controller
    before = c.scene
    for text, says in (("hello", "does not hold mechsketch elements"), ("", "nothing to paste"),
                       ('{"format": "mechsketch.scene", "schema_version": 3, "elements": [{"type": "cam", "id": "x"}]}',
                        "'cam' is not one of")):
        QGuiApplication.clipboard().setText(text)
        keys(qtbot, w, Qt.Key.Key_V)
        assert c.scene is before and says in w.statusBar().currentMessage(), w.statusBar().currentMessage()


def test_a_field_being_edited_keeps_its_own_copy(shell, qtbot):
    parts = shell()
    w, c = parts.window, parts.controller
    c.set_selection([("fourbar", "joint", "B")])
    field = w.properties.fields["x"]
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow, timeout=20000)
    field.setFocus()
    field.selectAll()
    qtbot.keyClick(field, Qt.Key.Key_C, Qt.KeyboardModifier.ControlModifier)
    assert QGuiApplication.clipboard().text() == field.text()   # the number, not scene JSON
    assert not QGuiApplication.clipboard().mimeData().hasFormat(MIME)


def test_recent_files_show_their_path_on_hover(shell, qtbot, tmp_path):
    parts = shell()
    w = parts.window
    (tmp_path / "deep").mkdir()
    assert parts.file_ops.save_as(tmp_path / "deep" / "x.json")
    menu = w.recent_menu
    assert menu.toolTipsVisible()
    first = menu.actions()[0]
    assert first.toolTip() == str(tmp_path / "deep" / "x.json") and first.text().endswith("x.json")
    menu.popup(w.mapToGlobal(QPoint(10, 10)))
    qtbot.waitUntil(menu.isVisible, timeout=20000)
    at = menu.actionGeometry(first).center()
    QApplication.sendEvent(menu, QHelpEvent(QHelpEvent.Type.ToolTip, at, menu.mapToGlobal(at)))
    qtbot.waitUntil(QToolTip.isVisible, timeout=20000)
    assert QToolTip.text() == str(tmp_path / "deep" / "x.json")
    menu.hide()
