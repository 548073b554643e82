"""Keyboard focus, window shortcuts and the wheel as a designer uses them (issue 24, items 1-2).

Enter in a Properties field commits it and gives the keyboard back to the canvas (F, Space and
the tool keys work at once, nothing is typed into the field); window shortcuts (Ctrl+E) work
while an unchanged field has the focus; a field the user is typing into keeps its keys; the
wheel over a combo box that does not have the focus scrolls the dock and never edits the design.
The same is checked in a real X11 window by docs/screenshots/check_focus_x11.py.
"""
from __future__ import annotations

from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QWheelEvent
from PySide6.QtWidgets import QApplication

from app_fakes import shell  # noqa: F401 - fixture


def _active(parts, qtbot):
    w = parts.window
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    return w


def test_enter_commits_and_gives_the_keys_back_to_the_canvas(shell, qtbot):
    parts = shell()
    w, ctl = _active(parts, qtbot), parts.controller
    ctl.set_selection([("fourbar", "joint", "E")])
    edit = w.properties.fields["x"]
    edit.setFocus()
    edit.selectAll()
    qtbot.keyClicks(edit, "60")
    qtbot.keyClick(edit, Qt.Key.Key_Return)
    assert ctl.scene.element("fourbar").joint("E").at[0] == 60.0
    assert w.canvas.hasFocus() and not edit.hasFocus()
    focus = QApplication.focusWidget()
    qtbot.keyClick(focus, Qt.Key.Key_G)                 # a tool key: the ground-pivot tool
    assert w.canvas.toolbox.name == "ground"
    qtbot.keyClick(QApplication.focusWidget(), Qt.Key.Key_Space)   # Space plays
    assert w.player.is_playing
    w.player.pause()
    assert edit.text() == "60"                          # nothing typed into the field ("60g ")


def test_window_shortcuts_beat_an_unchanged_field_but_not_one_being_typed_into(shell, qtbot):
    parts = shell()
    w, ctl = _active(parts, qtbot), parts.controller
    ctl.set_selection([("fourbar", "joint", "E")])
    edit = w.properties.fields["x"]
    edit.setFocus()
    shown = edit.text()
    assert edit.hasFocus() and not edit.isModified()
    qtbot.keyClick(edit, Qt.Key.Key_E, Qt.KeyboardModifier.ControlModifier)   # Export DXF…
    assert any(title.startswith("Export DXF") for title, _ in parts.dialogs.questions)
    qtbot.keyClick(edit, Qt.Key.Key_S)                  # a tool key from an unchanged field
    assert w.canvas.toolbox.name == "select" and edit.text() == shown
    qtbot.keyClick(edit, Qt.Key.Key_R)
    assert w.canvas.toolbox.name == "rrr"
    edit.selectAll()
    qtbot.keyClicks(edit, "1e")                         # being typed into: the field keeps its keys
    qtbot.keyClick(edit, Qt.Key.Key_G)
    assert edit.text() == "1eg" and w.canvas.toolbox.name == "rrr"
    qtbot.keyClick(edit, Qt.Key.Key_Escape)


def _wheel(widget, up: bool = False) -> None:
    pos = QPointF(widget.rect().center())
    ev = QWheelEvent(pos, QPointF(widget.mapToGlobal(pos.toPoint())), QPoint(0, 0), QPoint(0, 120 if up else -120),
                     Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False)
    QApplication.sendEvent(widget, ev)


def test_the_wheel_over_an_unfocused_combo_box_does_not_edit_the_design(shell, qtbot):
    parts = shell()
    w, ctl = _active(parts, qtbot), parts.controller
    w.resize(1024, 700)
    box = w.properties.direction
    before = ctl.scene.element("fourbar").driver
    start = box.currentIndex()
    for up in (False, True, False):
        _wheel(box, up)
    assert box.currentIndex() == start and ctl.scene.element("fourbar").driver == before
    assert ctl.undo_stack.count() == 0
    # under X11 a wheel gives a WheelFocus widget the focus before any filter sees it: not these
    assert box.focusPolicy() == Qt.FocusPolicy.StrongFocus
    box.setFocus()                                      # with the focus the wheel chooses
    _wheel(box, up=box.currentIndex() > 0)
    assert box.currentIndex() != start
