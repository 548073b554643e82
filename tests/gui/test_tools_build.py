"""Building linkages with the canvas tools by mouse clicks, checked against closed-form geometry."""
from __future__ import annotations

import math

import numpy as np
import pytest

from canvas_user import fourbar_by_formula, make_view
from mechsketch.core.model.linkage import JointKind


def build_fourbar(user) -> None:
    """Ground pivots A (0,0) and D (160,0), crank A-B to (20,40), RRR B-C-D with C at (130,110)."""
    user.tool("ground")
    user.click((0, 0))
    user.click((160, 0))
    user.tool("crank")
    user.click((0, 0))
    user.click((20, 40))
    user.tool("rrr")
    user.click((20, 40))
    user.click((160, 0))
    user.click((130, 110))


def test_four_bar_built_by_clicks_solves_like_circle_intersection(qtbot):
    ctl, view, user = make_view(qtbot)
    build_fourbar(user)
    (lk,) = ctl.linkages()
    # ids in the order of creation: pivots A, B; crank tip C; inner joint D
    assert {j.id: j.at for j in lk.joints} == {"A": (0.0, 0.0), "B": (160.0, 0.0), "C": (20.0, 40.0),
                                               "D": (130.0, 110.0)}
    assert lk.link("ground").joints == ("A", "B")
    assert lk.driver.link == "crank" and lk.link("crank").joints == ("A", "C") and lk.driver.pivot == "A"
    assert [lk.link(k).joints for k in ("link1", "link2")] == [("C", "D"), ("B", "D")]
    res = ctl.result(lk.id)
    assert res.ok and res.diagnostics.full_turn
    sol = res.solution
    c = sol.position("D")
    for k in (0, 37, 90, 181, 333):
        want = fourbar_by_formula(0j, 20 + 40j, 130 + 110j, 160 + 0j, float(sol.input[k]))
        assert abs(complex(*c[k]) - want) < 1e-9
    # four tools -> four ground/crank/dyad commands (two ground pivots)
    assert ctl.undo_stack.count() == 4
    assert [ctl.undo_stack.text(i) for i in range(4)] == [
        "add ground pivot A", "add ground pivot B", "add crank crank", "add RRR dyad C-D-B"]


def test_each_tool_step_is_one_undo_command_and_undo_redo_walks_back(qtbot):
    ctl, view, user = make_view(qtbot)
    build_fourbar(user)
    full = ctl.scene
    for expected_joints in (["A", "B", "C"], ["A", "B"], ["A"]):
        ctl.undo_stack.undo()
        assert list(ctl.scene.elements[0].joint_ids) == expected_joints
    ctl.undo_stack.undo()
    assert ctl.scene.elements == ()
    for _ in range(4):
        ctl.undo_stack.redo()
    assert ctl.scene == full
    assert ctl.result("linkage1").ok


def test_half_built_linkage_is_drawn_and_explained_not_raised(qtbot):
    ctl, view, user = make_view(qtbot)
    user.tool("ground")
    user.click((0, 0))
    res = ctl.result("linkage1")
    assert res.error and res.solution is None
    assert "ground pivot A added" in view.messages[-1]
    user.tool("crank")
    user.click((0, 0))
    user.click((20, 40))
    assert ctl.result("linkage1").ok            # a lone crank already turns
    assert "next: an RRR dyad" in view.messages[-1]
    view.grab()                                  # paints without error


def test_ground_pivot_goes_into_the_selected_linkage_else_a_new_one(qtbot):
    ctl, view, user = make_view(qtbot)
    user.tool("ground")
    user.click((0, 0))
    user.click((100, 0))
    assert ctl.scene.ids == ("linkage1",)
    ctl.set_selection([])
    user.click((0, 100))
    assert ctl.scene.ids == ("linkage1", "linkage2")


def test_slider_crank_with_guide_on_the_frame(qtbot):
    ctl, view, user = make_view(qtbot)
    user.tool("ground")
    user.click((0, 0))
    user.tool("crank")
    user.click((0, 0))
    user.click((40, 0))
    user.tool("rrp")
    user.click((40, 0))          # rod's known joint B
    user.click((100, 20))        # guide start, empty space -> on the frame
    user.click((190, 20))        # slider pin
    lk = ctl.linkages()[0]
    pin = lk.joint("C")        # A pivot, B crank tip, C pin, D the P joint
    slide = lk.joint("D")
    assert slide.kind is JointKind.P and slide.at == pin.at == (190.0, 20.0) and slide.axis_deg == 0.0
    assert "D" in lk.link("ground").joints
    res = ctl.result(lk.id)
    assert res.ok and res.diagnostics.full_turn
    sol = res.solution
    c = sol.position("C")
    r, l, e = 40.0, math.hypot(150.0, 20.0), 20.0
    th = sol.input
    x = r * np.cos(th) + np.sqrt(l * l - (e - r * np.sin(th)) ** 2)
    np.testing.assert_allclose(c[:, 0], x, atol=1e-9)
    np.testing.assert_allclose(c[:, 1], e, atol=1e-9)


