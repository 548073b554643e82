"""Motion laws (issue 10 item 4): the rise profiles against their 50-digit definitions (the
derivatives by mpmath's numerical differentiation, the modified trapezoid by integrating its
acceleration definition), the periodic spline against SciPy's and at its knots, and the laws in
time against finite differences of their own positions."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import CubicSpline

from mechsketch.core import Driver
from mechsketch.core.model.drivers import DriverKind, LawKind, MotionLaw
from mechsketch.core.solver.motion_law import MODTRAP_PEAK, PeriodicSpline, at_times, cycle, profile

mp = mpmath.mp
X = [0.0, 0.03, 0.1, 0.125, 0.2, 0.37, 0.375, 0.4, 0.5, 0.55, 0.625, 0.7, 0.875, 0.93, 1.0]


def mp_cycloidal(x):
    return x - mpmath.sin(2 * mpmath.pi * x) / (2 * mpmath.pi)


def mp_harmonic(x):
    return (1 - mpmath.cos(mpmath.pi * x)) / 2


def mp_modtrap_acc(s):
    """The modified trapezoid's acceleration per unit peak, by its definition on [0, 1]."""
    s = mpmath.mpf(s)
    if s <= mpmath.mpf(1) / 8:
        return mpmath.sin(4 * mpmath.pi * s)
    if s <= mpmath.mpf(3) / 8:
        return mpmath.mpf(1)
    if s <= mpmath.mpf(5) / 8:
        return mpmath.cos(4 * mpmath.pi * (s - mpmath.mpf(3) / 8))
    if s <= mpmath.mpf(7) / 8:
        return mpmath.mpf(-1)
    return -mpmath.sin(4 * mpmath.pi * (1 - s))


BREAKS = [mpmath.mpf(k) / 8 for k in (0, 1, 3, 5, 7, 8)]


def mp_modtrap(x):
    """(h, h', h'') by integrating the definition: h(x) = A∫0^x (x − s) a(s) ds, A from h(1) = 1."""
    def integral(f, x):
        pts = [b for b in BREAKS if b < x] + [x]
        return mpmath.quad(f, pts) if x > 0 else mpmath.mpf(0)
    one = mpmath.mpf(1)
    A = 1 / integral(lambda s: (one - s) * mp_modtrap_acc(s), one)
    x = mpmath.mpf(x)
    return (A * integral(lambda s: (x - s) * mp_modtrap_acc(s), x), A * integral(mp_modtrap_acc, x),
            A * mp_modtrap_acc(x), A)


@pytest.mark.parametrize("kind,f", [(LawKind.CYCLOIDAL, mp_cycloidal), (LawKind.HARMONIC, mp_harmonic)])
def test_rise_laws_and_their_derivatives_match_50_digits(kind, f):
    h, d1, d2 = profile(kind, np.array(X))
    with mpmath.workdps(50):
        for k, x in enumerate(X):
            x = mpmath.mpf(x)
            assert abs(h[k] - f(x)) <= 2e-16
            assert abs(d1[k] - mpmath.diff(f, x, 1)) <= 1e-14
            assert abs(d2[k] - mpmath.diff(f, x, 2)) <= 1e-13


def test_the_modified_trapezoid_is_its_acceleration_definition_integrated():
    h, d1, d2 = profile(LawKind.MODIFIED_TRAPEZOID, np.array(X))
    with mpmath.workdps(30):
        A = mp_modtrap(0.5)[3]
        assert MODTRAP_PEAK == pytest.approx(float(A), rel=1e-15)
        assert float(A) == pytest.approx(4.888, abs=5e-4)   # the textbook peak
        for k, x in enumerate(X):
            H, V, Acc, _ = mp_modtrap(x)
            assert abs(h[k] - H) <= 1e-15 and abs(d1[k] - V) <= 1e-14 and abs(d2[k] - Acc) <= 1e-13, x


@pytest.mark.parametrize("kind", [LawKind.CONSTANT, LawKind.CYCLOIDAL, LawKind.HARMONIC, LawKind.MODIFIED_TRAPEZOID])
def test_every_rise_goes_from_0_to_1(kind):
    h, d1, d2 = profile(kind, np.array([0.0, 1.0]))
    assert h[0] == 0.0 and h[1] == pytest.approx(1.0, abs=1e-15)
    if kind in (LawKind.CYCLOIDAL, LawKind.MODIFIED_TRAPEZOID):   # rest to rest, no jerk jump in a
        assert np.all(np.abs(d1) < 1e-15) and np.all(np.abs(d2) < 1e-14)


def test_the_periodic_spline_is_scipys_and_passes_through_the_points():
    tau = [0.0, 0.15, 0.4, 0.45, 0.8]
    y = [0.0, 30.0, 10.0, -5.0, 12.0]
    s = PeriodicSpline(tau, y)
    ref = CubicSpline(tau + [1.0], y + [0.0], bc_type="periodic")
    t = np.linspace(-1.3, 2.2, 2001)
    v, d1, d2 = s(t)
    f = np.mod(t, 1.0)
    assert np.max(np.abs(v - ref(f))) < 1e-12
    assert np.max(np.abs(d1 - ref(f, 1))) < 1e-10
    assert np.max(np.abs(d2 - ref(f, 2))) < 1e-8
    assert np.allclose(s(np.array(tau))[0], y, rtol=0, atol=1e-13)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-500, 500, allow_nan=False), min_size=3, max_size=9),
       st.lists(st.floats(0.02, 1.0), min_size=9, max_size=9), st.integers(-2, 2))
