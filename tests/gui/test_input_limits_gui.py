"""Issue 13 item 2 in the app: what the loader refuses is refused when typed, and never saved;
canvas picking survives the largest coordinates a record can hold."""
from __future__ import annotations

import sys
from dataclasses import replace

import pytest

from mechsketch.core import load_scene
from mechsketch.core.io.scene_file import validate_file
from mechsketch.gui.canvas.pose import drawn_pose, pick

from app_fakes import shell  # noqa: F401 - fixture
from app_fakes import type_into


@pytest.mark.parametrize("text", ["1e10", "1e308", "-1.7976931348623157e308"])
def test_a_coordinate_beyond_the_files_range_is_refused_when_typed(shell, qtbot, tmp_path, text):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "joint", "B")])
    before = c.scene
    type_into(qtbot, props.fields["y"], text)
    msg = parts.window.statusBar().currentMessage()
    assert "beyond ±1e+09 mm" in msg and "B" in msg, msg
    assert c.scene == before and c.undo_stack.count() == 0 and not c.is_dirty
    assert props.fields["y"].text() == "34.641016"
    assert parts.file_ops.save_as(tmp_path / "s.json")
    assert validate_file(tmp_path / "s.json") == []
    assert load_scene(tmp_path / "s.json") == before


def test_a_speed_beyond_the_range_is_refused_when_typed(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "joint", "B")])
    for text in ("1e6", "1e9", "0.0001"):
        type_into(qtbot, props.fields["speed"], text)
        msg = parts.window.statusBar().currentMessage()
        assert "speed_rpm" in msg and "100000" in msg, msg
    assert c.undo_stack.count() == 0
    type_into(qtbot, props.fields["speed"], "100000")          # the top of the range is fine
    assert c.scene.element("fourbar").driver.speed_rpm == 100000.0


def test_picking_never_overflows(qtbot):
    lk = load_scene(__import__("mechsketch.resources", fromlist=["x"]).example_path(
        "fourbar_crank_rocker")).element("fourbar")
    huge = sys.float_info.max
    far = lk.with_joints_moved({"B": (20.0, huge), "C": (-huge, huge)})
    pose = drawn_pose(far)
    for pos in [(0.0, 0.0), (20.0, 1e300), (-huge, huge), (huge, -huge), (1e9, 1e9)]:
        hit = pick([pose], pos, 5.0)      # must not raise OverflowError
        assert hit is None or hit.element == "fourbar"


def test_a_drag_beyond_the_range_is_refused_on_release(qtbot):
    from canvas_user import example, make_view
    from mechsketch.gui.canvas.events import CanvasEvent
    from mechsketch.gui.canvas.pose import Hit

    ctl, view, _ = make_view(qtbot, example("fourbar_crank_rocker"))
    before = ctl.scene
    hit = Hit("fourbar", "joint", "C")
    c = before.element("fourbar").joint("C").at
    view.dispatch(CanvasEvent("press", c, hit=hit, buttons=frozenset({"left"}), tolerance=2.0))
    for y in (1e3, 1e8, 5e9):
        view.dispatch(CanvasEvent("move", (c[0], y), button="none", buttons=frozenset({"left"}),
                                  tolerance=2.0))
    view.dispatch(CanvasEvent("release", (c[0], 5e9), tolerance=2.0))
    assert ctl.undo_stack.count() == 0 and ctl.scene == before
    assert any("beyond ±1e+09 mm" in m for m in view.messages), view.messages
