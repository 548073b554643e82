"""Any input link, linear actuators and motion laws (issue 10 items 2-4), against the generic
50-digit reference of :mod:`reference_drive` (rigid-body constraint equations plus the driver's
own equation, solved by Newton in mpmath; rates by 80-digit differences in the input) and against
closed forms: a V-engine crank with two pins, a crank carrying a traced point, an excavator-style
arm lifted by a cylinder with a cycloidal stroke, a cylinder pushing a slider, a slider driven
along a fixed guide, a cylinder stroke through a change point."""
from __future__ import annotations

import cmath
import math
from dataclasses import replace

import numpy as np
import pytest

import drive_builders as DB
import linkage_builders as LB
import reference_drive as RD
import solution_checks as CK
from mechsketch.core import StructureError, Workspace
from mechsketch.core.model.linkage import Link
from mechsketch.core.model.scene import Scene
from mechsketch.core.solver.motion_law import at_times
from mechsketch.core.solver.plan import compile_plan

LAWS = ["constant", "cycloidal", "harmonic", "modified_trapezoid"]


def _z(a):
    return a[:, 0] + 1j * a[:, 1]


def check_reference(lk, sol, samples, pos=1e-13, rates=1e-11):
    err = RD.relative(RD.compare(lk, sol, samples), LB.size_of(lk))
    assert err["pos"] <= pos and err["vel"] <= rates and err["acc"] <= rates, err
    return err


def test_a_vengine_crank_with_two_pins_solves_like_two_slider_cranks():
    lk = DB.vengine()
    plan = compile_plan(lk)
    assert [s.group.kind for s in plan.steps] == ["RRP", "RRP"]
    sol = plan.sweep(360)
    assert sol.valid.all()
    assert CK.closure_error(lk, sol) <= 1e-12 * LB.size_of(lk)
    check_reference(lk, sol, [0, 131, 250], pos=1e-15, rates=1e-13)
    # closed form: piston i at r·cos(θ − φi) + √(l² − r² sin²(θ − φi)) along its bank's direction φi
    th = sol.input
    for pin, piston, bank, off in (("B1", "P1", 45.0, 0.0), ("B2", "P2", 135.0, math.pi / 2)):
        phi = math.radians(bank)
        d = th + off - phi
        s = 45.0 * np.cos(d) + np.sqrt(160.0 ** 2 - (45.0 * np.sin(d)) ** 2)
        assert np.max(np.abs(_z(sol.position(piston)) - s * cmath.exp(1j * phi))) < 1e-12
    # each piston is the slider-crank of its own pin: the same numbers bit for bit
    single = lk.without_link("rod2").without_link("piston2").without_joint("P2").without_joint("G2")
    single = single.with_link(Link("crank", ("A", "B1", "B2")))
    one = compile_plan(single).sweep(360)
    assert np.array_equal(one.position("P1"), sol.position("P1"))
    assert np.array_equal(one.acceleration("P1"), sol.acceleration("P1"))


@pytest.mark.parametrize("kind", LAWS)
def test_a_crank_carrying_a_traced_point(kind):
    lk = DB.crank_with_point(kind=kind)
    sol = compile_plan(lk).sweep(180)
    assert sol.valid.all()
    check_reference(lk, sol, [0, 31, 97, 150], pos=1e-15, rates=1e-13)
    # the point turns rigidly with the crank: T = |T0|·e^{i(input − θ0 + arg T0)}
    t0 = complex(*lk.joint("T").at)
    want = abs(t0) * np.exp(1j * (sol.input - compile_plan(lk).theta0 + cmath.phase(t0)))
    assert np.max(np.abs(_z(sol.position("T")) - want)) < 1e-13
    # the rest of the four-bar is the binary crank's, bit for bit
    binary = replace(LB.fourbar(), driver=lk.driver)
    ref = compile_plan(binary).sweep(180)
    for j in "BCD":
        assert np.array_equal(ref.position(j), sol.position(j))
        assert np.array_equal(ref.acceleration(j), sol.acceleration(j))


@pytest.mark.parametrize("axis_off", [0.0, 4.0], ids=["axis through pivots", "axis offset"])
def test_an_excavator_arm_lifted_by_a_cylinder_with_a_cycloidal_stroke(axis_off):
    lk = DB.excavator(axis_off=axis_off)
    plan = compile_plan(lk)
    assert plan.input_unit == "mm"
    assert [s.group.name for s in plan.steps] == ["RRR(boom,barrel)", "RRR(stick,tie)"]
    sol = plan.sweep(240)
    assert sol.valid.all()
    size = LB.size_of(lk)
    assert CK.closure_error(lk, sol) <= 1e-12 * size
    assert sol.residual() <= 1e-12 * size
    check_reference(lk, sol, [0, 60, 171])
    # the input is the cylinder's length, following the cycloidal law over its stroke
    T = lk.driver.period
    tau = np.arange(240) / 240
    x = np.where(tau < 0.5, 2 * tau, 2 * tau - 1)
    h = x - np.sin(2 * np.pi * x) / (2 * np.pi)
    want = np.where(tau < 0.5, 850 + 400 * h, 1250 - 400 * h)
    assert np.max(np.abs(sol.input - want)) < 1e-12
    assert np.allclose(sol.t, tau * T, rtol=0, atol=1e-12)
    L = np.abs(_z(sol.position("C2")) - _z(sol.position("C1")))
    assert np.max(np.abs(L - sol.input)) < 1e-11
    # the boom's angle from the triangle O, C1, C2 (closed form, law of cosines)
    c1, c2 = complex(800, -550), complex(1200, 350)
    a, b = abs(c1), abs(c2)
    gamma = np.arccos((a * a + b * b - sol.input ** 2) / (2 * a * b))   # angle C1-O-C2
    boom = cmath.phase(c1) + gamma - cmath.phase(c2)                     # the boom's rotation
    assert np.max(np.abs(sol.rotation("boom") - boom)) < 1e-13
    if axis_off == 0.0:   # the slide is the length's change; barrel and rod turn with C1→C2
        out = sol.group_output("RRR(boom,barrel)")
        s = out.slides[-1]
        assert np.max(np.abs(s.s - (sol.input - abs(c2 - c1)))) < 1e-11
        assert np.max(np.abs(s.sd - sol.omega_driver)) < 1e-9
        d = _z(sol.position("C2")) - _z(sol.position("C1"))
        assert np.max(np.abs(np.angle(d / (c2 - c1)) - sol.rotation("rod"))) < 1e-13