def test_a_table_spline_is_continuous_to_the_second_derivative_everywhere(values, gaps, turns):
    n = len(values)
    g = np.array(gaps[:n])
    tau = np.concatenate(([0.0], np.cumsum(g)[:-1])) / g.sum()
    s = PeriodicSpline(tau, values, 360.0 * turns)
    knots = np.append(tau, 1.0)
    eps = 1e-9
    lo, hi = s(knots - eps), s(knots + eps)
    scale = 1.0 + max(abs(v) for v in values) + 360.0 * abs(turns)
    curv = 1e-9 + float(np.max(np.abs(s.M)))   # |S''| <= max |M|, the third derivative <= 2 max |M| / gap
    for a, b, tol in zip(lo, hi, (1e-9 * scale + 1e-6 * curv, 1e-6 * curv, 1e-4 * curv)):
        assert np.max(np.abs(a - b)) <= tol   # a jump would be of the order of the values themselves
    assert np.allclose(s(tau)[0], values, rtol=0, atol=1e-9 * scale)
    assert s(np.array([1.0]))[0][0] == pytest.approx(values[0] + 360.0 * turns, abs=1e-9 * scale)


def _driver(kind, law, stroke=None, points=(), rpm=12.0):
    return Driver("d", "p", rpm, kind, stroke, MotionLaw(law, tuple(points)))


CASES = [
    ("crank cycloidal", _driver(DriverKind.CRANK, LawKind.CYCLOIDAL, rpm=-40.0)),
    ("crank modified trapezoid", _driver(DriverKind.CRANK, LawKind.MODIFIED_TRAPEZOID)),
    ("crank table, one turn", _driver(DriverKind.CRANK, LawKind.TABLE, points=[(0, 0), (0.3, 60), (0.6, 200), (1, 360)])),
    ("crank table, swinging", _driver(DriverKind.CRANK, LawKind.TABLE, points=[(0, 0), (0.25, 40), (0.5, 0), (0.75, -40)])),
    ("cylinder harmonic", _driver(DriverKind.CYLINDER, LawKind.HARMONIC, (300.0, 420.0))),
    ("cylinder constant", _driver(DriverKind.CYLINDER, LawKind.CONSTANT, (300.0, 420.0))),
    ("slider table", _driver(DriverKind.SLIDER, LawKind.TABLE, (-10.0, 30.0), [(0, 0), (0.4, 25), (0.7, -5)])),
]


@pytest.mark.parametrize("name,drv", CASES, ids=[c[0] for c in CASES])
def test_the_law_in_time_has_the_rates_of_its_positions(name, drv):
    """Central differences (5 points) of q(t) against the closed-form q'(t) and q''(t), away from
    the constant-speed actuator's reversals (where its velocity jumps)."""
    T = drv.period
    t = np.linspace(0.013, 0.987, 37) * T
    if drv.law.kind is LawKind.CONSTANT:
        t = t[np.abs(np.mod(t / T, 0.5)) > 0.02]
    h = 1e-4 * T
    q = {j: at_times(drv, 0.3, t + j * h).q for j in (-2, -1, 0, 1, 2)}
    m = at_times(drv, 0.3, t)
    d1 = (q[-2] - 8 * q[-1] + 8 * q[1] - q[2]) / (12 * h)
    d2 = (-q[-2] + 16 * q[-1] - 30 * q[0] + 16 * q[1] - q[2]) / (12 * h * h)
    s1 = np.max(np.abs(m.qd)) + 1e-300
    s2 = np.max(np.abs(m.qdd)) + np.max(np.abs(m.qd)) / T
    assert np.max(np.abs(d1 - m.qd)) <= 1e-7 * s1
    assert np.max(np.abs(d2 - m.qdd)) <= 1e-5 * s2


def test_the_cycle_samples_the_law_at_equal_times():
    drv = _driver(DriverKind.CYLINDER, LawKind.CYCLOIDAL, (300.0, 420.0), rpm=6.0)
    m = cycle(drv, 0.0, 8)
    assert np.allclose(m.t, np.arange(8) * 10.0 / 8, rtol=0, atol=1e-15)
    assert m.q[0] == 300.0 and m.q[4] == pytest.approx(420.0, abs=1e-12)
    assert m.qd[0] == 0.0 and m.qd[4] == pytest.approx(0.0, abs=1e-12)
    crank = _driver(DriverKind.CRANK, LawKind.CONSTANT, rpm=-30.0)
    c = cycle(crank, 1.0, 4)
    assert np.array_equal(c.q, 1.0 - (2.0 * math.pi / 4) * np.arange(4))
    assert c.qd == crank.omega and c.qdd == 0.0
