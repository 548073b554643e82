"""Redo answers Ctrl+Y and Ctrl+Shift+Z, and the window fits a 1024×700 screen with no control
hidden (issue 10 item 6). Checked for real under Xvfb at 1024×700 with xdotool (the README's
"Window size" note); here offscreen: the shortcuts, and the window laid out at that size."""
from __future__ import annotations

from PySide6.QtCore import QPoint, Qt
from PySide6.QtGui import QKeySequence

from mechsketch.core import MoveJoint

from app_fakes import shell  # noqa: F401 - fixture


def test_redo_answers_ctrl_y_and_ctrl_shift_z(shell, qtbot):
    parts = shell()
    w, c = parts.window, parts.controller
    keys = [k.toString() for k in w.actions["redo"].shortcuts()]
    assert "Ctrl+Y" in keys and "Ctrl+Shift+Z" in keys
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow, timeout=20000)
    c.push(MoveJoint("fourbar", "D", (170.0, 0.0)), "move D")
    for key, mods, index in ((Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier, 0),
                             (Qt.Key.Key_Y, Qt.KeyboardModifier.ControlModifier, 1),
                             (Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier, 0),
                             (Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier, 1)):
        qtbot.keyClick(w, key, mods)
        qtbot.waitUntil(lambda index=index: c.undo_stack.index() == index, timeout=20000)


def visible_in(widget, area) -> bool:
    """``widget`` lies inside ``area``'s visible rectangle (mapped through their parents)."""
    top_left = widget.mapTo(area, QPoint(0, 0))
    return area.rect().contains(top_left) and area.rect().contains(top_left + QPoint(widget.width() - 1,
                                                                                        widget.height() - 1))


def test_the_window_fits_1024_by_700_with_every_control_shown(shell, qtbot):
    parts = shell()
    w = parts.window
    assert w.minimumSizeHint().width() <= 972   # 95 % of 1024: what fit_to_screen gives it
    w.resize(972, 665)
    qtbot.waitUntil(lambda: w.width() == 972, timeout=20000)
    w.size_docks()   # what the first show does (no saved layout)
    qtbot.waitUntil(lambda: w.docks["properties"].width() >= 280, timeout=20000)
    for toolbar in ("toolbar:main", "toolbar:tools"):
        bar = next(b for b in w.findChildren(type(w.addToolBar("probe"))) if b.objectName() == toolbar)
        assert bar.sizeHint().width() <= bar.width(), toolbar   # no overflow ("»") menu
    props = w.properties
    flip = props.flip_buttons["RRR(coupler,rocker)"]
    viewport = flip.parentWidget()
    while viewport.objectName() != "qt_scrollarea_viewport":
        viewport = viewport.parentWidget()
    qtbot.waitUntil(lambda: visible_in(flip, viewport) or flip.mapTo(viewport, QPoint(0, 0)).y() > 0, timeout=20000)
    assert flip.mapTo(viewport, QPoint(flip.width(), 0)).x() <= viewport.width()   # not cut off at the right
    assert props._content.minimumSizeHint().width() <= viewport.width()
    for name in ("PNG…", "CSV…"):
        assert any(b.text() == name for b in w.plots.findChildren(type(flip)))
    assert w.centralWidget().minimumSizeHint().width() + 300 + 250 <= 972
    assert QKeySequence("Ctrl+Y") in w.actions["redo"].shortcuts()
