"""Every dyad kind (RRR, RRP fixed and moving guide, RPR, PRP, RPP), in both assembly modes where
there are two, against a 50-digit mpmath solution of the raw constraint equations, against
finite differences of the solver's own positions, and against a generic Newton continuation.

Drawn poses include 2nd- and 3rd-quadrant inputs and guides (axis 90°, 150°, 200°, 270°, −90°).
"""
from __future__ import annotations

import functools
import math

import numpy as np
import pytest

import linkage_builders as LB
import reference as R
import solution_checks as CK
from mechsketch.core.solver.plan import compile_plan

POS_TOL = 1e-13     # relative to the mechanism's size
ANG_TOL = 1e-13     # rad
RATE_TOL = 1e-11    # relative to the largest reference value of the kind


def _cases():
    c = {}
    c["RRR+"] = (lambda: LB.fourbar(), ["RRR"], [1])
    c["RRR-"] = (lambda: LB.fourbar(mode=-1), ["RRR"], [-1])
    c["RRR+ drawn q2"] = (lambda: LB.fourbar(theta0=135.0), ["RRR"], [1])
    c["RRR- drawn q3, ground q3"] = (lambda: LB.fourbar(theta0=225.0, mode=-1, rot=200.0, origin=-300 - 90j),
                                    ["RRR"], [-1])
    c["RRR drag-link CW"] = (lambda: LB.fourbar(crank=60, coupler=110, rocker=100, ground=30, theta0=160,
                                               rpm=-45.0), ["RRR"], [1])
    c["RRP+"] = (lambda: LB.slider_crank(), ["RRP"], [1])
    c["RRP-"] = (lambda: LB.slider_crank(mode=-1), ["RRP"], [-1])
    c["RRP+ vertical guide, pin offset"] = (lambda: LB.slider_crank(xi=90.0, pin=3 + 4j, theta0=20.0),
                                            ["RRP"], [1])
    c["RRP- vertical guide"] = (lambda: LB.slider_crank(xi=90.0, mode=-1, theta0=135.0), ["RRP"], [-1])
    c["RRP guide 270"] = (lambda: LB.slider_crank(xi=270.0, offset=-12.0, theta0=300.0, pin=-2 + 5j),
                          ["RRP"], [1])
    c["RRP guide -90"] = (lambda: LB.slider_crank(xi=-90.0, offset=12.0, theta0=100.0, mode=-1),
                          ["RRP"], [-1])
    c["RRP q2 guide 150"] = (lambda: LB.slider_crank(xi=150.0, theta0=135.0, offset=-15.0, pin=-4 + 6j),
                             ["RRP"], [1])
    c["RRP q3 guide 200"] = (lambda: LB.slider_crank(xi=200.0, theta0=225.0, offset=10.0, mode=-1,
                                                    origin=-50 - 80j), ["RRP"], [-1])
    c["RRP moving guide +"] = (lambda: LB.sixbar_guide(1), ["RRR", "RRP"], [1, 1])
    c["RRP moving guide -"] = (lambda: LB.sixbar_guide(-1), ["RRR", "RRP"], [1, -1])
    c["RRP guide on the driver +"] = (lambda: LB.crank_guided(mode=1), ["RRP"], [1])
    c["RRP guide on the driver -"] = (lambda: LB.crank_guided(mode=-1, pin=(5.0, -6.0)), ["RRP"], [-1])
    c["RPR+"] = (lambda: LB.inverted_slider_crank(offset=8.0, q_along=12.0), ["RPR"], [1])
    c["RPR-"] = (lambda: LB.inverted_slider_crank(offset=8.0, q_along=-12.0, mode=-1), ["RPR"], [-1])
    c["RPR- q2/q3"] = (lambda: LB.inverted_slider_crank(offset=-6.0, theta0=200.0, mode=-1, rot=150.0,
                                                       origin=-40 + 70j), ["RPR"], [-1])
    c["PRP"] = (lambda: LB.prp_linkage(), ["PRP"], [1])
    c["PRP offset guide, vertical"] = (lambda: LB.prp_linkage(crank_dir=200.0, guide_offset=12.0, xi=90.0,
                                                             g=(-70.0, 15.0)), ["PRP"], [1])
    c["RPP scotch yoke"] = (lambda: LB.scotch_yoke(), ["RPP"], [1])
    c["RPP inclined"] = (lambda: LB.scotch_yoke(slot=120.0, guide=200.0, theta0=250.0, guide_at=(-20.0, 45.0)),
                         ["RPP"], [1])
    c["RRR+RRR both outer joints moving"] = (lambda: LB.sixbar_stephenson(on_rocker=True, f=(150.0, 60.0)),
                                             ["RRR", "RRR"], [1, 1])
    c["RRR+RRR Stephenson, modes -,-"] = (lambda: LB.sixbar_stephenson(mode1=-1, mode2=-1, f=(60.0, -150.0),
                                                                      e_pt=(50.0, -30.0)), ["RRR", "RRR"], [-1, -1])
    c["RRR then RRP on its inner joint"] = (lambda: LB.sixbar_compound(), ["RRR", "RRP"], [1, 1])
    c["RPR with both outer joints moving"] = (lambda: LB.rpr_on_moving_links(), ["RRR", "RPR"], [1, 1])
    c["RRP guide on the coupler, pin off the axis"] = (lambda: LB.rrp_guide_on_coupler(), ["RRR", "RRP"], [1, 1])
    c["eight-bar RRR, RRR, RRP"] = (lambda: LB.eight_bar(), ["RRR", "RRR", "RRP"], [1, 1, -1])
    return c


