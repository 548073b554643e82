"""Tests written to kill the mutants that survived the core tests (issue 8, "Mutation testing" and
item 6), each against an independent reference:

* an RPP group whose guide is on a moving link (the rocker of a four-bar): positions, velocities
  and accelerations against the linkage in closed form in mpmath at 50 digits, differentiated by
  ``mpmath.diffs`` (:class:`mutant_refs.RppChainMp`);
* a four-bar whose coupler (20) cannot reach the rocker (90) over part of the turn, and the
  mirror case: the exact number and set of assembled samples against the interval of crank
  angles from the law of cosines, and the loop closure on them;
* the exact rolling-lever integration: a stroke that does not start at the drawn pose (the
  lead-in θ = 0 → start is integrated first: its error must be counted), and strokes ending near
  the upper end of the working range, against DOP853 and a 30-digit quadrature
  (:class:`mutant_refs.LeverRef`);
* the Geneva contact at entry and exit against the closed forms of the notes (ε̃ = ±tan(π/z),
  ρ = A·cos(π/z)), entry/exit symmetry, and the wear invariant at a coarse sampling against an
  mpmath quadrature of the slip path.
"""
from __future__ import annotations

import cmath
import math

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
import mutant_refs as MR
import test_rolling_reference as RR
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.rolling.exact import integrate, working_range
from mechsketch.core.analyses.rolling.geometry import LeverGeometry
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.model.geneva import ContactModel, Drawing, Geneva, Load
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.solver.structure import mobility


# ---------------------------------------------------------------------------------------------
# 1. RPP whose guide is on a moving link
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("guide,slot,rpm", [(70.0, 130.0, 95.4929658551372), (200.0, 95.0, -60.0)])
def test_rpp_with_its_guide_on_a_moving_link_against_mpmath(guide, slot, rpm):
    """Kills mutants of the guide-motion terms of kernels.rpp and kernels._slider: the guide's
    velocity and acceleration at the pin (ω×, α× and ω² terms), the Coriolis term 2ω(ṡ1u1 + ṡ2u2)
    and the links' ω, α taken from the guide (all zero for a guide on the frame)."""
    lk = MR.rpp_on_rocker(guide, slot, rpm=rpm)
    assert mobility(lk) == 1
    plan = compile_plan(lk)
    rpp = [g for g in plan.groups if g.kind == "RPP"]
    assert len(rpp) == 1
    g = rpp[0]
    assert (g.link_i, g.link_j, g.known_i, g.known_j) == ("block", "yoke", "coupler", "rocker")
    assert g.known_j not in (lk.ground, lk.driver.link)   # the guide turns (and accelerates)
    n = 24
    sol = plan.sweep(samples=n, order=2)
    assert sol.valid.all()
    assert np.min(sol.conditioning(g.name)) > 0.5           # far from parallel axes
    ref = MR.RppChainMp(lk)
    w = sol.omega_driver
    size = LB.size_of(lk)
    err = dict(pos=0.0, vel=0.0, acc=0.0, omega=0.0, alpha=0.0)
    scale = dict(vel=0.0, acc=0.0, omega=0.0, alpha=0.0)
    for k in range(n):
        th = float(sol.input[k])
        for link in ("coupler", "rocker", "block", "yoke"):
            for j in lk.link(link).joints:
                p0 = lk.joint(j).at
                P, V, A = ref.pva(link, p0, th, w)
                for name, got, want in (("pos", sol.point(link, p0)[k], P),
                                        ("vel", sol.point_velocity(link, p0)[k], V),
                                        ("acc", sol.point_acceleration(link, p0)[k], A)):
                    err[name] = max(err[name], float(abs(mpmath.mpc(*got) - want)))
                    if name != "pos":
                        scale[name] = max(scale[name], float(abs(want)))
            om, al = ref.omega_alpha(link, th, w)
            err["omega"] = max(err["omega"], abs(sol.omega(link)[k] - float(om)))
            err["alpha"] = max(err["alpha"], abs(sol.alpha(link)[k] - float(al)))
            scale["omega"] = max(scale["omega"], abs(float(om)))
            scale["alpha"] = max(scale["alpha"], abs(float(al)))
        # the joints as reported (R joints: unambiguous), against the same reference
        for j, link in (("E", "block"), ("Y", "yoke")):
            P, V, A = ref.pva(link, lk.joint(j).at, th, w)
            for got, want, name in ((sol.position(j)[k], P, "pos"), (sol.velocity(j)[k], V, "vel"),
                                    (sol.acceleration(j)[k], A, "acc")):
                err[name] = max(err[name], float(abs(mpmath.mpc(*got) - want)))
    # measured: pos 3e-16, vel 5e-16, acc 5e-16, ω 4e-16, α 5e-16 (relative)
    assert err["pos"] <= 1e-13 * size, err
    for name in ("vel", "acc", "omega", "alpha"):
        assert err[name] <= 1e-12 * scale[name], (name, err, scale)
    # the guide really moves: its ω and α are a sizeable part of the driver's
    assert scale["omega"] > 0.2 * abs(w) and scale["alpha"] > 0.2 * w * w


