"""Assembly limits, pockets narrower than a sample step, singular poses and near-toggles found
between the samples (issue 20, item 1): the reachable ranges and dead points of every group kind
agree at 360, 3,600 and 36,000 samples and with closed-form references written here from the
geometry alone (law of cosines, the intersection of a line and a circle, an mpmath four-bar),
whether or not a sample falls near them. The repro: a six-bar whose PRP guides turn parallel
between samples (``prp_near_parallel_guides.json``) used to read "full revolution, dead points:
none" with a slider stroke of 9.2e6 mm."""
from __future__ import annotations

import math
from dataclasses import replace

import mpmath
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import drive_builders as DB
import linkage_builders as LB
from mechsketch.core import Workspace, load_scene
from mechsketch.core.cli import main
from mechsketch.core.solver.diagnostics import DeadPointKind, diagnose
from mechsketch.core.solver.plan import compile_plan

REPRO = "/work/shared/cases/s3/prp_near_parallel_guides.json"
NS = (360, 3600, 36000)


def _diag(lk, n):
    return diagnose(compile_plan(lk).sweep(samples=n, order=0))


def _limits(d):
    """The limits' inputs, crank angles in (−π, π] (actuators: mm), sorted."""
    return sorted(math.remainder(p.input, 2 * math.pi) if p.unit == "rad" else p.input
                  for p in d.dead_points if p.kind is DeadPointKind.LIMIT)


def _same_turn(a: float, b: float, tol: float) -> bool:
    return abs(math.remainder(a - b, 2 * math.pi)) <= tol


def _agree(diags, tol=1e-9):
    """Every diagnostics of ``diags`` has the same ranges and dead points (kind, group, input):
    limits and singular poses to ``tol`` (bisection and the V of a crossing locate them to an
    ulp); a near-toggle, the minimum of a smooth conditioning whose rounding noise is ~eps/cond,
    to 1e-7 rad (measured: 8.5e-9 between 360 and 3,600 samples at conditioning 6e-4)."""
    first = diags[0]
    for d in diags[1:]:
        assert d.full_turn == first.full_turn
        assert len(d.reachable) == len(first.reachable), (first.reachable, d.reachable)
        for (a, b), (c, e) in zip(first.reachable, d.reachable):
            assert a == pytest.approx(c, abs=tol) and b == pytest.approx(e, abs=tol)
        got = [(p.kind, p.group) for p in d.dead_points]
        assert got == [(p.kind, p.group) for p in first.dead_points], (first.dead_points, d.dead_points)
        for p, q in zip(first.dead_points, d.dead_points):
            t = tol if p.kind in (DeadPointKind.LIMIT, DeadPointKind.SINGULAR) else max(tol, 1e-7)
            assert _same_turn(p.input, q.input, t), (p, q)


# -- RRR: a pocket where the coupler and rocker cannot reach, and a near-miss toggle ------------
def _fourbar_reach(delta: float, theta0: float = 60.5):
    """Crank 40, ground 160 (|BD| at most 200 mm, at crank angle 180°); coupler 100 and rocker
    100 − delta: a pocket of half-width ~√(delta/16) rad about 180° for delta > 0, a near miss
    for delta < 0."""
    return LB.fourbar(crank=40.0, coupler=100.0, rocker=100.0 - delta, ground=160.0, theta0=theta0)


def _pocket_edges(delta: float) -> tuple[float, float]:
    """Crank angles (from A→D, in (−π, π]) bounding the pocket about 180°: |BD| = coupler +
    rocker, in 50 digits: (−a, a); the pocket is |angle| > a."""
    with mpmath.workdps(50):
        r, g, reach = mpmath.mpf(40), mpmath.mpf(160), mpmath.mpf(200) - mpmath.mpf(delta)
        a = mpmath.acos((r * r + g * g - reach * reach) / (2 * r * g))
        return float(-a), float(a)


def test_an_rrr_pocket_between_samples_is_found_at_every_sample_count():
    """No sample of the 360 falls in the pocket (half-width 0.2°, the nearest samples 0.5° away):
    the sampled sweep is all valid, yet the crank cannot pass 180°."""
    lk = _fourbar_reach(2e-4)
    lo, hi = _pocket_edges(2e-4)
    assert compile_plan(lk).sweep(samples=360, order=0).valid.all()     # the samples never see it
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert not d.full_turn
        assert _limits(d) == pytest.approx([lo, hi], abs=1e-9)
        assert all(p.group == "RRR(coupler,rocker)" for p in d.dead_points)
        (a, b), = d.reachable
        assert a == pytest.approx(lo, abs=1e-9) and b == pytest.approx(hi, abs=1e-9)   # through the drawn 60.5°
    _agree(diags)
    plan = compile_plan(lk)
    assert not plan.evaluate(np.array([math.pi]), order=0).valid[0]


