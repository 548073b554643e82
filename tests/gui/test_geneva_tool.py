"""Drawing a Geneva drive with the canvas tool and reshaping it by its handles, as a user would."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QRectF, Qt

from canvas_user import make_view
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.model.geneva import parse, wheel_dimensions
from mechsketch.gui.canvas.geneva_tool import scaled_drive

WINDOW = QRectF(-80.0, -120.0, 360.0, 300.0)


@pytest.mark.parametrize("z", range(3, 10))
@pytest.mark.parametrize("a", [4.0, 100.0, 2500.0])
def test_defaults_scaled_to_the_centre_distance_validate_for_every_slot_count(z, a):
    el = scaled_drive("g", z, (1.0, 2.0), (1.0 + a * 0.6, 2.0 + a * 0.8))
    assert el.center_distance == pytest.approx(a) and el.wheel_direction_deg == pytest.approx(math.degrees(math.atan2(0.8, 0.6)))
    _, problems = parse(el.to_dict(), "$")
    assert problems == []
    d = wheel_dimensions(z, a, el.roller_radius, el.clearance)
    assert d.hub_max > el.load.journal_radius > 0 and el.roller_radius <= 0.08 * a + 1e-12


def test_two_clicks_make_a_drive_and_keys_choose_the_slots(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    user.tool("geneva")
    assert view.toolbox.name == "geneva"
    user.click((0, 0))
    user.move((100, 0))
    qtbot.keyClick(view.viewport(), Qt.Key.Key_4)   # while placing: the preview takes 4 slots
    assert view.toolbox.tool.slots == 4
    qtbot.keyClick(view.viewport(), Qt.Key.Key_6)
    user.click((100, 0))
    (el,) = ctl.scene.elements
    assert el.type == "geneva" and el.slots == 6 and el.center_distance == pytest.approx(100.0)
    assert el.crank_center == (0.0, 0.0) and el.wheel_direction_deg == pytest.approx(0.0)
    assert el.roller_radius == pytest.approx(8.0)          # the notes' example, scaled from A = 100
    res = ctl.element_result(el.id)
    assert res.ok and res.geometry is not None
    # the drive's motion is the closed form of its kinematics (the core's result on the canvas)
    ref = kinematics(el, res.n_frames)
    np.testing.assert_allclose(res.wheel_rotation, math.radians(el.wheel_direction_deg) + ref.wheel_angle)
    assert (el.id, "element", el.id) in ctl.selection and ctl.undo_stack.count() == 1
    # a key after placing re-slots the new drive: one more undo step
    qtbot.keyClick(view.viewport(), Qt.Key.Key_8)
    assert ctl.scene.element(el.id).slots == 8 and ctl.undo_stack.count() == 2
    ctl.undo_stack.undo()
    assert ctl.scene.element(el.id).slots == 6
    view.grab()


def test_a_wheel_centre_on_the_crank_centre_is_explained_not_raised(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    user.tool("geneva")
    user.click((0, 0))
    user.click((0, 0))
    assert ctl.scene.elements == () and "crank centre" in view.messages[-1]


def _drive(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    user.tool("geneva")
    user.click((0, 0))
    user.click((100, 0))
    user.tool("select")
    eid = ctl.scene.ids[0]
    return ctl, view, user, eid


def test_dragging_the_wheel_centre_reanalyses_live_and_is_one_undo_step(qtbot):
    ctl, view, user, eid = _drive(qtbot)
    before = ctl.undo_stack.count()
    handles = {h.name: h for h in view.extras.handles.handles()}
    assert set(handles) == {"crank", "wheel", "roller"}
    seen = []
    ctl.changed.connect(lambda ch: seen.append((ch.preview, ctl.scene.element(eid).center_distance)))
    user.drag((100, 0), (120, 0), steps=4)
    el = ctl.scene.element(eid)
    assert el.center_distance == pytest.approx(120.0) and el.crank_center == (0.0, 0.0)
    assert any(p for p, _ in seen) and seen[-1][0] is False          # live previews, then one final change
    assert ctl.undo_stack.count() == before + 1
    assert ctl.element_result(eid).ok
    ctl.undo_stack.undo()
    assert ctl.scene.element(eid).center_distance == pytest.approx(100.0)


def test_the_roller_handle_sets_the_roller_radius(qtbot):
    ctl, view, user, eid = _drive(qtbot)
    h = next(h for h in view.extras.handles.handles() if h.name == "roller")
    el = ctl.scene.element(eid)
    rc = (h.at[0] - el.roller_radius * math.cos(math.atan2(h.at[1], h.at[0])),
          h.at[1] - el.roller_radius * math.sin(math.atan2(h.at[1], h.at[0])))
    view.snap_enabled = False
    u = ((h.at[0] - rc[0]) / el.roller_radius, (h.at[1] - rc[1]) / el.roller_radius)
    target = (rc[0] + 5.0 * u[0], rc[1] + 5.0 * u[1])
    user.drag(h.at, target, steps=3)
    assert ctl.scene.element(eid).roller_radius == pytest.approx(5.0, abs=0.05)


def test_an_impossible_drive_during_a_drag_is_explained_and_refused_on_release(qtbot):
    ctl, view, user, eid = _drive(qtbot)
    before, count = ctl.scene.element(eid), ctl.undo_stack.count()
    # the wheel 20 mm from the crank: the 8 mm roller no longer fits (no locking arc, no land)
    user.drag((100, 0), (60, 0), steps=2, release=False)
    good = ctl.scene.element(eid)
    assert good.center_distance == pytest.approx(60.0) and ctl.element_result(eid).ok
    user.move((20, 0))
    qtbot.mouseMove(view.viewport(), user.at((20, 0)))
    shown = ctl.scene.element(eid)
    assert shown.center_distance == pytest.approx(60.0)            # the last valid one stays drawn
    assert "impossible" in view.messages[-1] and "roller" in view.messages[-1]
    user.release((20, 0))
    assert ctl.scene.element(eid) == before and ctl.undo_stack.count() == count
    assert "kept as it was" in view.messages[-1]


def test_the_tool_is_a_plain_class_over_canvas_events(qtbot):
    """No Qt mouse events: CanvasEvents straight into the tool, as the view would hand them."""
    from mechsketch.gui.canvas.events import CanvasEvent
    from mechsketch.gui.canvas.geneva_tool import GenevaTool
    from mechsketch.gui.canvas.tool_base import ToolContext
    from mechsketch.gui.controller import SceneController

    ctl = SceneController()
    said = []
    ctl.message.connect(said.append)
    tool = GenevaTool(ToolContext(ctl))
    tool.handle(CanvasEvent("press", (10.0, 20.0)))
    tool.handle(CanvasEvent("move", (10.0, 120.0)))
    assert not tool.overlay().bad and "A = 100.00 mm" in tool.overlay().labels[0][1]
    assert tool.key("5") and tool.slots == 5
    assert not tool.key("2") and not tool.key("x")
    tool.handle(CanvasEvent("press", (10.0, 120.0)))
    (el,) = ctl.scene.elements
    assert el.slots == 5 and el.crank_center == (10.0, 20.0) and el.wheel_direction_deg == pytest.approx(90.0)
    assert "z = 5" in said[-1]
