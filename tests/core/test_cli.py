"""The headless CLI contract: ``analyze`` rows and columns, ``validate`` exit codes, structural
problems reported with their joints and a non-zero exit, never a traceback."""
from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core import load_scene
from mechsketch.core.cli import main
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path

MECHSKETCH = Path(sys.executable).with_name("mechsketch")


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


def read_csv(text: str):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def write(tmp_path, *linkages, name="scene.json") -> Path:
    p = tmp_path / name
    p.write_text(json.dumps(LB.scene_dict(*linkages)), encoding="utf-8")
    return p


def expected_columns(lk):
    cols = ["t", "input"]
    for j in lk.joint_ids:
        cols += [f"{j}.{q}" for q in ("x", "y", "vx", "vy", "ax", "ay")]
    for k in lk.moving_links:
        cols += [f"{k}.angle", f"{k}.omega", f"{k}.alpha"]
    return cols + ["valid", "rates_valid"]


@pytest.mark.parametrize("name,n", [("fourbar_crank_rocker", 36), ("sixbar_moving_guide", 50),
                                    ("inverted_slider_crank", 7)])
def test_analyze_csv_columns_rows_and_values(capsys, name, n):
    path = example_path(name)
    code, out, err = run(["analyze", path, "--samples", n, "--csv", "-"], capsys)
    assert code == 0 and err == ""
    head, rows = read_csv(out)
    lk = load_scene(path).elements[0]
    assert head == expected_columns(lk)
    assert len(rows) == n
    data = np.array([[float(v) for v in r] for r in rows])
    col = {c: data[:, i] for i, c in enumerate(head)}
    sol = compile_plan(lk).sweep(samples=n, order=2)
    # row 0 is the drawn pose; rows advance by 2π/N in the driver's direction; t = k·T/N
    assert col["t"][0] == 0.0 and col["input"][0] == pytest.approx(math.atan2(
        *np.subtract(lk.joint(lk.link(lk.driver.link).joints[1]).at, lk.joint(lk.driver.pivot).at)[::-1]), abs=1e-15)
    assert np.allclose(np.diff(col["input"]), 2 * math.pi / n, atol=1e-13)
    assert np.allclose(col["t"], np.arange(n) * 60.0 / lk.driver.speed_rpm / n, rtol=1e-14)
    for j in lk.joints:
        assert (col[f"{j.id}.x"][0], col[f"{j.id}.y"][0]) == pytest.approx(j.at, abs=1e-12)
        # full precision: the CSV reproduces the API's numbers bit for bit
        for q, arr in (("x", sol.position(j.id)[:, 0]), ("vy", sol.velocity(j.id)[:, 1]),
                       ("ax", sol.acceleration(j.id)[:, 0])):
            assert np.array_equal(col[f"{j.id}.{q}"], arr), (j.id, q)
    for k in lk.moving_links:
        assert np.array_equal(col[f"{k}.angle"], sol.angle(k))
        assert np.array_equal(col[f"{k}.omega"], sol.omega(k))
        assert np.array_equal(col[f"{k}.alpha"], sol.alpha(k))
    assert set(col["valid"]) == {1.0}
    assert all(r[-1] == "1" for r in rows)


def test_analyze_rows_follow_a_clockwise_driver(tmp_path, capsys):
    lk = LB.fourbar(theta0=200.0, rpm=-120.0)
    code, out, _ = run(["analyze", write(tmp_path, lk), "--samples", 8, "--csv", "-"], capsys)
    assert code == 0
    head, rows = read_csv(out)
    inp = np.array([float(r[head.index("input")]) for r in rows])
    assert math.remainder(inp[0] - math.radians(200.0), 2 * math.pi) == pytest.approx(0, abs=1e-14)
    assert np.allclose(np.diff(inp), -math.pi / 4, atol=1e-13)
    t = np.array([float(r[0]) for r in rows])
    assert np.allclose(t, np.arange(8) * 0.5 / 8)            # T = 60/120 s, time runs forward
    omega = np.array([float(r[head.index("crank.omega")]) for r in rows])
    assert np.allclose(omega, -120 * 2 * math.pi / 60)


def test_analyze_empty_fields_where_not_assemblable(capsys):
    code, out, _ = run(["analyze", example_path("double_rocker"), "--samples", 72, "--csv", "-"], capsys)
    assert code == 0
    head, rows = read_csv(out)
    valid = [r[-1] for r in rows]
    assert set(valid) == {"0", "1"}
    lim = 128.036374
    for k, r in enumerate(rows):
        a = math.degrees(float(r[1]))
        inside = abs(math.remainder(a, 360.0)) < lim
        assert valid[k] == ("1" if inside else "0"), a
        c = head.index("C.x")
        assert (r[c] == "") == (not inside)
        assert r[head.index("A.x")] == ("0.0" if inside else "")  # a whole row is blank when invalid
        assert r[0] != "" and r[1] != ""