def test_an_rrr_near_miss_between_samples_is_a_toggle_at_every_sample_count():
    """|BD| comes within 1e-5 mm of the reach at 180°: the group passes a toggle there with
    |sin μ| ≈ 6e-4 (below TOGGLE_COND), where the nearest of 360 samples reads 7e-3."""
    lk = _fourbar_reach(-1e-5)
    with mpmath.workdps(50):   # |sin μ| at 180° by Heron: 2·area / (coupler·rocker)
        a, b, c = mpmath.mpf(100), mpmath.mpf(100) + mpmath.mpf("1e-5"), mpmath.mpf(200)
        s = (a + b + c) / 2
        sin_mu = float(2 * mpmath.sqrt(s * (s - a) * (s - b) * (s - c)) / (a * b))
    sol = compile_plan(lk).sweep(samples=360, order=0)
    assert sol.valid.all() and np.min(sol.conditioning("RRR(coupler,rocker)")) > 3e-3
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert d.full_turn
        (p,), = [d.dead_points]
        assert p.kind is DeadPointKind.TOGGLE and _same_turn(p.input, math.pi, 1e-7)
        assert p.conditioning == pytest.approx(sin_mu, rel=1e-6)
    _agree(diags)


# -- RRP: a slider-crank whose rod falls just short where the crank stands up ---------------------
def test_an_rrp_pocket_between_samples_is_found():
    """Centric slider-crank, crank 40, rod 40 − 3.2e-4: the rod cannot reach the guide where
    |40·sin θ| > rod, two pockets of half-width 0.004 rad about ±90° (samples at x.5°)."""
    rod = 40.0 - 3.2e-4
    lk = LB.slider_crank(crank=40.0, rod=rod, offset=0.0, theta0=0.5)
    lim = math.asin(rod / 40.0)
    want = sorted(math.remainder(x, 2 * math.pi) for x in (lim, math.pi - lim, math.pi + lim, -lim))
    assert compile_plan(lk).sweep(samples=360, order=0).valid.all()
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert _limits(d) == pytest.approx(want, abs=1e-9)
        assert len(d.reachable) == 2 and not d.full_turn
    _agree(diags)


# -- RPR: an inverted slider-crank whose pin passes just inside the axis' offset -----------------
def test_an_rpr_pocket_between_samples_is_found():
    """Crank 40, pivots 100 apart, the slot 60.0002 mm off the rocker's pivot: where the pin comes
    within 60.0002 mm of it (the crank pointing at it) the slot cannot reach the pin."""
    c = 60.0002
    lk = LB.inverted_slider_crank(crank=40.0, ground=100.0, offset=c, theta0=180.5, mode=1)
    with mpmath.workdps(50):
        r, g = mpmath.mpf(40), mpmath.mpf(100)
        a = float(mpmath.acos((r * r + g * g - mpmath.mpf(c) ** 2) / (2 * r * g)))
    assert compile_plan(lk).sweep(samples=360, order=0).valid.all()
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert _limits(d) == pytest.approx([-a, a], abs=1e-9)
    _agree(diags)


# -- PRP: the repro, guides turning parallel between samples -------------------------------------
def _prp_crossings() -> list[float]:
    """Crank angles (rad) where the repro's guide F (24.8169° on link2, pivoted at B) turns
    parallel to G (30° on the frame): link2's rotation from the drawn pose is 5.1831°, from an
    mpmath four-bar A–C–D–B (crank 30, link1 C–D, link2 B–D) on its drawn side."""
    lk = load_scene(REPRO).elements[0]
    with mpmath.workdps(40):
        at = {j.id: mpmath.mpc(*j.at) for j in lk.joints}
        A, B, C0, D0 = at["A"], at["B"], at["C"], at["D"]
        crank, l1, l2 = abs(C0 - A), abs(D0 - C0), abs(D0 - B)
        side = 1 if ((B - C0).conjugate() * (D0 - C0)).imag > 0 else -1
        target = mpmath.radians(mpmath.mpf(30) - mpmath.mpf(lk.joint("F").axis_deg))

        def rot(th):
            C = A + crank * mpmath.expj(th)
            d = B - C
            dd = abs(d)
            a = (l1 * l1 - l2 * l2 + dd * dd) / (2 * dd)
            D = C + d / dd * (a + 1j * side * mpmath.sqrt(l1 * l1 - a * a))
            return mpmath.arg((D - B) / (D0 - B))

        return sorted(float(mpmath.findroot(lambda t: rot(t) - target, mpmath.radians(x)))
                      for x in (-33.09, 100.59))


