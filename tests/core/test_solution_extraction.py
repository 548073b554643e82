"""Solution's joint extraction (core/solver/plan.py, link_state.py): each joint's arrays are
fresh, equal to the per-point path bit for bit, and the rates' arithmetic stays silent where the
rates are not finite (it runs under np.errstate unless every sample assembles and every group is
conditioned: Solution._is_quiet)."""
from __future__ import annotations

import warnings

import numpy as np

import linkage_builders as LB
from mechsketch.core.solver.plan import compile_plan


def test_joint_arrays_equal_the_point_path_and_are_fresh():
    lk = LB.fourbar()
    plan = compile_plan(lk)
    sol = plan.sweep(36, order=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for j in lk.joint_ids:
            link = plan.reporter[j]
            at = lk.joint(j).at
            assert np.array_equal(sol.position(j), sol.point(link, at))
            assert np.array_equal(sol.velocity(j), sol.point_velocity(link, at))
            assert np.array_equal(sol.acceleration(j), sol.point_acceleration(link, at))
    p = sol.position("C")
    p[:] = 0.0                                   # the caller owns what it gets
    assert np.array_equal(sol.position("C"), sol.point(plan.reporter["C"], lk.joint("C").at))
    assert not np.array_equal(sol.position("C"), p)


def test_non_finite_rates_are_extracted_silently():
    """A group conditioned below 1e-8 at one sample, with infinite rates there (as at an exact
    toggle): the extraction must neither warn nor change the other samples."""
    lk = LB.fourbar()
    plan = compile_plan(lk)
    sol = plan.sweep(36, order=2)
    ref_v, ref_a = sol.velocity("C"), sol.acceleration("C")
    k = 5
    g = sol.groups[0].name
    sol.group_output(g).cond[k] = 0.0
    sol.group_output(g).cond_floor = 0.0    # the margins' bound: ~0 at a real toggle
    st = sol.link_state("coupler")
    arm = sol.position("C")[k] - sol.position("B")[k]
    st.omega = np.array(st.omega, dtype=float)
    st.alpha = np.array(st.alpha, dtype=float)
    st.omega[k] = np.inf
    # −ω²·arm_x and −α·arm_y infinite with opposite signs: inf − inf (invalid) unless silenced
    st.alpha[k] = -np.sign(arm[0] * arm[1]) * np.inf
    sol._quiet = None
    assert not sol._is_quiet()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v, a = sol.velocity("C"), sol.acceleration("C")
    assert not np.isfinite(a[k]).all()
    keep = np.arange(len(sol)) != k
    assert np.array_equal(v[keep], ref_v[keep]) and np.array_equal(a[keep], ref_a[keep])


def test_a_conditioned_sweep_is_quiet_and_a_toggle_is_not():
    sol = compile_plan(LB.fourbar()).sweep(36, order=2)
    assert sol._is_quiet()
    # parallelogram: the sweep passes its crossings (conditioning 0 up to rounding)
    par = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0, mode=1)
    sol = compile_plan(par).sweep(360, order=2)
    assert min(float(np.min(sol.conditioning(g.name))) for g in sol.groups) < 1e-8
    assert not sol._is_quiet()


def test_extreme_input_speed_is_not_quiet():
    """ω = 1e160 rpm: every sample assembles and is conditioned, but ω² overflows."""
    sol = compile_plan(LB.fourbar(samples=36, rpm=1e160)).sweep(order=2)
    assert sol.valid.all() and not sol._is_quiet()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = sol.acceleration("C")
    assert not np.isfinite(a).all()
