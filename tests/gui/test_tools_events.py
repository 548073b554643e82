"""The tools as plain classes fed with CanvasEvents (no Qt events), and every bad-input path:
each is explained through controller.message and leaves the document as it was."""
from __future__ import annotations

import numpy as np
import pytest

from canvas_user import example
from mechsketch.core.model.edits import AddElement, ReplaceElement
from mechsketch.core.model.linkage import Joint, JointKind, Link
from mechsketch.core.solver.plan import compile_plan
from mechsketch.gui.canvas import ops
from mechsketch.gui.canvas.events import CanvasEvent, Hit
from mechsketch.gui.canvas.pose import pick
from mechsketch.gui.frames import nearest_valid, walk_to
from mechsketch.gui.canvas.tools import (CouplerPointTool, CrankTool, DeleteTool, GroundPivotTool, RPRTool,
                                         RRRTool, SelectTool, SliderTool, ToolContext)
from mechsketch.gui.controller import SceneController

TOL = 2.0


class Driver:
    """Feeds one tool with events at world points, picking like the view does."""

    def __init__(self, scene=None) -> None:
        self.ctl = SceneController(scene)
        self.ctx = ToolContext(self.ctl)
        self.messages: list[str] = []
        self.ctl.message.connect(self.messages.append)

    def ev(self, kind: str, xy, **kw) -> CanvasEvent:
        return CanvasEvent(kind, (float(xy[0]), float(xy[1])), hit=self.ctx.pick(xy, TOL), tolerance=TOL, **kw)

    def click(self, tool, xy) -> None:
        tool.handle(self.ev("move", xy, button="none"))
        tool.handle(self.ev("press", xy))
        tool.handle(self.ev("release", xy))

    def unchanged(self, before) -> bool:
        return self.ctl.scene == before


def fourbar() -> Driver:
    return Driver(example("fourbar_crank_rocker"))


def test_a_four_bar_from_events_only():
    d = Driver()
    g, c, r = GroundPivotTool(d.ctx), CrankTool(d.ctx), RRRTool(d.ctx)
    d.click(g, (0, 0))
    d.click(g, (100, 0))
    d.click(c, (0, 0))
    d.click(c, (0, 30))
    d.click(r, (0, 30))
    d.click(r, (100, 0))
    r.handle(d.ev("move", (80, 70), button="none"))
    assert not r.overlay().bad and len(r.overlay().lines) == 2
    d.click(r, (80, 70))
    lk = d.ctl.linkages()[0]
    res = d.ctl.result(lk.id)
    assert res.ok and res.diagnostics.full_turn and d.ctl.undo_stack.count() == 4


def test_pick_prefers_joints_then_links_and_revolute_over_prismatic():
    d = Driver(example("slider_crank_offset"))
    poses = d.ctx.poses()
    c = d.ctl.scene.element("slider_crank").joint("C").at
    assert pick(poses, c, 1.0) == Hit("slider_crank", "joint", "C")          # not the P joint S there
    assert pick(poses, (20.0, 0.5), 1.0) == Hit("slider_crank", "link", "crank")
    assert pick(poses, (500.0, 500.0), 1.0) is None


def test_walking_frames_never_crosses_a_gap():
    valid = np.array([True] * 5 + [False] * 3 + [True] * 4)
    assert walk_to(valid, 3, 9) == (4, True)                   # shorter way is blocked: stop at the limit
    assert walk_to(valid, 3, 1) == (1, False)
    assert walk_to(valid, 9, 1, cyclic=True) == (1, False)     # through the wrap-around, all valid
    assert walk_to(valid, 9, 1, cyclic=False) == (8, True)     # straight along the bar: the gap
    assert nearest_valid(valid, 6) in (4, 8) and nearest_valid(np.zeros(3, bool), 1) is None


