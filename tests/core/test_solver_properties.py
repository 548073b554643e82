"""Property tests: hypothesis draws four-bars (Grashof or not), slider-cranks (offset, inclined or
vertical guide, offset pin), inverted slider-cranks and six-bars from drawn poses that close, and
checks loop closure on every sample, derivative consistency against finite differences, the
assembly mode kept from the drawn pose, continuity, and two samples against 50 digits.

Examples are derandomised (stable CI); run with ``--hypothesis-seed`` / a larger
``MECHSKETCH_PROPERTY_EXAMPLES`` to search harder.
"""
from __future__ import annotations

import os

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import linkage_builders as LB
import reference as R
import solution_checks as CK
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver.plan import compile_plan

N_EXAMPLES = int(os.environ.get("MECHSKETCH_PROPERTY_EXAMPLES", "40"))
SETTINGS = settings(max_examples=N_EXAMPLES, deadline=None, derandomize="MECHSKETCH_PROPERTY_EXAMPLES" not in os.environ,
                    database=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])

length = st.floats(5.0, 300.0)
angle = st.floats(0.0, 360.0, exclude_max=True)
sign = st.sampled_from([1, -1])
origin = st.builds(complex, st.floats(-500.0, 500.0), st.floats(-500.0, 500.0))
rpm = st.sampled_from([60.0, -45.0, 95.4929658551372])


def build_or_reject(_builder, **kw):
    """The built object, or reject the example: no assembly, or (for a linkage) two joints of a link
    drawn at one point, which a scene file may not contain either (GeometryError, a ValueError)."""
    try:
        out = _builder(**kw)
        if isinstance(out, Linkage):
            compile_plan(out)
        return out
    except (ValueError, ZeroDivisionError):
        assume(False)


def drawn_conditioning_ok(lk, minimum=0.05):
    plan = compile_plan(lk)
    s = plan.evaluate([plan.theta0], order=0)
    return bool(s.valid[0]) and all(float(s.conditioning(g.name)[0]) > minimum for g in s.groups)


def check(lk, samples=120, continuation=False, mp_samples=2):
    size = LB.size_of(lk)
    assume(drawn_conditioning_ok(lk))
    plan = compile_plan(lk)
    sol = plan.sweep(samples=samples, order=2)
    # the drawn pose is sample 0
    assert sol.valid[0]
    for j in lk.joints:
        assert np.allclose(sol.position(j.id)[0], j.at, rtol=0, atol=1e-12 * size), j.id
    # loop closure on every assembled sample (independent check and the solver's own)
    assert CK.closure_error(lk, sol) <= 1e-9 * size
    assert sol.residual() <= 1e-9 * size
    # invalid samples are NaN, valid ones finite
    for j in lk.joint_ids:
        p = sol.position(j)
        assert np.isfinite(p[sol.valid]).all() and np.isnan(p[~sol.valid]).all()
    # the assembly mode read from the drawn pose is kept wherever the group is not at a toggle
    for g in sol.groups:
        s = CK.mode_signs(lk, sol, g)
        ok = sol.valid & (np.nan_to_num(sol.conditioning(g.name)) > 1e-9)
        assert np.all(s[ok] == s[0]), g.name
    # continuity: no jump between neighbouring well-conditioned samples beyond what v, a allow
    good = sol.valid.copy()
    for g in sol.groups:
        good &= np.nan_to_num(sol.conditioning(g.name)) > 1e-2
    pair = good[:-1] & good[1:]
    dt = abs(sol.t[1] - sol.t[0])
    for j in lk.joint_ids:
        p, v, a = sol.position(j), sol.velocity(j), sol.acceleration(j)
        step = np.hypot(*np.diff(p, axis=0).T)
        vm = np.maximum(np.hypot(*v[1:].T), np.hypot(*v[:-1].T))
        am = np.maximum(np.hypot(*a[1:].T), np.hypot(*a[:-1].T))
        bound = 2.0 * vm * dt + am * dt * dt + 1e-9 * size
        assert np.all(step[pair] <= bound[pair]), j
    # derivatives against finite differences of the solver's own positions / velocities
    bad_v, bad_a, checked, sharp, info = CK.fd_errors(plan, sol.input[::4])
    assert bad_v == 0 and bad_a == 0, info
    # the generic Newton continuation follows the same branch
    if continuation and sol.valid.all() and min(np.min(sol.conditioning(g.name)) for g in sol.groups) > 0.02:
        poses, ref = R.continuation(lk, sol.input, substeps=2)
        for link in ref.unknown:
            for j in lk.link(link).joints:
                p = R.continuation_point(ref, poses, link, lk.joint(j).at)
                assert np.max(np.abs(p - CK._z(sol.point(link, lk.joint(j).at)))) <= 1e-8 * size
    # and two samples against 50 digits
    ok = np.flatnonzero(good)
    if mp_samples and len(ok):
        pick = ok[np.linspace(0, len(ok) - 1, mp_samples).astype(int)]
        err = R.relative(R.compare(lk, sol, pick))
        assert err["pos"] <= 1e-12, err
        assert max(err[q] for q in ("vel", "acc", "omega", "alpha")) <= 1e-9, err
    return sol


