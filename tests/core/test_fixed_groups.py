"""Groups with zero mobility (issue 13, item 1): a dyad hung on frame joints only — an RRR between
two ground pivots, a slider whose rod pivots on the frame and whose guide is the frame, a dyad on
the crank's pivot and a ground pivot, a dyad on such a fixed dyad — is a structure: it is solved
once, its links do not move (positions exactly the drawn ones, rates exactly 0), it has no branch
points and no dead points, the diagnostics say so, and ``validate`` / ``analyze`` agree (they
used to say "ok" and then raise IndexError at an exactly collinear one)."""
from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core import load_scene
from mechsketch.core.cli import main
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.solver.structure import decompose, fixed_links
from mechsketch.core.workspace import Workspace


def _with(base, joints, links, ground_joints=()):
    """``base`` plus joints [(id, kind, xy[, axis])] and links {id: [joints]}; ``ground_joints``
    are added to the frame."""
    js = [(j.id, j.kind.value, j.at) + ((j.axis_deg,) if j.axis_deg is not None else ()) for j in base.joints]
    ls = {k.id: list(k.joints) for k in base.links}
    ls[base.ground] = ls[base.ground] + list(ground_joints)
    ls.update(links)
    return LB.build(base.id, js + list(joints), ls, base.ground, base.driver.link, base.driver.pivot,
                    base.driver.speed_rpm, base.samples)


def _crank_only():
    return LB.build("fx", [("A", "R", (0.0, 0.0)), ("B", "R", (20.0, 30.0))],
                    {"ground": ["A"], "crank": ["A", "B"]}, "ground", "crank", "A")


CASES = {
    # RRR between two ground pivots, drawn as a triangle
    "rrr": lambda: _with(_crank_only(), [("E", "R", (0.0, -50.0)), ("F", "R", (100.0, -50.0)),
                                         ("G", "R", (50.0, -10.0))],
                         {"u": ["E", "G"], "v": ["G", "F"]}, ["E", "F"]),
    # the same drawn exactly collinear (the IndexError of the issue)
    "rrr_collinear": lambda: _with(_crank_only(), [("E", "R", (0.0, -50.0)), ("F", "R", (100.0, -50.0)),
                                                   ("G", "R", (50.0, -50.0))],
                                   {"u": ["E", "G"], "v": ["G", "F"]}, ["E", "F"]),
    # a slider: rod from a ground pivot, block on a frame guide (RRP), guide through the pin
    "rrp": lambda: _with(_crank_only(), [("E", "R", (0.0, -50.0)), ("G", "R", (60.0, -20.0)),
                                         ("S", "P", (60.0, -20.0), 0.0)],
                         {"rod": ["E", "G"], "block": ["G", "S"]}, ["E", "S"]),
    # the slider drawn exactly at its dead point (rod perpendicular to the guide: |dn| = rod)
    "rrp_dead": lambda: _with(_crank_only(), [("E", "R", (0.0, -50.0)), ("G", "R", (0.0, -20.0)),
                                              ("S", "P", (0.0, -20.0), 0.0)],
                              {"rod": ["E", "G"], "block": ["G", "S"]}, ["E", "S"]),
    # an RPR between the crank's pivot A (on the frame and the crank) and a ground pivot
    "rpr_on_pivot": lambda: _with(_crank_only(), [("F", "R", (100.0, -50.0)), ("Q", "P", (0.0, 0.0), 153.434948823)],
                                  {"block": ["A", "Q"], "bar": ["F", "Q"]}, ["F"]),
    # a four-bar plus a fixed RRR listed before the moving links, and a second dyad hung on it
    "fourbar_chain": lambda: _with(LB.fourbar(eid="fx"), [
        ("E", "R", (0.0, -50.0)), ("F", "R", (100.0, -50.0)), ("G", "R", (50.0, -10.0)),
        ("H", "R", (150.0, -80.0)), ("K", "R", (120.0, -30.0))],
        {"u": ["E", "G"], "v": ["G", "F", "K"], "w": ["K", "H"], "x": ["H", "F"]}, ["E", "F"]),
}
FIXED = {"rrr": {"u", "v"}, "rrr_collinear": {"u", "v"}, "rrp": {"rod", "block"}, "rrp_dead": {"rod", "block"},
         "rpr_on_pivot": {"block", "bar"}, "fourbar_chain": {"u", "v", "w", "x"}}


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_group_on_frame_joints_is_solved_once_and_does_not_move(case):
    lk = CASES[case]()
    assert fixed_links(lk) == FIXED[case] | {"ground"}
    groups = decompose(lk)
    assert {l for g in groups if g.fixed for l in (g.link_i, g.link_j)} == FIXED[case]
    plan = compile_plan(lk)
    sol = plan.sweep(samples=360, order=2)
    assert sol.valid.all()
    moving = {j for k in FIXED[case] for j in lk.link(k).joints} - set(lk.link("ground").joints) - {"A"}
    for j in moving:
        p = sol.position(j)
        assert p.shape == (360, 2)
        assert np.array_equal(p, np.broadcast_to(lk.joint(j).at, (360, 2)))   # exactly the drawn pose
        assert np.array_equal(sol.velocity(j), np.zeros((360, 2)))
        assert np.array_equal(sol.acceleration(j), np.zeros((360, 2)))
    for k in FIXED[case]:
        assert np.array_equal(sol.omega(k), np.zeros(360)) and np.array_equal(sol.alpha(k), np.zeros(360))
        assert np.allclose(sol.rotation(k), 0.0, atol=0.0)
    assert sol.residual() < 1e-12
    for g in groups:
        if g.fixed:
            assert plan.branch_points()[g.name].size == 0
            assert sol.conditioning(g.name).shape == (360,)
    d = diagnose(sol)
    assert d.full_turn and not [p for p in d.dead_points if p.group in {g.name for g in groups if g.fixed}]
    text = str(d)
    for g in groups:
        if g.fixed:
            assert f"group {g.name}: kind {g.kind}" in text
            assert f"{g.name} is fixed to the frame" in text