def test_a_cylinder_pushing_a_slider_is_the_rod_of_an_rrp_group():
    lk = DB.cylinder_slider()
    plan = compile_plan(lk)
    assert [s.group.kind for s in plan.steps] == ["RRP"]
    sol = plan.sweep(120)
    assert sol.valid.all()
    check_reference(lk, sol, [0, 20, 45, 99])
    # closed form: the pin on y = 60 at distance L from M
    x = np.sqrt(sol.input ** 2 - 60.0 ** 2)
    assert np.max(np.abs(sol.position("L")[:, 0] - x)) < 1e-12


def test_a_slider_driven_along_a_fixed_guide_turns_a_crank():
    lk = DB.pushed_crank()
    plan = compile_plan(lk)
    sol = plan.sweep(120)
    assert sol.valid.all()
    check_reference(lk, sol, [0, 11, 40, 77], rates=1e-12)
    assert np.max(np.abs(sol.position("C")[:, 0] - (150.0 + sol.input))) < 1e-12
    assert np.all(sol.rotation("slider") == 0.0)


def test_a_cylinder_stroke_through_a_change_point_keeps_to_the_smooth_branch():
    """Boom O–E and tie F–G form an exact parallelogram O, E, G, F: the stick keeps its drawn
    orientation. Where the boom lines up with O→F the parallelogram folds flat (a change point);
    the motion must stay a parallelogram after it, not turn into an antiparallelogram."""
    lk = DB.excavator(kind="constant", F=(300.0, 400.0), E=(2000.0, 1000.0), G=(2300.0, 1400.0),
                      stroke=(850.0, 1500.0))
    plan = compile_plan(lk)
    c1, c2 = complex(800, -550), complex(1200, 350)
    psi = math.atan2(400, 300) - math.atan2(1000, 2000)      # boom rotation at the change point
    crossing = abs(c2 * cmath.exp(1j * psi) - c1)
    assert 850 < crossing < 1500
    bp = plan.branch_points()["RRR(stick,tie)"]
    assert bp.size == 1 and bp[0] == pytest.approx(crossing, abs=1e-4)   # a touch: ~√eps·size
    sol = plan.sweep(400)
    rot = sol.rotation("stick")
    ok = sol.valid
    assert ok.mean() > 0.99
    assert np.max(np.abs(rot[ok])) < 1e-6
    assert np.max(np.abs(sol.input[ok] - crossing)) > 100   # the sweep went well past it


def test_the_sweep_follows_the_law_with_its_closed_form_rates():
    lk = DB.crank_with_point(kind="harmonic")
    plan = compile_plan(lk)
    sol = plan.sweep(90)
    m = at_times(lk.driver, plan.theta0, sol.t)
    assert np.array_equal(sol.input, m.q)
    assert np.array_equal(sol.omega_driver, m.qd) and np.array_equal(sol.alpha_driver, m.qdd)
    # the crank's angular velocity and acceleration are the law's
    assert np.max(np.abs(sol.omega("crank") - m.qd)) == 0.0
    assert np.max(np.abs(sol.alpha("crank") - m.qdd)) == 0.0


@pytest.mark.parametrize("make,eid,moves", [
    (DB.excavator, "arm", (("K", (3000.0, 100.0), True), ("C1", (810.0, -560.0), False))),
    (lambda: DB.crank_with_point(kind="cycloidal"), "fourbar", (("D", (165.0, 2.0), True), ("T", (8.0, 40.0), True))),
], ids=["cylinder", "crank with a law"])
def test_a_workspace_resweeps_an_actuated_linkage_bit_for_bit(make, eid, moves):
    """Moving the bucket tip re-runs only the stick's group; moving a cylinder pivot changes the
    drawn length: a full solve. A law-driven crank re-sweeps with the law's rates and accelerations.
    Each equals a full solve of the moved linkage bit for bit."""
    from mechsketch.core import ReplaceElement
    lk = make()
    ws = Workspace(Scene((lk,)))
    ws.result(eid)
    for joint, at, incremental in moves:
        before = ws.stats["incremental"]
        moved = ws.element(eid).with_joint_moved(joint, at)
        ws.apply(ReplaceElement(moved))
        res = ws.result(eid)
        assert (ws.stats["incremental"] > before) is incremental
        full = compile_plan(moved).sweep(moved.samples)
        for j in moved.joint_ids:
            assert np.array_equal(res.solution.position(j), full.position(j), equal_nan=True)
            assert np.array_equal(res.solution.acceleration(j), full.acceleration(j), equal_nan=True)


def test_a_cylinder_that_is_not_a_two_pivot_actuator_is_a_structure_error():
    lk = DB.excavator()
    bad = lk.with_link(Link("barrel", ("C1", "P", "O")))
    with pytest.raises(StructureError, match="barrel"):
        compile_plan(bad)
