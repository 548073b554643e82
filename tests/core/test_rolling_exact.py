"""The exact rolling-lever synthesis (ODE dα/dθ = 1 − g/ℓ): known numbers of the notes, equal arc
lengths, tangency, independent integrations, k53 = dS5/dθ, the working range and its hard cases,
hypothesis-generated geometries."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import test_rolling_reference as ref
from mechsketch.core.analyses.rolling.exact import exact_path, working_range
from mechsketch.core.model.rolling_lever import parse
from mechsketch.core.analyses.rolling.geometry import LeverGeometry, pose_state
from mechsketch.core.analyses.rolling.slip import continuous_measures
from mechsketch.core.analyses.rolling.synthesis import synthesize
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
    from mechsketch.core.analyses.rolling import exact as rx
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


# -- degenerate and near-degenerate drawings ------------------------------------------------------
def _on_circle(**changes):
    """Lever circle R1 = 20 at the origin, rocker pivot (100, 0), pin (20, ~0): the rocker line passes
    through the centre and the pin lies on the circle (the drawing hypothesis found)."""
    d = dict(ref.PRESS, lever_circle={"center": [0.0, 0.0], "radius": 20.0}, pin=[20.0, 9.797174393178826e-15],
             rocker_pivot=[100.0, 0.0], slider_circle={"center": [0.0, 0.0], "radius": 40.0}, slider_axis_deg=0.0,
             slider_side=1, contact_branch="near", drive=None, points=60)
    d.update(changes)
    return {k: v for k, v in d.items() if v is not None}


@pytest.mark.parametrize("r2,to", [(30.0, -0.5926), (30.0, -2.356194490192345), (40.0, -3.141592653589793)])
def test_pin_on_the_lever_circle_as_the_contact_is_refused(r2, to):
    """Was: NaN slip measures (R2 30) or a refusal whose reachable range contradicted its own limit
    (R2 40). The pin is a lever point: on the circle it stays on the moved circle and on the rocker
    line in every pose, so as the contact g = ℓ and dα/dθ = 1 − g/ℓ = 0 for ever; the lever only
    turns about the pin and pair D has no profile. The drawing is refused, saying why."""
    d = _on_circle(slider_circle={"center": [0.0, 0.0], "radius": r2}, stroke={"from": 0.0, "to": to})
    el, problems = parse(d, "$")
    assert el is None and [p.path for p in problems] == ["$.pin"]
    msg = problems[0].message
    for part in ("lies on the lever circle", "the contact itself: g = ℓ", "dα/dθ = 1 − g/ℓ = 0",
                 "the lever only turns about the pin", "use the 'far' branch"):
        assert part in msg, msg
    # the reason, with the reference geometry: with the rocker standing still (α = α0) the near
    # contact is the pin for every θ until the rocker line touches the circle at θ = ±π/2, so
    # α ≡ α0 solves the ODE: no rolling
    geo = ref.Geo(d)
    th = np.linspace(-1.5, 1.5, 31)
    g, P, _, _, _, _ = geo.contact(np.full_like(th, geo.a0), th)
    assert np.abs(g - geo.ell).max() < 1e-12 * geo.ell
    assert np.abs(P - np.asarray(d["pin"])).max() < 1e-12


def test_rocker_pivot_on_the_lever_circle_as_the_contact_is_refused():
    """The mirror case: the pivot on the circle as the (near) contact gives g = 0 and dα/dθ = 1 for
    ever, lever and rocker turning about the pivot as one body."""
    G = [50.0 * math.cos(2.5), 50.0 * math.sin(2.5)]
    pin = [G[0] + 120.0 * math.cos(-0.4), G[1] + 120.0 * math.sin(-0.4)]  # the line enters the circle at G
    d = dict(ref.PRESS, rocker_pivot=G, pin=pin)
    el, problems = parse(d, "$")
    assert el is None and [p.path for p in problems] == ["$.rocker_pivot"]
    assert "lies on the lever circle" in problems[0].message and "dα/dθ = 1 − g/ℓ = 1" in problems[0].message
    geo = ref.Geo(d)
    th = np.linspace(-0.3, 0.3, 13)
    g = geo.contact(geo.a0 + th, th)[0]  # rocker and lever turned together about G: the contact stays at G
    assert np.abs(g).max() < 1e-12 * geo.ell
    assert parse(dict(d, contact_branch="far"), "$")[0] is not None  # the far intersection is fine


def test_pin_on_the_lever_circle_with_the_other_intersection_as_the_contact():
    """Legitimate: the contact rolls from the antipode towards the pin; the range ends where it
    reaches the pin, the rocker line then touching the moved circle at the pin (a double root the
    discriminant touches without changing sign: before the fix the march stepped over it and
    reported ±2π, and slip measures near it were NaN). Ends against the separable quadrature."""
    d = _on_circle(pin=[20.0, 0.0], contact_branch="far")
    el = ref.element(**{k: v for k, v in d.items() if k != "type"})
    wr = working_range(LeverGeometry.from_element(el))
    assert "contact reaches the pin" in wr.lower_reason and "contact reaches the pin" in wr.upper_reason
    # the tangent at the pin is perpendicular to the rocker line (which passes through the centre)
    a0 = math.pi
    assert wr.lower == pytest.approx(float(ref.mp_theta_of_psi(d, a0 + math.pi / 2)), abs=1e-8)
    assert wr.upper == pytest.approx(float(ref.mp_theta_of_psi(d, a0 - math.pi / 2)), abs=1e-8)
    assert wr.upper == pytest.approx(-wr.lower, abs=1e-9)  # the drawing is symmetric
    for gap in (1e-2, 1e-5, 1e-9):  # up to the end: finite, no slip (was NaN within 2e-4 of it)
        end = wr.lower + gap
        res = synthesize(ref.element(**{k: v for k, v in d.items() if k not in ("type", "stroke")},
                                     stroke={"from": 0.0, "to": end}), measures=True)
        c = res.slip.continuous
        assert c.worst < 1e-9
        a_ref, s_ref = ref.scipy_reference(d | {"stroke": {"from": 0.0, "to": end}}, res.theta[:-1])
        assert np.abs(res.alpha[:-1] - a_ref).max() < 1e-9
    # at the end the contact has run over half the lever circle, from the antipode to the pin
    assert c.length_moving == pytest.approx(math.pi * 20.0, abs=1e-6)
    assert c.length_fixed == pytest.approx(c.length_moving, rel=1e-9)
    # beyond the end: refused, the limit and the reachable range agree
    el_far = ref.element(**{k: v for k, v in d.items() if k not in ("type", "stroke")},
                         stroke={"from": 0.0, "to": -1.5})
    with pytest.raises(GeometryError) as exc:
        synthesize(el_far)
    msg = str(exc.value)
    assert f"after θ ≈ {wr.lower:.6f} rad the contact reaches the pin" in msg
    assert f"θ ∈ [{wr.lower:.6f} rad (the contact reaches the pin" in msg


def test_pin_just_outside_the_lever_circle():
    """The rocker line misses the circle only over a sliver of directions (~2√(2δ/R1) for a gap δ):
    the fixed-step march used to jump over it and report ±2π 'searched no further' while the
    stroke's integration stopped there. The ends are the tangents from the pin, at ±asin(R1/d) from
    the direction to the centre (modulo π; the nearest on either side of the drawn direction, where
    the discriminant vanishes), reached at the θ of the separable quadrature."""
    G = (100.0, 7.0)
    e = np.array([20 * math.cos(0.1), 20 * math.sin(0.1)]) - G
    e /= np.linalg.norm(e)
    b = -np.dot(G, e)
    for delta in (1e-6, 1e-3):
        t = b - math.sqrt(b * b - (np.dot(G, G) - (20.0 + delta) ** 2))
        d = _on_circle(pin=[float(x) for x in np.array(G) + t * e], rocker_pivot=list(G))
        el = ref.element(**{k: v for k, v in d.items() if k != "type"})
        wr = working_range(LeverGeometry.from_element(el))
        mp = ref.mp
        psi0, _, D, _ = ref.mp_lever_frame(d)
        u = [mp.mpf(0) - mp.mpf(x) for x in d["pin"]]  # pin → centre
        beta = mp.asin(20 / mp.sqrt(u[0] ** 2 + u[1] ** 2))
        tangents = [mp.atan2(u[1], u[0]) + s * beta + k * mp.pi for s in (1, -1) for k in range(-3, 4)]
        ends = (min(t for t in tangents if t > psi0), max(t for t in tangents if t < psi0))
        for end, psi_end in zip((wr.lower, wr.upper), ends):  # ψ = α − θ falls as θ grows
            assert abs(D(psi_end)) < 1e-20
            assert end == pytest.approx(float(ref.mp_theta_of_psi(d, psi_end)), abs=1e-8)
        assert "tangent" in wr.lower_reason and "tangent" in wr.upper_reason
        res = synthesize(ref.element(**{k: v for k, v in d.items() if k not in ("type", "stroke")},
                                     stroke={"from": 0.0, "to": 0.9 * wr.lower}), measures=True)
        assert res.slip.continuous.worst < 1e-9


def test_working_range_ends_against_the_separable_quadrature():
    """Pair-D ends are placed to 1e-9 rad (they were 1.5e-7 and 7e-7 rad early: fixed RK4 steps
    lose accuracy in the square-root singularity at the tangency)."""
    wr = working_range(LeverGeometry.from_element(ref.element()))
    psi0, _, D, _ = ref.mp_lever_frame(ref.PRESS)
    for end, sgn in ((wr.lower, 1), (wr.upper, -1)):
        p, step = psi0, sgn * ref.mp.mpf("0.01")
        while D(p + step) > 0:
            p += step
        psi_end = ref.mp.findroot(D, (p, p + step), solver="anderson")
        assert end == pytest.approx(float(ref.mp_theta_of_psi(ref.PRESS, psi_end)), abs=1e-9)


def test_contact_creeping_towards_the_rocker_pivot():
    """The pivot 6.6e-7 mm outside the circle and the near contact next to it (found by a sweep of
    near-degenerate drawings): g → 0 makes dψ/dθ = −g/ℓ → 0, so the contact approaches the pivot
    only asymptotically and α − θ soon changes by less than its last bit. The march used to loop
    for ever there; now it ends where the contact comes within κ of the pivot, and the stroke's
    refusal agrees with it."""
    d = {"type": "rolling_lever", "id": "press", "lever_circle": {"center": [0.0, 0.0], "radius": 34.48599426072094},
         "contact_branch": "near", "pin": [32.493985605690305, -12.34110823461407],
         "rocker_pivot": [21.020420428692077, -27.339088699937186],
         "slider_circle": {"center": [4.662077394800403, -6.063482310203766], "radius": 50.812081133480746},
         "slider_axis_deg": 55.47671629894913, "slider_side": -1, "stroke": {"from": 0.0, "to": 0.5}, "points": 60}
    el = ref.element(**{k: v for k, v in d.items() if k != "type"})
    geom = LeverGeometry.from_element(el)
    wr = working_range(geom)
    assert "reaches the rocker pivot" in wr.upper_reason and 1.0 < wr.upper < 1.3
    path = exact_path(geom, 0.0, wr.upper - 1e-3, 1e-10)
    g = pose_state(geom, path.alpha[-1:], path.theta[-1:]).g[0]
    assert geom.kappa < g < 1.2 * geom.kappa  # κ = 1e-9 × the drawing's size
    res = synthesize(el, measures=True)
    assert res.slip.continuous.worst < 1e-9
    with pytest.raises(GeometryError) as exc:
        synthesize(ref.element(**{k: v for k, v in d.items() if k not in ("type", "stroke")},
                               stroke={"from": 0.0, "to": 2.0}))
    limit = str(exc.value).split("after θ ≈ ")[1].split(" rad")[0]
    assert f"{limit} rad (the contact point reaches the rocker pivot" in str(exc.value)


def test_refusal_reports_the_nearer_end():
    """The stroke's integration and the working-range march may find an end at slightly different
    θ (or, before the fixes, at very different θ); the refusal names one end and a range that
    agrees with it."""
    from mechsketch.core.analyses.rolling.exact import _beyond_message, _OutOfRange

    geom = LeverGeometry.from_element(ref.element())
    wr = working_range(geom)
    early = _beyond_message(geom, 0.0, -0.9, _OutOfRange(-0.7, geom.alpha0, 0.0, 3), -1.0)
    assert "after θ ≈ -0.700000 rad the normal to the slider axis" in early
    assert "θ ∈ [-0.700000 rad (the normal to the slider axis" in early
    late = _beyond_message(geom, 0.0, -0.9, _OutOfRange(-0.85, geom.alpha0, 0.0, 1), -1.0)
    assert f"after θ ≈ {wr.lower:.6f} rad the rocker line" in late and f"θ ∈ [{wr.lower:.6f} rad" in late
    up = _beyond_message(geom, 0.0, 3.0, _OutOfRange(2.0, geom.alpha0, 0.0, 3), 1.0)
    assert "after θ ≈ 2.000000 rad" in up and "2.000000 rad (the normal to the slider axis" in up


def test_no_nan_comes_back_silently(monkeypatch):
    """Measures over a span the motion cannot reach, and samples that are not finite, are refused."""
    from mechsketch.core.analyses.rolling import exact as rolling_exact

    geom = LeverGeometry.from_element(ref.element())
    path = exact_path(geom, 0.0, -0.79, 1e-10)
    with pytest.raises(GeometryError, match="continuous slip measures .* cannot be evaluated near θ ≈"):
        continuous_measures(path, 0.0, -0.85)  # beyond the working range (it ends at −0.7996)
    real = rolling_exact.ExactPath.at

    def broken(self, theta_q, base=None):
        a, s = real(self, theta_q, base)
        if len(a) > 5:
            a = a.copy()
            a[5] = np.nan
        return a, s

    monkeypatch.setattr(rolling_exact.ExactPath, "at", broken)
    with pytest.raises(GeometryError, match=r"cannot evaluate the motion at point 5 of 60"):
        synthesize(ref.element(points=60), measures=False)


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
    # the pin drawn on the lever circle as the contact itself is refused (see
    # test_pin_on_the_lever_circle_as_the_contact_is_refused); checked here with the reference geometry
    geo = ref.Geo(d)
    g0 = geo.contact(np.array([geo.a0]), np.array([0.0]))[0][0]
    assume(abs(g0 - geo.ell) > 1e-8 * max(geo.ell, r1, dist))
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
