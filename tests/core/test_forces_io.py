"""Masses and loads in scene files, the workspace's forces request, ``analyze --forces`` and the
Geneva drive's crank torque.

Scene fields are additive in schema_version 1: old files load unchanged, new ones round-trip,
bad values are refused naming the JSON path and what to change. The workspace computes forces
only when asked and caches them by element value. The CLI writes exactly the issue's columns
(read back), and its summary. The Geneva crank torque equals the power balance M·ω2/ω1 without
journal friction.
"""
from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest

from mechsketch.core import SceneFormatError, Workspace, load_scene, loads_scene
from mechsketch.core.analyses.geneva.torque import crank_torque
from mechsketch.core.cli import main
from mechsketch.core.io.scene_file import dumps_scene
from mechsketch.core.model.edits import ReplaceElement
from mechsketch.core.model.loads import LinkMass, Torque
from mechsketch.resources import example_path, example_paths
from forces_reference import FloatKin, equilibrium

LOADED = example_path("fourbar_loaded")


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


def doc_with(**fields):
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    el = doc["elements"][0]
    for key, value in fields.items():
        if key == "links":
            for name, extra in value.items():
                next(lk for lk in el["links"] if lk["id"] == name).update(extra)
        elif key == "joints":
            for name, extra in value.items():
                next(j for j in el["joints"] if j["id"] == name).update(extra)
        else:
            el[key] = value
    return doc


# -- scene files -----------------------------------------------------------------------------------
def test_old_files_load_unchanged_and_new_fields_round_trip():
    old = load_scene(example_path("fourbar_crank_rocker")).elements[0]
    assert old.masses == () and old.loads == () and old.gravity is None and old.friction == ()
    assert "loads" not in old.to_dict() and "gravity" not in old.to_dict()
    scene = load_scene(LOADED)
    lk = scene.elements[0]
    assert lk.mass_of("coupler").com == (75.0, 80.0) and lk.mass_of("rocker").inertia is None
    assert [ld.id for ld in lk.loads] == ["cut", "brake", "return", "damper"]
    assert lk.friction_of("A") == 1.5 and lk.friction_of("B") == 0.0
    again = loads_scene(dumps_scene(scene))
    assert again == scene


def test_loads_without_ids_get_stable_ones():
    doc = doc_with(loads=[{"link": "rocker", "torque": 1.0}, {"link": "coupler", "at": [0, 0], "force": [1, 2]},
                          {"id": "T1", "link": "crank", "torque": 2.0}])
    lk = loads_scene(json.dumps(doc)).elements[0]
    assert lk.load_ids == ("T2", "F1", "T1")


@pytest.mark.parametrize("fields,where,words", [
    (dict(links={"coupler": {"inertia": 0.1}}), "$.elements[0].links[2]", "no 'mass'"),
    (dict(joints={"D": {"friction_radius": 1.0}}, loads=[{"link": "ghost", "torque": 1}]),
     "$.elements[0].loads[0].link", "unknown link 'ghost'"),
    (dict(loads=[{"link": "ground", "torque": 1}]), "$.elements[0].loads[0].link", "ground link"),
    (dict(loads=[{"link": "rocker", "torque": 1, "force": [1, 1]}]), "$.elements[0].loads[0]", "one of"),
    (dict(loads=[{"link": "rocker", "force": [1, 1]}]), "$.elements[0].loads[0]", "needs 'at'"),
    (dict(loads=[{"ends": [{"link": "rocker", "at": [0, 0]}, {"link": "rocker", "at": [1, 1]}],
                  "stiffness": 1}]), "$.elements[0].loads[0].ends", "two different links"),
    (dict(loads=[{"id": "x", "link": "rocker", "torque": 1}, {"id": "x", "link": "crank", "torque": 1}]),
     "$.elements[0].loads[0].id", "duplicate load id"),
    (dict(loads=[{"link": "rocker", "torque": 1, "ends": [{"link": "ground", "at": [0, 0]},
                                                           {"link": "rocker", "at": [1, 1]}]}]),
     "$.elements[0].loads[0]", "no field(s) ends"),
])
def test_bad_loads_are_refused_naming_the_json_path(fields, where, words):
    with pytest.raises(SceneFormatError) as exc:
        loads_scene(json.dumps(doc_with(**fields)))
    found = [p for p in exc.value.problems if p.path == where]
    assert found and words in found[0].message, exc.value.problems


