"""The hard cases, on purpose: sweeps passing 1e-6 and 1e-10 mm from a toggle (RRR, RRP, RPR, both
modes), length ratios of 1e-4 and 1e4, whole mechanisms translated to coordinates near 1e6 mm.

Tolerances near a toggle follow the notes (§A, conditioning): positions lose about
eps·sqrt(size/gap) (relative to the size) and rates about eps·size/gap, i.e. up to ~8e-4 for a
gap of 1e-10 mm in a 200 mm mechanism.
"""
from __future__ import annotations

import functools
import math

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
import reference as R
import solution_checks as CK
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan

EPS = 2.220446049250313e-16
GAPS = (1e-6, 1e-10)


def toggle_case(kind: str, gap: float, mode: int):
    """(linkage, driver angle of the near-toggle) for a sweep passing ``gap`` mm from a toggle."""
    if kind == "RRR":      # coupler + rocker = crank + ground + gap: nearly straight at θ = π
        return LB.fourbar(rocker=60.0 + gap, mode=mode), math.pi
    if kind == "RRP":      # rod = crank + offset + gap: rod ⟂ guide at θ = 270°
        return LB.slider_crank(crank=40.0, rod=60.0 + gap, offset=20.0, theta0=30.0, mode=mode), 1.5 * math.pi
    # RPR: |offset| = ground − crank − gap: the axis nearly tangent at θ = 0
    return LB.inverted_slider_crank(crank=40.0, ground=100.0, offset=60.0 - gap, theta0=60.0, mode=mode), 2 * math.pi


def actual_gap(kind: str, lk) -> mpmath.mpf:
    """The gap realised by the float drawn coordinates, in 50 digits."""
    with mpmath.workdps(50):
        at = {j.id: mpmath.mpc(*j.at) for j in lk.joints}
        r = abs(at["B"] - at["A"])
        if kind == "RRR":
            return abs(at["C"] - at["B"]) + abs(at["C"] - at["D"]) - r - abs(at["D"] - at["A"])
        if kind == "RRP":
            return abs(at["C"] - at["B"]) - r - at["S"].imag
        u = mpmath.expjpi(mpmath.mpf(lk.joint("Q").axis_deg) / 180)
        c = abs((mpmath.conj(u) * (at["B"] - at["C"])).imag)
        return abs(at["C"] - at["A"]) - r - c


TOGGLE_IDS = [(k, g, m) for k in ("RRR", "RRP", "RPR") for g in GAPS for m in (1, -1)]


@functools.lru_cache(maxsize=None)
def toggle_solved(kind, gap, mode):
    lk, t = toggle_case(kind, gap, mode)
    plan = compile_plan(lk)
    return lk, t, plan, plan.sweep(360, order=2)


@pytest.mark.parametrize("kind,gap,mode", TOGGLE_IDS)
def test_near_toggle_accuracy_against_mpmath(kind, gap, mode):
    lk, t, plan, sol = toggle_solved(kind, gap, mode)
    g = float(actual_gap(kind, lk))
    assert g == pytest.approx(gap, rel=1e-3)
    assert sol.valid.all()
    size = LB.size_of(lk)
    near = t + np.array([0.0, 1e-8, -1e-8, 1e-6, -1e-6, 1e-5, -1e-4, 1e-3, 2 * math.pi / 360])
    ev = plan.evaluate(near, order=2)
    k = int(np.argmin(np.abs(np.angle(np.exp(1j * (sol.input - t))))))
    err = R.relative(R.compare(lk, ev, range(len(near))))
    err_sweep = R.relative(R.compare(lk, sol, [k - 1, k, k + 1]))
    pos_tol = 4 * EPS * math.sqrt(size / gap)
    rate_tol = 4 * EPS * size / gap            # 8.8e-4 for 1e-10 mm at size 200 mm
    for e in (err, err_sweep):
        assert e["pos"] <= pos_tol, e
        assert e["ang"] <= pos_tol * size / 40.0, e
        for q in ("vel", "acc", "omega", "alpha"):
            assert e[q] <= rate_tol, (q, e)
    # the conditioning reported at the toggle is the true |sin| (relative accuracy ~ eps·size/gap)
    c = ev.conditioning(ev.groups[0].name)[0]
    assert 0 < c < 10 * math.sqrt(gap / 40.0)
    ref = R.MpReference(lk)
    st = ref.solve(float(near[0]), 1.0, ref.guess_from(ev, 0))
    grp = ev.groups[0]
    true = _true_conditioning(lk, grp, st)
    assert c == pytest.approx(float(true), rel=rate_tol)


