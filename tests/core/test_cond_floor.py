"""The kernels' lower bound of a group's conditioning from its assembly margins
(``DyadOut.cond_floor``, core/solver/kernels.py), which lets ``Solution._is_quiet`` skip a
reduction over the samples: it must never exceed the conditioning the kernel computes (checked
over random RRR and RRP dyads, near their toggles too), must be 0 where some sample does not
assemble, and must not hide a real toggle from ``_is_quiet``."""
from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import linkage_builders as LB
from mechsketch.core.solver import kernels as K
from mechsketch.core.solver.plan import compile_plan

TH = np.linspace(0.0, 2.0 * np.pi, 721)


def _rrr(r: float, a: float, b: float, d: float, th: np.ndarray = TH, mode: int = 1) -> K.DyadOut:
    """Crank of radius r about 0, coupler a from the crank pin M to L, rocker b from H = (d, 0)."""
    m0, h0 = complex(r, 0.0), complex(d, 0.0)
    dist = abs(h0 - m0)
    x = (a * a - b * b + dist * dist) / (2.0 * dist)
    y = mode * math.sqrt(max(a * a - x * x, 0.0))
    l0 = m0 + complex(x, y) * (h0 - m0) / dist
    with np.errstate(invalid="ignore", divide="ignore"):
        crank = K.crank(0j, 0.0, th, 2.0, 0.0, 2)
        return K.rrr(crank, m0, K.ground_state(), h0, l0, 2, None, 1e-9, 1e-9)


def _rrp(r: float, a: float, e: float, th: np.ndarray = TH) -> K.DyadOut:
    """Crank r, rod a from the crank pin to a slider on the horizontal guide at height e."""
    m0 = complex(r, 0.0)
    dx = math.sqrt(a * a - (e - 0.0) ** 2)
    l0 = complex(r + dx, e)
    with np.errstate(invalid="ignore", divide="ignore"):
        crank = K.crank(0j, 0.0, th, 2.0, 0.0, 2)
        return K.rrp(crank, m0, K.ground_state(), complex(0.0, e), 1 + 0j, l0, 2, None, 1e-9)


def _check(out: K.DyadOut) -> None:
    if out.ok.all():
        assert out.cond_floor <= float(out.cond.min()) * (1.0 + 1e-9) + 1e-13
    else:
        assert out.cond_floor == 0.0


@settings(max_examples=300, deadline=None)
@given(r=st.floats(1.0, 100.0), a=st.floats(1.0, 400.0), b=st.floats(1.0, 400.0),
       d=st.floats(1.0, 400.0), mode=st.sampled_from([1, -1]))
def test_rrr_floor_is_below_the_computed_conditioning(r, a, b, d, mode):
    if abs(d - r) < 1e-3:
        return
    dist = abs(d - r)
    if not (abs(a - b) < dist < a + b):          # the drawn pose must assemble
        return
    _check(_rrr(r, a, b, d, mode=mode))


@settings(max_examples=300, deadline=None)
@given(r=st.floats(1.0, 100.0), a=st.floats(1.0, 400.0), e=st.floats(-200.0, 200.0))
def test_rrp_floor_is_below_the_computed_conditioning(r, a, e):
    if abs(e) >= a * (1.0 - 1e-9):
        return
    _check(_rrp(r, a, e))


def test_floor_near_a_toggle_is_tiny_and_at_a_crank_rocker_is_close():
    # Grashof crank-rocker (40 + 110 < 100 + 70) far from toggles: min sin μ 0.70, bound 0.167
    far = _rrr(40.0, 100.0, 70.0, 110.0)
    assert far.ok.all() and 0.2 * far.cond.min() < far.cond_floor <= far.cond.min()
    # change-point linkage 40 + 120 = 100 + 60 exactly: coupler and rocker fold flat at θ = π
    flat = _rrr(40.0, 100.0, 60.0, 120.0, th=np.linspace(0.0, 2.0 * np.pi, 720, endpoint=False))
    assert flat.cond.min() < 1e-6 and flat.cond_floor < 1e-6
    # the offset slider-crank's rod at its steepest (|e| + r close to the rod's length)
    steep = _rrp(40.0, 50.0, 9.0)
    assert steep.ok.all() and steep.cond_floor <= steep.cond.min()
    assert steep.cond_floor > 0.5 * steep.cond.min()


def test_a_toggle_still_makes_the_extraction_guarded():
    # a parallelogram passes its crossings: conditioning 0 to rounding, margins 0 to rounding
    par = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0, mode=1)
    sol = compile_plan(par).sweep(360, order=2)
    assert all(sol.group_output(g.name).cond_floor < 1e-6 for g in sol.groups)
    assert not sol._is_quiet()


def test_floor_unknown_where_a_sample_does_not_assemble():
    out = _rrr(40.0, 100.0, 60.0, 120.0, th=np.concatenate([TH, [np.nan]]))
    assert not out.ok[-1] and out.cond_floor == 0.0
    # a double-rocker driven through its limits: some samples do not assemble
    out = _rrr(80.0, 60.0, 70.0, 120.0)
    assert not out.ok.all() and out.cond_floor == 0.0


def test_reading_rates_makes_no_conditioning_the_floor_bounds():
    """Issue 26 item 4 (fixed cost per sweep): deciding that the extraction is quiet reads a
    group's conditioning only where its floor does not already bound it (the conditioning is two
    passes over the samples, made on first read). The rates are the same either way, and the
    conditioning made later equals |det| / (li·lj) as before."""
    from mechsketch.resources import example_path
    from mechsketch.core import Workspace

    plan = Workspace.open(example_path("sixbar_moving_guide"))["sixbar"].compile()
    sol = plan.sweep(3600, order=2)
    bounded = [name for name, out in sol._outs.items() if out.cond_floor >= 1e-6]
    assert bounded, "the six-bar's groups keep away from their toggles: their floors bound them"
    vel = sol.velocity("E")
    assert all(callable(sol._outs[name]._cond) for name in bounded)     # not made
    fresh = plan.sweep(3600, order=2)
    for name in bounded:
        fresh.conditioning(name)                                         # made first this time
    np.testing.assert_array_equal(fresh.velocity("E"), vel)
    for name in bounded:
        np.testing.assert_array_equal(sol.conditioning(name), fresh.conditioning(name))
        assert sol.conditioning(name).min() >= sol._outs[name].cond_floor