def test_the_rpp_reference_sees_a_wrong_guide_acceleration():
    """The check above is not blind: a solution whose yoke acceleration misses the guide's
    centripetal term −ω²·r (what a dropped ω² term gives) fails it by far."""
    lk = MR.rpp_on_rocker()
    sol = compile_plan(lk).sweep(samples=6, order=2)
    ref = MR.RppChainMp(lk)
    k, p0 = 2, lk.joint("Y").at
    th, w = float(sol.input[k]), sol.omega_driver
    _, _, A = ref.pva("yoke", p0, th, w)
    om = sol.omega("rocker")[k]
    r = sol.point("yoke", p0)[k] - sol.point("rocker", lk.joint("D").at)[k]
    bad = sol.point_acceleration("yoke", p0)[k] + om * om * r
    assert float(abs(mpmath.mpc(*bad) - A)) > 1e-3 * float(abs(A))
    assert float(abs(mpmath.mpc(*sol.point_acceleration("yoke", p0)[k]) - A)) < 1e-12 * float(abs(A))


# ---------------------------------------------------------------------------------------------
# 1b. PRP whose two guides both turn (issue 20, item 13: kernels.prp's second Coriolis term)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("g1,g2,rpm", [(75.0, -15.0, 95.4929658551372), (110.0, 30.0, -60.0)])
def test_prp_with_both_guides_turning_against_mpmath(g1, g2, rpm):
    """Kills the mutant that drops the second guide's Coriolis term 2·ω2·ṡ2·(J·u2) from the
    acceleration system of kernels.prp (162 solver tests passed without it: every PRP tested had
    its second guide on the frame): block 1 slides on the rocker's guide, block 2 on the
    coupler's, both turning with angular acceleration; positions, velocities, accelerations,
    ω, α of every link and both slides' s, ṡ, s̈ against the closed form in mpmath
    (:class:`mutant_refs.PrpBothTurnMp`, differentiated by ``mpmath.diffs``)."""
    lk = MR.prp_both_guides_turn(g1, g2, rpm=rpm)
    assert mobility(lk) == 1
    plan = compile_plan(lk)
    (g,) = [g for g in plan.groups if g.kind == "PRP"]
    assert {g.known_i, g.known_j} == {"rocker", "coupler"}     # both guides on moving links
    n = 24
    sol = plan.sweep(samples=n, order=2)
    assert sol.valid.all() and np.min(sol.conditioning(g.name)) > 0.3
    ref = MR.PrpBothTurnMp(lk)
    w = sol.omega_driver
    size = LB.size_of(lk)
    out = sol.group_output(g.name)
    which = {g.outer_i: 0, g.outer_j: 1}                          # slide index by its P joint
    slide_of = {which["Q1"]: 0, which["Q2"]: 1}                   # the reference's 0: Q1 (rocker), 1: Q2 (coupler)
    err = dict(pos=0.0, vel=0.0, acc=0.0, omega=0.0, alpha=0.0, s=0.0, sd=0.0, sdd=0.0)
    scale = dict(vel=0.0, acc=0.0, omega=0.0, alpha=0.0, sd=0.0, sdd=0.0)
    for k in range(n):
        th = float(sol.input[k])
        for link in ("coupler", "rocker", "block1", "block2"):
            for j in lk.link(link).joints:
                p0 = lk.joint(j).at
                P, V, A = ref.pva(link, p0, th, w)
                for name, got, want in (("pos", sol.point(link, p0)[k], P),
                                        ("vel", sol.point_velocity(link, p0)[k], V),
                                        ("acc", sol.point_acceleration(link, p0)[k], A)):
                    err[name] = max(err[name], float(abs(mpmath.mpc(*got) - want)))
                    if name != "pos":
                        scale[name] = max(scale[name], float(abs(want)))
            om, al = ref.omega_alpha(link, th, w)
            err["omega"] = max(err["omega"], abs(sol.omega(link)[k] - float(om)))
            err["alpha"] = max(err["alpha"], abs(sol.alpha(link)[k] - float(al)))
            scale["omega"] = max(scale["omega"], abs(float(om)))
            scale["alpha"] = max(scale["alpha"], abs(float(al)))
        for idx, i in slide_of.items():
            s_, sd, sdd = ref.slide(i, th, w)
            sl = out.slides[idx]
            err["s"] = max(err["s"], abs(sl.s[k] - float(s_)))
            err["sd"] = max(err["sd"], abs(sl.sd[k] - float(sd)))
            err["sdd"] = max(err["sdd"], abs(sl.sdd[k] - float(sdd)))
            scale["sd"] = max(scale["sd"], abs(float(sd)))
            scale["sdd"] = max(scale["sdd"], abs(float(sdd)))
    assert err["pos"] <= 1e-13 * size and err["s"] <= 1e-13 * size, err
    for name in ("vel", "acc", "omega", "alpha", "sd", "sdd"):
        assert err[name] <= 1e-12 * scale[name], (name, err, scale)
    # both guides really turn and both blocks really slide: each Coriolis term 2·ω·ṡ is far
    # above the tolerance the accelerations meet
    for link, joint in (("rocker", "Q1"), ("coupler", "Q2")):
        cor = np.max(np.abs(2.0 * sol.omega(link) * out.slides[which[joint]].sd))
        assert cor > 1e-6 * scale["acc"], (link, cor, scale)


