"""What a headless command imports and computes (issue 14): no heavy library, no geometry a
command does not use. Not timed: these check ``sys.modules`` in fresh processes and count calls.
The speed itself is reported by benchmarks/bench_cli.py.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mechsketch.core.analyses.geneva import geometry as geneva_geometry
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.analyses.geneva.report import analysis_table
from mechsketch.core.cli import main
from mechsketch.core.io.scene_file import load_scene, loads_scene
from mechsketch.core.workspace import Workspace

EX = Path(__file__).resolve().parents[2] / "resources" / "examples"
HEAVY = ("ezdxf", "shapely", "jsonschema", "pyqtgraph", "imageio", "scipy", "PySide6", "matplotlib")

PROBE = r"""
import contextlib, io, json, sys
from mechsketch.core.cli import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    rc = main(json.loads(sys.argv[1]))
roots = sorted({m.split('.')[0] for m in sys.modules} & set(json.loads(sys.argv[2])))
print(json.dumps({"rc": rc, "heavy": roots}))
"""


def _heavy_after(args: list[str]) -> tuple[int, set[str]]:
    """Run the CLI with ``args`` in a fresh interpreter; (exit status, heavy packages imported)."""
    out = subprocess.run([sys.executable, "-c", PROBE, json.dumps(args), json.dumps(HEAVY)],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout.strip().splitlines()[-1])
    return got["rc"], set(got["heavy"])


@pytest.mark.parametrize("args, allowed", [
    (["analyze", "fourbar_crank_rocker.json", "--summary"], set()),
    (["analyze", "sixbar_moving_guide.json", "--summary", "--forces"], set()),
    (["analyze", "geneva_z6.json", "--summary"], set()),
    (["synthesize", "rolling_lever_press.json", "--summary"], set()),
    (["validate", "fourbar_crank_rocker.json"], {"shapely"}),      # the drawing check builds the parts
    (["validate", "geneva_z6.json"], {"shapely"}),
], ids=lambda v: " ".join(v) if isinstance(v, list) else "")
def test_commands_import_no_heavy_library_they_do_not_use(args, allowed):
    rc, heavy = _heavy_after([args[0], str(EX / args[1]), *args[2:]])
    assert rc == 0
    assert heavy <= allowed, f"{' '.join(args)} imported {sorted(heavy - allowed)}"


def test_the_probe_sees_a_heavy_import_when_one_is_made(tmp_path):
    """Control: exporting DXF does import ezdxf, and a rejected scene imports jsonschema (which
    words the problems), so the probe above would see them."""
    rc, heavy = _heavy_after(["export", str(EX / "geneva_z6.json"), "--dxf", str(tmp_path / "g.dxf")])
    assert rc == 0 and {"ezdxf", "shapely"} <= heavy
    doc = json.loads((EX / "fourbar_crank_rocker.json").read_text())
    doc["elements"][0]["bogus"] = 1
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    rc, heavy = _heavy_after(["validate", str(bad)])
    assert rc == 1 and "jsonschema" in heavy


def test_export_option_constants_agree_with_their_modules():
    from mechsketch.core.analyses.parts import LAYOUTS
    from mechsketch.core.analyses.parts.build import DEFAULT_TOLERANCE
    from mechsketch.core.cli import export_cmds
    from mechsketch.core.io.dxf_parts import ARC_STYLES

    assert export_cmds.LAYOUTS == LAYOUTS
    assert export_cmds.ARC_STYLES == ARC_STYLES
    assert export_cmds.DEFAULT_TOLERANCE == DEFAULT_TOLERANCE


@pytest.fixture
def geometry_calls(monkeypatch):
    calls = []
    real = geneva_geometry.geometry

    def counting(element):
        calls.append(element.id)
        return real(element)

    monkeypatch.setattr(geneva_geometry, "geometry", counting)
    return calls


def test_geneva_csv_builds_no_geometry_and_writes_the_closed_form_table(tmp_path, geometry_calls):
    target = tmp_path / "g.csv"
    assert main(["analyze", str(EX / "geneva_z6.json"), "--csv", str(target)]) == 0
    assert geometry_calls == []
    el = load_scene(EX / "geneva_z6.json").elements[0]
    ref = analysis_table(kinematics(el, el.samples), contact(el, el.samples, el.model))
    assert target.read_text() == ref.to_csv()
    got = np.genfromtxt(target, delimiter=",", skip_header=1)
    assert got.shape == ref.data.shape
    assert np.array_equal(got, ref.data, equal_nan=True)


def test_geneva_summary_builds_the_geometry_once(capsys, geometry_calls):
    assert main(["analyze", str(EX / "geneva_z6.json"), "--summary"]) == 0
    assert len(geometry_calls) == 1
    assert "relief of the locking disc" in capsys.readouterr().out


def test_geneva_result_builds_geometry_on_first_read(geometry_calls):
    ws = Workspace(load_scene(EX / "geneva_z6.json"))
    res = ws.result(ws.scene.elements[0].id)
    assert geometry_calls == [] and res.kinematics is not None
    assert res.n_frames == res.element.samples and res.geometry is not None and res.error is None
    assert res.geometry is res.geometry and len(geometry_calls) == 1


def test_geneva_drawing_error_still_reported_by_the_result():
    doc = json.loads((EX / "geneva_z6.json").read_text())
    doc["elements"][0].setdefault("drawing", {})["crank_bore_radius"] = 11.5
    ws = Workspace(loads_scene(json.dumps(doc)))
    res = ws.result(doc["elements"][0]["id"])
    assert res.kinematics is not None and res.contact is not None
    assert res.error.startswith("cannot draw the drive: ") and "crank_bore_radius = 11.5 mm" in res.error
    assert res.geometry is None and res.n_frames == 0 and not res.ok
    assert "crank_bore_radius = 11.5 mm" in str(res.exception)
    assert "  drawing: " in res.summary()


def test_entry_points_ask_for_one_blas_thread_unless_the_user_chose():
    code = ("import os, sys\nfrom mechsketch.gui.launcher import main\n"
            "rc = main(['validate', sys.argv[1]])\nimport numpy\nprint(os.environ.get('OPENBLAS_NUM_THREADS'), rc)")
    env = {k: v for k, v in __import__("os").environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", code, str(EX / "fourbar_crank_rocker.json")], capture_output=True,
                         text=True, timeout=120, env=env)
    assert out.stdout.split()[-2:] == ["1", "0"], out.stderr
    out = subprocess.run([sys.executable, "-c", code, str(EX / "fourbar_crank_rocker.json")], capture_output=True,
                         text=True, timeout=120, env=dict(env, OPENBLAS_NUM_THREADS="2"))
    assert out.stdout.split()[-2:] == ["2", "0"], out.stderr