def _true_conditioning(lk, grp, st):
    """|sin| of the angle between the velocity system's columns, from 50-digit positions."""
    def pt(link, j):
        P, _, _ = st.point(link, lk.joint(j).at)
        return mpmath.mpc(*P)
    with mpmath.workdps(50):
        if grp.kind == "RRR":
            L = pt(grp.link_i, grp.inner)
            a, b = pt(grp.link_i, grp.outer_i) - L, pt(grp.link_j, grp.outer_j) - L
        elif grp.kind == "RRP":   # columns u and J·(L − M)
            b = 1j * (pt(grp.link_i, grp.inner) - pt(grp.link_i, grp.outer_i))
            th = st.pose[grp.link_j][2]
            a = mpmath.expj(th) * mpmath.expjpi(mpmath.mpf(lk.joint(grp.outer_j).axis_deg) / 180)
        else:  # RPR: columns u and J(M − H)
            th = st.pose[grp.link_j][2]
            a = mpmath.expj(th) * mpmath.expjpi(mpmath.mpf(lk.joint(grp.inner).axis_deg) / 180)
            b = 1j * (pt(grp.link_i, grp.outer_i) - pt(grp.link_j, grp.outer_j))
            # |σ| scaled by the drawn size max(|M0 − H0|, |offset|): 0 also as the pin nears the pivot
            m0, h0 = (mpmath.mpc(*lk.joint(j).at) for j in (grp.outer_i, grp.outer_j))
            u0 = mpmath.expjpi(mpmath.mpf(lk.joint(grp.inner).axis_deg) / 180)
            c = (mpmath.conj(u0) * (m0 - h0)).imag
            return min(abs((mpmath.conj(a) * b).imag) / max(abs(m0 - h0), abs(c)), 1)
        return abs((mpmath.conj(a) * b).imag) / (abs(a) * abs(b))


@pytest.mark.parametrize("kind,gap,mode", TOGGLE_IDS)
def test_mode_kept_and_motion_continuous_through_near_toggle(kind, gap, mode):
    lk, t, plan, sol = toggle_solved(kind, gap, mode)
    g = sol.groups[0]
    assert np.all(CK.mode_signs(lk, sol, g) == mode)
    # densely around the toggle: same mode, no jump larger than the motion allows
    x = t + np.linspace(-2e-3, 2e-3, 4001)
    ev = plan.evaluate(x, order=2)
    assert ev.valid.all()
    assert np.all(CK.mode_signs(lk, ev, g) == mode)
    dt = (x[1] - x[0]) / abs(plan.omega)
    for j in lk.joint_ids:
        p, v, a = ev.position(j), ev.velocity(j), ev.acceleration(j)
        step = np.hypot(*np.diff(p, axis=0).T)
        vmax = np.maximum(np.hypot(*v[1:].T), np.hypot(*v[:-1].T))
        amax = np.maximum(np.hypot(*a[1:].T), np.hypot(*a[:-1].T))
        assert np.all(step <= 1.01 * vmax * dt + amax * dt * dt + 1e-12), j
    size = LB.size_of(lk)
    assert CK.closure_error(lk, ev) <= 1e-12 * size
    assert CK.closure_error(lk, sol) <= 1e-12 * size


@pytest.mark.parametrize("kind,gap,mode", [(k, g, 1) for k in ("RRR", "RRP", "RPR") for g in GAPS])
def test_near_toggle_found_as_dead_point(kind, gap, mode):
    lk, t, plan, sol = toggle_solved(kind, gap, mode)
    d = diagnose(sol)
    toggles = [p for p in d.dead_points if p.kind == "toggle"]
    assert len(toggles) == 1, d.dead_points
    assert abs(math.remainder(toggles[0].input - t, 2 * math.pi)) < 1e-6
    expect = math.sqrt(gap) * _cond_coeff(kind)
    if kind == "RPR":  # σ is scaled by the drawn size |M0 − H0| (not by |M − H| = 60 at the toggle)
        g = sol.groups[0]
        expect *= 60.0 / abs(complex(*lk.joint(g.outer_i).at) - complex(*lk.joint(g.outer_j).at))
    assert toggles[0].conditioning == pytest.approx(expect, rel=1e-3)
    assert d.full_turn


