"""The workspace: edits with inverses, change events, results cached by element value, and the
incremental re-sweep of a dragged linkage checked bit for bit against a full solve."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from chains import dyad_chain
from linkage_builders import fourbar
from mechsketch.core import (AddElement, EditError, MoveJoint, RemoveElement, ReplaceElement, RequestError,
                             Scene, UnknownIdError, load_scene)
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.model.linkage import Link
from mechsketch.core.solver.incremental import dirty_steps, moved_joints, resweep
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.workspace import Change, ElementChange, LinkageResult, Workspace
from mechsketch.resources import example_path


def solved_counts(ws: Workspace) -> int:
    """Solves run so far (an incremental re-sweep counts once, as a linkage solve)."""
    return sum(v for k, v in ws.stats.items() if k.startswith("solve:"))


def assert_same_solution(a, b, linkage) -> None:
    """Every joint's position, velocity and acceleration and every link's angle, ω and α agree
    exactly (NaN where the other has NaN)."""
    assert np.array_equal(a.valid, b.valid)
    for j in linkage.joint_ids:
        for fa, fb in ((a.position, b.position), (a.velocity, b.velocity), (a.acceleration, b.acceleration)):
            assert np.array_equal(fa(j), fb(j), equal_nan=True), j
    for k in linkage.moving_links:
        for fa, fb in ((a.angle, b.angle), (a.omega, b.omega), (a.alpha, b.alpha)):
            assert np.array_equal(fa(k), fb(k), equal_nan=True), k


@pytest.fixture
def two_linkages() -> Workspace:
    six = load_scene(example_path("sixbar_moving_guide")).element("sixbar")
    return Workspace(Scene((six, dyad_chain(32, samples=360))))


# -- edits and change events ----------------------------------------------------------------
def test_apply_returns_the_inverse_and_tells_listeners_which_element_changed(two_linkages):
    ws = two_linkages
    seen: list[Change] = []
    ws.subscribe(seen.append)
    before = ws.scene
    inverse = ws.apply(MoveJoint("sixbar", "C", (130.0, 118.0)))
    assert ws.scene.element("sixbar").joint("C").at == (130.0, 118.0)
    assert seen[-1].ids == {"sixbar"} and seen[-1].kind("sixbar") is ElementChange.MODIFIED
    assert not seen[-1].preview and not seen[-1].replaced
    ws.apply(inverse)
    assert ws.scene == before and len(seen) == 2
    ws.apply(RemoveElement("chain"))
    assert seen[-1].kind("chain") is ElementChange.REMOVED
    ws.apply(AddElement(dyad_chain(2, eid="small")))
    assert seen[-1].kind("small") is ElementChange.ADDED
    ws.reset(Scene())
    assert seen[-1].replaced and ws.scene.elements == ()


def test_a_refused_edit_leaves_the_document_and_tells_no_one(two_linkages):
    ws = two_linkages
    seen: list[Change] = []
    ws.subscribe(seen.append)
    before = ws.scene
    with pytest.raises(EditError):
        ws.apply(AddElement(dyad_chain(2, eid="chain")))       # the id exists
    with pytest.raises(UnknownIdError) as info:
        ws.apply(MoveJoint("sixbar", "nope", (0.0, 0.0)))
    assert isinstance(info.value, KeyError) and "nope" in str(info.value)
    assert ws.scene is before and seen == []


def test_an_edit_re_solves_only_the_element_it_touches_and_undo_re_solves_nothing(two_linkages):
    ws = two_linkages
    chain0, six0 = ws.result("chain"), ws.result("sixbar")
    assert chain0.ok and six0.ok
    n0 = solved_counts(ws)
    inverse = ws.apply(MoveJoint("sixbar", "C", (131.0, 118.0)))
    six1 = ws.result("sixbar")
    assert ws.result("chain") is chain0                         # untouched: the same object
    assert six1 is not six0 and solved_counts(ws) == n0 + 1     # one element solved once
    ws.apply(inverse)                                           # undo: the old value is cached
    assert ws.result("sixbar") is six0 and solved_counts(ws) == n0 + 1
    ws.apply(MoveJoint("sixbar", "C", (131.0, 118.0)))          # redo: cached too
    assert ws.result("sixbar") is six1 and solved_counts(ws) == n0 + 1


def test_drag_previews_report_each_move_and_one_final_change_on_release(two_linkages):
    ws = two_linkages
    seen: list[Change] = []
    ws.subscribe(seen.append)
    base = ws.scene
    ws.begin_preview()
    for x in (130.0, 131.0, 132.0):
        ws.preview(MoveJoint("sixbar", "C", (x, 118.0)))
    assert [c.preview for c in seen] == [True, True, True] and all(c.ids == {"sixbar"} for c in seen)
    ws.preview(MoveJoint("sixbar", "C", (132.0, 118.0)))        # no move: no change
    assert len(seen) == 3
    ws.end_preview(notify=False)
    assert ws.scene is base and len(seen) == 3                  # held for the final edit
    ws.apply(MoveJoint("sixbar", "C", (132.0, 118.0)))
    assert len(seen) == 4 and not seen[-1].preview and seen[-1].ids == {"sixbar"}
    # a cancelled drag: one final change back to the base
    ws.begin_preview()
    ws.preview(MoveJoint("chain", "P32", (3150.0, 85.0)))
    ws.end_preview()
    assert len(seen) == 6 and not seen[-1].preview and seen[-1].ids == {"chain"}


# -- results --------------------------------------------------------------------------------
def test_a_linkage_that_cannot_be_solved_is_a_result_with_the_message():
    lk = fourbar()
    broken = lk.with_link(Link("extra", ("B", "D")))             # over-constrained
    ws = Workspace(Scene((broken,)))
    res = ws.result(broken.id)
    assert isinstance(res, LinkageResult) and not res.ok and res.solution is None
    assert "mobility 0" in res.error and res.summary().endswith(res.error)
    with pytest.raises(UnknownIdError):
        ws.result("nope")


def test_solve_requests_are_cached_by_element_value_and_request():
    ws = Workspace.open(example_path("sixbar_moving_guide"))
    a = ws.solve("sixbar", samples=100, order=1)
    assert ws.solve("sixbar", samples=100, order=1) is a
    b = ws.solve("sixbar", samples=100, order=0, joints=["C"])
    assert b is not a and b.groups and all("rod2" not in g.name for g in b.groups)
    ref = compile_plan(ws.element("sixbar")).sweep(samples=100, order=1)
    assert np.array_equal(a.velocity("E"), ref.velocity("E"))
    assert ws.solve("sixbar") is ws.result("sixbar").solution   # the default request is the result
    with pytest.raises(RequestError):
        a.acceleration("E")


def test_facade_one_line_api_reads_the_workspace_caches():
    ws = Workspace.open(example_path("sixbar_moving_guide"))
    link = ws["sixbar"]
    assert link.joints == ws.element("sixbar").joints and link.compile() is link.compile()
    sol = link.solve(samples=3600, order=2)
    ref = compile_plan(ws.element("sixbar")).sweep(samples=3600, order=2)
    assert np.array_equal(sol.acceleration("E"), ref.acceleration("E"), equal_nan=True)
    assert link.summary().startswith("linkage 'sixbar'")
    with pytest.raises(RequestError, match="is a linkage"):
        link.kinematics()
    g = Workspace.open(example_path("geneva_z6"))
    gid = g.scene.ids[0]
    assert np.array_equal(g[gid].kinematics(720).omega, kinematics(g.element(gid), 720).omega)


def test_geneva_results_are_kept_per_value_and_a_candidate_check_is_reused():
    ws = Workspace.open(example_path("geneva_z6"))
    gid = ws.scene.ids[0]
    g = ws.element(gid)
    first = ws.result(gid)
    assert first.ok and first.n_frames == g.samples
    import dataclasses
    bigger = dataclasses.replace(g, roller_radius=g.roller_radius * 1.05)
    assert ws.check_element(bigger) is None
    n = solved_counts(ws)
    ws.apply(ReplaceElement(bigger))
    assert ws.result(gid).element is bigger and solved_counts(ws) == n   # checked before: no solve
    ws.samples = 90
    assert ws.result(gid).n_frames == 90


# -- incremental re-sweep -------------------------------------------------------------------
def test_moving_the_last_joint_of_a_chain_runs_one_group_and_equals_a_full_solve():
    lk = dyad_chain(8, samples=720)
    old = compile_plan(lk).sweep(order=2)
    new = lk.with_joint_moved("P8", (752.0, 83.0))
    moved = moved_joints(lk, new)
    assert moved == {"P8"}
    plan = compile_plan(new)
    assert dirty_steps(plan, moved) == {7}
    sol = resweep(old, plan, moved)
    assert sol is not None
    for name in [s.group.name for s in plan.steps[:7]]:
        assert sol.group_output(name) is old.group_output(name)   # reused, not recomputed
    assert_same_solution(sol, plan.sweep(order=2), new)


def test_moving_a_joint_upstream_re_runs_everything_downstream():
    lk = dyad_chain(6)
    plan = compile_plan(lk.with_joint_moved("P2", (152.0, 81.0)))
    assert dirty_steps(plan, {"P2"}) == {1, 2, 3, 4, 5}     # the group of P2 is dyad 2 (index 1)
    assert dirty_steps(plan, {"G4"}) == {3, 4, 5}
    assert moved_joints(lk, lk.with_link(Link("r9", ("P1", "G1")))) is None   # topology changed


def test_dragging_the_farthest_joint_still_re_sweeps_only_its_group():
    """The six-bar's E is its farthest joint from the origin: moving it changes the linkage's
    coordinate scale, but a group's rounding tolerance follows only its own neighbourhood."""
    six = load_scene(example_path("sixbar_moving_guide")).element("sixbar")
    old = compile_plan(six).sweep(samples=720, order=2)
    at = six.joint("E").at
    new = six.with_joints_moved({"E": (at[0] + 3.0, at[1] + 2.0), "Q": (at[0] + 3.0, at[1] + 2.0)})
    plan = compile_plan(new)
    assert plan.coord_scale != old.plan.coord_scale
    sol = resweep(old, plan, moved_joints(six, new))
    rrr = plan.steps[0].group.name
    assert sol is not None and sol.group_output(rrr) is old.group_output(rrr)
    assert_same_solution(sol, plan.sweep(samples=720, order=2), new)