def test_the_prp_reference_sees_a_dropped_coriolis_term():
    """The check above is not blind: the second guide's Coriolis term 2·ω2·ṡ2·J·u2 (on the
    coupler), computed from the core's own slides and rates, is far above the tolerance within
    which block 2's acceleration matches the reference, so leaving it out fails the check."""
    lk = MR.prp_both_guides_turn()
    plan = compile_plan(lk)
    (g,) = [g for g in plan.groups if g.kind == "PRP"]
    sol = plan.sweep(samples=12, order=2)
    ref = MR.PrpBothTurnMp(lk)
    out = sol.group_output(g.name)
    j2 = 1 if g.outer_j == "Q2" else 0                            # the slide on the coupler's guide
    k, w = 5, sol.omega_driver
    th = float(sol.input[k])
    _, _, A = ref.pva("block2", lk.joint("L").at, th, w)
    got = sol.point_acceleration("block2", lk.joint("L").at)[k]
    assert float(abs(mpmath.mpc(*got) - A)) < 1e-12 * float(abs(A))
    u2 = cmath.exp(1j * math.radians(lk.joint("Q2").axis_deg)) * cmath.exp(1j * float(sol.rotation("coupler")[k]))
    coriolis = 2.0 * float(sol.omega("coupler")[k]) * out.slides[j2].sd[k] * 1j * u2
    assert abs(coriolis) > 1e-3 * float(abs(A))                  # far above the tolerance


