"""Branch decisions (issue 13, item 8): whether a group passes *through* a toggle (a change point,
where the motion continues in the other assembly mode) or only *near* it (the mode is kept) must
not depend on where the linkage sits in the plane; a rhombus and a kite must not jump where B
meets D (that one sample is reported singular); a parallelogram drawn exactly at its crossing
runs as a parallelogram. References: closed forms of the parallelogram, rhombus and kite, and a
30-digit circle intersection (mpmath) for the near misses. Every linkage here has coordinates on
a dyadic grid, so that its translations by 1e3, 1e6 (and 1e9) mm are exact: the *same* linkage.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan

GROUP = "RRR(coupler,rocker)"


def _z(a):
    return a[:, 0] + 1j * a[:, 1]


def fourbar_at(A, B, C, D, offset=0.0, rpm=60.0, samples=3600, eid="fb"):
    """Four-bar A–B (crank), B–C (coupler), D–C (rocker) from drawn points, all moved by
    (offset, −offset) mm (exactly, for the dyadic coordinates used here)."""
    o = complex(offset, -offset)
    pts = {k: complex(*v) + o for k, v in zip("ABCD", (A, B, C, D))}
    for k, v in zip("ABCD", (A, B, C, D)):
        assert pts[k] - o == complex(*v), "the translation must be exact"
    return LB.build(eid, [(k, "R", LB.xy(pts[k])) for k in "ABCD"],
                    {"ground": ["A", "D"], "crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
                    "ground", "crank", "A", rpm, samples)


def kept_mode_reference(lk, sol, offset):
    """C for the drawn assembly mode kept at every sample (30-digit circle intersection), minus
    the offset; the crank angle of each sample is the solver's input."""
    o = complex(offset, -offset)
    at = {j.id: complex(*j.at) - o for j in lk.joints}
    A, B0, C0, D = (at[k] for k in "ABCD")
    with mpmath.workdps(30):
        a = mpmath.sqrt(mpmath.mpf(B0.real - A.real) ** 2 + mpmath.mpf(B0.imag - A.imag) ** 2)
        li = mpmath.sqrt(mpmath.mpf(C0.real - B0.real) ** 2 + mpmath.mpf(C0.imag - B0.imag) ** 2)
        lj = mpmath.sqrt(mpmath.mpf(C0.real - D.real) ** 2 + mpmath.mpf(C0.imag - D.imag) ** 2)
        mode = 1 if LB.cross2(D - B0, C0 - B0) > 0 else -1
        out = []
        for th in sol.input:
            th = mpmath.mpf(float(th))
            b = mpmath.mpc(A.real, A.imag) + a * mpmath.expj(th)
            dvec = mpmath.mpc(D.real, D.imag) - b
            dd = abs(dvec)
            x = (li * li - lj * lj + dd * dd) / (2 * dd)
            h2 = li * li - x * x
            if h2 < 0:
                out.append(complex("nan"))
                continue
            c = b + dvec / dd * (x + 1j * mode * mpmath.sqrt(h2))
            out.append(complex(c))
    return np.array(out)


# -------------------------------------------------------------------------------------------
# near misses: gap > 0, the mode is kept wherever the linkage sits
# -------------------------------------------------------------------------------------------
def near_parallelogram(delta, offset, rpm=60.0):
    """A parallelogram (crank 40, coupler 100) with C raised by ``delta``: both crossings become
    near misses with gap 0.8·delta mm (coupler + rocker = 140 + 0.8·delta)."""
    return fourbar_at((0.0, 0.0), (24.0, 32.0), (124.0, 32.0 + delta), (100.0, 0.0), offset, rpm)


@pytest.mark.parametrize("delta,offsets,tol", [
    (2.0 ** -27, (0.0, 1e3, 1e6), 1e-6),      # gap 6.0e-9 mm
    (2.0 ** -20, (0.0, 1e3, 1e6, 1e9), 1e-2),   # gap 7.6e-7 mm (coordinates at 1e9 carry 1.2e-7)
])
@pytest.mark.parametrize("rpm", [60.0, -60.0])
def test_a_near_miss_keeps_its_mode_at_any_offset(delta, offsets, tol, rpm):
    ref = None
    for off in offsets:
        lk = near_parallelogram(delta, off, rpm)
        plan = compile_plan(lk)
        assert plan.branch_points()[GROUP].size == 0, off
        sol = plan.sweep(order=0)
        assert sol.valid.all(), off
        o = complex(off, -off)
        C = _z(sol.position("C")) - o
        if ref is None:
            ref = kept_mode_reference(lk, sol, off)
        err = np.max(np.abs(C - ref))
        assert err < tol, (off, err)     # a flip would put C 20–100 mm away


def test_a_tiny_gap_at_the_origin_is_not_a_change_point():
    """gap 1e-12 mm at a size of 280 mm (coupler + rocker = crank + frame + 1e-12 at one crossing,
    |coupler − rocker| = frame − crank − 1e-12 at the other): resolvable (rounding ~1e-13 mm), so
    not a touch; and an overlap of 1e-12 mm (within the kernels' rounding tolerance, so assembled)
    is not one either."""
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0 + 1e-12, ground=100.0, theta0=30.0, samples=3600)
    plan = compile_plan(lk)
    assert plan.branch_points()[GROUP].size == 0
    sol = plan.sweep(order=0)
    B, C, D = (_z(sol.position(j)) for j in "BCD")
    mode = np.sign(((D - B).conjugate() * (C - B)).imag)
    assert np.all(mode[sol.valid] == mode[0])
    over = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0 - 1e-12, ground=100.0, theta0=30.0, samples=3600)
    assert compile_plan(over).branch_points()[GROUP].size == 0