def _cond_coeff(kind):
    """conditioning ≈ coeff·sqrt(gap) at the closest approach (small-angle geometry)."""
    if kind == "RRR":   # sin μ ≈ sqrt(2 gap (li + lj) / (li lj)), li = 140, lj = 60
        return math.sqrt(2 * 200.0 / (140.0 * 60.0))
    # RRP: cos(φ_i − ξ) ≈ sqrt(2 gap / rod); RPR: σ/D ≈ sqrt(2 gap / D), rod = D = 60
    return math.sqrt(2.0 / 60.0)


# ---------------------------------------------------------------------------------------------
RATIO_CASES = {
    "four-bar crank 1e-4 of the rest": lambda: LB.fourbar(crank=0.01, coupler=100.0, rocker=100.0, ground=100.0),
    "four-bar ground 1e-4 of the crank (drag link)": lambda: LB.fourbar(crank=1000.0, coupler=1000.0, rocker=10.0,
                                                                        ground=0.1, theta0=135.0),
    "four-bar coupler 1e4 of the crank": lambda: LB.fourbar(crank=1.0, coupler=1e4, rocker=9999.5, ground=20.0,
                                                           theta0=225.0, mode=-1),
    "slider-crank rod 1e4 of the crank": lambda: LB.slider_crank(crank=0.01, rod=100.0, offset=0.0, theta0=225.0),
    "slider-crank rod 1e4 of the crank, 1e6 long": lambda: LB.slider_crank(crank=100.0, rod=1e6, offset=50.0,
                                                                          theta0=135.0),
    "inverted slider-crank crank 1e-4": lambda: LB.inverted_slider_crank(crank=0.01, ground=100.0, offset=3.0),
    "scotch yoke crank 1e-4 of the yoke": lambda: LB.scotch_yoke(crank=0.01, slot_along=100.0, guide_at=(100.0, -100.0)),
    "PRP guide 1e4 from the pivot": lambda: LB.prp_linkage(guide_offset=0.01, g=(100.0, 100.0), xi=95.0),
}