# ---------------------------------------------------------------------------------------------
# 2. the four-bar whose second link cannot always reach
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("coupler,rocker", [(20.0, 90.0), (90.0, 20.0)])
@pytest.mark.parametrize("mode", [1, -1])
@pytest.mark.parametrize("n", [997, 3600])
def test_rrr_that_cannot_always_close_valid_samples_and_closure(coupler, rocker, mode, n):
    """Crank 40, ground 100, coupler 20, rocker 90 (and coupler 90, rocker 20): the loop closes
    only where 70 ≤ |B − D| ≤ 110, i.e. for cos φ in [−0.0625, 0.8375] (law of cosines). Kills
    mutants of the RRR assembly test (a factor of Heron's product left out of the margin, lengths
    swapped) and of the position formula (closure)."""
    theta0 = 60.0
    lk = LB.fourbar(crank=40.0, coupler=coupler, rocker=rocker, ground=100.0, theta0=theta0, mode=mode)
    sol = compile_plan(lk).sweep(samples=n, order=2)
    count, margin = MR.rrr_valid_count(40.0, 100.0, coupler, rocker, theta0, n)
    assert margin > 1e-6   # no sample sits on an interval end: the count is exact
    assert int(sol.valid.sum()) == count
    assert count == {997: 336, 3600: 1208}[n]      # the closed form, evaluated once by hand
    # sample by sample: the valid set is exactly where cos φ_k is in the closed-form interval
    c_lo, c_hi = (float(c) for c in MR.rrr_feasible_cos(40.0, 100.0, coupler, rocker))
    assert (c_lo, c_hi) == (pytest.approx(-0.0625, abs=1e-15), pytest.approx(0.8375, abs=1e-15))
    with mpmath.workdps(30):
        phis = [mpmath.radians(theta0) + 2 * mpmath.pi * k / n for k in range(n)]
        inside = np.array([c_lo <= float(mpmath.cos(p)) <= c_hi for p in phis])
    assert np.array_equal(sol.valid, inside)
    # the invalid samples are NaN, the valid ones close the loop to round-off
    B, C, D = sol.position("B"), sol.position("C"), sol.position("D")
    assert np.isnan(C[~sol.valid]).all() and np.isfinite(C[sol.valid]).all()
    v = sol.valid
    res_coupler = np.abs(np.hypot(*(C - B)[v].T) - coupler) / coupler
    res_rocker = np.abs(np.hypot(*(C - D)[v].T) - rocker) / rocker
    assert res_coupler.max() <= 1e-12 and res_rocker.max() <= 1e-12
    # the crank point itself is exact: |B − A| = 40 on every valid sample
    assert np.abs(np.hypot(*B[v].T) - 40.0).max() <= 1e-12 * 40.0
    # and the side of C (assembly mode) is the drawn one wherever the motion is smooth:
    # on the run of valid samples that contains the drawn pose, cross(D − B, C − B) keeps its sign
    crs = (D - B)[:, 0] * (C - B)[:, 1] - (D - B)[:, 1] * (C - B)[:, 0]
    run = 0
    while run < n and v[run]:
        run += 1
    assert np.all(np.sign(crs[:run][np.abs(crs[:run]) > 1e-6]) == mode)


# ---------------------------------------------------------------------------------------------
# 3. the rolling lever: error estimate with a lead-in, and the upper end of the working range
# ---------------------------------------------------------------------------------------------
def _lever(**changes):
    d = dict(RR.PRESS, drive=None)
    d.update(changes)
    return d, RR.element(**{k: v for k, v in d.items() if k != "type"})


def _actual_error(ref: MR.LeverRef, res, exact_at=()):
    """Largest |P − P_ref|, |Q − Q_ref| over the samples (mm) and largest |α − α_ref| (rad).
    α_ref, S5_ref by DOP853; at the sample indices ``exact_at`` α_ref from the 30-digit quadrature."""
    a, s = ref.dop853(res.theta)
    for i in exact_at:
        a[i] = float(ref.alpha_exact(float(res.theta[i]), float(a[i])))
    P, Q = ref.contacts(a, res.theta, s)
    err = np.maximum(np.hypot(*(res.P - P).T), np.hypot(*(res.Q - Q).T))
    return float(err.max()), float(np.abs(res.alpha - a).max()), float(np.abs(res.S5 - s).max())