@pytest.mark.parametrize("case", [
    "ground_on_joint", "crank_from_nothing", "crank_from_moving_joint", "crank_second_driver",
    "crank_tip_on_joint", "rrr_same_joint", "rrr_other_linkage", "rrr_collinear", "rrr_on_joint",
    "rrr_pick_empty", "slider_pin_at_guide_start", "slider_pin_on_joint", "rpr_same_joint",
    "coupler_on_empty", "coupler_on_joint", "delete_nothing", "move_onto_joint",
])
def test_bad_input_is_explained_and_changes_nothing(case):
    d = fourbar()
    before = d.ctl.scene
    B, C, D = (20.0, 34.641016151), (133.22973437, 116.975864511), (160.0, 0.0)
    if case == "ground_on_joint":
        d.click(GroundPivotTool(d.ctx), D)
        want = "already here"
    elif case == "crank_from_nothing":
        d.click(CrankTool(d.ctx), (300, 300))
        want = "click a ground pivot first"
    elif case == "crank_from_moving_joint":
        d.click(CrankTool(d.ctx), C)
        want = "not on the frame"
    elif case == "crank_second_driver":
        d.click(CrankTool(d.ctx), D)
        want = "already has a driver"
    elif case == "crank_tip_on_joint":
        dd = Driver()
        g, t = GroundPivotTool(dd.ctx), CrankTool(dd.ctx)
        dd.click(g, (0, 0))
        dd.click(g, (50, 0))
        before2 = dd.ctl.scene
        dd.click(t, (0, 0))
        dd.click(t, (50, 0))
        assert dd.unchanged(before2) and "already there" in dd.messages[-1]
        return
    elif case == "rrr_same_joint":
        t = RRRTool(d.ctx)
        d.click(t, C)
        d.click(t, C)
        want = "picked already"
    elif case == "rrr_other_linkage":
        d.ctl.push(AddElement(ops.new_linkage("other", Joint("A", JointKind.R, (300.0, 0.0)))))
        before = d.ctl.scene
        t = RRRTool(d.ctx)
        d.click(t, C)
        d.click(t, (300.0, 0.0))
        want = "a dyad joins one linkage"
    elif case == "rrr_collinear":
        t = RRRTool(d.ctx)
        d.click(t, B)
        d.click(t, D)
        mid = ((B[0] + D[0]) / 2, (B[1] + D[1]) / 2)
        t.handle(d.ev("move", mid, button="none"))
        assert t.overlay().bad
        d.click(t, mid)
        want = "dead point"
    elif case == "rrr_on_joint":
        t = RRRTool(d.ctx)
        d.click(t, B)
        d.click(t, D)
        d.click(t, C)
        want = "coincide with joint C"
    elif case == "rrr_pick_empty":
        d.click(RRRTool(d.ctx), (300, 300))
        want = "pick a revolute joint"
    elif case == "slider_pin_at_guide_start":
        t = SliderTool(d.ctx)
        d.click(t, C)
        d.click(t, (250.0, 150.0))
        d.click(t, (250.0, 150.0))
        want = "give the guide a direction"
    elif case == "slider_pin_on_joint":
        t = SliderTool(d.ctx)
        d.click(t, C)
        d.click(t, (250.0, 150.0))
        d.click(t, D)
        want = "coincide with joint D"
    elif case == "rpr_same_joint":
        t = RPRTool(d.ctx)
        d.click(t, B)
        d.click(t, B)
        want = "picked already"
    elif case == "coupler_on_empty":
        d.click(CouplerPointTool(d.ctx), (300, 300))
        want = "empty space"
    elif case == "coupler_on_joint":
        d.click(CouplerPointTool(d.ctx), C)
        want = "not on joint C"
    elif case == "delete_nothing":
        d.click(DeleteTool(d.ctx), (300, 300))
        want = "click a joint or a link"
    else:  # move_onto_joint: C dragged straight onto B (same link)
        t = SelectTool(d.ctx)
        t.handle(d.ev("press", C))
        t.handle(CanvasEvent("move", B, buttons=frozenset({"left"}), button="none", hit=d.ctx.pick(B, TOL),
                             tolerance=TOL))
        t.handle(CanvasEvent("release", B, hit=None, tolerance=TOL))
        want = "zero length"
    assert d.unchanged(before), case
    assert any(want in m for m in d.messages), (case, d.messages)
    assert d.ctl.undo_stack.count() == (1 if case == "rrr_other_linkage" else 0)


def test_a_dyad_that_would_break_a_working_linkage_is_refused():
    d = fourbar()
    before = d.ctl.scene
    lk = before.element("fourbar")
    broken = lk.with_link(Link("extra", ("B", "D")))        # over-constrains it
    assert ops.structure_error(broken)
    assert not d.ctx.commit("fourbar", broken, "add a bar")
    assert d.unchanged(before) and "cannot add a bar" in d.messages[-1]


def test_delete_items_cleans_up_dangling_parts():
    lk = example("slider_crank_offset").element("slider_crank")
    out = ops.delete_items(lk, joints=["C"])                    # the slider pin
    assert "S" not in out.joint_ids and "slider" not in out.link_ids and "rod" not in out.link_ids
    assert set(out.joint_ids) == {"A", "B"} and out.driver == lk.driver
    assert ops.delete_items(lk, joints=["A", "B", "C", "S"]) is None
    assert ops.fresh_joint_id(lk) == "D" and ops.fresh_link_id(lk) == "link1"
    assert ops.fresh_link_id(lk, "crank", bare=True) == "crank1"


def test_a_pick_undone_under_a_tool_restarts_it_politely():
    d = fourbar()
    t = RRRTool(d.ctx)
    d.click(t, (20.0, 34.641016151))            # B
    d.click(t, (53.090624797, 108.159793008))   # E, the coupler point
    lk = d.ctl.scene.element("fourbar")
    d.ctl.push(ReplaceElement(ops.delete_items(lk, joints=["E"])))
    t.handle(d.ev("move", (100.0, 150.0), button="none"))
    assert "a picked joint is gone" in d.messages[-1] and t.picks() == []
    assert t.overlay().picked == []


@pytest.mark.parametrize("name,pin,slide", [("inverted_slider_crank", "B", "Q"), ("sixbar_moving_guide", "E", "Q"),
                                             ("slider_crank_offset", "C", "S")])
def test_a_slider_block_is_shown_on_its_pin_and_rebasing_keeps_the_motion(name, pin, slide):
    from mechsketch.gui.canvas.pose import rebase

    d = Driver(example(name))
    el = d.ctl.scene.ids[0]
    lk = d.ctl.scene.element(el)
    n = d.ctl.sample_count()
    for k in (0, n // 5, n // 2, 4 * n // 5):
        d.ctl.set_frame(k)
        pose = d.ctx.pose(el)
        assert pose.index == k
        assert np.allclose(pose.at[slide], pose.at[pin], atol=1e-9)     # the block sits on its pin
    k = n // 3
    arrays = d.ctx.pose(el).arrays
    moved = rebase(lk, arrays, k)
    assert moved is not lk
    again = compile_plan(moved).sweep(samples=n, order=0)
    for j in lk.joint_ids:
        if lk.joint(j).kind is JointKind.R:
            want = arrays.pos[j][k:k + 1]
            assert np.allclose(again.position(j)[0], want[0], atol=1e-9), j
    # one full cycle later it is the same curve again (same lengths, same assembly mode)
    orig = arrays.pos[pin]
    shifted = np.roll(orig, -k, axis=0)
    assert np.allclose(again.position(pin), shifted, atol=1e-7)