def test_the_workspace_re_sweeps_a_dragged_linkage_incrementally():
    ws = Workspace(Scene((dyad_chain(16, samples=720),)))
    ws.result("chain")
    ws.begin_preview()
    ws.preview(MoveJoint("chain", "P16", (1552.0, 84.0)))
    res = ws.result("chain")
    assert res.incremental and ws.stats["incremental"] == 1
    full = compile_plan(ws.element("chain")).sweep(samples=720, order=2)
    assert_same_solution(res.solution, full, ws.element("chain"))
    assert res.diagnostics.full_turn


@settings(max_examples=25, deadline=None)
@given(joint=st.sampled_from(["P1", "P3", "P5", "G2", "G5", "P0"]),
       dx=st.floats(-4.0, 4.0), dy=st.floats(-4.0, 4.0))
def test_incremental_and_full_solves_agree_bit_for_bit(joint, dx, dy):
    lk = dyad_chain(5, samples=360)
    old = compile_plan(lk).sweep(order=2)
    at = lk.joint(joint).at
    new = lk.with_joint_moved(joint, (at[0] + dx, at[1] + dy))
    plan = compile_plan(new)
    sol = resweep(old, plan, moved_joints(lk, new))
    if sol is None:   # the driver changed: the caller solves in full
        assert joint == "P0" and (dx, dy) != (0.0, 0.0)
        return
    assert_same_solution(sol, plan.sweep(order=2), new)


