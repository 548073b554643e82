"""The kernels' fast path (every sample assembles strictly: no clamping pass, no masks, and for an
RRR with |li − lj| above the singular distance no meeting test) gives bit for bit what the general
path gives, and is not taken where it would be wrong."""
from __future__ import annotations

import numpy as np

from mechsketch.core.solver import kernels as K

M0, H0, L0 = complex(20.0, 0.0), complex(60.0, 0.0), complex(45.0, 38.0)


def _run(inputs: np.ndarray, l0: complex = L0, near: float = 1e-9) -> K.DyadOut:
    with np.errstate(invalid="ignore", divide="ignore"):
        crank = K.crank(0j, 0.0, inputs, 3.0, 0.5, 2)
        return K.rrr(crank, M0, K.ground_state(), H0, l0, 2, None, 1e-9, near)


def _arrays(out: K.DyadOut) -> list[np.ndarray]:
    si, sj = out.state_i, out.state_j
    return [*si.xy, *si.cs, *si.vxy, si.omega, *si.axy, si.alpha,
            *sj.xy, *sj.cs, sj.omega, sj.alpha, out.ok, out.cond, out.gap]


def test_rrr_fast_path_equals_general_path_bit_for_bit():
    th = np.linspace(0.0, 2.0 * np.pi, 97)
    fast = _run(th)                                   # crank-rocker: every sample assembles
    assert fast.ok.all() and fast.gap.min() > 0.0 and fast.singular is None
    general = _run(np.concatenate([th, [np.nan]]))    # a NaN margin forces the general path
    assert not general.ok[-1]
    assert fast.probe == 0.0                          # every pose proved finite: no probe pass
    assert isinstance(general.probe, np.ndarray) and np.isfinite(general.probe[:-1]).all()
    for a, b in zip(_arrays(fast), _arrays(general)):
        a, b = np.broadcast_to(a, th.shape), np.broadcast_to(b, (th.size + 1,))[:-1]
        assert np.array_equal(a, b)                   # the same bits (NaN nowhere here)