@pytest.mark.parametrize("fields,where", [
    (dict(links={"rocker": {"mass": -1.0}}), "links"),
    (dict(gravity=[0.0]), "gravity"),
    (dict(loads=[{"ends": [{"link": "ground", "at": [0, 0]}, {"link": "rocker", "at": [1, 1]}],
                  "stiffness": -2.0}]), "stiffness"),
])
def test_schema_refuses_negative_or_malformed_values(fields, where):
    with pytest.raises(SceneFormatError) as exc:
        loads_scene(json.dumps(doc_with(**fields)))
    assert any(where in p.path for p in exc.value.problems), exc.value.problems


def test_friction_on_a_prismatic_joint_is_refused():
    doc = json.loads(example_path("slider_crank_offset").read_text())
    next(j for j in doc["elements"][0]["joints"] if j["kind"] == "P")["friction_radius"] = 1.0
    with pytest.raises(SceneFormatError, match="prismatic joints are frictionless"):
        loads_scene(json.dumps(doc))


def test_removing_a_link_drops_its_mass_and_loads():
    lk = load_scene(LOADED).elements[0]
    smaller = lk.without_link("rocker")
    assert smaller.mass_of("rocker") is None
    assert all("rocker" not in ld.links for ld in smaller.loads)
    assert [ld.id for ld in smaller.loads] == ["cut", "damper"]
    assert smaller.without_joint("A").friction_of("A") == 0.0


# -- the workspace ---------------------------------------------------------------------------------
def test_workspace_computes_forces_only_when_asked_and_caches_them_by_value():
    ws = Workspace.open(LOADED)
    eid = "loaded_fourbar"
    ws.result(eid)
    assert ws.stats["forces"] == 0
    res = ws[eid].forces()
    assert ws.stats["forces"] == 1 and ws.forces(eid) is res
    lk = ws.element(eid)
    inverse = ws.apply(ReplaceElement(lk.with_load(Torque("brake", "rocker", -3.0)), "brake"))
    other = ws.forces(eid)
    assert other is not res and ws.stats["forces"] == 2
    assert not np.allclose(other.driver.values, res.driver.values)
    ws.apply(inverse)                 # undo: the old value's forces are still cached
    assert ws.forces(eid) is res and ws.stats["forces"] == 2
    assert len(ws.forces(eid, samples=90)) == 90


def test_forces_of_a_geneva_element_are_refused_with_a_message():
    ws = Workspace.open(example_path("geneva_z6"))
    with pytest.raises(Exception, match="forces apply to linkages"):
        ws.forces(ws.scene.elements[0].id)