def test_the_readme_python_api_example_runs_and_undo_solves_nothing(monkeypatch):
    """The README's Python API block, run as written (from the repository root)."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    text = (root / "README.md").read_text(encoding="utf-8")
    block = text.split("## Python API", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(root)
    env: dict = {"angles": np.linspace(0.0, 1.0, 5)}
    monkeypatch.setattr("builtins.print", lambda *a, **k: None)
    exec(compile(block, "README.md", "exec"), env)
    ws, link = env["ws"], env["link"]
    assert env["sol"].position("E").shape == (3600, 2)
    assert ws.element("sixbar").joint("C").at == link.joint("C").at   # the undo restored C
    assert ws.stats["incremental"] >= 1


def test_a_drag_decomposes_the_linkage_once_then_reuses_its_groups():
    ws = Workspace(Scene((dyad_chain(6),)))
    ws.result("chain")
    ws.begin_preview()
    for x in (352.0, 353.0, 354.0):
        ws.preview(MoveJoint("chain", "P4", (x, 80.0)))
        assert ws.result("chain").ok
    assert ws.stats["decompose"] == 1 and ws.stats["incremental"] == 3
    ws.end_preview()
    ws.apply(AddElement(fourbar()))
    ws.result(fourbar().id)
    assert ws.stats["decompose"] == 2
