"""Diagnostics of a sweep: reachable input ranges and assembly limits (to ~1e-9 rad against the
closed-form limit angles computed in 50 digits), near-toggle dead points, transmission angles."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core import load_scene
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


def same_angle(a: float, b: float, tol: float) -> bool:
    return abs(math.remainder(a - b, 2 * math.pi)) <= tol


def fourbar_limit(lk) -> float:
    """Crank angle (from A→D) where |BD| = coupler + rocker, in 50 digits from the drawn data."""
    with mpmath.workdps(50):
        at = {j.id: mpmath.mpc(*j.at) for j in lk.joints}
        r, g = abs(at["B"] - at["A"]), abs(at["D"] - at["A"])
        reach = abs(at["C"] - at["B"]) + abs(at["C"] - at["D"])
        base = mpmath.arg(at["D"] - at["A"])
        return float(base + mpmath.acos((r * r + g * g - reach * reach) / (2 * r * g)))


@pytest.mark.parametrize("rpm", [30.0, -30.0])
def test_double_rocker_reachable_range_and_limits(rpm):
    lk = load_scene(example_path("double_rocker")).elements[0]
    lk = lk.with_driver(lk.driver.__class__(lk.driver.link, lk.driver.pivot, rpm))
    sol = compile_plan(lk).sweep(samples=720)
    d = diagnose(sol)
    lim = fourbar_limit(lk)
    assert not d.full_turn
    assert len(d.reachable) == 1
    lo, hi = sorted(d.reachable[0])
    assert lo <= math.pi / 2 <= hi, "the range goes through the drawn pose"
    assert lo == pytest.approx(-lim, abs=1e-9) and hi == pytest.approx(lim, abs=1e-9)
    limits = [p for p in d.dead_points if p.kind == "limit"]
    assert len(limits) == 2 and all(p.group == "RRR(coupler,output)" for p in limits)
    assert sorted(p.input for p in limits) == pytest.approx([-lim, lim], abs=1e-9)
    assert d.valid_fraction == pytest.approx(sol.valid.mean())
    assert d.valid_fraction == pytest.approx(lim / math.pi, abs=1.5 / 720)
    text = str(d)
    a, b = (-lim, lim) if rpm > 0 else (lim, -lim)      # stated in the driver's direction
    assert d.reachable[0] == pytest.approx((a, b), abs=1e-9)
    assert f"reachable: input {math.degrees(a):.6f}° to {math.degrees(b):.6f}°" in text
    for x in (-lim, lim):
        assert f"dead point: {math.degrees(x):.6f}° RRR(coupler,output): assembly limit" in text
    # just inside the limit the linkage assembles, just outside it does not
    plan = sol.plan
    ok = plan.evaluate(np.array([lim - 1e-8, lim + 1e-8, -lim + 1e-8, -lim - 1e-8]), order=0).valid
    assert list(ok) == [True, False, True, False]


def test_slider_crank_limits():
    lk = LB.slider_crank(crank=40.0, rod=30.0, offset=20.0, theta0=10.0)
    sol = compile_plan(lk).sweep(samples=360)
    d = diagnose(sol)
    lim = math.asin(-0.25)             # B_y − e = −rod
    (lo, hi), = d.reachable
    assert same_angle(lo, lim, 1e-9) and same_angle(hi, math.pi - lim, 1e-9)
    assert hi - lo == pytest.approx(math.pi - 2 * lim, abs=1e-9)
    assert len([p for p in d.dead_points if p.kind == "limit"]) == 2


def test_never_assemblable_is_reported():
    """Samples taken only inside the double rocker's gap: nothing reachable, and said so."""
    lk = load_scene(example_path("double_rocker")).elements[0]
    sol = compile_plan(lk).evaluate(np.radians(np.linspace(140.0, 220.0, 41)), order=2)
    assert not sol.valid.any()
    d = diagnose(sol)
    assert d.reachable == [] and d.valid_fraction == 0.0 and not d.full_turn
    assert "reachable: none" in str(d)


def test_crank_rocker_summary_numbers():
    lk = load_scene(example_path("fourbar_crank_rocker")).elements[0]
    d = diagnose(compile_plan(lk).sweep(samples=360))
    assert d.full_turn and d.mobility == 1 and d.valid_fraction == 1.0
    assert d.dead_points == []
    (name, (lo, hi)), = d.transmission_deg.items()
    assert lo == pytest.approx(math.degrees(math.acos(19600 / 33600)), abs=1e-7)
    assert hi == pytest.approx(math.degrees(math.acos(-6000 / 33600)), abs=1e-7)
    assert d.groups == [("RRR(coupler,rocker)", "RRR", 1.0)]
    assert d.residual < 1e-12
    assert "dead points: none" in str(d) and "full revolution" in str(d)


def test_modes_in_the_summary():
    d = diagnose(compile_plan(LB.sixbar_guide(-1)).sweep(samples=90))
    assert [(k, m) for _, k, m in d.groups] == [("RRR", 1.0), ("RRP", -1.0)]
    d = diagnose(compile_plan(LB.inverted_slider_crank(mode=-1, offset=4.0)).sweep(samples=90))
    assert [(k, m) for _, k, m in d.groups] == [("RPR", -1.0)]


def test_prp_parallel_guides_are_assembly_limits():
    """The crank's guide turns parallel to the fixed one twice per turn (at 100° and 280°): the pin
    runs off to infinity there, and beyond them the lines cross the other way, which the mechanism
    cannot reach from its drawn pose (40°): one range from −80° to 100°, limited at both ends."""
    lk = LB.prp_linkage()
    sol = compile_plan(lk).sweep(samples=360)
    d = diagnose(sol)
    limits = sorted(p.input for p in d.dead_points if p.kind == "limit")
    assert len(limits) == 2 and not d.full_turn
    xi = math.radians(100.0)
    for x in limits:
        assert abs(math.remainder(x - xi, math.pi)) < 1e-5
    (a, b), = d.reachable
    assert a == pytest.approx(math.radians(-80.0), abs=1e-5) and b == pytest.approx(xi, abs=1e-5)
    assert all("turn parallel" in str(p) for p in d.dead_points)
