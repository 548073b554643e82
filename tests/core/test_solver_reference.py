"""Tests of the test references themselves: a reference that cannot fail, or that agrees with
anything, would make every solver test worthless.

* the 50-digit reference's rates equal high-precision differences of its own position solve;
* its positions satisfy every constraint to ~1e-45 and keep every link rigid;
* :func:`solution_checks.closure_error`, :func:`reference.compare` and the FD check
  (:func:`solution_checks.fd_errors`) flag small, deliberate corruptions of a correct solution.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
import reference as R
import solution_checks as CK
from mechsketch.core.solver.plan import compile_plan

LINKAGES = {
    "fourbar": lambda: LB.fourbar(mode=-1, theta0=135.0),
    "slider pin offset": lambda: LB.slider_crank(xi=150.0, pin=-4 + 6j, theta0=200.0),
    "inverted offset": lambda: LB.inverted_slider_crank(offset=8.0, q_along=12.0),
    "prp": lambda: LB.prp_linkage(guide_offset=7.0),
    "yoke inclined": lambda: LB.scotch_yoke(slot=120.0, guide=200.0),
    "moving guide": lambda: LB.sixbar_guide(-1),
    "guide on driver": lambda: LB.crank_guided(pin=(5.0, -6.0)),
}


@pytest.mark.parametrize("name", list(LINKAGES))
def test_reference_rates_are_derivatives_of_its_positions(name):
    """q'(t), q''(t) from the differentiated equations == central differences (h = 1e-20,
    80 digits) of the Newton position solve along θ(t) = θ_k + ω t + α t²/2."""
    lk = LINKAGES[name]()
    sol = compile_plan(lk).sweep(samples=12)
    ref = R.MpReference(lk)
    w, al = 2.5, -4.0
    k = next(k for k in (5, 1, 11) if sol.valid[k])   # a PRP reaches only the side of its drawn crossing
    guess = ref.guess_from(sol, k)
    st = ref.solve(float(sol.input[k]), w, guess, al=al)
    with mpmath.workdps(80):
        h = mpmath.mpf("1e-20")
        rho0 = mpmath.mpf(float(sol.input[k])) - ref.theta0

        def q_at(t):
            q, _, _ = ref.solve_positions(rho0 + w * t + al * t * t / 2, guess)
            return q

        qm, q0, qp = q_at(-h), q_at(0), q_at(h)
        for link in ref.unknown:
            i = ref.col[link]
            for c in range(3):
                d1 = (qp[i + c] - qm[i + c]) / (2 * h)
                d2 = (qp[i + c] - 2 * q0[i + c] + qm[i + c]) / (h * h)
                r1 = (st.rate[link][c])
                r2 = (st.acc[link][c])
                assert abs(d1 - r1) <= mpmath.mpf("1e-30") * (1 + abs(r1)), (link, c)
                assert abs(d2 - r2) <= mpmath.mpf("1e-25") * (1 + abs(r2)), (link, c)


@pytest.mark.parametrize("name", list(LINKAGES))
def test_reference_positions_close_to_50_digits(name):
    lk = LINKAGES[name]()
    sol = compile_plan(lk).sweep(samples=12)
    ref = R.MpReference(lk)
    k = next(k for k in (7, 1, 11) if sol.valid[k])   # a PRP reaches only the side of its drawn crossing
    st = ref.solve(float(sol.input[k]), 1.0, ref.guess_from(sol, k))
    with mpmath.workdps(50):
        q = []
        for link in ref.unknown:
            q += list(st.pose[link])
        res = ref.residual(q, mpmath.mpf(float(sol.input[k])) - ref.theta0)
        assert max(abs(v) for v in res) < mpmath.mpf("1e-44") * LB.size_of(lk)
        for link in lk.links:   # every link rigid at 50 digits
            pts = [st.point(link.id, lk.joint(j).at)[0] for j in link.joints]
            for a, ja in zip(pts, link.joints):
                for b, jb in zip(pts, link.joints):
                    d0 = math.dist(lk.joint(ja).at, lk.joint(jb).at)
                    d = mpmath.hypot(a[0] - b[0], a[1] - b[1])
                    assert abs(d - mpmath.hypot(*(mpmath.mpf(x) - mpmath.mpf(y) for x, y in
                                                  zip(lk.joint(ja).at, lk.joint(jb).at)))) < 1e-44 * (1 + d0)


class _Corrupt:
    """A Solution whose ``what`` for ``link`` is perturbed (the rest delegates)."""

    def __init__(self, sol, what, link, f):
        self._sol, self._what, self._link, self._f = sol, what, link, f

    def __getattr__(self, name):
        attr = getattr(self._sol, name)
        if name != self._what:
            return attr

        def wrapped(link, *a):
            out = attr(link, *a)
            return self._f(out) if link == self._link else out
        return wrapped

    def __len__(self):
        return len(self._sol)


def test_closure_check_catches_a_stretched_link():
    lk = LB.fourbar()
    sol = compile_plan(lk).sweep(samples=90)
    assert CK.closure_error(lk, sol) < 1e-12
    size = LB.size_of(lk)

    def stretch(p):   # points of the coupler 1 µm further from the origin
        return p * (1 + 1e-6 / 200)
    bad = _Corrupt(sol, "point", "coupler", stretch)
    assert CK.closure_error(lk, bad) > 1e-8
    # a consistent error in every link's frame that is not a rigid motion is also caught
    bad = _Corrupt(sol, "point", "rocker", lambda p: p[:, ::-1])   # mirrored
    assert CK.closure_error(lk, bad) > 1e-3 * size


def test_closure_check_catches_a_P_joint_leaving_its_axis():
    lk = LB.slider_crank(xi=90.0)
    sol = compile_plan(lk).sweep(samples=90)
    assert CK.closure_error(lk, sol) < 1e-12
    bad = _Corrupt(sol, "point", "slider", lambda p: p + np.array([1e-7, 0.0]))
    assert CK.closure_error(lk, bad) > 5e-8


def test_compare_catches_small_rate_errors():
    lk = LB.slider_crank(pin=2 + 3j)
    sol = compile_plan(lk).sweep(samples=36)
    pick = [3, 11, 20]
    good = R.relative(R.compare(lk, sol, pick))
    assert max(good[k] for k in ("pos", "vel", "acc", "omega", "alpha")) < 1e-14
    for what, key in (("point_velocity", "vel"), ("point_acceleration", "acc"), ("point", "pos")):
        bad = _Corrupt(sol, what, "rod", lambda v: v * (1 + 1e-10))
        assert R.relative(R.compare(lk, bad, pick))[key] > 1e-11, what
    bad = _Corrupt(sol, "omega", "rod", lambda v: v * (1 + 1e-10))
    assert R.relative(R.compare(lk, bad, pick))["omega"] > 1e-11


def test_fd_check_catches_a_wrong_velocity():
    lk = LB.fourbar()
    plan = compile_plan(lk)
    inputs = plan.sweep(24).input
    assert CK.fd_errors(plan, inputs)[:2] == (0, 0)

    class Bent:   # the plan, with velocities of the rocker 1e-6 too large
        def __init__(self, p):
            self.p, self.linkage, self.omega = p, p.linkage, p.omega

        def evaluate(self, x, order=2):
            return _Corrupt(self.p.evaluate(x, order=order), "point_velocity", "rocker",
                            lambda v: v * (1 + 1e-6))
    bad_v, bad_a, checked, sharp, _ = CK.fd_errors(Bent(plan), inputs)
    assert checked == sharp == 24 and bad_v == 24


def test_continuation_reproduces_drawn_pose_and_stops_at_limits():
    lk = LB.fourbar(crank=90, coupler=95, rocker=85, ground=110, theta0=90.0, mode=-1)
    sol = compile_plan(lk).sweep(samples=72)
    poses, ref = R.continuation(lk, sol.input)
    c = R.continuation_point(ref, poses, "coupler", lk.joint("C").at)
    assert c[0] == complex(*lk.joint("C").at)
    done = np.isfinite(c)
    # a double rocker: the continuation cannot cross the assembly limit at 128.04°
    assert done[:7].all() and not done[8:].any()
