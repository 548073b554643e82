"""A dyad hung on frame joints only (issue 13, item 1): the RRR, slider and RPR tools refuse to
draw one, saying why in the status bar; a scene file that holds one (drawn by hand or by an older
version) loads in the controller and the canvas, solves, plays and paints."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from canvas_user import make_view
from mechsketch.core import load_scene

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core"))
import linkage_builders as LB  # noqa: E402


def _frame_with_crank(user) -> None:
    """Ground pivots A (0, 0), B (160, 0), C (100, -60); a crank A–D to (20, 40)."""
    user.tool("ground")
    for p in ((0, 0), (160, 0), (100, -60)):
        user.click(p)
    user.tool("crank")
    user.click((0, 0))
    user.click((20, 40))


def test_rrr_tool_refuses_a_dyad_between_two_ground_pivots(qtbot):
    ctl, view, user = make_view(qtbot)
    _frame_with_crank(user)
    before, count = ctl.scene, ctl.undo_stack.count()
    user.tool("rrr")
    user.click((160, 0))
    user.click((100, -60))
    assert "B and C are both fixed to the frame" in view.messages[-1]
    assert "would not move" in view.messages[-1]
    user.click((150, -50))               # the inner joint: nothing is added
    assert ctl.scene == before and ctl.undo_stack.count() == count
    # from a moving joint (the crank tip) to a ground pivot it works
    user.click((20, 40))
    user.click((160, 0))
    user.click((130, 110))
    assert ctl.undo_stack.count() == count + 1
    assert ctl.result("linkage1").ok


def test_rrr_tool_refuses_the_crank_pivot_with_a_ground_pivot(qtbot):
    ctl, view, user = make_view(qtbot)
    _frame_with_crank(user)
    count = ctl.undo_stack.count()
    user.tool("rrr")
    user.click((0, 0))                   # A: on the frame and on the crank, but it does not move
    user.click((100, -60))
    assert "A and C are both fixed to the frame" in view.messages[-1]
    user.click((50, -60))
    assert ctl.undo_stack.count() == count


def test_slider_tool_refuses_a_rod_from_a_ground_pivot_on_a_frame_guide(qtbot):
    ctl, view, user = make_view(qtbot)
    _frame_with_crank(user)
    before, count = ctl.scene, ctl.undo_stack.count()
    user.tool("rrp")
    user.click((160, 0))                 # the rod's joint: a ground pivot
    user.click((200, -80))               # empty space: the guide would be on the frame
    assert "would not move" in view.messages[-1] and "B" in view.messages[-1]
    user.click((240, -80))
    assert ctl.scene == before and ctl.undo_stack.count() == count


def test_rpr_tool_refuses_two_ground_pivots(qtbot):
    ctl, view, user = make_view(qtbot)
    _frame_with_crank(user)
    count = ctl.undo_stack.count()
    user.tool("rpr")
    user.click((160, 0))
    user.click((100, -60))
    assert "B and C are both fixed to the frame" in view.messages[-1]
    assert ctl.undo_stack.count() == count


def test_a_file_with_a_fixed_dyad_loads_solves_plays_and_paints(qtbot, tmp_path):
    fb = LB.fourbar(eid="fx")
    js = [(j.id, "R", j.at) for j in fb.joints] + [("E", "R", (0.0, -50.0)), ("F", "R", (100.0, -50.0)),
                                                    ("G", "R", (50.0, -50.0))]   # exactly collinear
    links = {k.id: list(k.joints) for k in fb.links}
    links["ground"] += ["E", "F"]
    links["u"], links["v"] = ["E", "G"], ["G", "F"]
    lk = LB.build("fx", js, links, "ground", "crank", "A", samples=120)
    path = tmp_path / "fixed.json"
    path.write_text(json.dumps(LB.scene_dict(lk)), encoding="utf-8")
    ctl, view, user = make_view(qtbot, load_scene(path))
    res = ctl.result("fx")
    assert res.ok and res.diagnostics.full_turn and res.diagnostics.fixed == ("RRR(u,v)",)
    g = res.solution.position("G")
    assert np.allclose(g, [50.0, -50.0], atol=1e-12, rtol=0.0)
    for k in (0, 17, 60, 119):
        ctl.set_frame(k)
        view.grab()
    # dragging the fixed dyad's inner joint previews and commits without error
    user.tool("select")
    user.drag((50, -50), (50, -40))
    qtbot.waitUntil(lambda: ctl.undo_stack.count() == 1, timeout=20000)
    assert ctl.result("fx").ok
    view.grab()
