"""Kinetostatics of linkages driven by a linear actuator: the driving force (``driver.force``, N,
positive extending), the reactions at a cylinder's pivots and slide, the power balance (actuator
power = force × extension rate).

Checked against the whole mechanism's equilibrium (one linear system per sample, the driver's
unknown a force along the actuator: :mod:`forces_reference`) on the float kinematics and on the
50-digit kinematics of :mod:`reference_drive` (:class:`forces_reference.DriveKin`), on the
excavator arm example (a cylinder with a cycloidal stroke, also with its slide axis off the line of
its pivots), a cylinder pushing a slider (the rod of an RRP group) and a slider driven along a
fixed guide turning a crank; plus hand-worked statics and the CLI.
"""
from __future__ import annotations

import csv
import io
import re
import json
import math
from dataclasses import replace

import mpmath
import numpy as np
import pytest

import drive_builders as DB
from forces_reference import DriveKin, FloatKin, equilibrium
from mechsketch.core import Workspace, load_scene
from mechsketch.core.analyses.forces.kinetostatics import linkage_forces
from mechsketch.core.analyses.forces.report import force_summary
from mechsketch.core.cli import main
from mechsketch.core.model.loads import LinkMass, PointForce
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path
from reference_drive import DPS, DriveReference
from test_forces import errors, loaded

EXCAVATOR = example_path("excavator_arm")


def example_arm():
    return next(el for el in load_scene(EXCAVATOR).elements if el.type == "linkage")


def heavy(lk, masses=(180.0, 60.0, 25.0, 95.0, 12.0)):
    """The excavator arm with masses on boom, barrel, rod, stick and tie (kg), gravity and a
    digging force at the bucket tip K."""
    links = ("boom", "barrel", "rod", "stick", "tie")
    ms = tuple(LinkMass(k, m, None, None) for k, m in zip(links, masses))
    tip = lk.joint("K").at
    return replace(lk, masses=ms, gravity=(0.0, -9.81), loads=(PointForce("dig", "stick", tip, (-2.0e3, 1.5e3)),))


class _Drive(DriveKin):
    def __init__(self, ref, sol, k):
        super().__init__(ref, sol, k)
        self.sample = k


def solve(lk, n=72):
    plan = compile_plan(lk)
    sol = plan.sweep(n)
    return sol, linkage_forces(plan, sol)


CASES = {"excavator_example": lambda: heavy(example_arm()),
         "excavator_example_loaded": lambda: loaded(example_arm(), 50.0),
         "excavator_axis_off": lambda: loaded(DB.excavator(axis_off=4.0), 50.0),
         "cylinder_slider": lambda: loaded(DB.cylinder_slider()),
         "slider_driven": lambda: loaded(DB.pushed_crank())}


@pytest.mark.parametrize("name", list(CASES))
def test_actuator_force_matches_the_mpmath_reference_and_the_linear_solve(name):
    lk = CASES[name]()
    sol, res = solve(lk)
    assert res.driver.kind == "force" and res.driver.column == "driver.force" and res.driver.unit == "N"
    assert res.valid.all() and np.ptp(res.driver.values) > 1.0
    worst_lin = max(errors(lk, sol, res, FloatKin(sol, k)) for k in range(0, 72, 7))
    ref = DriveReference(lk)
    with mpmath.workdps(DPS):
        worst_mp = max(errors(lk, sol, res, _Drive(ref, sol, k)) for k in (5, 40))
    assert worst_lin < 1e-12 and worst_mp < 1e-12, (worst_lin, worst_mp)
    assert res.power.worst < 1e-13


def test_cylinder_reactions_at_its_pivots_and_slide():
    """The barrel's pivot C1 (on the frame) and the rod's C2 (on the boom) carry reactions; the
    slide P its normal force and moment; the cylinder (barrel + rod) is in equilibrium with them."""
    lk = heavy(example_arm())
    sol, res = solve(lk)
    assert set(res.pins) >= {"C1", "C2", "O", "E", "F", "G"} and "P" in res.slides
    assert res.slides["P"].on == "rod" and res.slides["P"].by == "barrel"
    # the whole cylinder: pins at C1 and C2, its weight and inertia balance (the pins' forces
    # on the cylinder are +C1 (ground→barrel) and −C2 (rod→boom reversed))
    assert lk.links_of("C1") == ("ground", "barrel") and lk.links_of("C2") == ("boom", "rod")
    on_cyl = res.pins["C1"]["barrel"] + res.pins["C2"]["rod"]
    g = np.array([0.0, -9.81])
    inertia = np.zeros_like(on_cyl)
    for link, m in (("barrel", 60.0), ("rod", 25.0)):
        pts = [lk.joint(j).at for j in lk.link(link).joints]
        com = (sum(p[0] for p in pts) / 2, sum(p[1] for p in pts) / 2)
        inertia += m * (g - 1e-3 * sol.point_acceleration(link, com))
    assert np.allclose(on_cyl + inertia, 0.0, atol=1e-9 * np.abs(on_cyl).max())