EXAMPLES = [p for p in example_paths() for e in load_scene(p).elements if e.type == "linkage" and e.has_dynamics]


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_every_example_with_loads_balances_power_and_matches_the_linear_solve(path):
    ws = Workspace.open(path)
    for el in ws.scene.elements:
        if el.type != "linkage" or not el.has_dynamics:
            continue
        res = ws.forces(el.id)
        sol = ws.solve(el.id)
        assert res.power.worst < 1e-13 and res.valid.all()
        for k in (0, len(sol) // 3, 2 * len(sol) // 3):
            e = equilibrium(el, FloatKin(sol, k))
            assert math.isclose(res.driver.values[k], e["T"], rel_tol=1e-12, abs_tol=1e-12)
        if res.friction is not None:
            assert res.friction.converged.all() and res.friction.power.worst < 1e-13


# -- the CLI ---------------------------------------------------------------------------------------
def test_analyze_forces_writes_exactly_the_issue_columns(capsys, tmp_path):
    target = tmp_path / "forces.csv"
    code, out, err = run(["analyze", LOADED, "--forces", "--csv", target], capsys)
    assert code == 0 and err == ""
    rows = list(csv.reader(io.StringIO(target.read_text())))
    head = rows[0]
    plain = list(csv.reader(io.StringIO(_csv(["analyze", LOADED, "--csv", "-"], capsys))))[0]
    added = head[len(plain):]
    assert head[:len(plain)] == plain
    forces = ["driver.torque", "A.Fx", "A.Fy", "B.Fx", "B.Fy", "C.Fx", "C.Fy", "D.Fx", "D.Fy",
              "shaking.Fx", "shaking.Fy", "shaking.M", "driver.torque_friction"]
    # the forces, the row's flag (issue 20: forces only where the rates are valid) and each
    # column's error estimate
    assert added == forces + ["forces_valid"] + [f"{c}.err" for c in forces]
    assert len(rows) == 361
    ws = Workspace.open(LOADED)
    res = ws.forces("loaded_fourbar")
    col = head.index("driver.torque")
    values = np.array([float(r[col]) for r in rows[1:]])
    assert np.array_equal(values, res.driver.values)          # repr round-trips exactly
    bx = np.array([float(r[head.index("B.Fx")]) for r in rows[1:]])
    assert np.array_equal(bx, res.pins["B"]["coupler"][:, 0])


def _csv(argv, capsys) -> str:
    code, out, _ = run(argv, capsys)
    assert code == 0
    return out


def test_a_scene_without_friction_has_no_friction_column(capsys):
    out = _csv(["analyze", example_path("slider_crank_offset"), "--forces", "--csv", "-"], capsys)
    head = out.splitlines()[0].split(",")
    forces = head[head.index("driver.torque"):head.index("forces_valid")]
    assert forces[-4:] == ["C.Fy", "shaking.Fx", "shaking.Fy", "shaking.M"]
    assert not any(c.startswith("S.") and c.endswith("Fx") for c in head)   # S is prismatic: no pin columns


def test_analyze_forces_summary(capsys):
    code, out, _ = run(["analyze", LOADED, "--forces", "--summary"], capsys)
    assert code == 0
    assert "driving torque (crank): peak" in out and "RMS" in out
    assert "joint B (on coupler): peak |F|" in out
    assert "power balance" in out and "worst relative residual" in out
    assert "with joint friction (friction circles A 1.5 mm, D 1.5 mm)" in out
    code, out, _ = run(["analyze", example_path("fourbar_crank_rocker"), "--forces", "--summary"], capsys)
    assert "no masses or loads: every force is zero" in out


def test_geneva_crank_torque_is_the_power_balance_without_journal_friction(capsys):
    from dataclasses import replace

    from mechsketch.core.analyses.geneva.contact import contact
    from mechsketch.core.analyses.geneva.kinematics import kinematics

    el = load_scene(example_path("geneva_z6")).elements[0]
    free = replace(el, load=replace(el.load, journal_friction=0.0, external_moment=0.7))
    kin, con = kinematics(free, 720), contact(free, 720, free.model)
    tq = crank_torque(free, con)
    wheel_power = np.where(con.engaged, con.moment, 0.0) * -kin.omega   # indexing sense is −world
    assert np.allclose(tq.torque * free.omega1, wheel_power, rtol=1e-12, atol=1e-12 * np.abs(wheel_power).max())
    assert np.allclose(tq.torque, tq.frictionless, rtol=1e-12, atol=1e-12)
    assert np.all(tq.torque[~con.engaged] == 0.0)
    # with journal friction the motor works harder while driving and less while braking
    con_f = contact(el, 720, el.model)
    no_f = replace(el, load=replace(el.load, journal_friction=0.0))
    with_f, without = crank_torque(el, con_f), crank_torque(no_f, contact(no_f, 720, el.model))
    drive, brake = con_f.engaged & (con_f.moment > 0), con_f.engaged & (con_f.moment < 0)
    assert drive.any() and brake.any()
    assert np.all(np.abs(with_f.torque[drive]) > np.abs(without.torque[drive]))
    assert np.all(np.abs(with_f.torque[brake]) < np.abs(without.torque[brake]))
    code, out, _ = run(["analyze", example_path("geneva_z6"), "--forces", "--csv", "-"], capsys)
    head = out.splitlines()[0].split(",")
    assert code == 0 and head[-1] == "driver.torque"


def test_samples_that_cannot_be_assembled_have_no_forces(capsys, tmp_path):
    """The double rocker reaches only part of a turn: there the forces are NaN (empty CSV fields),
    the summary counts those samples, and the rest still balance power."""
    from dataclasses import replace as dc_replace

    lk = load_scene(example_path("double_rocker")).elements[0]
    lk = dc_replace(lk, masses=tuple(LinkMass(k, 0.5) for k in lk.moving_links), gravity=(0.0, -9.81))
    ws = Workspace(load_scene(example_path("double_rocker")))
    ws.apply(ReplaceElement(lk, "masses"))
    res = ws.forces(lk.id)
    sol = ws.solve(lk.id)
    assert not sol.valid.all() and np.array_equal(res.valid, sol.rates_valid)
    assert np.isnan(res.driver.values[~res.valid]).all() and np.isfinite(res.driver.values[res.valid]).all()
    assert res.power.worst < 1e-12
    from mechsketch.core.analyses.forces.report import force_summary, force_table

    assert f"{int((~res.valid).sum())} samples without forces (forces_valid 0)" in force_summary(res)
    text = force_table(res).to_csv().splitlines()
    bad = int(np.flatnonzero(~res.valid)[0])
    row = text[bad + 1].split(",")
    assert row[text[0].split(",").index("forces_valid")] == "0"
    assert set(row) == {"", "0"}
