"""Branch points: at an exact change point the motion keeps to its smooth branch; near one it
keeps its mode. References: the parallelogram's closed form (coupler parallel to the frame),
central finite differences, and the rhombus/kite geometry."""
from __future__ import annotations

import math

import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan


def _z(a):
    return a[:, 0] + 1j * a[:, 1]


@pytest.mark.parametrize("theta0", [30.0, 123.0, 250.0])
@pytest.mark.parametrize("samples", [360, 3600, 7201])
def test_parallelogram_stays_a_parallelogram_through_both_change_points(theta0, samples):
    mode = 1 if math.sin(math.radians(theta0)) > 0 else -1  # the drawn pose is the parallelogram
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=theta0, mode=mode)
    sol = compile_plan(lk).sweep(samples=samples, order=2)
    assert sol.valid.all()
    # closed form of the parallelogram branch: C = D + (B − A), so the coupler keeps its angle
    A, B, C, D = (_z(sol.position(j)) for j in "ABCD")
    assert np.max(np.abs(C - (D + (B - A)))) < 1e-5  # within the change points' own conditioning
    assert np.ptp(sol.angle("coupler")) < 1e-6
    # rates are undefined exactly at a change point (0/0); everywhere else the rocker follows the crank
    away = sol.conditioning("RRR(coupler,rocker)") > 1e-6
    assert away.sum() >= samples - 2
    assert np.allclose(sol.omega("rocker")[away], sol.omega("crank")[away], atol=1e-9 * 10)
    clear = sol.conditioning("RRR(coupler,rocker)") > 1e-2  # accelerations lose eps/sin²μ near it
    assert np.allclose(sol.alpha("rocker")[clear], 0.0, atol=1e-6)
    offsets = sorted(np.degrees(compile_plan(lk).branch_points()["RRR(coupler,rocker)"]))
    expect = sorted(((0.0 - theta0) % 360.0, (180.0 - theta0) % 360.0))
    assert offsets == pytest.approx(expect, abs=1e-4)


def test_change_points_are_reported_as_such():
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0)
    d = diagnose(compile_plan(lk).sweep(samples=720, order=2))
    kinds = sorted((round(math.degrees(p.input)) % 360, p.kind) for p in d.dead_points)
    assert kinds == [(0, "change point"), (180, "change point")]
    assert d.full_turn


def test_velocity_is_continuous_across_a_change_point():
    """On the smooth branch the closed-form velocity equals the finite difference of positions
    on both sides of the change point (on the crossed branch it would jump)."""
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0)
    plan = compile_plan(lk)
    h = 1e-5
    for side in (-1e-3, 1e-3):
        x = np.array([math.pi + side])
        v = _z(plan.evaluate(x, order=1).velocity("C"))[0]
        fd = (_z(plan.evaluate(x + h, order=0).position("C"))[0]
              - _z(plan.evaluate(x - h, order=0).position("C"))[0]) / (2 * h) * plan.omega
        assert abs(v - fd) < 1e-6 * abs(v)


@pytest.mark.parametrize("gap", [1e-6, 1e-10])
def test_a_near_miss_is_not_a_branch_point(gap):
    """Grashof four-bar with s + l = p + q − gap: it passes close to the toggle and keeps its mode."""
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0 - gap, ground=100.0, theta0=30.0)
    plan = compile_plan(lk)
    sol = plan.sweep(3600, order=0)
    branches = plan.branch_points()["RRR(coupler,rocker)"]
    L = _z(sol.position("C")) - _z(sol.position("B"))
    M = _z(sol.position("D")) - _z(sol.position("B"))
    mode = np.sign((np.conj(M) * L).imag)
    assert branches.size == 0
    assert np.all(mode[sol.valid] == mode[0])


def test_kite_outer_joints_pass_through_each_other_without_a_jump():
    """Rhombus four-bar: B passes through D; the coupler keeps its direction (no 2·length jump)."""
    lk = LB.fourbar(crank=60.0, coupler=60.0, rocker=60.0, ground=60.0, theta0=36.67)
    x = compile_plan(lk).theta0 + np.linspace(0.0, 2 * math.pi, 7200, endpoint=False) + 1e-7
    sol = compile_plan(lk).evaluate(x, order=0)
    C = _z(sol.position("C"))
    assert np.max(np.abs(np.diff(C[sol.valid]))) < 2 * 60.0 * (2 * math.pi / 7200) * 1.5


def test_a_margin_constant_to_rounding_is_not_a_thousand_minima(monkeypatch):
    """A dyad A–D–B on a ground pivot and a crank pin is a rigid triangle turning with the crank: its
    assembly margin is the same at every sample up to rounding (0.7349857336991 ± 7e-15 mm here),
    and that noise made ~1,000 sampled 'local minima', each refined by a golden-section search
    (6.6 s CPU to place one dyad; the GUI monkey's one hang). A margin constant over the turn and
    away from zero has no branch point: no search, the same (empty) answer, the same poses."""
    from mechsketch.core.model.linkage import Joint, JointKind, Link
    from mechsketch.core.solver import branches

    import dataclasses

    from mechsketch.core import load_scene
    from mechsketch.resources import example_path
    (base,) = load_scene(example_path("fourbar_crank_rocker")).elements
    a, b = base.joint("A").at, base.joint("B").at
    d = (a[0] + 10.0, a[1] + 10.0)
    lk = dataclasses.replace(base, joints=base.joints + (Joint("X", JointKind.R, d),),
                             links=base.links + (Link("l1", ("A", "X")), Link("l2", ("B", "X"))))
    calls = []
    real = branches.golden_min
    monkeypatch.setattr(branches, "golden_min", lambda *x, **k: calls.append(1) or real(*x, **k))
    sol = compile_plan(lk).sweep(360, 2)
    assert len(calls) < 40
    assert sol.valid.all()
    A, B, D = (sol.position(j) for j in ("A", "B", "X"))
    for p, q, want in ((A, D, math.dist(a, d)), (B, D, math.dist(b, d))):
        assert np.max(np.abs(np.hypot(*(p - q).T) - want)) < 1e-11
    side = np.cross(B - A, D - A)
    assert np.all(np.sign(side) == np.sign(side[0]))   # the triangle never flips