CASES = _cases()
IDS = list(CASES)


@functools.lru_cache(maxsize=None)
def solved(case: str, samples: int = 360):
    lk = CASES[case][0]()
    plan = compile_plan(lk)
    return lk, plan, plan.sweep(samples=samples, order=2)


def well_conditioned(sol, cond_min=1e-3):
    ok = sol.valid.copy()
    for g in sol.groups:
        ok &= np.nan_to_num(sol.conditioning(g.name), nan=0.0) > cond_min
    return ok


@pytest.mark.parametrize("case", IDS)
def test_group_kinds_and_modes(case):
    lk, plan, sol = solved(case)
    kinds, modes = CASES[case][1], CASES[case][2]
    assert [g.kind for g in sol.groups] == kinds
    assert sol.valid[0], "the drawn pose must assemble"
    ok = sol.valid & well_conditioned(sol, 1e-9)
    for g, mode in zip(sol.groups, modes):
        s = CK.mode_signs(lk, sol, g)
        assert s[0] == mode, f"{g.name}: drawn pose is in mode {s[0]}, expected {mode}"
        assert np.all(s[ok] == mode), f"{g.name}: assembly mode changes along the sweep"


@pytest.mark.parametrize("case", IDS)
def test_starts_at_drawn_pose(case):
    lk, plan, sol = solved(case)
    size = LB.size_of(lk)
    assert sol.input[0] == pytest.approx(plan.theta0, abs=0)
    for j in lk.joints:
        assert np.allclose(sol.position(j.id)[0], j.at, rtol=0, atol=1e-13 * size), j.id
        for link in lk.links_of(j.id):
            assert np.allclose(sol.point(link, j.at)[0], j.at, rtol=0, atol=1e-13 * size), (j.id, link)


@pytest.mark.parametrize("case", IDS)
def test_loop_closure_every_sample(case):
    lk, plan, sol = solved(case)
    size = LB.size_of(lk)
    # a PRP whose guide turns with the crank reaches half a turn: the side of its drawn crossing
    assert sol.valid.sum() > (0.45 if case.startswith("PRP") else 0.7) * len(sol)
    assert CK.closure_error(lk, sol) <= 1e-12 * size
    assert sol.residual() <= 1e-12 * size


