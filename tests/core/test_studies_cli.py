"""``mechsketch study``: sweeps, Monte Carlo and optimisation from a study file, their files read
back, and bad input refused with the entry named, exit 1 and nothing written.

The numbers are checked against independent references: a sweep's metrics against the batch
engine's one-design path (the diagnostics), an optimisation recovers a known four-bar from its
own coupler curve, the Pareto scenes load and re-evaluate to the objectives in the CSV.
"""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from mechsketch.core.cli import main
from mechsketch.core.cli.study_cmds import run_study_file
from mechsketch.core.io.scene_file import load_scene
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.studies.study import evaluate
from mechsketch.core.workspace import Workspace

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = str(ROOT / "resources/examples/fourbar_crank_rocker.json")
LOADED = str(ROOT / "resources/examples/fourbar_loaded.json")
GENEVA = str(ROOT / "resources/examples/geneva_z6.json")


def write(tmp_path: Path, study: dict, name: str = "study.json") -> str:
    p = tmp_path / name
    p.write_text(json.dumps(study))
    return str(p)


def read_csv(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    head, body = rows[0], rows[1:]
    return {h: np.array([float(r[i]) if r[i] != "" else math.nan for r in body]) for i, h in enumerate(head)}


def test_grid_sweep_writes_the_designs_and_their_metrics(tmp_path, capsys):
    study = {"scene": FOURBAR, "element": "fourbar", "samples": 120, "seed": 1,
             "variables": {"length:crank:A:B": {"values": [30.0, 40.0, 70.0]}, "length:rocker:D:C": {"range": [100, 140]}},
             "metrics": ["min_transmission_angle", "full_cycle", "swing:rocker"], "sweep": {"method": "grid", "points": 3}}
    out = tmp_path / "out"
    assert main(["study", write(tmp_path, study), "--out", str(out)]) == 0
    assert "sweep of 'fourbar'" in capsys.readouterr().out
    rows = read_csv(out / "designs.csv")
    summary = json.loads((out / "summary.json").read_text())
    assert len(rows["design"]) == 9 == summary["designs"]
    assert summary["columns"]["min_transmission_angle"] == "°" and summary["columns"]["length:crank:A:B"] == "mm"
    lk = Workspace.open(FOURBAR).element("fourbar")
    from mechsketch.core.solver.dimensions import set_dimension
    for i in range(9):   # each row against the one-design path
        one = set_dimension(set_dimension(lk, "length:crank:A:B", rows["length:crank:A:B"][i]), "length:rocker:D:C",
                            rows["length:rocker:D:C"][i])
        sol = compile_plan(one).sweep(120, 0)
        d = diagnose(sol)
        assert rows["full_cycle"][i] == float(d.full_turn)
        mu = np.degrees(sol.transmission_angle("RRR(coupler,rocker)"))
        assert rows["min_transmission_angle"][i] == pytest.approx(np.nanmin(np.minimum(mu, 180 - mu)), abs=1e-7)
        a = np.degrees(sol.angle("rocker")[sol.valid])
        assert rows["swing:rocker"][i] == pytest.approx(a.max() - a.min(), abs=1e-7)


def test_sobol_sweep_of_a_geneva_drive(tmp_path):
    study = {"scene": GENEVA, "seed": 4, "variables": {"center_distance": {"range": [90, 110]},
                                                       "roller_radius": {"range": [5.0, 8.0]}},
             "metrics": ["p_max", "wear_life"], "sweep": {"method": "sobol", "designs": 8}}
    res = run_study_file(write(tmp_path, study), str(tmp_path / "g"))
    c = res.columns
    assert (c["assembled"] == 1).all() and np.isfinite(c["p_max"]).all()
    # the same seed, the same designs; a bigger roller carries the load at a lower pressure
    again = run_study_file(write(tmp_path, study, "again.json"), str(tmp_path / "g2"))
    assert np.array_equal(again.columns["p_max"], c["p_max"])
    from mechsketch.core.analyses.geneva.contact import contact
    from mechsketch.core.studies.metrics import geneva_design
    g = Workspace.open(GENEVA).scene.elements[0]
    el = geneva_design(g, {k: c[k] for k in ("center_distance", "roller_radius")}, 3)
    assert c["p_max"][3] == pytest.approx(contact(el, min(el.samples, 720), el.model).pressure_max, rel=1e-12)


def test_montecarlo_is_the_tolerance_run_with_its_envelope(tmp_path):
    study = {"scene": FOURBAR, "samples": 60, "seed": 5,
             "variables": {"length:crank:A:B": {"normal": 0.02}, "length:coupler:B:C": {"uniform": 0.05}},
             "clearance": {"B": "H7/g6"}, "metrics": ["min_transmission_angle"],
             "montecarlo": {"builds": 3000, "joints": ["E"], "links": ["rocker"]}}
    out = tmp_path / "mc"
    res = run_study_file(write(tmp_path, study), str(out))
    rows = read_csv(out / "builds.csv")
    t = Workspace.open(FOURBAR)["fourbar"].tolerance({"length:crank:A:B": {"normal": 0.02},
                                                       "length:coupler:B:C": {"uniform": 0.05},
                                                       "clearance": {"B": "H7/g6"}},
                                                      builds=3000, samples=60, seed=5, joints=["E"], links=["rocker"])
    assert np.allclose(rows["deviation:E"], t.deviation("E"), rtol=1e-9, atol=0)
    s = json.loads((out / "summary.json").read_text())
    assert s["deviation"]["E"]["p95"] == pytest.approx(t.percentile("E", 95), rel=1e-9)
    assert s["failed"] == 0 and abs(sum(s["sensitivity"]["E"].values()) - 1) < 1e-12
    env = read_csv(out / "envelope.csv")
    assert np.allclose(env["E.q0.995.x"], t.envelope("E", 0.995)[:, 0], equal_nan=True)
    # each build's metric is that build's: the same draws as the deviations (rows line up)
    assert np.all(np.abs(rows["min_transmission_angle"] - np.nanmedian(rows["min_transmission_angle"])) < 0.5)
    assert res.summary["metrics"]["min_transmission_angle"]["unit"] == "°"


def test_optimisation_recovers_a_known_four_bar_from_its_coupler_curve(tmp_path):
    """Target: the coupler curve of the example with crank 44 mm and rocker 112 mm; differential
    evolution over the two lengths finds them."""
    lk = Workspace.open(FOURBAR).element("fourbar")
    target = evaluate  # noqa: F841 (the reference curve comes from the one-design path below)
    from mechsketch.core.solver.dimensions import set_dimension
    known = set_dimension(set_dimension(lk, "length:crank:A:B", 44.0), "length:rocker:D:C", 112.0)
    pts = compile_plan(known).sweep(40, 0).position("E")
    study = {"scene": FOURBAR, "samples": 180, "seed": 2,
             "variables": {"length:crank:A:B": {"range": [35, 50]}, "length:rocker:D:C": {"range": [100, 125]}},
             "target": {"joint": "E", "points": pts.tolist()},
             "optimize": {"objectives": ["path_error:E"], "algorithm": "de", "population": 20, "generations": 40,
                          "pareto_scenes": 1}}
    out = tmp_path / "opt"
    res = run_study_file(write(tmp_path, study), str(out))
    best = res.summary["pareto"][0]
    assert best["length:crank:A:B"] == pytest.approx(44.0, abs=0.05)
    assert best["length:rocker:D:C"] == pytest.approx(112.0, abs=0.15)
    assert best["path_error:E"] < 0.05
    scene = load_scene(out / res.summary["pareto_scenes"][0])       # opens like any scene
    el = scene.element("fourbar")
    again = evaluate(el, {}, 1, ["path_error:E"], 180, np.asarray(pts))
    assert again["path_error:E"][0] == pytest.approx(best["path_error:E"], rel=1e-6)


def test_nsga2_pareto_front_and_its_scenes(tmp_path):
    study = {"scene": LOADED, "element": "loaded_fourbar", "samples": 48, "seed": 3,
             "variables": {"length:crank:A:B": {"range": [30, 45]}, "length:rocker:D:C": {"range": [100, 140]}},
             "optimize": {"objectives": [{"minimize": "peak_torque"}, {"maximize": "min_transmission_angle"}],
                          "constraints": [{"metric": "min_transmission_angle", "min": 35}],
                          "population": 16, "generations": 4, "pareto_scenes": 3}}
    out = tmp_path / "nsga"
    res = run_study_file(write(tmp_path, study), str(out))
    rows = read_csv(out / "evaluations.csv")
    front = rows["pareto"] > 0
    assert front.any() and (rows["feasible"][front] > 0).all() and (rows["min_transmission_angle"][front] >= 35).all()
    F = np.column_stack([rows["peak_torque"], -rows["min_transmission_angle"]])
    ok = rows["feasible"] > 0
    for i in np.flatnonzero(front):   # nothing feasible dominates a point of the front
        assert not np.any(ok & np.all(F <= F[i], axis=1) & np.any(F < F[i], axis=1))
    for name, (row, _rec) in zip(res.summary["pareto_scenes"], res.pareto):
        el = load_scene(out / name).element("loaded_fourbar")
        ws = Workspace(load_scene(out / name))
        f = ws.forces("loaded_fourbar", samples=48)
        assert np.nanmax(np.abs(f.driver.values)) == pytest.approx(rows["peak_torque"][row], rel=1e-9)
        assert el.id == "loaded_fourbar"


@pytest.mark.parametrize("study, words", [
    ({"variables": {"length:crank:A:Q": {"range": [1, 2]}}, "sweep": {}, "metrics": ["full_cycle"]}, "length:crank:A:Q"),
    ({"variables": {"length:crank:A:B": {"normal": -0.1}}, "montecarlo": {"builds": 10}}, "negative"),
    ({"variables": {"length:crank:A:B": {"normal": 0.1}}, "clearance": {"B": "H7/z6"}, "montecarlo": {}}, "clearance 'B'"),
    ({"variables": {"length:crank:A:B": {"range": [50, 40]}}, "sweep": {}, "metrics": ["full_cycle"]}, "low end"),
    ({"variables": {"length:crank:A:B": {"range": [40, 50]}}, "sweep": {}, "metrics": ["torque"]}, "metric 'torque'"),
    ({"variables": {"length:crank:A:B": {"range": [40, 50]}}, "sweep": {}, "optimize": {}}, "exactly one"),
    ({"variables": {"length:crank:A:B": {"range": [40, 50]}}, "sweep": {}, "metrics": ["path_error:E"]}, "target"),
    ({"variables": {"length:crank:A:B": {"range": [40, 50]}}, "sweep": {"points": 10_000}, "metrics": ["full_cycle"],
      "samples": 360}, "designs"),
    ({"variables": {"length:crank:A:B": {"normal": 0.1}}, "montecarlo": {"builds": 10_000_000}, "samples": 360},
     "MECHSKETCH_MEMORY_MB"),
])
def test_bad_studies_exit_1_naming_the_entry_and_write_nothing(tmp_path, capsys, monkeypatch, study, words):
    monkeypatch.setenv("MECHSKETCH_MEMORY_MB", "200")
    study = {"scene": FOURBAR, "element": "fourbar", **study}
    if "sweep" in study and "points" in study["sweep"]:
        study["variables"]["length:coupler:B:C"] = {"range": [130, 150]}
        study["variables"]["length:rocker:D:C"] = {"range": [110, 130]}
    out = tmp_path / "never"
    assert main(["study", write(tmp_path, study), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert words in err, err
    assert not out.exists()


def test_an_unreachable_scheduler_is_named_and_nothing_is_written(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("mechsketch.core.studies.execute.CONNECT_TIMEOUT", 1.0)
    study = {"scene": FOURBAR, "variables": {"length:crank:A:B": {"range": [40, 42]}}, "metrics": ["full_cycle"],
             "sweep": {"points": 2}}
    out = tmp_path / "never"
    assert main(["study", write(tmp_path, study), "--out", str(out), "--scheduler", "tcp://127.0.0.1:9"]) == 1
    assert "tcp://127.0.0.1:9" in capsys.readouterr().err
    assert not out.exists()


# -- Parquet ---------------------------------------------------------------------------------------
def _parquet(path: Path) -> dict[str, np.ndarray]:
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    return {name: table.column(name).to_numpy() for name in table.column_names}, table.schema


def _same_table(csv_path: Path, pq_path: Path) -> None:
    """The Parquet table is the CSV's: the same columns in the same order, and each value printed as
    the CSV prints it (10 significant digits, NaN empty) gives the CSV's text exactly."""
    cols, schema = _parquet(pq_path)
    with open(csv_path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == list(cols)
    for i, name in enumerate(rows[0]):
        a = np.asarray(cols[name], dtype=float)
        text = np.where(np.isnan(a), "", np.char.mod("%.10g", a))
        assert list(text) == [r[i] for r in rows[1:]], name


def test_parquet_tables_are_the_csv_tables(tmp_path, capsys):
    """A sweep and a Monte Carlo written as Parquet (from the study file, and by --format) read back
    with pyarrow: the CSV's columns and values, full precision, sensible types, units attached."""
    sweep = {"scene": FOURBAR, "element": "fourbar", "samples": 60, "seed": 1,
             "variables": {"length:crank:A:B": {"values": [30.0, 40.0, 400.0]}, "length:rocker:D:C": {"range": [100, 140]}},
             "metrics": ["min_transmission_angle", "full_cycle"], "sweep": {"method": "grid", "points": 3}}
    assert main(["study", write(tmp_path, sweep), "--out", str(tmp_path / "c")]) == 0
    assert main(["study", write(tmp_path, {**sweep, "output": {"format": "parquet"}}, "p.json"), "--out",
                 str(tmp_path / "p")]) == 0
    assert not (tmp_path / "p" / "designs.csv").exists()
    _same_table(tmp_path / "c" / "designs.csv", tmp_path / "p" / "designs.parquet")
    cols, schema = _parquet(tmp_path / "p" / "designs.parquet")
    assert cols["design"].dtype == np.int64 and cols["min_transmission_angle"].dtype == np.float64
    assert schema.field("length:crank:A:B").metadata == {b"unit": b"mm"}
    assert schema.field("min_transmission_angle").metadata == {b"unit": "°".encode()}
    broken = cols["assembled"] == 0                                   # crank 400: not assembled, NaN kept
    assert broken.sum() == 3 and np.isnan(cols["min_transmission_angle"][broken]).all()
    ref = run_study_file(write(tmp_path, sweep, "again.json"), str(tmp_path / "r"))
    assert np.array_equal(cols["min_transmission_angle"], ref.columns["min_transmission_angle"], equal_nan=True)

    mc = {"scene": FOURBAR, "samples": 36, "seed": 5, "variables": {"length:crank:A:B": {"normal": 0.02}},
          "clearance": {"B": "H7/g6"}, "montecarlo": {"builds": 500, "joints": ["E"]}, "output": {"format": "csv"}}
    assert main(["study", write(tmp_path, mc, "mc.json"), "--out", str(tmp_path / "mc")]) == 0
    assert main(["study", write(tmp_path, mc, "mc.json"), "--out", str(tmp_path / "mq"), "--format", "parquet"]) == 0
    for name in ("builds", "envelope"):
        _same_table(tmp_path / "mc" / f"{name}.csv", tmp_path / "mq" / f"{name}.parquet")
    summary = json.loads((tmp_path / "mq" / "summary.json").read_text())
    assert summary["builds"] == 500


@pytest.mark.parametrize("where", ["study", "cli"])
def test_a_bad_format_is_named_and_nothing_is_written(tmp_path, capsys, where):
    study = {"scene": FOURBAR, "variables": {"length:crank:A:B": {"range": [40, 42]}}, "metrics": ["full_cycle"],
             "sweep": {"points": 2}}
    args = ["--format", "xlsx"] if where == "cli" else []
    if where == "study":
        study["output"] = {"format": "xlsx"}
    out = tmp_path / "never"
    assert main(["study", write(tmp_path, study), "--out", str(out), *args]) == 1
    err = capsys.readouterr().err
    assert "'xlsx'" in err and "parquet" in err, err
    assert not out.exists()
