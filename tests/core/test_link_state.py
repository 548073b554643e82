"""LinkState (core/solver/link_state.py): the real (x, y) storage and the complex views agree,
a rotation made lazily from the link's current vector equals v / v0, the points a state keeps
follow a new anchor or rotation, and the rates are the rigid-body formulas in complex form."""
from __future__ import annotations

import numpy as np

from mechsketch.core.solver.link_state import LinkState, ground_state

RNG = np.random.default_rng(7)
N = 64


def _pair():
    return RNG.normal(size=N) * 50.0, RNG.normal(size=N) * 50.0


def _state() -> LinkState:
    ang = RNG.uniform(-np.pi, np.pi, N)
    st = LinkState.real(3.0 - 2.0j, _pair(), (np.cos(ang), np.sin(ang)), _pair(), RNG.normal(size=N),
                        _pair(), RNG.normal(size=N))
    return st


def test_complex_views_of_a_real_state_and_back():
    st = _state()
    for z, p in ((st.A, st.xy), (st.rot, st.cs), (st.vA, st.vxy), (st.aA, st.axy)):
        assert np.array_equal(z.real, p[0]) and np.array_equal(z.imag, p[1])
    back = LinkState(st.a0, st.A, st.rot, st.vA, st.omega, st.aA, st.alpha)
    for a, b in ((back.xy, st.xy), (back.cs, st.cs), (back.vxy, st.vxy), (back.axy, st.axy)):
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_points_and_rates_are_the_rigid_body_formulas():
    st = _state()
    p0 = 10.0 + 7.5j
    arm = st.rot * (p0 - st.a0)
    assert np.allclose(st.point(p0), st.A + arm, rtol=0, atol=1e-12)
    assert np.allclose(st.velocity(p0), st.vA + 1j * st.omega * arm, rtol=0, atol=1e-12)
    assert np.allclose(st.acceleration(p0), st.aA + (1j * st.alpha - st.omega ** 2) * arm, rtol=0, atol=1e-11)
    out = np.empty((N, 2))
    assert np.array_equal(st.write_velocity(p0, out), np.column_stack(st.vel_xy(st.arm_xy(p0))))
    assert np.array_equal(st.write_acceleration(p0, np.empty((N, 2))),
                          np.column_stack(st.acc_xy(st.arm_xy(p0))))
    assert np.array_equal(st.write_point(p0, np.empty((N, 2))), np.column_stack(st.point_xy(p0)))


def test_turned_rotation_is_v_over_v0_and_points_agree_before_and_after_it_is_made():
    v0 = 30.0 + 40.0j
    vx, vy = _pair()
    st = LinkState.turned(1.0 + 1.0j, _pair(), (vx, vy), v0)
    p0 = -4.0 + 9.0j
    before = st.point(p0)                       # turned straight from v, rot not made
    assert st._rot is None and st._rot_xy is None
    rot = st.rot
    assert np.allclose(rot, (vx + 1j * vy) / v0, rtol=1e-15, atol=0)
    fresh = LinkState.real(st.a0, st.xy, st.cs)
    assert np.allclose(fresh.point(p0), before, rtol=0, atol=1e-12)
    # a point first read after the rotation was made has the same bits as one read before
    # (issue 20 item 4: a cached solution whose rotations the forces made equals a fresh one)
    q0 = 7.0 - 2.0j
    other = LinkState.turned(1.0 + 1.0j, st.xy, (vx, vy), v0)
    want = other.point(q0)
    assert np.array_equal(st.point(q0), want)


def test_a_new_rotation_or_anchor_moves_the_kept_points():
    st = _state()
    p0 = 5.0 + 5.0j
    first = st.point(p0)
    st.rot = st.rot * 1j                        # a quarter turn more
    turned = st.point(p0)
    assert np.allclose(turned - st.A, (first - st.A) * 1j, rtol=0, atol=1e-12)
    st.xy = (st.xy[0] + 1.0, st.xy[1])
    assert np.allclose(st.point(p0), turned + 1.0, rtol=0, atol=1e-12)


def test_the_frame_is_still():
    g = ground_state()
    assert g.still() and g.A == 0j and g.rot == 1 + 0j
    assert g.point_xy(2.0 + 3.0j) == (2.0, 3.0)
    assert not _state().still()
