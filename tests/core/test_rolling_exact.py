"""The exact rolling-lever synthesis (ODE dα/dθ = 1 − g/ℓ): known numbers of the notes, equal arc
lengths, tangency, independent integrations, k53 = dS5/dθ, the working range and its hard cases,
hypothesis-generated geometries."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import test_rolling_reference as ref
from mechsketch.core.analyses.rolling_exact import exact_path, working_range
from mechsketch.core.analyses.rolling_geometry import LeverGeometry, pose_state
from mechsketch.core.analyses.rolling_slip import continuous_measures
from mechsketch.core.analyses.rolling_synthesis import synthesize
from mechsketch.core.errors import GeometryError


@pytest.fixture(scope="module")
def press():
    return synthesize(ref.element(), measures=True)


def test_default_scene_numbers_of_the_notes(press):
    r = press
    assert r.S5[-1] == pytest.approx(50.4371, abs=1e-4)  # notes: S5 = 50.43 mm
    assert math.degrees(r.u1[0]) == pytest.approx(-143.76, abs=0.01)  # π1
    assert math.degrees(r.u1[-1]) == pytest.approx(-93.85, abs=0.01)  # π6
    rate = pose_state(r.geom, r.alpha, r.theta).rate
    assert rate.max() == pytest.approx(0.4778, abs=1e-4) and rate.min() == pytest.approx(0.3321, abs=1e-4)
    assert r.k53.max() == pytest.approx(-82.004, abs=1e-3) and r.k53.min() == pytest.approx(-92.897, abs=1e-3)
    c = r.slip.continuous
    assert c.length_fixed == pytest.approx(43.5558, abs=1e-4)  # notes: 43.55 mm


def test_against_mpmath_taylor_integration(press):
    mpsol = ref.mp_reference("press")
    for th in (-0.2, -0.5926):
        a_mp, s_mp = mpsol(th)
        a, s = press.path.at(np.array([th]))
        assert abs(a[0] - float(a_mp)) < 1e-12
        assert abs(s[0] - float(s_mp)) < 5e-10  # mm; the stated tolerance is 1e-10 mm per P and Q


def test_against_an_independent_scipy_integration(press):
    th = press.theta
    a, s5 = ref.scipy_reference(ref.PRESS, th)
    geo = ref.Geo(ref.PRESS)
    _, P, _, _, P0, _ = geo.contact(a, th)
    assert np.abs(press.P - P).max() < 1e-9
    assert np.abs(press.Q - (P0 - s5[:, None] * geo.ds)).max() < 1e-9
    assert press.error_mm < 1e-10  # the integrator's own estimate is below the tolerance


def test_error_estimate_tracks_the_true_error():
    geom = LeverGeometry.from_element(ref.element())
    th = np.linspace(0.0, -0.5926, 101)
    a_ref, s_ref = ref.scipy_reference(ref.PRESS, th)
    for tol in (1e-5, 1e-7, 1e-9):
        path = exact_path(geom, 0.0, -0.5926, tol)
        a, s = path.at(th)
        st_ = pose_state(geom, a, th)
        P_ref = ref.Geo(ref.PRESS).contact(a_ref, th)[1]
        err = max(np.abs(st_.P - P_ref).max(), np.abs(s - s_ref).max())
        assert err <= tol  # the tolerance is met
        assert err <= 10 * path.error_mm + 1e-12  # and the estimate is not wildly optimistic


def test_equal_arc_lengths_and_no_slip_of_the_computed_motion(press):
    c = press.slip.continuous
    assert abs(c.mismatch_d) <= 1e-9 * c.length_fixed
    assert abs(c.mismatch_e) <= 1e-9 * c.length_slider
    assert c.slip_d <= 1e-9 and c.slip_e <= 1e-9
    # a wrong rate law shows up: integrate dα/dθ = 1 − g/ℓ with ℓ off by 0.1 %
    from mechsketch.core.analyses import rolling_exact as rx
    geom = LeverGeometry.from_element(ref.element())
    bad = rx.ExactPath(geom, *_bad_path(geom), 0.0, 0)
    cb = continuous_measures(bad, 0.0, -0.5926)
    assert cb.slip_d > 1e-3 and abs(cb.mismatch_d) > 1e-4


def _bad_path(geom):
    """A motion integrated with a slightly wrong rocker length (the slip measures must see it)."""
    th = np.linspace(0.0, -0.5926, 2001)
    a = np.empty_like(th)
    a[0] = geom.alpha0
    s = np.zeros_like(th)
    for i in range(len(th) - 1):
        st_ = pose_state(geom, a[i:i + 1], th[i:i + 1])
        a[i + 1] = a[i] + (th[i + 1] - th[i]) * (1.0 - st_.g[0] / (geom.ell * 1.001))
        s[i + 1] = s[i] + (th[i + 1] - th[i]) * st_.k53[0]
    return th, a, s


def _fd(f, t, h=1e-4):
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h)


def test_centrodes_touch_tangentially_at_the_contact(press):
    t = np.linspace(-0.01, -0.58, 40)
    geom = press.geom

    def P(tt):
        return pose_state(geom, press.path.at(tt)[0], tt).P

    def Q(tt):
        a, s5 = press.path.at(tt)
        return pose_state(geom, a, tt).P0 - s5[:, None] * np.asarray(geom.ds)

    st_ = pose_state(geom, press.path.at(t)[0], t)
    for d, radius in ((_fd(P, t), st_.P - st_.C1), (_fd(Q, t), st_.P0 - st_.C2)):
        cos = np.einsum("ij,ij->i", d, radius) / np.linalg.norm(d, axis=1) / np.linalg.norm(radius, axis=1)
        assert np.abs(cos).max() < 1e-9  # the profile's tangent is perpendicular to the circle's radius


def test_k53_is_the_derivative_of_s5(press):
    t = press.theta[2:-2]
    dS5 = _fd(lambda tt: press.path.at(tt)[1], t)
    assert np.abs(dS5 - press.k53[2:-2]).max() < 1e-8


def test_working_range_of_the_default_scene():
    wr = working_range(LeverGeometry.from_element(ref.element()))
    assert wr.lower == pytest.approx(-0.799587, abs=2e-6)
    assert wr.upper == pytest.approx(2.527904, abs=2e-6)
    assert "tangent" in wr.lower_reason
    # at the end the rocker line is tangent: the discriminant vanishes
    geom = LeverGeometry.from_element(ref.element())
    path = exact_path(geom, 0.0, wr.lower + 1e-9, 1e-10)
    d1 = pose_state(geom, path.alpha[-1:], path.theta[-1:]).D1[0]
    assert 0.0 < d1 < 1e-3 * geom.R1 ** 2


def test_stroke_beyond_the_working_range_is_refused_with_the_reachable_range():
    el = ref.element(stroke={"from": 0.0, "to": -0.9})
    with pytest.raises(GeometryError) as exc:
        synthesize(el)
    msg = str(exc.value)
    assert "beyond the working range" in msg and "tangent to the moved lever circle" in msg
    assert "-0.7995" in msg and "2.5279" in msg  # the reachable range


@pytest.mark.parametrize("gap", [1e-2, 1e-4, 1e-7])
def test_stroke_ending_close_to_the_rocker_tangency(gap):
    """The square-root singularity at the working-range end: the adaptive steps still keep the
    stated tolerance (checked against DOP853) and the slip measures stay at round-off."""
    lim = working_range(LeverGeometry.from_element(ref.element())).lower
    end = lim + gap
    el = ref.element(stroke={"from": 0.0, "to": end}, points=50)
    res = synthesize(el, measures=False)
    a_ref, s_ref = ref.scipy_reference(ref.PRESS | {"stroke": {"from": 0.0, "to": end}}, res.theta)
    assert np.abs(res.alpha - a_ref).max() < 1e-9
    assert np.abs(res.S5 - s_ref).max() < 1e-8
    c = continuous_measures(res.path, 0.0, end)
    assert abs(c.mismatch_d) < 1e-8 and abs(c.mismatch_e) < 1e-8
    assert res.error_mm < 1e-9


def test_stroke_not_starting_at_the_drawn_pose():
    el = ref.element(stroke={"from": -0.2, "to": -0.5})
    res = synthesize(el, points=30, measures=False)
    a_ref, s_ref = ref.scipy_reference(ref.PRESS, np.array([0.0, -0.2, -0.35, -0.5]))
    assert res.alpha[0] == pytest.approx(a_ref[1], abs=1e-12)
    assert res.S5[0] == pytest.approx(s_ref[1], abs=1e-9)  # S5 is counted from the drawn pose
    assert res.S5[-1] == pytest.approx(s_ref[3], abs=1e-9)


def test_positive_stroke_and_far_branch():
    el = ref.element(stroke={"from": 0.0, "to": 0.8})
    res = synthesize(el, points=40)
    assert res.slip.continuous.worst < 1e-9
    assert np.all(np.diff(res.theta) > 0)


def test_slider_normal_leaving_the_slider_circle_is_refused():
    # a small slider circle: reachable in the drawn pose, left behind during the stroke
    el = ref.element(slider_circle={"center": [-50, -10], "radius": 14})
    with pytest.raises(GeometryError, match="normal to the slider axis through the contact leaves the slider circle") as exc:
        synthesize(el)
    assert "after θ ≈ -0.372026 rad" in str(exc.value) and "Reachable range" in str(exc.value)
    # the end is where the normal becomes tangent to the moved slider circle
    geom = LeverGeometry.from_element(el)
    path = exact_path(geom, 0.0, -0.372025, 1e-10)
    d2 = pose_state(geom, path.alpha[-1:], path.theta[-1:]).D2[0]
    assert 0.0 <= d2 < 1e-3 * geom.R2 ** 2


# -- hypothesis: valid random geometries -------------------------------------------------------
@st.composite
def geometries(draw):
    r1 = draw(st.floats(20.0, 80.0))
    dist = draw(st.floats(1.5, 5.0)) * r1
    phi = draw(st.floats(-math.pi, math.pi))
    G = (dist * math.cos(phi), dist * math.sin(phi))
    half = math.asin(r1 / dist)
    alpha0 = phi + math.pi + draw(st.floats(-0.8, 0.8)) * half  # the rocker line cuts the circle
    ell = draw(st.floats(0.8, 2.0)) * dist
    pin = (G[0] + ell * math.cos(alpha0), G[1] + ell * math.sin(alpha0))
    off = draw(st.floats(0.0, 0.5)) * r1
    c2 = (off * math.cos(phi), off * math.sin(phi))
    r2 = r1 + off + draw(st.floats(0.1, 1.0)) * r1  # contact always inside: the normal always meets it
    d = dict(ref.PRESS, lever_circle={"center": [0.0, 0.0], "radius": r1}, rocker_pivot=list(G), pin=list(pin),
             slider_circle={"center": list(c2), "radius": r2},
             slider_axis_deg=draw(st.floats(-90.0, 90.0)), slider_side=draw(st.sampled_from([1, -1])),
             contact_branch=draw(st.sampled_from(["near", "far"])), drive=None, points=60)
    frac = draw(st.floats(0.2, 0.95))
    up = draw(st.booleans())
    return d, frac, up


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(geometries())
def test_random_geometries_roll_without_slip(case):
    d, frac, up = case
    base = ref.element(**{k: v for k, v in d.items() if k != "type"})
    wr = working_range(LeverGeometry.from_element(base))
    end = frac * (wr.upper if up else wr.lower)
    if abs(end) < 1e-3:
        return
    el = ref.element(**{k: v for k, v in d.items() if k not in ("type", "stroke")}, stroke={"from": 0.0, "to": end})
    res = synthesize(el, measures=False)
    c = continuous_measures(res.path, 0.0, end)
    assert abs(c.mismatch_d) <= 1e-9 * max(c.length_fixed, 1.0)
    assert abs(c.mismatch_e) <= 1e-9 * max(c.length_slider, 1.0)
    assert c.slip_d < 1e-8 and c.slip_e < 1e-8
    a_ref, s_ref = ref.scipy_reference(d | {"stroke": {"from": 0.0, "to": end}}, res.theta)
    assert np.abs(res.alpha - a_ref).max() < 1e-9
    assert np.abs(res.S5 - s_ref).max() < 1e-7 * max(1.0, np.abs(s_ref).max())