@pytest.mark.parametrize("start,end,strict", [(-0.55, -0.54, False), (-0.5, -0.45, True), (1.2, 1.25, True)])
@pytest.mark.parametrize("tol", [1e-8, 1e-9])
def test_error_estimate_counts_the_lead_in(start, end, strict, tol):
    """The stroke does not start at the drawn pose: θ = 0 → start is integrated first and its
    error is carried into the whole stroke. The reported estimate (sum of local errors of P and Q)
    must account for the actual error, measured against DOP853 at rtol 1e-13 (its own error is
    ~1e-11 mm here, 100× below the errors measured), and the stated tolerance must hold. A short
    stroke after a long lead-in makes the lead-in's error nearly all of it: leaving the lead-in
    out of ``error_mm`` (an estimate ~1e-11 against an actual ~5e-9) or integrating the lead-in
    more loosely breaks this.

    The estimate is not a strict bound: measured actual/estimate is 0.66–0.92 for the strokes
    above 1.2 rad or ending at −0.45, but 1.04–1.05 for −0.55 → −0.54 (and 1.02–1.05 for the
    same stroke from the drawn pose, without lead-in). Hence the factor 1.25 here; the strict bound
    is asserted where it holds (see also the expected failure near the range ends below)."""
    d, el = _lever(stroke={"from": start, "to": end}, tolerance=tol)
    res = synthesize(el, points=20, measures=False)
    ref = MR.LeverRef(d)
    actual, da, ds = _actual_error(ref, res)
    assert res.theta[0] == start and res.theta[-1] == end
    assert actual <= tol                                     # measured 0.37–0.70 × tol
    assert actual <= 1.25 * res.error_mm
    if strict:
        assert actual <= res.error_mm
    assert res.error_mm <= 2.0 * tol                         # lead-in and stroke, each ≤ tol
    # the lead-in alone carries most of the error of this short stroke, and it is counted
    lead = integrate(LeverGeometry.from_element(el), start, tol)
    assert lead.error_mm > 0.5 * actual
    assert res.error_mm >= lead.error_mm
    assert res.path.evaluations > lead.evaluations           # its cost is counted too
    # α and S5 at the stroke's first sample are the lead-in's end state
    a_ex = float(ref.alpha_exact(start, res.alpha[0]))
    assert abs(res.alpha[0] - a_ex) < 1e-10
    assert abs(res.S5[0] - ref.dop853([start])[1][0]) < tol


@pytest.fixture(scope="module")
def press_range():
    return working_range(LeverGeometry.from_element(RR.element()))


@pytest.mark.parametrize("gap", [3e-2, 1e-2])
@pytest.mark.parametrize("tol", [1e-10, 1e-8])
def test_stroke_to_near_the_upper_end_of_the_working_range(press_range, gap, tol):
    """The press's working range ends at θ = 2.5279 rad (the rocker line tangent to the moved lever
    circle); only the lower end was integrated up to by the tests. A stroke from the drawn pose to
    `gap` rad before the upper end: P and Q within the stated tolerance of the references, the
    estimate bounding the actual error and itself within the tolerance; α at the end against the
    30-digit quadrature (DOP853's α loses nothing there, but P moves ~1/√gap faster than α)."""
    hi = press_range.upper
    assert press_range.upper_reason.startswith("the rocker line becomes tangent")
    assert hi == pytest.approx(2.527904964, abs=1e-8)
    end = hi - gap
    d, el = _lever(stroke={"from": 0.0, "to": end}, tolerance=tol)
    res = synthesize(el, points=20, measures=False)
    ref = MR.LeverRef(d)
    actual, da, ds = _actual_error(ref, res, exact_at=(len(res.theta) - 1,))
    assert actual <= tol                  # measured 0.2–0.4 × tol
    assert actual <= res.error_mm <= tol  # the estimate bounds it (measured ratio 0.3–0.6)
    a_ex = float(ref.alpha_exact(end, res.alpha[-1]))
    assert abs(res.alpha[-1] - a_ex) <= 1e-3 * tol    # rad; measured 4e-14 at tol 1e-10
    assert ds <= 10 * tol                              # S5 (mm) against DOP853


