"""``mechsketch validate`` answers whether a scene can be analysed; whether its parts can be cut is
a separate section of warnings (exit 0), errors with ``--strict``; ``export`` still refuses parts
that cannot be cut. Plate sizes live in a linkage's optional ``drawing`` block (schema version 3),
so a scene can carry the values that make it cut-ready. No message names a flag the command that
prints it does not have (issue 20, item 6)."""
from __future__ import annotations

import json
import re
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from mechsketch.core import load_scene, loads_scene
from mechsketch.core.cli import build_parser, main
from mechsketch.core.io.scene_file import dumps_scene, scene_from_dict
from mechsketch.core.model.drawing import LinkageDrawing
from mechsketch.core.model.scene import Scene
from mechsketch.core.workspace import Workspace

from chains import dyad_chain

TINY = Path("/work/shared/cases/s3/fourbar_tiny.json")
HERE = Path(__file__).parent
TINY_COPY = HERE.parent / "fixtures" / "cases" / "fourbar_tiny.json"


def tiny_path() -> Path:
    """The repro case of issue 20 (a copy is kept with the tests)."""
    return TINY_COPY


def run(args, capsys):
    code = main([str(a) for a in args])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def flags_of(command: str) -> set[str]:
    """Every option string of one sub-command of the CLI's parser."""
    sub = next(a for a in build_parser()._actions if a.__class__.__name__ == "_SubParsersAction")
    return {s for act in sub.choices[command]._actions for s in act.option_strings}


def named_flags(text: str) -> set[str]:
    return set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", text))


def test_the_repro_copy_is_the_shared_case():
    if TINY.exists():
        assert json.loads(TINY.read_text()) == json.loads(TINY_COPY.read_text())


def test_a_tiny_four_bar_validates_with_manufacturability_warnings(capsys):
    code, out, err = run(["validate", tiny_path()], capsys)
    assert code == 0, out + err
    head, _, warnings = out.partition("manufacturability")
    assert f"{tiny_path()}: ok" in head
    assert warnings, out
    # one warning per part that cannot be cut, each naming the drawing keys to change
    lines = [ln for ln in warnings.splitlines() if "part '" in ln]
    assert {re.search(r"part '(\w+)'", ln)[1] for ln in lines} == {"ground", "crank", "coupler", "rocker"}
    for ln in lines:
        assert "thinnest web 0.36" in ln and "drawing.boss_radius" in ln and "drawing.min_web" in ln
    assert named_flags(out + err) <= flags_of("validate")
    assert "--strict" in flags_of("validate")


def test_strict_makes_the_warnings_errors(capsys):
    code, out, err = run(["validate", "--strict", tiny_path()], capsys)
    assert code == 1
    assert "part 'crank'" in out and ": ok" not in out
    assert named_flags(out + err) <= flags_of("validate")


def test_export_still_refuses_and_names_only_its_own_flags_and_scene_keys(tmp_path, capsys):
    code, out, err = run(["export", tiny_path(), "--dxf", tmp_path / "t.dxf"], capsys)
    assert code == 1 and not (tmp_path / "t.dxf").exists()
    assert "thinnest web" in err and "--boss-radius" in err and "drawing.boss_radius" in err
    assert named_flags(err) <= flags_of("export")


@pytest.mark.parametrize("n", [8, 16, 32])
def test_dyad_chains_validate(tmp_path, capsys, n):
    path = tmp_path / f"chain{n}.json"
    path.write_text(dumps_scene(Scene((dyad_chain(n, samples=90),))))
    code, out, err = run(["validate", path], capsys)
    assert code == 0, out + err
    assert f"{path}: ok" in out
    assert named_flags(out + err) <= flags_of("validate")
    # what validate accepts, the analysis does
    code, out, err = run(["analyze", path, "--summary"], capsys)
    assert code == 0 and "mobility: 1" in out


def tiny_with_drawing(tmp_path, drawing: dict) -> Path:
    doc = json.loads(tiny_path().read_text())
    doc["schema_version"] = 3
    doc["elements"][0]["drawing"] = drawing
    path = tmp_path / "tiny_drawn.json"
    path.write_text(json.dumps(doc))
    return path


CUT_READY = {"boss_radius": 0.8, "bore_diameter": 0.3, "min_web": 0.5}


