"""Burmester theory (core/design/burmester.py) against independent constructions.

- 3 poses: the centre of a circle point by the complex circumcentre formula vs the perpendicular
  bisectors solved as a real 2 × 2 linear system.
- 4 poses: every dyad of the compatibility-linkage sweep is concyclic in all four poses; and,
  independently, the circle-point curve is the cubic det[|z_j|², x_j, y_j, 1] = 0: its real
  roots along a line are found with numpy's polynomial roots, and each must be produced by the
  compatibility sweep at the crank turn β₂ that root's dyad makes (so the sweep misses none).
- The closed-form topologies (families) against the product's solver and their derivatives
  against central differences.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mechsketch.core.design import burmester as BM
from mechsketch.core.design import families as F
from mechsketch.core.design.candidates import build_linkage
from mechsketch.core.design.targets import DesignError, pose_target
from mechsketch.core.solver.plan import compile_plan

POSES4 = [[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80]]


def _bisectors(z: np.ndarray) -> complex:
    """Centre of the circle through z[0..2] from the perpendicular bisectors (real linear solve)."""
    p = np.stack([z.real, z.imag], axis=1)
    A = 2.0 * (p[1:] - p[0])
    b = (p[1:] ** 2).sum(axis=1) - (p[0] ** 2).sum()
    c = np.linalg.solve(A, b)
    return complex(c[0], c[1])


@given(st.lists(st.floats(-200, 200), min_size=9, max_size=9), st.floats(-100, 100), st.floats(-100, 100))
@settings(max_examples=60, deadline=None)
def test_three_pose_centres_match_bisectors(v, mx, my):
    poses = np.array(v).reshape(3, 3)
    poses[:, 2] = np.remainder(poses[:, 2], 360.0)
    try:
        t = pose_target(poses)
    except DesignError:
        return
    m = np.array([complex(mx, my)])
    z = BM.positions(t, m)[0]
    A = 2.0 * np.array([[z[1].real - z[0].real, z[1].imag - z[0].imag], [z[2].real - z[0].real, z[2].imag - z[0].imag]])
    if abs(np.linalg.det(A)) < 1e-6 * max(1.0, np.abs(z).max()) ** 2:
        return   # (nearly) collinear positions: no finite centre
    ref = _bisectors(z)
    got = BM.circle_centres(t, m)[0]
    assert abs(got - ref) <= 1e-9 * max(1.0, abs(ref), np.abs(z).max()) * (1 + abs(ref) / max(1.0, np.abs(z).max()))


def test_four_pose_dyads_are_concyclic():
    t = pose_target(POSES4)
    m, g, beta = BM.four_pose_dyads(t, 720)
    assert len(m) > 500
    res = BM.concyclic_residual(t, m, g) / np.maximum(np.abs(m - g), 1.0)
    assert res.max() < 1e-11
    # the crank's turns are those of the dyad: m_j − G = e^{iβ_j}(m_1 − G)
    z = BM.positions(t, m)
    for k in range(3):
        turn = np.angle((z[:, k + 1] - g) / (z[:, 0] - g))
        assert np.max(np.abs(np.remainder(turn - beta[:, k] + math.pi, 2 * math.pi) - math.pi)) < 1e-9


def _det4(t, m: np.ndarray) -> np.ndarray:
    z = BM.positions(t, m)
    rows = np.stack([np.abs(z) ** 2, z.real, z.imag, np.ones_like(z.real)], axis=-1)
    return np.linalg.det(rows)


@pytest.mark.parametrize("poses", [POSES4, [[10, 5, 10], [40, 0, -15], [60, 30, -40], [35, 60, -70]],
                                   [[0, 0, 0], [100, 0, 90], [100, 100, 170], [0, 110, 270]]])
def test_circle_point_cubic_roots_come_from_the_sweep(poses):
    t = pose_target(poses)
    rng = np.random.default_rng(3)
    found = 0
    for _ in range(6):
        m0 = complex(*(t.points.mean(axis=0) + rng.normal(scale=40, size=2)))
        v = np.exp(1j * rng.uniform(0, math.pi))
        ts = np.linspace(-300, 300, 9)
        coef = np.polyfit(ts, _det4(t, m0 + ts * v), 4)   # degree 3 in exact arithmetic
        coef = coef[1:] if abs(coef[0]) < 1e-6 * np.abs(coef).max() else coef
        for r in np.roots(coef):
            if abs(r.imag) > 1e-9 * max(1.0, abs(r)) or abs(r.real) > 1e4:
                continue
            m = m0 + r.real * v
            z = BM.positions(t, np.array([m]))[0]
            g = BM.circumcentre(z[:1], z[1:2], z[2:3])[0]
            assert abs(abs(z[3] - g) - abs(z[0] - g)) < 1e-7 * max(abs(z[0] - g), 1.0)   # a circle point
            beta2 = np.angle((z[1] - g) / (z[0] - g))
            ms, gs, _ = BM.four_pose_dyads(t, beta2=np.array([beta2]))
            assert len(ms) and np.min(np.abs(ms - m)) < 1e-7 * max(1.0, abs(m))
            assert np.min(np.abs(gs - g)) < 1e-7 * max(1.0, abs(g))
            found += 1
    assert found >= 6


def test_pose_target_refusals():
    with pytest.raises(DesignError, match="at least 3 poses"):
        pose_target([[0, 0, 0], [1, 1, 10]])
    with pytest.raises(DesignError, match="poses 1 and 3 are the same pose"):
        pose_target([[0, 0, 0], [1, 1, 10], [0, 0, 0]])
    with pytest.raises(DesignError, match="pure translation along a line"):
        pose_target([[0, 0, 5], [10, 10, 5], [25, 25, 5], [30, 30, 5]])
    with pytest.raises(DesignError, match="same place"):
        pose_target([[3, 4, 0], [3, 4, 10], [3, 4, 30]])
    with pytest.raises(DesignError, match="not numbers"):
        pose_target([[0, 0, 0], [1, float("nan"), 10], [3, 4, 30]])
    with pytest.raises(DesignError, match=r"turned about one point \(50, 50\)"):
        pose_target([[0, 0, 0], [100, 0, 90], [100, 100, 180], [0, 100, 270]])
    # collinear points that turn are a proper problem
    assert len(pose_target([[0, 0, 0], [10, 0, 20], [20, 0, 50]]).points) == 3


@pytest.mark.parametrize("topology,x", [
    ("fourbar", [3, 4, 160, 10, 40, 140, 120, 30, 20.0]),
    ("slider_crank", [1, 2, 0.3, 20, 40, 150, 30, -10.0]),
    ("inverted_slider_crank", [0, 0, 100, 0, 35, 10, 20, 15.0]),
    ("sixbar", [0, 0, 100, 0, 13.35, 49.61, 84.37, 65.82, 35.68, 150.03, -51.48, 241.37, 129.35, -34.70, -210.73]),
    ("watt_sixbar", [0, 0, 100, 0, 35, 110, 90, 40, 30, 130, 120, 80, 70, 30, -20.0]),
])
@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_families_agree_with_the_solver(topology, x, sigma):
    x = np.array(x)
    if topology in ("sixbar", "watt_sixbar"):
        sigma = 1.0 if sigma > 0 else 2.0    # the six-bars' code: both groups in one mode, or opposite
    th0 = 0.7
    lk = build_linkage(topology, x, sigma, th0, "c")
    sol = compile_plan(lk).sweep(360, order=1)
    assert sol.valid.all()
    ev = F.evaluate(topology, x[None], sol.input[None], sigma, grad=True)
    p = sol.position("P")
    assert np.max(np.abs(p[:, 0] + 1j * p[:, 1] - ev.P[0])) < 1e-12 * 400
    v = sol.velocity("P") / lk.driver.omega          # dP/dθ from the kernels
    assert np.max(np.abs(v[:, 0] + 1j * v[:, 1] - ev.dP[0, :, -1])) < 1e-10 * 400
    rot = sol.angle("coupler")
    turn = np.remainder((ev.cpl[0] - ev.cpl[0, 0]) - (rot - rot[0]) + math.pi, 2 * math.pi) - math.pi
    assert np.max(np.abs(turn)) < 1e-12
    xm, sm = F.mirror(topology, x[None], np.array([sigma]))      # the mirror image at −θ
    assert np.max(np.abs(F.evaluate(topology, xm, -sol.input[None], sm).P[0] - np.conj(ev.P[0]))) < 1e-12 * 400
    s, t = 1.3 * np.exp(0.4j), 2 + 1j                             # a similarity at θ + arg s
    moved = F.evaluate(topology, F.transform(topology, x[None], s, t), sol.input[None] + 0.4, sigma).P[0]
    assert np.max(np.abs(moved - (s * ev.P[0] + t))) < 1e-12 * 600


@pytest.mark.parametrize("topology,x", [
    ("fourbar", [3, 4, 160, 10, 40, 140, 120, 30, 20.0]),
    ("slider_crank", [1, 2, 0.3, 20, 40, 150, 30, -10.0]),
    ("inverted_slider_crank", [0, 0, 100, 0, 35, 10, 20, 15.0]),
    ("sixbar", [0, 0, 100, 0, 13.35, 49.61, 84.37, 65.82, 35.68, 150.03, -51.48, 241.37, 129.35, -34.70, -210.73]),
    ("watt_sixbar", [0, 0, 100, 0, 35, 110, 90, 40, 30, 130, 120, 80, 70, 30, -20.0]),
])
def test_family_derivatives_match_central_differences(topology, x):
    x = np.array([x])
    th = np.linspace(0.1, 6.0, 11)[None]
    ev = F.evaluate(topology, x, th, 1.0, grad=True)
    h = 1e-6
    for j in range(x.shape[1] + 1):
        xp, xm, tp, tm = x.copy(), x.copy(), th, th
        if j < x.shape[1]:
            xp[0, j] += h
            xm[0, j] -= h
        else:
            tp, tm = th + h, th - h
        a, b = F.evaluate(topology, xp, tp, 1.0), F.evaluate(topology, xm, tm, 1.0)
        for name, d in (("P", ev.dP), ("out", ev.dout), ("cpl", ev.dcpl), ("sin_mu", ev.dsin_mu)):
            fd = (getattr(a, name) - getattr(b, name)) / (2 * h)
            assert np.max(np.abs(fd - d[..., j])) < 1e-6 * max(1.0, np.max(np.abs(d[..., j]))), (name, j)