@SETTINGS
@given(crank=length, coupler=length, rocker=length, ground=length, theta0=angle, mode=sign, rot=angle,
       origin=origin, rpm=rpm)
def test_random_four_bars(crank, coupler, rocker, ground, theta0, mode, rot, origin, rpm):
    s, l = min(crank, coupler, rocker, ground), max(crank, coupler, rocker, ground)
    pq = crank + coupler + rocker + ground - s - l
    # not a change point (s + l = p + q: the sweep touches a toggle with zero gap, a bifurcation;
    # see test_solver_hard for what the solver does there)
    assume(abs(s + l - pq) > 1e-6 * l)
    lk = build_or_reject(LB.fourbar, crank=crank, coupler=coupler, rocker=rocker, ground=ground, theta0=theta0,
                         mode=mode, rot=rot, origin=origin, rpm=rpm, coupler_point=(0.3, 0.4))
    sol = check(lk, continuation=True)
    if crank == s and s + l < pq:   # Grashof with the crank shortest: the crank turns fully
        assert sol.valid.all()


@SETTINGS
@given(crank=length, rod=st.floats(5.0, 600.0), offset=st.floats(-200.0, 200.0),
       xi=st.one_of(angle, st.sampled_from([90.0, 270.0, -90.0, 180.0])), theta0=angle, mode=sign,
       pin=st.builds(complex, st.floats(-30.0, 30.0), st.floats(-30.0, 30.0)), origin=origin, rpm=rpm)
def test_random_slider_cranks(crank, rod, offset, xi, theta0, mode, pin, origin, rpm):
    e_eff = abs(offset + pin.imag)          # the pin's offset from the slide axis adds to the guide's
    assume(abs(rod - crank - e_eff) > 1e-6 * rod)      # not a change point
    lk = build_or_reject(LB.slider_crank, crank=crank, rod=rod, offset=offset, xi=xi, theta0=theta0, mode=mode,
                         pin=pin, origin=origin, rpm=rpm)
    sol = check(lk, continuation=True)
    if rod > crank + e_eff:   # the crank turns fully
        assert sol.valid.all()


@SETTINGS
@given(crank=length, ground=length, offset=st.floats(-100.0, 100.0), theta0=angle, mode=sign,
       q_along=st.floats(-50.0, 50.0), rot=angle, origin=origin)
def test_random_inverted_slider_cranks(crank, ground, offset, theta0, mode, q_along, rot, origin):
    b = origin + crank * LB.e(theta0 + rot)
    c = origin + ground * LB.e(rot)
    assume(abs(b - c) > abs(offset) * 1.01)
    # not a change point (|ground − crank| = |offset|: the pin touches the toggle D = |c|; with
    # offset 0 the pin runs through the rocker pivot, see test_solver_hard)
    assume(abs(abs(ground - crank) - abs(offset)) > 1e-3 * (ground + crank))
    lk = build_or_reject(LB.inverted_slider_crank, crank=crank, ground=ground, offset=offset, theta0=theta0,
                         mode=mode, q_along=q_along, rot=rot, origin=origin)
    check(lk)


@SETTINGS
@given(mode1=sign, mode2=sign, e_pt=st.tuples(st.floats(-80.0, 150.0), st.floats(-80.0, 80.0)),
       f=st.tuples(st.floats(-250.0, 350.0), st.floats(-250.0, 250.0)), rod=length, out=length,
       on_rocker=st.booleans(), theta0=angle, kind=st.sampled_from(["RRR", "RRP", "compound"]),
       xi=angle)
def test_random_six_bars(mode1, mode2, e_pt, f, rod, out, on_rocker, theta0, kind, xi):
    if kind == "RRR":
        lk = build_or_reject(LB.sixbar_stephenson, mode1=mode1, mode2=mode2, e_pt=e_pt, f=f, rod=rod, out=out,
                             on_rocker=on_rocker, theta0=theta0)
    else:
        # a four-bar whose coupler point E (or, "compound", the joint C) drives a slider on a guide
        # through f at xi degrees: on the rocker (a moving guide) or on the ground
        fb = build_or_reject(LB.fourbar, mode=mode1, theta0=theta0, coupler_point=e_pt)
        at = {j.id: complex(*j.at) for j in fb.joints}
        m = "C" if kind == "compound" else "E"
        G = complex(*f)
        S = build_or_reject(LB.line_circle, o=G, u=LB.e(xi), c=at[m], r=rod, sign=mode2)
        joints = [(j.id, j.kind.value, j.at) for j in fb.joints] + [("S", "R", LB.xy(S)), ("Q", "P", LB.xy(S), xi)]
        links = {k.id: list(k.joints) for k in fb.links}
        links["rod"] = [m, "S"]
        links["block"] = ["S", "Q"]
        links["rocker" if on_rocker else "ground"].append("Q")
        lk = LB.build("six", joints, links, "ground", "crank", "A", 60.0)
    sol = check(lk, samples=90)
    assert len(sol.groups) == 2