def test_rrr_meeting_test_kept_when_lengths_are_equal():
    # a kite: |L − M| = |L − H| (li = lj), H on the crank circle: the crank pin M passes
    # through H after a half turn
    h0 = complex(-20.0, 0.0)
    l0 = complex(0.0, 30.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        crank = K.crank(0j, 0.0, np.array([0.0, np.pi, 0.5 * np.pi]), 3.0, 0.0, 2)
        out = K.rrr(crank, M0, K.ground_state(), h0, l0, 2, None, 1e-9, 1e-7)
    # at θ = π the crank pin M sits on H: every margin ≥ 0 there, yet the pose is singular
    assert out.gap.min() >= 0.0
    assert out.singular is not None and out.singular.tolist() == [False, True, False]
    assert out.ok.tolist() == [True, False, True]


def test_rrp_pin_rates_recorded_on_the_rod_equal_the_rods_own_rates():
    # sixbar_moving_guide: the block's pin E sits on its guide point Q (moving guide), so the rod
    # records E's velocity and acceleration from the block's; they must be the rod's own, bit for bit
    from mechsketch.core import load_scene
    from mechsketch.core.solver.plan import compile_plan
    from mechsketch.resources import example_path

    lk = load_scene(example_path("sixbar_moving_guide")).elements[0]
    sol = compile_plan(lk).sweep(240, order=2)
    rod = sol.link_state("rod2")
    e0 = complex(*lk.joint("E").at)
    arm = rod.arm_xy(e0)
    assert len(rod._points[e0]) == 4             # the shortcut is taken here
    v, a = rod.vel_xy(arm), rod.acc_xy(arm)      # recomputed from the rod's motion
    assert sol.valid.all()
    assert np.array_equal(sol.velocity("E"), np.stack(v, axis=1))
    assert np.array_equal(sol.acceleration("E"), np.stack(a, axis=1))
    assert np.array_equal(sol.velocity("Q"), sol.velocity("E"))


def test_rrp_fixed_guide_pin_rates_are_the_sliders_and_agree_with_the_rods():
    # slider_crank_offset: a fixed guide, so the rod's pin C takes the slider's rates ṡ·u, s̈·u;
    # the rod's own expressions (v_B + ω·J·r, a_B + (αJ − ω²)·r) agree to rounding
    from mechsketch.core import load_scene
    from mechsketch.core.solver.plan import compile_plan
    from mechsketch.resources import example_path

    lk = load_scene(example_path("slider_crank_offset")).elements[0]
    sol = compile_plan(lk).sweep(360, order=2)
    assert sol.valid.all()
    rod = sol.link_state("rod")
    c0 = complex(*lk.joint("C").at)
    arm = rod.arm_xy(c0)
    assert len(rod._points[c0]) == 4             # the shortcut is taken here
    v, a = np.stack(rod.vel_xy(arm), axis=1), np.stack(rod.acc_xy(arm), axis=1)
    V, A = sol.velocity("C"), sol.acceleration("C")
    assert np.abs(V - v).max() <= 1e-13 * np.abs(v).max()
    assert np.abs(A - a).max() <= 1e-13 * np.abs(a).max()
    u = complex(*sol.velocity("S")[1]) / abs(complex(*sol.velocity("S")[1]))
    assert np.abs(V[:, 0] * u.imag - V[:, 1] * u.real).max() <= 1e-12 * np.abs(v).max()   # along the guide


def test_rrr_probe_kept_where_the_outer_joints_can_meet():
    # li = lj: the margin alone does not keep M and H apart, so the finiteness probe stays
    h0 = complex(-20.0, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        crank = K.crank(0j, 0.0, np.linspace(0.1, 1.0, 5), 3.0, 0.0, 2)
        out = K.rrr(crank, M0, K.ground_state(), h0, complex(0.0, 30.0), 2, None, 1e-9, 1e-7)
    assert out.gap.min() >= 0.0 and isinstance(out.probe, np.ndarray)


def _sixbar_rrp(th: np.ndarray) -> tuple[K.DyadOut, K.DyadOut, dict]:
    """The six-bar's groups by hand: RRR(coupler, rocker), then its rod and block on the rocker's
    guide (a turning guide), at crank offsets ``th``."""
    from mechsketch.core import load_scene
    from mechsketch.core.solver.plan import compile_plan
    from mechsketch.resources import example_path

    lk = load_scene(example_path("sixbar_moving_guide")).elements[0]
    plan = compile_plan(lk)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        outs = plan.run_steps(plan.theta0 + th, 2, range(len(plan.steps)), {}, plan.omega, 0.0)
    rrr, rrp = (outs[s.group.name] for s in plan.steps)
    return rrr, rrp, outs


def test_rrp_on_a_turning_guide_proves_its_poses_finite_and_equals_the_general_path():
    th = np.linspace(0.0, 2.0 * np.pi, 61)
    rrr, fast, _ = _sixbar_rrp(th)
    assert fast.every and fast.probe == 0.0 and fast.ok.all()      # no probe pass
    assert rrr.every and rrr.probe == 0.0
    _, general, _ = _sixbar_rrp(np.concatenate([th, [np.nan]]))     # a NaN sample: general path
    assert not general.every and isinstance(general.probe, np.ndarray)
    assert not general.ok[-1] and general.ok[:-1].all()
    for a, b in zip(_arrays(fast), _arrays(general)):
        a, b = np.broadcast_to(a, th.shape), np.broadcast_to(b, (th.size + 1,))[:-1]
        assert np.array_equal(a, b)


def test_rrp_on_a_fixed_axis_guide_keeps_its_probe():
    # u = (1, 0) scalars: the margin reads only one coordinate of M, so it proves nothing
    with np.errstate(invalid="ignore", divide="ignore"):
        crank = K.crank(0j, 0.0, np.array([0.1, 0.5, np.inf]), 3.0, 0.0, 2)
        out = K.rrp(crank, M0, K.ground_state(), complex(0.0, 5.0), 1 + 0j, complex(70.0, 5.0), 2,
                    None, 1e-9)
    assert isinstance(out.probe, np.ndarray) and not np.isfinite(out.probe[-1])


def test_an_outer_joints_rates_are_computed_once_and_shared_by_both_groups():
    # B, the crank pin, is the outer joint of both groups: the RRP reads the RRR's arrays
    rrr, rrp, _ = _sixbar_rrp(np.linspace(0.0, 2.0 * np.pi, 13))
    assert rrp.state_i.a0 == rrr.state_i.a0                    # rod and coupler anchored at B
    v_rrr, v_rod = rrr.state_i.vxy, rrp.state_i.vxy            # both anchors' velocity: v_B
    assert v_rrr[0] is v_rod[0] and v_rrr[1] is v_rod[1]
    a_rrr, a_rod = rrr.state_i.axy, rrp.state_i.axy
    assert a_rrr[0] is a_rod[0] and a_rrr[1] is a_rod[1]


def test_cached_rates_are_dropped_when_a_states_motion_is_replaced():
    st = K.crank(0j, 0.0, np.linspace(0.0, 1.0, 4), 3.0, 0.0, 2)
    p0 = M0
    arm = st.arm_xy(p0)
    v = st.vel_at(p0, arm)
    assert st.vel_at(p0, arm) is v                              # kept
    assert np.array_equal(v[0], st.vel_xy(arm)[0]) and np.array_equal(v[1], st.vel_xy(arm)[1])
    st.vxy = (np.ones(4), np.zeros(4))                          # a new anchor velocity
    v2 = st.vel_at(p0, arm)
    assert v2 is not v and np.array_equal(v2[0], 1.0 - 3.0 * np.asarray(arm[1]))


def test_lazy_conditioning_is_the_determinants():
    """cond is made on first read (most solves never read it) and equals |sin| of the angle
    between the velocity system's columns, computed here from the joint positions."""
    import math

    from mechsketch.core import load_scene
    from mechsketch.core.solver.plan import compile_plan
    from mechsketch.resources import example_path

    lk = load_scene(example_path("sixbar_moving_guide")).elements[0]
    sol = compile_plan(lk).sweep(37, order=2)
    rrr_name, rrp_name = (g.name for g in sol.groups)
    for name in (rrr_name, rrp_name):
        out = sol.group_output(name)
        assert callable(out._cond)                              # not made during the solve
        c = out.cond
        assert out.cond is c and c.shape == (37,)
    P = {j: sol.position(j) for j in "BCDEQ"}
    z = {j: P[j][:, 0] + 1j * P[j][:, 1] for j in P}
    at = {j: complex(*lk.joint(j).at) for j in "BCDEQ"}
    ri, rj = z["C"] - z["B"], z["C"] - z["D"]                   # RRR: coupler and rocker at C
    sin_mu = np.abs((ri.conjugate() * rj).imag) / (np.abs(ri) * np.abs(rj))
    assert np.abs(sol.conditioning(rrr_name) - sin_mu).max() <= 1e-14
    a = math.radians(lk.joint("Q").axis_deg or 0.0)
    u = (z["C"] - z["D"]) / (at["C"] - at["D"]) * complex(math.cos(a), math.sin(a))   # the guide
    rod = z["E"] - z["B"]
    cos_rod = np.abs((u.conjugate() * rod).real) / (np.abs(u) * np.abs(rod))
    assert np.abs(sol.conditioning(rrp_name) - cos_rod).max() <= 1e-14