def test_a_drawing_block_makes_the_tiny_four_bar_cut_ready(tmp_path, capsys):
    path = tiny_with_drawing(tmp_path, CUT_READY)
    code, out, _ = run(["validate", "--strict", path], capsys)
    assert code == 0 and "manufacturability" not in out, out
    code, out, err = run(["export", path, "--dxf", tmp_path / "t.dxf", "--layout", "assembled"], capsys)
    assert code == 0, err
    assert "boss radius 0.800 mm, bores Ø0.300 mm" in out and "minimum 0.5 mm" in out
    lk = load_scene(path).elements[0]
    circles = ezdxf.readfile(tmp_path / "t.dxf").modelspace().query("CIRCLE")
    assert len(circles) == len(lk.joints)
    for c in circles:
        assert c.dxf.radius == pytest.approx(0.15, abs=1e-15)
        assert min(np.hypot(c.dxf.center.x - j.at[0], c.dxf.center.y - j.at[1]) for j in lk.joints) <= 1e-15


def test_export_options_override_the_drawing_block(tmp_path, capsys):
    path = tiny_with_drawing(tmp_path, CUT_READY)
    code, out, err = run(["export", path, "--dxf", tmp_path / "t.dxf", "--boss-radius", "0.7",
                          "--bore-diameter", "0.2"], capsys)
    assert code == 0, err
    assert "boss radius 0.700 mm, bores Ø0.200 mm" in out and "minimum 0.5 mm" in out
    code, _, err = run(["export", path, "--dxf", tmp_path / "u.dxf", "--min-web", "0.7"], capsys)
    assert code == 1 and "below the minimum web 0.7 mm" in err


def test_an_inconsistent_drawing_block_is_a_warning_naming_the_keys(tmp_path, capsys):
    path = tiny_with_drawing(tmp_path, {"boss_radius": 0.5, "bore_diameter": 1.2})
    code, out, _ = run(["validate", path], capsys)
    assert code == 0 and "manufacturability" in out
    assert "drawing.bore_diameter" in out and "drawing.boss_radius" in out
    assert named_flags(out) <= flags_of("validate")
    code, _, err = run(["export", path, "--svg", tmp_path / "x.svg"], capsys)
    assert code == 1 and named_flags(err) <= flags_of("export")


def test_the_drawing_block_round_trips_and_its_values_are_checked():
    doc = json.loads(tiny_path().read_text())
    doc["elements"][0]["drawing"] = {**CUT_READY, "link_width": 1.2, "block_length": 3.0, "block_width": 2.0}
    scene = loads_scene(json.dumps(doc))
    lk = scene.elements[0]
    assert lk.drawing == LinkageDrawing(boss_radius=0.8, bore_diameter=0.3, link_width=1.2, min_web=0.5,
                                        block_length=3.0, block_width=2.0)
    out = json.loads(dumps_scene(scene))
    assert out["schema_version"] == 3 and out["elements"][0]["drawing"] == doc["elements"][0]["drawing"]
    assert loads_scene(dumps_scene(scene)) == scene
    # without a block nothing is written
    assert "drawing" not in json.loads(dumps_scene(load_scene(tiny_path())))["elements"][0]
    for key, value, words in (("boss_radius", 0.0, "drawing.boss_radius"), ("min_web", -1.0, "drawing.min_web"),
                              ("bore_diameter", -0.1, "drawing.bore_diameter"), ("link_width", 2e9, "1e+09"),
                              ("glue", 1.0, "unknown key")):
        bad = json.loads(json.dumps(doc))
        bad["elements"][0]["drawing"] = {key: value}
        scene, problems = scene_from_dict(bad)
        assert scene is None and any(words in p.message or words in p.path for p in problems), (key, problems)
        assert all(p.path.startswith("$.elements[0].drawing") for p in problems)


def test_the_drawing_block_is_kept_by_edits_in_the_workspace():
    doc = json.loads(tiny_path().read_text())
    doc["elements"][0]["drawing"] = CUT_READY
    ws = Workspace(loads_scene(json.dumps(doc)))
    from mechsketch.core import MoveJoint

    ws.apply(MoveJoint("fourbar", "C", (6.7, 5.8)))
    assert ws.scene.elements[0].drawing == LinkageDrawing(**CUT_READY)