def test_power_is_the_force_times_the_extension_rate():
    """On the pivots' line the extension rate is L̇ (the input's rate); with the axis 4° off it is
    the rod's speed out of the barrel, L·L̇/√(L² − c²) — and the balance closes either way."""
    for lk, off in ((heavy(example_arm()), False), (loaded(DB.excavator(axis_off=4.0), 50.0), True)):
        sol, res = solve(lk)
        motor = res.power.motor
        rate = np.broadcast_to(sol.omega_driver, (len(sol),)) * 1e-3   # m/s
        if not off:
            assert np.allclose(motor, res.driver.values * rate, rtol=1e-14, atol=1e-12)
        else:
            u = math.radians(lk.joint("P").axis_deg)
            d = complex(*lk.joint("C2").at) - complex(*lk.joint("C1").at)
            c = (complex(math.cos(u), math.sin(u)).conjugate() * d).imag
            L = sol.input
            assert np.allclose(motor, res.driver.values * rate * L / np.sqrt(L * L - c * c), rtol=1e-13)
        assert res.power.worst < 1e-13


def test_hand_worked_slider_pushing_against_a_force():
    """A slider driven along its guide against 50 N along the guide, nothing else loaded: the
    actuator pushes +50 N; the rod and the unloaded crank carry nothing, the guide neither."""
    lk = DB.pushed_crank()
    pin = lk.joint("C").at
    lk = replace(lk, loads=(PointForce("P", "slider", pin, (-50.0, 0.0)),))
    sol, res = solve(lk, 24)
    assert np.allclose(res.driver.values, 50.0, rtol=1e-13)
    assert np.allclose(res.pins["B"]["rod"], 0.0, atol=1e-11)
    assert np.allclose(res.slides["S"].normal, 0.0, atol=1e-11)
    # the frame takes the actuator's reaction: −50 N along the guide
    assert np.allclose(res.shaking_force, [[-50.0, 0.0]] * 24, atol=1e-11)
    assert np.allclose(res.power.motor, 50.0 * 1e-3 * np.broadcast_to(sol.omega_driver, (24,)), rtol=1e-13)


def test_hand_worked_cylinder_holding_a_slider():
    """A cylinder from the frame pivot M to the pin L of a horizontal slider, 100 N pushing the
    slider back towards −x: the cylinder pushes F/cos φ (φ its angle to the guide)."""
    lk = DB.cylinder_slider()
    lk = replace(lk, loads=(PointForce("F", "slider", lk.joint("L").at, (-100.0, 0.0)),))
    sol, res = solve(lk, 24)
    L = sol.position("L") - sol.position("M")
    cos_phi = L[:, 0] / np.hypot(L[:, 0], L[:, 1])
    assert np.allclose(res.driver.values, 100.0 / cos_phi, rtol=1e-13)
    assert res.power.worst < 1e-14


def test_actuator_summary_and_cli_columns(capsys, tmp_path):
    doc = json.loads(EXCAVATOR.read_text())
    el = doc["elements"][0]
    for link in el["links"]:
        if link["id"] != el["ground"]:
            link["mass"] = 40.0
    el["gravity"] = [0.0, -9.81]
    scene = tmp_path / "arm.json"
    scene.write_text(json.dumps(doc))
    target = tmp_path / "arm.csv"
    assert main(["analyze", str(scene), "--forces", "--csv", str(target)]) == 0
    head, *rows = list(csv.reader(io.StringIO(target.read_text())))
    assert "driver.force" in head and "driver.torque" not in head
    assert {"C1.Fx", "C1.Fy", "C2.Fx", "C2.Fy"} <= set(head)
    res = Workspace.open(scene).forces("arm")
    got = np.array([float(r[head.index("driver.force")]) for r in rows])
    assert np.array_equal(got, res.driver.values)
    capsys.readouterr()
    assert main(["analyze", str(scene), "--forces", "--summary"]) == 0
    out = capsys.readouterr().out
    assert "driving force (barrel): peak" in out and re.search(r" N \(± \S+\) at input ", out) and " mm, RMS " in out
    assert "not computed yet" not in out
    text = force_summary(res)
    assert "°" not in text.split("driving force")[1].split("\n")[0]


def test_joint_friction_on_a_cylinder_arm_balances_and_costs_force():
    """Friction circles at the cylinder's pivots and the boom pivot: the iteration converges, the
    power balance with the friction moments closes, and the peak driving force grows."""
    from mechsketch.core.model.loads import JointFriction
    lk = heavy(example_arm())
    lk = replace(lk, friction=(JointFriction("C1", 5.0), JointFriction("C2", 5.0), JointFriction("O", 8.0)))
    sol, res = solve(lk)
    fr = res.friction
    assert fr.driver.kind == "force" and fr.converged.all() and fr.power.worst < 1e-13
    assert np.abs(fr.driver.values).max() > np.abs(res.driver.values).max()
    # the friction result is the equilibrium with its friction moments as known couples
    k = 30
    couples = {}
    for j, rho in fr.radii.items():
        a, b = lk.links_of(j)
        f = fr.pins[j][b][k]
        rel = sol.omega(b)[k] - (0.0 if a == lk.ground else sol.omega(a)[k])
        c = -rho * 1e-3 * math.hypot(*f) * np.sign(rel)
        couples[b] = couples.get(b, 0.0) + c
        couples[a] = couples.get(a, 0.0) - c
    e = equilibrium(lk, FloatKin(sol, k), couples)
    assert math.isclose(fr.driver.values[k], e["T"], rel_tol=1e-9)