def test_the_moving_part_is_unchanged_by_a_fixed_group_beside_it():
    fb = LB.fourbar(eid="fx")
    with_fixed = CASES["fourbar_chain"]()
    a = compile_plan(fb).sweep(samples=720)
    b = compile_plan(with_fixed).sweep(samples=720)
    for j in fb.joint_ids:
        assert np.array_equal(a.position(j), b.position(j))
        assert np.array_equal(a.acceleration(j), b.acceleration(j))


def test_fixed_links_ignore_the_driver_and_need_no_driver():
    lk = CASES["rrr"]()
    nodrv = LB.build("nd", [(j.id, "R", j.at) for j in lk.joints if j.id != "B"],
                     {"ground": ["A", "E", "F"], "u": ["E", "G"], "v": ["G", "F"]}, "ground", "crank", "A")
    assert fixed_links(nodrv) == {"ground", "u", "v"}
    assert fixed_links(LB.fourbar()) == {"ground"}
    assert fixed_links(LB.sixbar_stephenson()) == {"ground"}


def _cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


@pytest.mark.parametrize("case", ["rrr_collinear", "rrp_dead", "fourbar_chain"])
def test_validate_and_analyze_agree_on_a_fixed_group(tmp_path, capsys, case):
    lk = CASES[case]()
    path = tmp_path / "s.json"
    path.write_text(json.dumps(LB.scene_dict(lk)), encoding="utf-8")
    code, out, _ = _cli(["validate", path], capsys)
    assert code == 0 and out.strip().endswith("ok")
    code, out, err = _cli(["analyze", path, "--samples", 24, "--csv", "-", "--summary"], capsys)
    assert code == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    head, body = rows[0], rows[1:]
    assert len(body) == 24 and all(r[head.index("valid")] == "1" for r in body)
    g = next(g for g in decompose(lk) if g.fixed)
    assert f"{g.name} is fixed to the frame" in err
    ws = Workspace(load_scene(path))
    res = ws.result(lk.id)
    assert res.error is None and res.diagnostics.full_turn