@pytest.mark.parametrize("case", IDS)
def test_against_mpmath_50_digits(case):
    lk, plan, sol = solved(case)
    # a PRP's pin runs off towards infinity near its parallel poses (positions ~ size/cond): the
    # picks keep to where it stays within ten sizes
    ok = np.flatnonzero(well_conditioned(sol, 0.1 if case.startswith("PRP") else 1e-3))
    pick = ok[:: max(1, len(ok) // 14)]
    assert len(pick) >= 10
    err = R.relative(R.compare(lk, sol, pick))
    assert err["pos"] <= POS_TOL, err
    assert err["ang"] <= ANG_TOL, err
    for k in ("vel", "acc", "omega", "alpha"):
        assert err[k] <= RATE_TOL, (k, err)


@pytest.mark.parametrize("case", IDS)
def test_against_mpmath_with_driver_acceleration(case):
    """A driver with angular acceleration (evaluate(..., omega, alpha)) at arbitrary inputs."""
    lk, plan, sol = solved(case)
    ok = np.flatnonzero(well_conditioned(sol))
    pick = sol.input[ok[[len(ok) // 5, len(ok) // 2, 4 * len(ok) // 5]]]
    ev = plan.evaluate(pick, order=2, omega=-3.7, alpha=25.0)
    ref = R.MpReference(lk)
    for k in range(len(pick)):
        st = ref.solve(float(pick[k]), -3.7, ref.guess_from(ev, k), al=25.0)
        pts = [(link.id, lk.joint(j).at) for link in lk.links for j in link.joints]
        refs = [st.point(link, p0) for link, p0 in pts]
        vs = max(float(abs(V[0]) + abs(V[1])) for _, V, _ in refs)
        as_ = max(float(abs(A[0]) + abs(A[1])) for _, _, A in refs)
        for (link, p0), (_, V, A) in zip(pts, refs):
            v = ev.point_velocity(link, p0)[k]
            a = ev.point_acceleration(link, p0)[k]
            assert math.hypot(v[0] - float(V[0]), v[1] - float(V[1])) <= RATE_TOL * vs
            assert math.hypot(a[0] - float(A[0]), a[1] - float(A[1])) <= RATE_TOL * as_
        ws = max(float(abs(st.rate[x][2])) for x in lk.moving_links)
        als = max([float(abs(st.acc[x][2])) for x in lk.moving_links] + [25.0])
        for x in lk.moving_links:
            assert abs(ev.omega(x)[k] - float(st.rate[x][2])) <= RATE_TOL * ws
            assert abs(ev.alpha(x)[k] - float(st.acc[x][2])) <= RATE_TOL * als


@pytest.mark.parametrize("case", IDS)
def test_against_central_finite_differences(case):
    lk, plan, sol = solved(case)
    inputs = sol.input[::5]
    bad_v, bad_a, checked, sharp, info = CK.fd_errors(plan, inputs)
    assert checked >= 0.8 * len(inputs) * sol.valid.mean() - 3
    assert sharp >= 0.8 * checked, "finite differences too blunt to test anything"
    assert bad_v == 0 and bad_a == 0, info


@pytest.mark.parametrize("case", IDS)
def test_generic_newton_continuation_follows_the_same_branch(case):
    """Newton continuation of the raw constraints from the drawn pose, in the driver's direction,
    lands on the solver's solution (the solver picked and kept the right assembly)."""
    lk, plan, sol = solved(case, 180)
    poses, ref = R.continuation(lk, sol.input)
    size = LB.size_of(lk)
    first_bad = np.flatnonzero(~sol.valid)
    stop = first_bad[0] if len(first_bad) else len(sol)
    done = np.isfinite(next(iter(poses.values()))[:, 0]) if poses else np.ones(len(sol), bool)
    # the continuation must get (nearly) as far as the solver's first gap
    assert done[: max(stop - 2, 1)].all()
    seg = slice(0, max(stop - 2, 1))
    for link in ref.unknown:
        for j in lk.link(link).joints:
            p = R.continuation_point(ref, poses, link, lk.joint(j).at)[seg]
            s = CK._z(sol.point(link, lk.joint(j).at))[seg]
            assert np.max(np.abs(p - s)) <= 1e-9 * size, (link, j)


@pytest.mark.parametrize("case", ["RRR+", "RRP moving guide -", "RPR-", "PRP", "RPP inclined"])
def test_orders_agree(case):
    """Positions do not depend on the requested order; order 1 has velocities equal to order 2's."""
    lk, plan, sol = solved(case)
    s0 = plan.sweep(360, order=0)
    s1 = plan.sweep(360, order=1)
    for j in lk.joint_ids:
        assert np.array_equal(s0.position(j), sol.position(j), equal_nan=True)
        assert np.array_equal(s1.velocity(j), sol.velocity(j), equal_nan=True)
    with pytest.raises(ValueError, match="order"):
        s0.velocity(lk.joint_ids[1])
    with pytest.raises(ValueError, match="order"):
        s1.acceleration(lk.joint_ids[1])
    with pytest.raises(ValueError, match="order"):
        s1.alpha(lk.moving_links[0])


def test_mirrored_fourbar_is_the_other_mode():
    """Mirroring C across B–D gives the other branch: same B, D paths, C reflected at sample 0."""
    a = LB.fourbar()
    b = LB.mirrored(a, "C", "B", "D")
    sa, sb = compile_plan(a).sweep(samples=360), compile_plan(b).sweep(samples=360)
    assert np.allclose(sa.position("B"), sb.position("B"), atol=1e-12)
    assert not np.allclose(sa.position("C"), sb.position("C"), atol=1.0)
    g = sb.groups[0]
    assert np.all(CK.mode_signs(b, sb, g) == -1)
    # the mirrored branch has the same coupler/rocker lengths at every sample
    for s in (sa, sb):
        assert np.allclose(np.hypot(*(s.position("C") - s.position("B")).T), 140.0, atol=1e-11)