@pytest.mark.parametrize("gap", [1e-2, 1e-4, 1e-6])
def test_alpha_and_s5_up_to_the_upper_end_against_the_quadrature(press_range, gap):
    """Up to 1e-6 rad from the upper end, from a stroke that does not start at the drawn pose
    (a lead-in of 1.5 rad): α against the 30-digit quadrature, S5 against DOP853."""
    end = press_range.upper - gap
    d, el = _lever(stroke={"from": 1.5, "to": end})
    res = synthesize(el, points=10, measures=False)
    ref = MR.LeverRef(d)
    a_ex = float(ref.alpha_exact(end, res.alpha[-1]))
    assert abs(res.alpha[-1] - a_ex) < 1e-11            # measured ≤ 4e-13
    s_ref = ref.dop853(res.theta)[1]
    assert np.abs(res.S5 - s_ref).max() < 1e-9
    assert res.error_mm < 2 * el.tolerance


@pytest.mark.parametrize("which", ["lower", "upper"])
def test_error_estimate_bounds_the_error_close_to_either_end(press_range, which):
    end = press_range.lower + 1e-2 if which == "lower" else press_range.upper - 1e-4
    d, el = _lever(stroke={"from": 0.0, "to": end}, tolerance=1e-10)
    res = synthesize(el, points=20, measures=False)
    ref = MR.LeverRef(d)
    actual, _, _ = _actual_error(ref, res, exact_at=(len(res.theta) - 1,))
    assert actual <= res.error_mm and actual <= el.tolerance


# ---------------------------------------------------------------------------------------------
# 4. the Geneva contact at entry and exit, symmetry, and the wear invariant
# ---------------------------------------------------------------------------------------------
def _geneva(z, rpm, f02=0.05, r02=15.0, j2=0.05, mext=0.0):
    return Geneva("g", z, 100.0, 8.0, drawing=Drawing(wheel_bore_radius=1.0), speed_rpm=rpm,
                  load=Load(wheel_inertia=j2, external_moment=mext, journal_friction=f02, journal_radius=r02))


def _entry_exit(c, phi0):
    e = np.nonzero(c.engaged)[0]
    i_in = e[np.argmin(np.abs(c.u[e] + phi0))]
    i_out = e[np.argmin(np.abs(c.u[e] - phi0))]
    assert abs(c.u[i_in] + phi0) < 1e-9 and abs(c.u[i_out] - phi0) < 1e-9   # both are samples
    return i_in, i_out