def test_rpr_inverted_slider_crank(qtbot):
    ctl, view, user = make_view(qtbot)
    user.tool("ground")
    user.click((0, 0))
    user.click((100, 0))
    user.tool("crank")
    user.click((0, 0))
    user.click((30, 20))
    user.tool("rpr")
    user.click((30, 20))     # M: the block pivots on the crank tip
    user.click((100, 0))     # H: the slotted bar's pivot
    lk = ctl.linkages()[0]
    q = next(j for j in lk.joints if j.kind is JointKind.P)
    assert q.at == (30.0, 20.0)
    assert q.axis_deg == pytest.approx(math.degrees(math.atan2(20, -70)))
    # A, B pivots; C crank tip; D the P joint at C
    assert lk.links_of(q.id) == ("block1", "link1") and lk.link("link1").joints == ("B", q.id)
    res = ctl.result(lk.id)
    assert res.ok and res.diagnostics.full_turn
    sol = res.solution
    b = sol.position("C")
    want = np.arctan2(b[:, 1], b[:, 0] - 100.0)          # the bar through B points at the crank tip
    diff = np.angle(np.exp(1j * (sol.angle("link1") - want)))
    np.testing.assert_allclose(diff, 0.0, atol=1e-9)


def test_coupler_point_is_added_to_the_link_and_traced(qtbot):
    ctl, view, user = make_view(qtbot)
    build_fourbar(user)
    user.tool("coupler")
    user.click((80, 78))        # on link1 (C-D); snapped to the 10 mm grid
    lk = ctl.linkages()[0]
    assert lk.joint_ids == ("A", "B", "C", "D", "E") and lk.joint("E").at == (80.0, 80.0)
    carrier = lk.links_of("E")
    assert carrier == ("link1",) and lk.link("link1").joints == ("C", "D", "E")
    assert "E" in view.traced_joints(lk)
    sol = ctl.result(lk.id).solution
    # a point of the coupler keeps its distances to B and C
    e, b, c = sol.position("E"), sol.position("C"), sol.position("D")
    db = np.hypot(*(e - b).T)
    dc = np.hypot(*(e - c).T)
    assert np.ptp(db) < 1e-9 and np.ptp(dc) < 1e-9


def test_slider_on_a_moving_guide_by_clicks(qtbot):
    from canvas_user import example

    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    user.tool("rrp")
    user.click((53.090624797, 108.159793008))   # the rod starts at the coupler point E
    user.click((153.0, 30.0))                   # guide start on the rocker D-C (snaps to (150, 30))
    user.click((140.0, 90.0))                   # slider pin; the guide runs (150,30) -> (140,90)
    lk = ctl.scene.element("fourbar")
    pin, slide = lk.joint("F"), lk.joint("G")
    assert slide.kind is JointKind.P and "G" in lk.link("rocker").joints
    assert slide.axis_deg == pytest.approx(math.degrees(math.atan2(60.0, -10.0)))
    res = ctl.result("fourbar")
    assert res.ok, res.error
    sol = res.solution
    assert sol.residual() < 1e-9
    # the pin stays on the guide line carried by the rocker, at every valid sample
    g0 = sol.point("rocker", (150.0, 30.0))
    g1 = sol.point("rocker", (140.0, 90.0))
    f = sol.position("F")
    cross = (g1 - g0)[:, 0] * (f - g0)[:, 1] - (g1 - g0)[:, 1] * (f - g0)[:, 0]
    ok = sol.valid
    assert ok.any() and np.nanmax(np.abs(cross[ok])) < 1e-8
    view.grab()


def test_a_coupler_point_added_at_an_animation_frame_lands_where_clicked(qtbot):
    from canvas_user import example

    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    ctl.set_frame(120)
    pose = view.ctx.pose("fourbar")
    b, c = (complex(*pose.at[j]) for j in "BC")
    p = b + 0.5 * (c - b)
    user.tool("coupler")
    view.snap_enabled = False
    user.click((p.real, p.imag))
    assert ctl.frame == 120 and ctl.undo_stack.count() == 1
    lk = ctl.scene.element("fourbar")
    new = [j for j in lk.joint_ids if j not in "ABCDE"]
    assert len(new) == 1
    shown = ctl.result("fourbar").solution.position(new[0])[120]
    assert abs(complex(*shown) - p) < 2 * view.px()          # where it was clicked, at that frame
