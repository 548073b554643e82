"""Typed input while placing and snapping with a modifier (issue 24, item 7): a number typed on
the canvas opens an inline box (x, y; or length and angle from the tool's anchor), Tab moves
between its fields, Enter places the point; Shift snaps to 15° and whole grid steps."""
from __future__ import annotations

import math

import pytest
from PySide6.QtCore import Qt

from app_fakes import DISCARD, shell  # noqa: F401 - fixture
from canvas_user import User


def _new(shell, qtbot):
    parts = shell()
    w = parts.window
    parts.dialogs.save_changes.append(DISCARD)
    w.actions["new"].trigger()
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    view = w.canvas
    view.setFocus()
    return parts, parts.controller, view, User(qtbot, view)


def _type(qtbot, view, first: str, rest: str, second: str) -> None:
    qtbot.keyClick(view, first)                     # opens the box with the first character
    box = view.typed
    assert box.isVisible()
    qtbot.keyClicks(box.fields[0], rest)
    qtbot.keyClick(box.fields[0], Qt.Key.Key_Tab)   # Tab: the second field, its text selected
    assert box.fields[1].hasFocus()
    qtbot.keyClicks(box.fields[1], second)
    qtbot.keyClick(box.fields[1], Qt.Key.Key_Return)
    assert not box.isVisible() and view.hasFocus()


def test_typed_coordinates_then_length_and_angle_place_a_pivot_and_a_crank(shell, qtbot):
    parts, ctl, view, user = _new(shell, qtbot)
    user.tool("ground")
    _type(qtbot, view, "1", "2.5", "-7")           # x = 12.5, y = -7
    lk = ctl.linkages()[0]
    assert [j.at for j in lk.joints] == [(12.5, -7.0)]
    assert view.typed.labels[0].text() == "x"
    user.tool("crank")
    user.click((12.5, -7.0))                        # the pivot: the crank measures from it
    _type(qtbot, view, "4", "0", "30")              # length 40 mm at 30°
    assert view.typed.labels[0].text().startswith("length")
    tip = ctl.linkages()[0].joints[-1].at
    assert tip == pytest.approx((12.5 + 40 * math.cos(math.radians(30)), -7.0 + 20.0), abs=1e-9)


def test_a_typed_point_that_is_not_a_number_is_not_placed_and_esc_closes_the_box(shell, qtbot):
    parts, ctl, view, user = _new(shell, qtbot)
    user.tool("ground")
    qtbot.keyClick(view, "5")
    box = view.typed
    qtbot.keyClick(box.fields[0], Qt.Key.Key_Tab)
    box.fields[1].setText("abc")
    qtbot.keyClick(box.fields[1], Qt.Key.Key_Return)
    assert box.isVisible() and not ctl.linkages()      # refused: the box stays for a correction
    qtbot.keyClick(box.fields[1], Qt.Key.Key_Escape)
    assert not box.isVisible() and not ctl.linkages()


def test_shift_snaps_the_crank_tip_to_15_degrees_and_whole_grid_steps(shell, qtbot):
    parts, ctl, view, user = _new(shell, qtbot)
    user.tool("ground")
    user.click((0.0, 0.0))
    user.tool("crank")
    user.click((0.0, 0.0))
    step = view.snap_step()
    raw = (37.3 * step / 10.0, 11.9 * step / 10.0)   # about 17.7° and 3.9 steps away
    user.click(raw, modifiers=Qt.KeyboardModifier.ShiftModifier)
    tip = ctl.linkages()[0].joints[-1].at
    length, angle = math.hypot(*tip), math.degrees(math.atan2(tip[1], tip[0]))
    assert angle == pytest.approx(15.0, abs=1e-9)
    assert length == pytest.approx(4 * step, abs=1e-9)
