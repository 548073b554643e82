"""The Geneva CLI (``analyze``, ``export``) and the example scenes: columns, units, empty contact
fields in the dwell, values equal to the API's, summary with every assumption, exit codes."""
from __future__ import annotations

import csv
import io
import json
import math

import ezdxf
import numpy as np
import pytest

from mechsketch.core import load_scene
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.geneva.geometry import geometry
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.cli import main
from mechsketch.core.cli.geneva_cmds import COLUMNS
from mechsketch.resources import example_path

EXAMPLES = ["geneva_z4", "geneva_z6", "geneva_z8"]


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


def table(text: str):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def test_columns_are_the_issues():
    assert " ".join(COLUMNS) == ("t input wheel.angle wheel.omega wheel.alpha wheel.jerk engaged contact_valid Rn Rn_paper moment "
                                 "strip_width hertz_half_width deformation rolling_ratio slip_speed slip_path "
                                 "wear_invariant contact_pressure")


@pytest.mark.parametrize("name", EXAMPLES)
def test_analyze_csv_rows_values_and_empty_dwell(capsys, name):
    path = example_path(name)
    code, out, err = run(["analyze", path, "--element", "indexer", "--samples", 360, "--csv", "-"], capsys)
    assert code == 0 and err == ""
    head, rows = table(out)
    assert head == list(COLUMNS) and len(rows) == 360
    el = load_scene(path).element("indexer")
    kin, con = kinematics(el, 360), contact(el, 360, el.model)
    col = {h: k for k, h in enumerate(head)}
    for i in (0, 100, 150, 180, 250, 359):
        r = rows[i]
        assert float(r[col["t"]]) == kin.t[i] and float(r[col["input"]]) == kin.phi[i]
        assert float(r[col["wheel.alpha"]]) == kin.alpha[i]
        assert r[col["engaged"]] == ("1" if kin.engaged[i] else "0")
        for name_ in ("Rn", "Rn_paper", "moment", "slip_path", "wear_invariant", "contact_pressure"):
            if kin.engaged[i]:
                assert float(r[col[name_]]) == getattr(con, name_)[i]
            else:
                assert r[col[name_]] == ""  # contact columns are empty outside the engagement
    dwell = [r for r in rows if r[col["engaged"]] == "0"]
    assert dwell and all(r[col["wheel.omega"]] == "0.0" for r in dwell)
    z = el.slots
    assert len(rows) - len(dwell) == pytest.approx(360 * (z - 2) / (2 * z), abs=1)


def test_summary_states_numbers_limits_and_assumptions(capsys):
    code, out, _ = run(["analyze", example_path("geneva_z6"), "--summary"], capsys)
    assert code == 0
    for words in ("z = 6", "i_max", "ε̃_max = 1.34964", "φ = -22.9° (speeding up)", "tan(π/z)·ω1² = 57.73",
                  "never interpolated", "maximum hub radius 41.4500", "slot depth 45.1525", "land angle 2.672°",
                  "relief of the locking disc", "87.602 mm drawn", "87.50181 to avoid contact",
                  "L_s = 0.779849", "Gauss–Legendre", "ends there", "would give 0.779849", "N·min/m", "p_max", "Archard",
                  "crank turns", "assumptions:", "note B3", "a_paper/2", "deformed radius", "upper bound",
                  "λ = r/A = sin(π/z)"):
        assert words in out, words


def test_summary_goes_to_stderr_when_the_csv_is_on_stdout(capsys):
    code, out, err = run(["analyze", example_path("geneva_z4"), "--samples", 8, "--csv", "-", "--summary"], capsys)
    assert code == 0 and out.startswith("t,input,") and "assumptions:" in err


def test_clockwise_drive_through_the_cli(tmp_path, capsys):
    doc = json.loads(example_path("geneva_z6").read_text())
    doc["elements"][0]["speed_rpm"] = -60.0
    p = tmp_path / "cw.json"
    p.write_text(json.dumps(doc))
    code, out, _ = run(["analyze", p, "--samples", 12, "--csv", "-"], capsys)
    assert code == 0
    head, rows = table(out)
    phi = [float(r[1]) for r in rows]
    assert phi[0] == pytest.approx(math.pi) and phi[1] < phi[0]
    omega = np.array([float(r[3]) for r in rows])
    assert omega.max() > 0 and omega.min() > -1e-12  # a CW crank turns the wheel CCW (0 at entry: radial)


def test_export_writes_a_dxf_and_reports(tmp_path, capsys):
    target = tmp_path / "wheel.dxf"
    code, out, err = run(["export", example_path("geneva_z8"), "--element", "indexer", "--dxf", target], capsys)
    assert code == 0 and err == ""
    assert "millimetres" in out and "exact lines and arcs" in out and "relief radius" in out
    doc = ezdxf.readfile(target)
    assert not doc.audit().has_errors and doc.header["$INSUNITS"] == 4


def test_export_to_an_unwritable_place_fails_cleanly(tmp_path, capsys):
    code, out, err = run(["export", example_path("geneva_z6"), "--dxf", tmp_path / "missing" / "w.dxf"], capsys)
    assert code == 1 and "cannot write" in err and "missing" in err


def test_a_drive_that_cannot_be_drawn_still_analyses_and_export_says_why(tmp_path, capsys):
    doc = json.loads(example_path("geneva_z6").read_text())
    doc["elements"][0]["drawing"] = {"crank_bore_radius": 11.5}
    p = tmp_path / "bore.json"
    p.write_text(json.dumps(doc))
    code, out, _ = run(["analyze", p, "--summary"], capsys)
    assert code == 0 and "drawing: geneva 'indexer': drawing.crank_bore_radius = 11.5 mm" in out
    code, out, _ = run(["validate", p], capsys)   # analysable: a manufacturability warning (issue 20, item 6)
    assert code == 0 and "manufacturability warnings" in out and "drawing.crank_bore_radius = 11.5 mm" in out
    code, out, _ = run(["validate", "--strict", p], capsys)
    assert code == 1 and "drawing.crank_bore_radius = 11.5 mm" in out
    code, out, err = run(["export", p, "--dxf", tmp_path / "w.dxf"], capsys)
    assert code == 1 and "crank_bore_radius" in err and not (tmp_path / "w.dxf").exists()


def test_invalid_scene_exits_1_naming_the_limit(tmp_path, capsys):
    doc = json.loads(example_path("geneva_z6").read_text())
    doc["elements"][0]["slots"] = 2
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(doc))
    code, out, err = run(["analyze", p], capsys)
    assert code == 1 and "$.elements[0].slots [indexer]" in err and "at least 3 slots" in err
    code, out, _ = run(["validate", p], capsys)
    assert code == 1 and "1 short" in out


@pytest.mark.parametrize("name,z,eps", [("geneva_z4", 4, 5.41), ("geneva_z6", 6, 1.35), ("geneva_z8", 8, 0.70)])
def test_example_scenes_are_the_notes_defaults(name, z, eps):
    el = load_scene(example_path(name)).element("indexer")
    assert el.slots == z and el.center_distance == 100.0 and el.roller_radius == 8.0 and el.roller_length == 10.0
    assert el.omega1 == pytest.approx(10.0, rel=1e-4)  # 95.49 rpm
    assert (el.load.wheel_inertia, el.load.journal_friction, el.load.journal_radius) == (0.05, 0.05, 15.0)
    k = kinematics(el, el.samples)
    assert round(k.accel_peak_ratio, 2) == eps
    geo = geometry(el)
    assert geo.relief.drawn > geo.relief.classical