@pytest.mark.parametrize("z,n", [(4, 360), (6, 360), (5, 3600)])
@pytest.mark.parametrize("rpm", [300.0 / math.pi, -137.0])
def test_geneva_contact_at_entry_and_exit_closed_forms(z, n, rpm):
    """At entry and exit (u = ∓φ0) the notes give everything in closed form: ε̃ = ±tan(π/z),
    D = 1 − λ² = cos²(π/z), ρ = A·cos(π/z), |ω_pi| = r/r_p. Hence M = ±J2·ω1²·tan(π/z) and
    R_n derived = J2ω1² tan(π/z)/(A cos(π/z) ∓ f02 r02) (friction helps the roller only while it
    brakes, at exit), R_n paper = λ J2ω1² tan(π/z)/(r cos(π/z) + f02 r02) at both; the Hertz
    pressure 2R_n/(π b l) with b = √(4R_n r_p/(π l E*)); the slip-speed invariant
    (ρ_eff/r_p)(r/r_p)(a/2r_p)² with the paper's strip width a and Δ of eq. 6."""
    el = _geneva(z, rpm)
    model = ContactModel()
    c = contact(el, n, model)
    i_in, i_out = _entry_exit(c, el.phi0)
    with mpmath.workdps(30):
        pi = mpmath.pi
        t, co = mpmath.tan(pi / z), mpmath.cos(pi / z)
        lam = mpmath.sin(pi / z)
        A, rp, l_ = mpmath.mpf(100), mpmath.mpf(8), mpmath.mpf(10)
        r = A * lam
        w1 = mpmath.mpf(rpm) * pi / 30
        m = mpmath.mpf("0.05") * w1 ** 2 * t
        fr = mpmath.mpf("0.05") * 15
        E, nu = mpmath.mpf(210000), mpmath.mpf("0.3")
        estar = E / (2 * (1 - nu ** 2))
        epair = E
        want = {}
        for i, sgn in ((i_in, 1), (i_out, -1)):
            rn_d = m / ((A * co - sgn * fr) * mpmath.mpf("1e-3"))
            rn_p = lam * m / ((r * co + fr) * mpmath.mpf("1e-3"))
            bh = mpmath.sqrt(4 * rn_d * rp / (pi * l_ * estar))
            a = mpmath.mpf("2.16") * mpmath.sqrt(rn_d * 2 * rp / (l_ * epair))
            delta = 4 * rn_d / l_ * (1 - nu ** 2) / E * (mpmath.mpf("0.41") + mpmath.log(4 * rp / a))
            inv = (rp - delta) / rp * (r / rp) * (a / 2 / rp) ** 2
            want[i] = dict(moment=sgn * m, Rn_derived=rn_d, Rn_paper=rn_p, Rn=rn_d,
                           rolling_ratio=-sgn * r / rp, contact_pressure=2 * rn_d / (pi * bh * l_),
                           mean_pressure=rn_d / (2 * bh * l_), hertz_half_width=bh, strip_width=a,
                           deformation=delta, slip_speed_invariant=inv,
                           slip_speed=inv * abs(w1) * rp)
    for i, vals in want.items():
        for name, v in vals.items():
            assert getattr(c, name)[i] == pytest.approx(float(v), rel=1e-12), (name, i)
    # the two forms of the normal force differ at entry and exit by the closed-form ratios
    assert c.Rn_derived[i_in] / c.Rn_derived[i_out] == pytest.approx(
        (100 * math.cos(math.pi / z) + 0.75) / (100 * math.cos(math.pi / z) - 0.75), rel=1e-13)
    assert c.Rn_paper[i_in] == pytest.approx(c.Rn_paper[i_out], rel=1e-14)
    # crank angle of the samples: φ = sign(ω1)·u
    assert c.phi[i_in] == pytest.approx(-math.copysign(el.phi0, rpm), abs=1e-12)


def _slip_path_mp(z, rpm, f02, r02):
    """L_s per engagement (mm) by mpmath quadrature (30 digits) of ρ_eff·|ω_pi|·sin²ψ over
    [−φ0, 0] and [0, φ0] (M_ext = 0: M changes sign only at 0), derived normal force, b = a/2."""
    with mpmath.workdps(30):
        pi = mpmath.pi
        lam = mpmath.sin(pi / z)
        A, rp, l_ = mpmath.mpf(100), mpmath.mpf(8), mpmath.mpf(10)
        r = A * lam
        w1 = mpmath.mpf(rpm) * pi / 30
        fr = mpmath.mpf(f02) * mpmath.mpf(r02) * mpmath.mpf("1e-3")
        E, nu = mpmath.mpf(210000), mpmath.mpf("0.3")
        phi0 = pi / 2 - pi / z

        def g(u):
            D = 1 - 2 * lam * mpmath.cos(u) + lam ** 2
            m = mpmath.mpf("0.05") * w1 ** 2 * (-lam * (1 - lam ** 2) * mpmath.sin(u) / D ** 2)
            if m == 0:
                return mpmath.mpf(0)
            rn = abs(m) / (A * mpmath.sqrt(D) * mpmath.mpf("1e-3") - mpmath.sign(m) * fr)
            a = mpmath.mpf("2.16") * mpmath.sqrt(rn * 2 * rp / (l_ * E))
            delta = 4 * rn / l_ * (1 - nu ** 2) / E * (mpmath.mpf("0.41") + mpmath.log(4 * rp / a))
            wpi = r / rp * abs(mpmath.sin(u)) / mpmath.sqrt(D)
            return (rp - delta) * wpi * (a / 2 / rp) ** 2
        return mpmath.quad(g, [-phi0, 0, phi0])


