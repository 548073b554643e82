"""Kinetostatics: the closed-form group-by-group forces against independent references.

* the 50-digit mpmath reference (whole-mechanism equilibrium on the mpmath kinematics) and the
  float linear solve per sample (:mod:`forces_reference`), for a loaded four-bar, slider-crank and
  six-bar to ~1e-12 relative, and for every group kind, moving guides, compound hinges and a
  chain of three groups;
* the power balance at round-off, hand-worked unit cases (mm in the model, SI out), the identity
  of the shaking force with −Σ m·a_c, the friction result as a fixed point of the equilibrium,
  the report near a dead point; hypothesis over random masses and loads.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import linkage_builders as LB
from forces_reference import FloatKin, MpKin, equilibrium
from mechsketch.core import RequestError
from mechsketch.core.analyses.forces.kinetostatics import COND_WARN, linkage_forces
from mechsketch.core.model.loads import Damper, End, LinkMass, PointForce, Spring, Torque
from mechsketch.core.solver.plan import compile_plan
from reference import MpReference


def loaded(lk, scale: float = 1.0):
    """``lk`` with masses on every moving link (com default or given, inertia given or the
    estimate), gravity, a point force, a torque, a spring and a damper to the frame."""
    moving = lk.moving_links
    masses = tuple(LinkMass(k, 0.3 + 0.2 * i, None if i % 2 else (lk.joint(lk.link(k).joints[0]).at[0] + 3.0,
                                                                   lk.joint(lk.link(k).joints[0]).at[1] - 2.0),
                            None if i % 2 else 1e-3 * (i + 1)) for i, k in enumerate(moving))
    last, mid = moving[-1], moving[1]
    p = lk.joint(lk.link(mid).joints[0]).at
    q = lk.joint(lk.link(last).joints[0]).at
    loads = (PointForce("F1", mid, (p[0] + 5.0, p[1] + 7.0), (12.0 * scale, -30.0 * scale)),
             Torque("T1", last, 1.5 * scale),
             Spring("K1", (End(lk.ground, (0.0, 80.0)), End(last, q)), 0.8 * scale, 50.0),
             Damper("C1", (End(lk.ground, (30.0, -60.0)), End(mid, lk.joint(lk.link(mid).joints[-1]).at)),
                    0.02 * scale))
    return replace(lk, masses=masses, gravity=(0.0, -9.81), loads=loads)


def solve(lk, n=72):
    plan = compile_plan(lk)
    sol = plan.sweep(n)
    return sol, linkage_forces(plan, sol)


def errors(lk, sol, res, kin) -> float:
    """Largest difference from the reference equilibrium at one sample, relative to the largest
    reference force or torque (N, N·m): driver, every revolute pin, every slide, shaking."""
    k = kin.k if hasattr(kin, "k") else kin.sample
    e = equilibrium(lk, kin)
    scale = max([abs(float(e["T"]))] + [math.hypot(float(a), float(b)) for a, b in e["pins"].values()])
    d = abs(res.driver.values[k] - float(e["T"]))
    for (j, b), (fx, fy) in e["pins"].items():
        d = max(d, math.hypot(res.pins[j][b][k][0] - float(fx), res.pins[j][b][k][1] - float(fy)))
    for j, (N, C) in e["slides"].items():
        d = max(d, abs(res.slides[j].normal[k] - float(N)), abs(res.slides[j].moment[k] - float(C)))
    sx, sy, sm = (float(v) for v in e["shaking"])
    d = max(d, abs(res.shaking_force[k][0] - sx), abs(res.shaking_force[k][1] - sy), abs(res.shaking_moment[k] - sm))
    return d / scale


class _Mp(MpKin):
    def __init__(self, ref, sol, k):
        super().__init__(ref, sol, k)
        self.sample = k


DONE_WHEN = [LB.fourbar(), LB.slider_crank(), LB.sixbar_guide()]


@pytest.mark.parametrize("base", DONE_WHEN, ids=lambda lk: lk.id)
def test_loaded_mechanisms_match_the_mpmath_reference_and_the_linear_solve(base):
    """The issue's 'done when': driving torque, reactions (and shaking) of a loaded four-bar,
    slider-crank and six-bar against the 50-digit reference and the float linear solve."""
    lk = loaded(base)
    sol, res = solve(lk)
    ref = MpReference(lk)
    worst_mp = max(errors(lk, sol, res, _Mp(ref, sol, k)) for k in (0, 17, 40, 63))
    worst_lin = max(errors(lk, sol, res, FloatKin(sol, k)) for k in range(0, 72, 7))
    assert worst_mp < 1e-12 and worst_lin < 1e-12, (worst_mp, worst_lin)
    assert res.power.worst < 1e-13
    assert np.isfinite(res.driver.values).all() and np.ptp(res.driver.values) > 0.5   # not trivially 0


KINDS = [LB.inverted_slider_crank(), LB.prp_linkage(), LB.scotch_yoke(), LB.crank_guided(),
         LB.sixbar_stephenson(on_rocker=True), LB.sixbar_compound(), LB.two_dyads(), LB.rpr_on_moving_links(),
         LB.rrp_guide_on_coupler(), LB.eight_bar(), LB.translated(LB.fourbar(eid="far"), 1e4, -3e4)]


@pytest.mark.parametrize("base", KINDS, ids=lambda lk: lk.id)
def test_every_group_kind_matches_the_linear_solve(base):
    """RPR, PRP, RPP, RRP on a turning guide, moving guides, a compound hinge (three links on
    one joint), three groups in a chain, a mechanism far from the origin."""
    lk = loaded(base)
    sol, res = solve(lk)
    kinds = {g.kind.value for g in res.groups}
    assert kinds
    samples = [k for k in range(0, 72, 5) if sol.valid[k] and min(c[k] for c in res.conditioning.values()) > 0.05]
    assert len(samples) >= 5
    worst = max(errors(lk, sol, res, FloatKin(sol, k)) for k in samples)
    assert worst < 1e-12, worst
    assert res.power.worst < 1e-12


def test_compound_hinge_reports_one_pair_per_further_link():
    lk = loaded(LB.sixbar_compound())
    sol, res = solve(lk)
    carriers = lk.links_of("C")
    assert len(carriers) == 3 and list(res.pins["C"]) == list(carriers[1:])
    first = res.reaction("C", carriers[0])   # the first link takes the balance
    assert np.allclose(first, -(res.pins["C"][carriers[1]] + res.pins["C"][carriers[2]]))


# -- units and hand-worked cases ----------------------------------------------------------------
def test_units_a_metre_crank_holding_a_kilogram_against_gravity():
    """A slider-crank at a crawl with 1 kg on the crank pin 1000 mm from the pivot: the motor
    holds m·g·L·cos θ = 9.81 N·m at θ = 0 (mm in the model, N·m out)."""
    lk = LB.slider_crank(crank=1000.0, rod=3000.0, offset=0.0, rpm=1e-3)
    crank_pin = lk.joint("B").at
    lk = replace(lk, masses=(LinkMass("crank", 1.0, crank_pin, 0.0),), gravity=(0.0, -9.81))
    sol, res = solve(lk, 8)
    theta = sol.input
    assert np.allclose(res.driver.values, 9.81 * 1.0 * np.cos(theta), rtol=1e-9, atol=1e-9)
    assert res.driver.unit == "N·m" and res.driver.column == "driver.torque"
    # the pivot carries the weight: the frame pushes up on the crank with m·g
    assert np.allclose(res.pins["A"]["crank"][:, 1], 9.81, rtol=1e-6)


def test_units_virtual_work_of_a_force_on_the_slider():
    """A force P along the guide on the slider needs T = −P·ds/dθ (s in m): the velocity ratio
    from the kinematics (mm/s over rad/s, converted) and the statics agree."""
    lk = LB.slider_crank(crank=40.0, rod=160.0, offset=20.0)
    slider_pin = lk.joint("C").at
    lk = replace(lk, loads=(PointForce("P", "slider", slider_pin, (-500.0, 0.0)),))
    sol, res = solve(lk, 36)
    ratio = sol.velocity("C")[:, 0] * 1e-3 / sol.omega("crank")      # m/rad
    assert np.allclose(res.driver.values, 500.0 * ratio, rtol=1e-12, atol=1e-12)


def test_units_spring_and_damper():
    """A spring of 2 N/mm stretched by 10 mm pulls with 20 N; a damper of 0.01 N·s/mm at the
    rate the kinematics gives: checked through the pivot reaction of a crank-loaded four-bar."""
    lk = LB.fourbar()
    B = lk.joint("B").at
    anchor = (B[0] - 60.0, B[1])               # 60 mm left of the crank pin, drawn
    spring = Spring("K", (End("ground", anchor), End("crank", B)), 2.0, 50.0)
    damper = Damper("C", (End("ground", anchor), End("crank", B)), 0.01)
    sol, res = solve(replace(lk, loads=(spring, damper)), 36)
    d = sol.point("crank", B) - np.array(anchor)
    length = np.hypot(d[:, 0], d[:, 1])
    e = d / length[:, None]
    rate = (sol.point_velocity("crank", B) * e).sum(axis=1)
    tension = 2.0 * (length - 50.0) + 0.01 * rate
    assert math.isclose(tension[0] - 0.01 * rate[0], 20.0, rel_tol=1e-12)
    # moment about the crank pivot A of the spring/damper force (−tension·e at B), mm -> m
    arm = sol.point("crank", B)
    torque_of_load = 1e-3 * (arm[:, 0] * (-tension * e[:, 1]) - arm[:, 1] * (-tension * e[:, 0]))
    assert np.allclose(res.driver.values, -torque_of_load, rtol=1e-11, atol=1e-11)


def test_scaled_mechanism_scales_the_torque_as_the_square_of_its_size():
    """Lengths ×k with the same masses, inertias ×k² and the same speed: inertia forces grow as k,
    torques and moments as k² (a check of every mm -> m conversion at once)."""
    base = LB.fourbar()
    k = 7.0
    big = replace(base, joints=tuple(j.moved((j.at[0] * k, j.at[1] * k)) for j in base.joints))

    def massive(lk, s):
        return replace(lk, masses=(LinkMass("crank", 0.4, None, 2e-4 * s * s), LinkMass("coupler", 1.1, None, None),
                                   LinkMass("rocker", 0.7, None, 5e-4 * s * s)))

    _, small_res = solve(massive(base, 1.0), 36)
    _, big_res = solve(massive(big, k), 36)
    assert np.allclose(big_res.driver.values, k * k * small_res.driver.values, rtol=1e-11, atol=1e-12)
    assert np.allclose(big_res.pins["B"]["coupler"], k * small_res.pins["B"]["coupler"], rtol=1e-11, atol=1e-9)
    assert np.allclose(big_res.shaking_moment, k * k * small_res.shaking_moment, rtol=1e-11, atol=1e-12)


def test_shaking_force_and_moment_equal_the_inertia_of_the_moving_links():
    """No external loads: the frame feels −Σ m·a_c and the moment −Σ (I·α + (c − A) × m·a_c)."""
    lk = LB.sixbar_guide()
    masses = tuple(LinkMass(k, 0.2 + 0.1 * i, None, 1e-4 * (i + 1)) for i, k in enumerate(lk.moving_links))
    lk = replace(lk, masses=masses)
    sol, res = solve(lk, 48)
    pivot = np.array(lk.joint(lk.driver.pivot).at)
    f = np.zeros((48, 2))
    m = np.zeros(48)
    for ms in masses:
        pts = [lk.joint(j).at for j in lk.link(ms.link).joints]
        c0 = (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))
        a = sol.point_acceleration(ms.link, c0) * 1e-3
        c = (sol.point(ms.link, c0) - pivot) * 1e-3
        f -= ms.mass * a
        m -= ms.inertia * sol.alpha(ms.link) + ms.mass * (c[:, 0] * a[:, 1] - c[:, 1] * a[:, 0])
    assert np.allclose(res.shaking_force, f, rtol=1e-12, atol=1e-12 * np.abs(f).max())
    assert np.allclose(res.shaking_moment, m, rtol=1e-12, atol=1e-12 * np.abs(m).max())


def test_default_inertia_is_the_stated_slender_bar_estimate():
    lk = LB.fourbar()
    a = replace(lk, masses=(LinkMass("coupler", 1.3),))
    span = 140.0   # the coupler B–C, mm
    b = replace(lk, masses=(LinkMass("coupler", 1.3, None, 1.3 * (span * 1e-3) ** 2 / 12.0),))
    (_, ra), (_, rb) = solve(a, 24), solve(b, 24)
    assert np.allclose(ra.driver.values, rb.driver.values, rtol=1e-12, atol=1e-14)


def test_no_masses_and_no_loads_give_zero_forces():
    sol, res = solve(LB.fourbar(), 24)
    assert np.all(res.driver.values == 0) and all(np.all(f == 0) for on in res.pins.values() for f in on.values())
    assert res.power.worst == 0.0


def test_forces_need_accelerations_and_every_group():
    plan = compile_plan(LB.fourbar())
    with pytest.raises(RequestError, match="order 2"):
        linkage_forces(plan, plan.sweep(12, order=1))
    with pytest.raises(RequestError, match="every group"):
        linkage_forces(plan, plan.sweep(12, order=2, joints=["B"]))


# -- friction --------------------------------------------------------------------------------------
def test_friction_result_is_a_fixed_point_and_dissipates():
    """With friction circles at every joint: the result satisfies the equilibrium with the
    friction moments ρ·|R| its own reactions give; the motor does more work per cycle than
    without; the power balance (friction included) holds at round-off."""
    lk = loaded(LB.fourbar())
    for j in ("A", "B", "C", "D"):
        lk = lk.with_friction(j, 2.0)
    sol, res = solve(lk)
    fr = res.friction
    assert fr is not None and fr.converged.all() and fr.iterations < 30
    assert fr.power.worst < 1e-13
    for k in (0, 20, 50):
        couples: dict[str, float] = {}
        for f in lk.friction:
            a, b = lk.links_of(f.joint)
            rel = sol.omega(b)[k] - sol.omega(a)[k]
            c = -f.radius * 1e-3 * float(np.hypot(*fr.pins[f.joint][b][k])) * np.sign(rel)
            couples[b] = couples.get(b, 0.0) + c
            couples[a] = couples.get(a, 0.0) - c
        e = equilibrium(lk, FloatKin(sol, k), couples)
        assert math.isclose(fr.driver.values[k], e["T"], rel_tol=1e-11, abs_tol=1e-12)
        for (j, b), (fx, fy) in e["pins"].items():
            assert np.allclose(fr.pins[j][b][k], (fx, fy), rtol=1e-11, atol=1e-10)
    w = sol.omega("crank")
    assert np.mean(fr.driver.values * w) > np.mean(res.driver.values * w) + 1e-3


# -- dead points -----------------------------------------------------------------------------------
def test_near_a_dead_point_the_report_says_where_forces_blow_up():
    """A four-bar whose transmission angle nearly closes: the note names the group, the input
    where its conditioning is lowest, and a reaction there far above the cycle's typical one."""
    lk = LB.fourbar(crank=40.0, coupler=60.0, rocker=120.0, ground=140.0)
    lk = replace(lk, masses=tuple(LinkMass(k, 0.5) for k in lk.moving_links),
                 loads=(Torque("T", "rocker", -2.0),))
    sol, res = solve(lk, 720)
    cond = res.conditioning[res.groups[0].name]
    notes = res.dead_point_notes()
    assert cond.min() < COND_WARN and len(notes) == 1
    note = notes[0]
    # the least conditioning among the samples that have forces (where the rates are valid)
    assert note.group == res.groups[0].name and note.index == int(np.nanargmin(np.where(res.valid, cond, np.nan)))
    assert "1/conditioning" in str(note) and note.at in str(note) and note.at.endswith("°")
    typical = np.nanmedian(np.hypot(*res.pins["C"]["rocker"].T))
    assert note.force > 3.0 * typical