def test_analyze_summary_and_csv_file(tmp_path, capsys):
    target = tmp_path / "out.csv"
    code, out, err = run(["analyze", example_path("slider_crank_offset"), "--csv", target], capsys)
    assert code == 0 and out == "" and err == ""
    head, rows = read_csv(target.read_text())
    assert len(rows) == 360 and head[0] == "t"
    code, out, err = run(["analyze", example_path("slider_crank_offset"), "--csv", "-", "--summary"], capsys)
    assert code == 0
    assert "mobility: 1" in err and "group RRP(rod,slider): kind RRP, mode +1" in err
    assert out.startswith("t,input,")
    code, out, err = run(["analyze", example_path("slider_crank_offset")], capsys)
    assert code == 0 and "reachable: full revolution" in out and "dead points: none" in out
    assert "max loop-closure residual" in out


def test_analyze_csv_to_an_unwritable_path(tmp_path, capsys):
    code, out, err = run(["analyze", example_path("fourbar_crank_rocker"), "--csv",
                          tmp_path / "missing" / "x.csv"], capsys)
    assert code == 1 and "error:" in err and "missing" in err


def test_element_selection(tmp_path, capsys):
    a, b = LB.fourbar(eid="first"), LB.slider_crank(eid="second")
    p = write(tmp_path, a, b)
    code, out, err = run(["analyze", p, "--samples", 4, "--csv", "-"], capsys)
    assert code == 0 and "using element 'first'" in err
    assert read_csv(out)[0] == expected_columns(a)
    code, out, err = run(["analyze", p, "--element", "second", "--samples", 4, "--csv", "-"], capsys)
    assert code == 0 and read_csv(out)[0] == expected_columns(b)
    code, out, err = run(["analyze", p, "--element", "third"], capsys)
    assert code == 1 and "third" in err and "'first'" in err


@pytest.mark.parametrize("n", [1, 0, -5])
def test_bad_sample_counts(capsys, n):
    code, out, err = run(["analyze", example_path("fourbar_crank_rocker"), "--samples", n], capsys)
    assert code == 1 and "--samples" in err


def test_usage_error_exit_2(capsys):
    with pytest.raises(SystemExit) as info:
        main(["analyze"])
    assert info.value.code == 2


# -- validate ---------------------------------------------------------------------------------
def test_validate_ok_and_problems(tmp_path, capsys):
    code, out, _ = run(["validate", example_path("sixbar_moving_guide")], capsys)
    assert code == 0 and out.strip().endswith(": ok")
    doc = LB.scene_dict(LB.fourbar())
    doc["elements"][0]["links"][2]["joints"][1] = "Z"
    doc["elements"][0]["joints"][1]["at"] = [float("nan"), 0]
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(doc))
    code, out, _ = run(["validate", p], capsys)
    assert code == 1
    lines = out.strip().splitlines()
    assert "$.elements[0].joints[1].at[0] [B]: number must be finite, got nan" in lines


# -- structural problems ---------------------------------------------------------------------
@pytest.mark.parametrize("builder,words", [
    (LB.class3, ["class-II", "X1", "X2", "X3", "G2", "G3", "b1", "tri"]),
    (lambda: LB.build("fivebar", [("A", "R", (0, 0)), ("B", "R", (20, 30)), ("C", "R", (70, 60)),
                                 ("D", "R", (120, 40)), ("E", "R", (140, 0))],
                     {"ground": ["A", "E"], "crank": ["A", "B"], "l2": ["B", "C"], "l3": ["C", "D"],
                      "l4": ["D", "E"]}, "ground", "crank", "A"), ["mobility 2", "under-constrained"]),
    (lambda: LB.fourbar().with_link(LB.fourbar().link("coupler").__class__("diag", ("B", "D"))),
     ["mobility 0", "over-constrained"]),
])
def test_structural_problems_exit_non_zero_naming_the_joints(tmp_path, capsys, builder, words):
    p = write(tmp_path, builder())
    for argv in (["analyze", p], ["analyze", p, "--csv", "-"], ["analyze", p, "--summary"]):
        code, out, err = run(argv, capsys)
        assert code == 1, argv
        assert out == ""
        assert err.startswith("error:")
        for w in words:
            assert w in err, (w, err)


# -- the real entry point ---------------------------------------------------------------------
@pytest.mark.skipif(not MECHSKETCH.exists(), reason="console script not installed")
def test_entry_point_end_to_end(tmp_path):
    r = subprocess.run([str(MECHSKETCH), "analyze", str(example_path("slider_crank_offset")), "--samples", "12",
                        "--csv", "-"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and len(r.stdout.strip().splitlines()) == 13
    bad = write(tmp_path, LB.class3())
    r = subprocess.run([str(MECHSKETCH), "analyze", str(bad)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and "Traceback" not in r.stderr and "X1" in r.stderr
    # the table piped into a reader that stops early: no traceback, exit 0
    cmd = f"'{MECHSKETCH}' analyze '{example_path('fourbar_crank_rocker')}' --samples 200000 --csv - | head -n 2"
    r = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], capture_output=True, text=True, timeout=120)
    assert "Traceback" not in r.stderr and "Error" not in r.stderr
    assert len(r.stdout.splitlines()) == 2