@pytest.mark.parametrize("name", list(RATIO_CASES))
def test_extreme_length_ratios(name):
    lk = RATIO_CASES[name]()
    sol = compile_plan(lk).sweep(samples=360)
    size = LB.size_of(lk)
    ok = np.flatnonzero(sol.valid & (np.nan_to_num(sol.conditioning(sol.groups[0].name)) > 1e-3))
    # a PRP whose guide turns with the crank reaches half a turn: the side of its drawn crossing
    assert len(ok) > (170 if name.startswith("PRP") else 300)
    err = R.relative(R.compare(lk, sol, ok[:: len(ok) // 10]))
    assert err["pos"] <= 1e-13, err
    assert err["ang"] <= 1e-13, err
    for q in ("vel", "acc", "omega", "alpha"):
        assert err[q] <= 1e-11, (q, err)
    assert CK.closure_error(lk, sol) <= 1e-12 * size
    assert sol.residual() <= 1e-12 * size


# ---------------------------------------------------------------------------------------------
FAR = (1e6, -1e6)
FAR_CASES = {
    "RRR": lambda: LB.fourbar(theta0=135.0),
    "RRR-": lambda: LB.fourbar(mode=-1, theta0=250.0),
    "RRP vertical, pin offset": lambda: LB.slider_crank(xi=90.0, pin=3 + 4j),
    "RRP moving guide": lambda: LB.sixbar_guide(-1),
    "RPR": lambda: LB.inverted_slider_crank(offset=5.0, q_along=10.0),
    "PRP": lambda: LB.prp_linkage(),
    "RPP": lambda: LB.scotch_yoke(slot=120.0, guide=200.0),
    "RRR+RRR": lambda: LB.sixbar_stephenson(on_rocker=True, f=(150.0, 60.0)),
}


@pytest.mark.parametrize("name", list(FAR_CASES))
def test_translated_by_1e6_equals_untranslated(name):
    near = FAR_CASES[name]()
    far = LB.translated(near, *FAR)
    s1, s2 = compile_plan(near).sweep(samples=360), compile_plan(far).sweep(samples=360)
    both = s1.valid & s2.valid
    for g in s1.groups:
        both &= np.nan_to_num(s1.conditioning(g.name)) > 1e-3
    assert both.sum() > (170 if name == "PRP" else 300)   # a PRP on the crank: half a turn
    size = LB.size_of(near)
    # the drawn crank angle itself carries the coordinates' rounding (eps·1e6 / crank)
    assert np.allclose(s1.input, s2.input, rtol=0, atol=1e-10)
    for link in near.links:
        for j in link.joints:
            p1, p2 = near.joint(j).at, far.joint(j).at
            a, b = s1.point(link.id, p1)[both], s2.point(link.id, p2)[both] - FAR
            assert np.max(np.abs(a - b)) <= 1e-9 * size, (link.id, j)
            for f in ("point_velocity", "point_acceleration"):
                a, b = getattr(s1, f)(link.id, p1)[both], getattr(s2, f)(link.id, p2)[both]
                assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a)), (f, link.id, j)
        if link.id != near.ground:
            for f in ("omega", "alpha"):
                a, b = getattr(s1, f)(link.id)[both], getattr(s2, f)(link.id)[both]
                assert np.max(np.abs(a - b)) <= 1e-9 * max(np.max(np.abs(a)), abs(near.driver.omega) ** (1 + (f == "alpha"))), (f, link.id)
            a = s1.angle(link.id)[both] - s2.angle(link.id)[both]
            assert np.max(np.abs(a)) <= 1e-9
    # and the far copy is itself accurate against 50 digits of its own exact coordinates
    ok = np.flatnonzero(both)
    err = R.relative(R.compare(far, s2, ok[:: len(ok) // 6]))
    scale = EPS * 1e6 / size       # coordinates carry ~eps·1e6 mm of absolute rounding
    assert err["pos"] <= 40 * scale, err
    for q in ("vel", "acc", "omega", "alpha"):
        assert err[q] <= 1e-10, (q, err)
    assert CK.closure_error(far, s2) <= 1e-9 * size


@pytest.mark.parametrize("shift", [(0.0, 0.0), FAR])
def test_prp_at_exactly_parallel_guides_is_not_assembled(shift):
    """Crank drawn at 40°, fixed guide at 100°: samples 60 and 240 put the guide on the crank
    exactly parallel to the fixed one. There the lines do not meet (in float the intersection is
    rounding noise ~1e16 mm away): NaN and valid False, never a 'valid' pose whose loop is open.
    Between them the lines cross the other way: the pin would have run off to infinity and back,
    which the mechanism cannot do (issue 20, item 1): not assembled either."""
    lk = LB.translated(LB.prp_linkage(), *shift)
    sol = compile_plan(lk).sweep(samples=360)
    assert not sol.valid[60] and not sol.valid[240]
    assert np.isnan(sol.position("L")[[60, 240]]).all()
    assert sol.valid[241:].all() and sol.valid[:60].all() and not sol.valid[60:241].any()
    assert CK.closure_error(lk, sol) <= 1e-9 * LB.size_of(lk)
    assert sol.residual() <= 1e-9 * LB.size_of(lk)


# ---------------------------------------------------------------------------------------------
# exact change points (a toggle touched with zero gap: a bifurcation of the assembly)
def _max_jump_ratio(lk, x):
    """Largest step between neighbouring samples over what |v| and |a| allow (≤ 1: no jump)."""
    plan = compile_plan(lk)
    ev = plan.evaluate(x, order=2)
    dt = abs(x[1] - x[0]) / abs(plan.omega)
    worst = 0.0
    for link in lk.links:
        for j in link.joints:
            p = ev.point(link.id, lk.joint(j).at)
            v = ev.point_velocity(link.id, lk.joint(j).at)
            a = ev.point_acceleration(link.id, lk.joint(j).at)
            step = np.hypot(*np.diff(p, axis=0).T)
            vm = np.maximum(np.hypot(*v[1:].T), np.hypot(*v[:-1].T))
            am = np.maximum(np.hypot(*a[1:].T), np.hypot(*a[:-1].T))
            worst = max(worst, float(np.nanmax(step / (1.01 * vm * dt + am * dt * dt + 1e-12))))
    return worst


def test_parallelogram_change_points_keep_positions_continuous():
    """crank = rocker, coupler = ground: at θ = 0 and π all four links are collinear. The mode
    is kept, so the motion continues without a jump (on the crossed branch after the first
    change point: the classic parallelogram/antiparallelogram bifurcation)."""
    lk = LB.fourbar(crank=50.0, coupler=150.0, rocker=50.0, ground=150.0, theta0=37.0)
    sol = compile_plan(lk).sweep(samples=720)
    # only the samples exactly at θ = 0, π may fall into the ~1e-8 rad rounding-wide gap there
    at_change = np.abs(np.sin(sol.input)) < 1e-9
    assert at_change.sum() == 2 and sol.valid[~at_change].all()
    assert CK.closure_error(lk, sol) < 1e-11
    x = sol.input[0] + np.linspace(0.0, 2 * math.pi, 20000, endpoint=False) + 1e-7
    assert _max_jump_ratio(lk, x) <= 1.0


def test_rhombus_four_bar_passes_b_through_d_without_a_jump():
    lk = LB.fourbar(crank=60.0, coupler=60.0, rocker=60.0, ground=60.0, theta0=36.67)
    x = compile_plan(lk).theta0 + np.linspace(0.0, 2 * math.pi, 7200, endpoint=False) + 1e-7
    assert _max_jump_ratio(lk, x) <= 1.0


def test_inverted_slider_crank_pin_through_the_pivot_without_a_jump():
    lk = LB.inverted_slider_crank(crank=50.0, ground=50.0, offset=0.0, theta0=40.0)
    x = compile_plan(lk).theta0 + np.linspace(0.0, 2 * math.pi, 7200, endpoint=False) + 1e-7
    assert _max_jump_ratio(lk, x) <= 1.0


@pytest.mark.parametrize("theta0", [10.0, 30.0, 45.0])
def test_rhombus_drawn_on_grid_angles_never_gives_an_open_loop(theta0):
    """All four lengths equal, crank drawn at a whole degree: the 1° sweep samples the input
    where the crank pin lies on the rocker pivot to ~1e-14 mm, and inputs nearby put it 1e-14 to
    1e-6 mm away. There the coupler's direction is all but undetermined (a position error of
    ~eps·size²/|BD|): whatever pose is returned as valid must close its loop (it used to be open
    by up to 96 mm) and be the parallelogram's (it used to be off by 31–141 mm, issue 13); where
    B and D coincide within rounding the sample is singular, not valid (issue 13, item 8)."""
    lk = LB.fourbar(crank=60.0, coupler=60.0, rocker=60.0, ground=60.0, theta0=theta0)
    size = LB.size_of(lk)
    sol = compile_plan(lk).sweep(samples=360)
    assert CK.closure_error(lk, sol) <= 1e-9 * size
    assert sol.residual() <= 1e-9 * size
    assert sol.valid.sum() >= 359 and (sol.valid | sol.singular).all()
    d = np.array([1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7])
    x = np.concatenate([d, -d])
    ev = compile_plan(lk).evaluate(x, order=0)
    assert (ev.valid | ev.singular).all()
    assert ev.valid[np.abs(x) >= 1e-7].all()              # |BD| ≥ 6e-6 mm: solved
    assert ev.singular[np.abs(x) <= 1e-12].all()          # |BD| ≤ 6e-11 mm: undetermined
    assert CK.closure_error(lk, ev) <= 1e-9 * size
    z = {j: ev.position(j)[:, 0] + 1j * ev.position(j)[:, 1] for j in "ABCD"}
    off = np.abs(z["C"] - (z["B"] + z["D"] - z["A"]))[ev.valid]
    assert off.size and off.max() <= 1e-6 * size          # the parallelogram, as drawn