# -- random loads ----------------------------------------------------------------------------------
@settings(max_examples=12, deadline=None)
@given(masses=st.lists(st.floats(0.0, 5.0), min_size=3, max_size=3),
       force=st.tuples(st.floats(-200, 200), st.floats(-200, 200)),
       torque=st.floats(-10, 10), g=st.tuples(st.floats(-20, 20), st.floats(-20, 20)),
       k=st.integers(0, 71))
def test_random_loads_agree_with_the_linear_solve(masses, force, torque, g, k):
    lk = LB.sixbar_compound()
    moving = lk.moving_links
    lk = replace(lk, masses=tuple(LinkMass(name, m) for name, m in zip(moving[1:4], masses)), gravity=g,
                 loads=(PointForce("F", moving[2], (30.0, 40.0), force), Torque("T", moving[-1], torque)))
    sol, res = solve(lk)
    e = equilibrium(lk, FloatKin(sol, k))
    scale = max(1e-9, abs(e["T"]), *(math.hypot(a, b) for a, b in e["pins"].values()))
    assert abs(res.driver.values[k] - e["T"]) <= 1e-12 * scale
    for (j, b), f in e["pins"].items():
        assert np.hypot(*(res.pins[j][b][k] - np.array(f))) <= 1e-12 * scale
    assert res.power.worst < 1e-12