def test_prp_guides_turning_parallel_between_samples_are_limits_at_every_sample_count():
    """The guides turn parallel at −33.09° and 100.59° (the drawn pose, 90°, between them): the
    pin runs off to infinity as the input approaches them and, beyond, the lines cross the other
    way, which the mechanism cannot reach: one range between the crossings, limited at both."""
    cross = _prp_crossings()
    lk = load_scene(REPRO).elements[0]
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert not d.full_turn
        lim = _limits(d)
        assert lim == pytest.approx(cross, abs=1e-5)    # |sin| = 1e-6 within a few µrad of parallel
        for y, x in zip(lim, cross):                     # on the drawn side of each crossing
            assert abs(y - math.radians(90.0)) < abs(x - math.radians(90.0))
        assert all("turn parallel" in str(p) for p in d.dead_points)
        (a, b), = d.reachable
        assert a == pytest.approx(lim[0], abs=1e-12) and b == pytest.approx(lim[1], abs=1e-12)
    _agree(diags)
    # no row is valid at the crossings or beyond them, and there is no stroke over the cycle
    plan = compile_plan(lk)
    assert not plan.evaluate(np.array(cross), order=2).valid.any()
    sol = plan.sweep(samples=3600, order=2)
    inside = (sol.input > cross[0] + 2 * math.pi) | (sol.input < cross[1])   # inputs from 90° round
    assert np.array_equal(sol.valid, inside)
    ws = Workspace.open(REPRO)
    text = ws["linkage1"].summary()
    assert "full revolution" not in text and "9.2" not in text
    assert "output 'block2' (slider): the cycle stops at assembly limits" in text


def test_validate_reports_guides_turning_parallel(capsys):
    code = main(["validate", REPRO])
    out = capsys.readouterr().out
    assert code == 0            # every analysis can do it: a warning, not an error
    assert "PRP(block1,block2)" in out and "parallel" in out
    assert "-33.09°" in out and "100.59°" in out
    assert "F" in out and "G" in out and "axis_deg" in out


# -- a cylinder and a slider whose limit lies between the samples at a stroke end -----------------
def test_cylinder_limit_near_its_stroke_end():
    """The cylinder pushing a slider reaches the pin's line (60 mm from its pivot) only if it is
    at least 60 mm long: a stroke from 59.97 mm has its limit between the first samples."""
    lk = DB.cylinder_slider(stroke=(59.97, 190.0))
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert not d.full_turn and d.unit == "mm"
        (a, b), = d.reachable
        assert a == pytest.approx(60.0, abs=1e-9) and b == pytest.approx(190.0, abs=1e-12)
        (p,), = [d.dead_points]
        assert p.kind is DeadPointKind.LIMIT and p.input == pytest.approx(60.0, abs=1e-9)
    _agree(diags)


def test_slider_driven_limit_near_its_stroke_end():
    """The slider turning a crank (crank 50, rod 120, pin 20 mm off the crank's pivot line) stops
    where |C − A| = 170 mm: s* = √(170² − 20²) − 150."""
    lk = DB.pushed_crank(stroke=(-20.0, 18.8307))
    s_star = math.sqrt(170.0 ** 2 - 20.0 ** 2) - 150.0
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        (a, b), = d.reachable
        assert a == pytest.approx(-20.0) and b == pytest.approx(s_star, abs=1e-9)
    _agree(diags)


# -- hypothesis: four-bars near their limits agree at 360 and 3,600 samples -------------------------
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(delta=st.floats(-3e-3, 3e-3).filter(lambda v: abs(v) > 1e-7),
       theta0=st.floats(20.0, 100.0), mode=st.sampled_from([1, -1]))
def test_four_bars_near_a_limit_agree_at_any_sample_count(delta, theta0, mode):
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=100.0 - delta, ground=160.0, theta0=theta0, mode=mode)
    d1, d2 = _diag(lk, 360), _diag(lk, 3600)
    _agree([d1, d2], tol=1e-8)
    if delta > 0:     # a pocket, seen or not by the samples; the kernel's touch tolerance (~5e-12
        # mm here) moves its edges by up to tol / slope = 5e-12 / (8·√delta) rad
        assert _limits(d1) == pytest.approx(list(_pocket_edges(delta)), abs=1e-9 + 2e-12 / math.sqrt(delta))


# -- RRR: a rhombus whose outer joints meet between the samples -----------------------------------
def test_a_rhombus_meeting_between_samples_is_a_singular_pose_at_every_sample_count():
    """A rhombus (all sides 60) drawn at crank angle 90.5°: B passes through D at 0°, which no
    sample of 360 meets (3,600 meet it exactly). The pose there is undetermined: one singular
    dead point at 0° whatever the samples, and no sample there is given as valid."""
    B = 60.0 * LB.e(90.5)
    lk = LB.build("rh", [("A", "R", (0.0, 0.0)), ("B", "R", LB.xy(B)), ("C", "R", LB.xy(B + 60.0)),
                         ("D", "R", (60.0, 0.0))],
                  {"ground": ["A", "D"], "crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
                  "ground", "crank", "A")
    diags = [_diag(lk, n) for n in NS]
    for d in diags:
        assert d.full_turn
        sing = [p for p in d.dead_points if p.kind is DeadPointKind.SINGULAR]
        assert len(sing) == 1 and _same_turn(sing[0].input, 0.0, 1e-9)
        assert not [p for p in d.dead_points if p.kind is not DeadPointKind.SINGULAR and _same_turn(p.input, 0.0, 1e-6)]
    _agree(diags)
    assert not compile_plan(lk).evaluate(np.array([0.0]), order=0).valid[0]