# -------------------------------------------------------------------------------------------
# change points: found at the same inputs wherever the linkage sits
# -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rpm", [60.0, -60.0])
def test_a_parallelogram_has_the_same_change_points_and_motion_at_any_offset(rpm):
    base = None
    for off in (0.0, 1e3, 1e6):
        lk = fourbar_at((0.0, 0.0), (24.0, 32.0), (124.0, 32.0), (100.0, 0.0), off, rpm)
        plan = compile_plan(lk)
        br = plan.branch_points()[GROUP]
        if base is None:
            base = br
        assert br.size == 2 and np.allclose(br, base, atol=1e-7, rtol=0.0), off
        sol = plan.sweep(order=0)
        A, B, C, D = (_z(sol.position(j)) for j in "ABCD")
        assert np.max(np.abs(C - (B + (D - A)))) < 1e-5 * (1 + off * 1e-6), off


# -------------------------------------------------------------------------------------------
# a parallelogram drawn exactly at one of its crossings
# -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("crossing", ["extended", "folded"])
@pytest.mark.parametrize("rpm", [60.0, -60.0])
@pytest.mark.parametrize("offset", [0.0, 1e6])
def test_a_parallelogram_drawn_at_its_crossing_runs_as_a_parallelogram(crossing, rpm, offset):
    """All four joints on one line: the drawn pose is itself a change point and does not say
    which branch; the one on which the coupler follows the crank (the parallelogram) is taken."""
    B, C = ((40.0, 0.0), (140.0, 0.0)) if crossing == "folded" else ((-40.0, 0.0), (60.0, 0.0))
    lk = fourbar_at((0.0, 0.0), B, C, (100.0, 0.0), offset, rpm)
    sol = compile_plan(lk).sweep(order=2)
    assert sol.valid.all()
    A, Bz, Cz, D = (_z(sol.position(j)) for j in "ABCD")
    err = np.abs(Cz - (Bz + (D - A)))
    assert np.max(err) < 1e-5 * (1 + offset * 1e-6)
    assert np.ptp(sol.angle("coupler")) < 1e-6
    d = diagnose(sol)
    assert sorted(round(math.degrees(p.input - sol.input[0])) % 360 for p in d.dead_points) == [0, 180]
    # and over a second turn it is still the parallelogram (the drawn crossing counts once per turn)
    plan = sol.plan
    x = plan.theta0 + plan.direction * (2 * math.pi + np.linspace(0.1, 6.2, 50))
    s2 = plan.evaluate(x, order=0)
    A, Bz, Cz, D = (_z(s2.position(j)) for j in "ABCD")
    assert np.max(np.abs(Cz - (Bz + (D - A)))) < 1e-5 * (1 + offset * 1e-6)


# -------------------------------------------------------------------------------------------
# rhombus and kite: B passes through D
# -------------------------------------------------------------------------------------------
def _rhombus(offset=0.0):
    return fourbar_at((0.0, 0.0), (0.0, 60.0), (60.0, 60.0), (60.0, 0.0), offset)   # a square


def _kite(offset=0.0):
    return fourbar_at((0.0, 0.0), (0.0, 20.0), (80.0, 80.0), (20.0, 0.0), offset)   # 20, 100, 100, 20


def kite_reference(theta, a, c, sigma):
    """Deltoid with crank = frame = a, coupler = rocker = c, on its smooth branch: C on the
    perpendicular bisector of BD, on the side σ·exp(iθ/2) (continuous through B = D)."""
    B = a * np.exp(1j * theta)
    D = a + 0j
    h = np.sqrt(c * c - np.abs(D - B) ** 2 / 4)
    return (B + D) / 2 + sigma * np.exp(1j * theta / 2) * h


@pytest.mark.parametrize("offset", [0.0, 1e6])
def test_a_rhombus_does_not_jump_where_b_meets_d(offset):
    lk = _rhombus(offset)
    sol = compile_plan(lk).sweep(order=1)
    meet = np.abs(np.remainder(sol.input + math.pi, 2 * math.pi) - math.pi) < 1e-9   # B = D
    assert meet.sum() == 1
    assert not sol.valid[meet].any() and sol.singular[meet].all()   # reported, not jumped over
    assert sol.valid[~meet].all()
    A, B, C, D = (_z(sol.position(j)) for j in "ABCD")
    assert np.all(np.isnan(C[meet]))
    err = np.abs(C - (B + (D - A)))[~meet]
    assert np.max(err) < 1e-6 * (1 + offset * 1e-6)
    d = diagnose(sol)
    assert d.full_turn
    assert any(p.kind == "singular" and abs(math.remainder(p.input, 2 * math.pi)) < 1e-6 for p in d.dead_points)
    assert "singular" in str(d)


@pytest.mark.parametrize("offset", [0.0, 1e6])
def test_a_kite_does_not_jump_where_b_meets_d(offset):
    lk = _kite(offset)
    sol = compile_plan(lk).sweep(order=0)
    meet = np.abs(np.remainder(sol.input + math.pi, 2 * math.pi) - math.pi) < 1e-9
    assert meet.sum() == 1 and sol.singular[meet].all() and sol.valid[~meet].all()
    o = complex(offset, -offset)
    C = _z(sol.position("C")) - o
    sigma = 1.0 if abs(kite_reference(np.array([sol.input[0]]), 20.0, 100.0, 1.0)[0] - (80 + 80j)) < 1e-9 else -1.0
    ref = kite_reference(sol.input, 20.0, 100.0, sigma)
    assert abs(ref[0] - (80 + 80j)) < 1e-9
    err = np.abs(C - ref)[~meet]
    assert np.max(err) < 1e-6 * (1 + offset * 1e-6)
