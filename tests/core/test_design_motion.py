"""Motion synthesis (core/design/motion.py): every candidate checked independently.

Each candidate is driven by the product's solver at crank angles found independently of the
synthesis (the crank pin's position in pose j is the drawn pin carried by pose j's rigid motion),
and must carry P through every pose (position to 1e-9 of the size, turn to 1e-9 rad), meet them
in order turning its crank in its driver's direction, and pass between them with every sample
assembled and the transmission angle above the minimum — so a circuit, branch or order defect
in a returned candidate fails the test. With 5 poses taken from a known four-bar the least
squares must recover an exact one.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from mechsketch.core.design import families as F
from mechsketch.core.design.motion import synthesize_motion
from mechsketch.core.design.options import LinkageOptions
from mechsketch.core.design.targets import Cancelled, DesignError, pose_target
from mechsketch.core.io.scene_file import element_problems
from mechsketch.core.solver.plan import compile_plan


def _c(j) -> complex:
    return complex(*j.at)


def _independent_check(cand, target, exact: float, mu_min: float, th=None) -> float:
    lk = cand.linkage
    A, B = _c(lk.joint("A")), _c(lk.joint("B"))
    P, ph = target.complex_points, target.angles_rad
    Bj = P + np.exp(1j * (ph - ph[0])) * (B - P[0])           # the pin carried by each pose
    th = np.angle(Bj - A) if th is None else th
    sgn = 1.0 if lk.driver.speed_rpm > 0 else -1.0
    off = np.remainder(sgn * (th - th[0]), 2 * math.pi)
    assert np.all(np.diff(off) > 0), "order defect: the poses are not met in the crank's direction"
    plan = compile_plan(lk)
    sol = plan.evaluate(th, order=0)
    assert sol.valid.all()
    p = sol.position("P")
    pos = np.max(np.abs(p[:, 0] + 1j * p[:, 1] - P))
    rot = sol.angle("coupler")
    turn = np.remainder((rot - rot[0]) - (ph - ph[0]) + math.pi, 2 * math.pi) - math.pi
    assert pos <= exact * target.size and np.max(np.abs(turn)) <= exact, (pos, turn)
    span = th[0] + sgn * np.linspace(0.0, off[-1], 721)
    dense = plan.evaluate(span, order=0)
    assert dense.valid.all(), "a dead point or a gap between the poses"
    g = dense.groups[0].name
    assert math.degrees(math.asin(dense.conditioning(g).min())) >= mu_min - 1e-6
    assert not element_problems(lk)
    return pos


@pytest.mark.parametrize("poses", [
    [[0, 0, 0], [30, 10, 20], [50, 35, 45]],
    [[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80]],
    [[120, -40, 90], [100, -10, 60], [60, 5, 20], [20, 0, -10]],
])
def test_three_and_four_poses_exact(poses):
    t = pose_target(poses)
    res = synthesize_motion(t, LinkageOptions(candidates=3, min_transmission_deg=30))
    assert len(res.candidates) == 3
    for c in res.candidates:
        assert c.deviation <= 1e-9 * t.size and c.angle_deviation <= 1e-9
        _independent_check(c, t, 1e-9, 30)
        assert c.linkage.link("coupler").joints[-1] == "P"


def test_five_poses_of_a_known_fourbar_are_recovered():
    x = np.array([[0, 0, 100, 0, 30, 90, 80, 40, 25.0]])
    ev = F.evaluate("fourbar", x, np.radians([10, 50, 90, 130, 170])[None], 1.0)
    poses = np.stack([ev.P[0].real, ev.P[0].imag, np.degrees(ev.cpl[0])], axis=1)
    t = pose_target(poses)
    res = synthesize_motion(t, LinkageOptions(candidates=2, min_transmission_deg=20))
    best = res.candidates[0]
    assert best.deviation <= 1e-9 * t.size
    _independent_check(best, t, 1e-9, 20)


def test_six_poses_least_squares_is_honest():
    t = pose_target([[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80], [40, 90, 110], [10, 100, 130]])
    res = synthesize_motion(t, LinkageOptions(candidates=2, min_transmission_deg=20))
    for c in res.candidates:
        # at the crank angles the least squares chose: the reported deviation is the solver's
        pos = _independent_check(c, t, 0.2, 20, c.inputs_rad)
        assert abs(pos - c.deviation) <= 1e-9 * t.size
        # and no crank angle brings P nearer a pose than the least squares does by much
        sol = compile_plan(c.linkage).sweep(3600, order=0)
        p = sol.position("P")
        near = np.nanmin(np.abs((p[:, 0] + 1j * p[:, 1])[:, None] - t.complex_points[None, :]), axis=0)
        assert np.max(near) <= c.deviation + 1e-9 and np.max(near) >= 0.25 * c.deviation


def test_pivot_region_and_full_turn_are_obeyed():
    t = pose_target([[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80]])
    region = (-200.0, -200.0, 0.0, 200.0)
    res = synthesize_motion(t, LinkageOptions(candidates=2, pivot_region=region, full_turn=True))
    for c in res.candidates:
        for j in ("A", "D"):
            x, y = c.linkage.joint(j).at
            assert region[0] <= x <= region[2] and region[1] <= y <= region[3]
        assert c.full_turn
        sol = compile_plan(c.linkage).sweep(720, order=0)
        assert sol.valid.all()


def test_impossible_requests_say_what_to_relax():
    t = pose_target([[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80]])
    with pytest.raises(DesignError, match="lower the minimum transmission angle|widen the pivot region"):
        synthesize_motion(t, LinkageOptions(candidates=2, min_transmission_deg=89.5))
    with pytest.raises(DesignError, match="pivot region"):
        synthesize_motion(t, LinkageOptions(pivot_region=(1e5, 1e5, 1e5 + 1, 1e5 + 1)))


def test_progress_and_cancel():
    t = pose_target([[0, 0, 0], [30, 10, 20], [50, 35, 45]])
    seen = []

    def progress(f, msg):
        seen.append(f)
        return len(seen) > 2

    with pytest.raises(Cancelled):
        synthesize_motion(t, LinkageOptions(candidates=2), progress)
    assert seen == sorted(seen) and seen[0] == 0.0


@pytest.mark.parametrize("poses", [
    [[0, 0, 0], [30, 10, 0.001], [50, 35, 0.002], [55, 70, 0.004]],            # hardly turns: pivots far away
    [[0, 0, 5], [10, 10, 5], [20, 20.001, 5], [30, 30, 5.0]],                   # nearly a translation on a line
    [[0, 0, 0], [30, 10, 20], [30, 10.0001, 20.0001], [55, 70, 80]],            # two poses nearly repeated
    [[0, 0, 0], [100, 0, 90], [100, 100, 180], [0, 100.000001, 270]],           # nearly one rotation
])
def test_near_degenerate_poses_are_exact_or_refused_clearly(poses):
    t = pose_target(poses)
    try:
        res = synthesize_motion(t, LinkageOptions(candidates=1))
    except DesignError as exc:
        assert "widen the pivot region" in str(exc) or "lower the minimum transmission angle" in str(exc)
        return
    for c in res.candidates:
        _independent_check(c, t, 1e-9, 30)