@pytest.mark.parametrize("n", [72, 360])
def test_geneva_wear_invariant_uses_the_sample_independent_slip_path(n):
    """T_i = π R_n z/(30 |ω1| L_s) with L_s per engagement in m (B8): L_s is the Gauss–Legendre
    total, independent of the sampling. At a coarse sampling (72 samples, 5° apart) the trapezoid
    total differs from it by ~1e-3, so T_i at every engaged sample is checked against L_s from an
    mpmath quadrature; the slip_path column ends at L_s (issue 13, item 11: it was the trapezoid's)."""
    z, rpm = 6, 300.0 / math.pi
    el = _geneva(z, rpm)
    c = contact(el, n, ContactModel())
    ls = float(_slip_path_mp(z, rpm, 0.05, 15.0))
    assert c.slip_path_total == pytest.approx(ls, rel=1e-10)
    if n == 72:
        assert abs(c.slip_path_total_trapezoid / ls - 1) > 5e-4   # the coarse rule: 8.7e-4 off
    e = c.engaged & (c.Rn > 0)
    want = math.pi * c.Rn[e] * z / (30.0 * abs(el.omega1) * ls * 1e-3)
    assert np.allclose(c.wear_invariant[e], want, rtol=1e-10, atol=0)
    assert c.wear_invariant_max == pytest.approx(want.max(), rel=1e-10)
    i_in, i_out = _entry_exit(c, el.phi0)
    assert c.slip_path[i_in] == 0.0
    assert c.slip_path[i_out] == pytest.approx(c.slip_path_total, rel=1e-14)   # issue 13, item 11


@pytest.mark.parametrize("rpm", [300.0 / math.pi, -137.0])
def test_geneva_contact_entry_exit_symmetry_without_journal_friction(rpm):
    """With f02 = 0 and M_ext = 0, |M|, R_n, the strip, the pressures and the slip speed are even
    in the progress angle u, M and ω_pi odd, and the cumulative slip path satisfies
    L_s(u) + L_s(−u) = L_s,total (entry and exit mirror each other). With friction the exit force
    is the smaller (friction helps the braking roller)."""
    el = _geneva(6, rpm, f02=0.0)
    c = contact(el, 720, ContactModel())
    e = np.nonzero(c.engaged)[0]
    u = c.u[e]
    mirror = np.array([e[np.argmin(np.abs(u + x))] for x in u])
    assert np.allclose(c.u[mirror], -u, atol=1e-12)
    for name in ("Rn", "Rn_derived", "Rn_paper", "strip_width", "deformation", "contact_pressure",
                 "mean_pressure", "slip_speed", "slip_speed_invariant", "wear_invariant"):
        col = getattr(c, name)
        assert np.allclose(col[mirror], col[e], rtol=1e-12, atol=1e-300), name
    for name in ("moment", "rolling_ratio"):
        col = getattr(c, name)
        assert np.allclose(col[mirror], -col[e], rtol=1e-12, atol=1e-15), name
    total = c.slip_path_total   # the column is Gauss–Legendre per interval (issue 13, item 11)
    assert np.allclose(c.slip_path[e] + c.slip_path[mirror], total, rtol=1e-13, atol=0)
    i0 = e[np.argmin(np.abs(u))]
    assert c.slip_path[i0] == pytest.approx(total / 2, rel=1e-13)
    with_friction = contact(_geneva(6, rpm), 720, ContactModel())
    i_in, i_out = _entry_exit(with_friction, el.phi0)
    assert c.Rn[i_out] == pytest.approx(c.Rn[i_in], rel=1e-13)
    assert with_friction.Rn[i_out] < c.Rn[i_out] and c.Rn[i_in] < with_friction.Rn[i_in]
