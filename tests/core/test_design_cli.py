"""``mechsketch design path|motion|function``: the names fixed by the issue, one line per
candidate, an ordinary scene that ``mechsketch validate`` accepts, and bad input refused with a
clear message, exit 1 and nothing written."""
from __future__ import annotations

import math
import os

import numpy as np
import pytest

from mechsketch.core.cli import main
from mechsketch.core.design import families as F
from mechsketch.core.io.scene_file import load_scene


def _csv(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(f"{v:.12g}" for v in r) for r in rows) + "\n")
    return str(path)


def _path_rows():
    th = np.linspace(0.3, 0.3 + 2 * math.pi, 40, endpoint=False)
    P = F.evaluate("fourbar", np.array([[0, 0, 100, 0, 35, 110, 90, 60, 35.0]]), th[None], 1.0).P[0]
    P = 0.7 * np.exp(1.2j) * P + (300 - 50j)
    return np.stack([P.real, P.imag], axis=1)


def test_design_path_writes_a_valid_scene(atlas_cache, tmp_path, capsys):
    target = _csv(tmp_path / "t.csv", "x,y", _path_rows())
    out = tmp_path / "out.json"
    assert main(["design", "path", target, "--out", str(out), "--topology", "fourbar", "--candidates", "2"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 2 and lines[0].startswith("1. candidate_1: fourbar, max deviation")
    assert "min transmission angle" in lines[0] and lines[0].endswith(" s")
    scene = load_scene(out)
    assert [e.id for e in scene.elements] == ["candidate_1", "candidate_2"]
    assert all("P" in e.link("coupler").joints for e in scene.elements)
    assert main(["validate", str(out)]) == 0


def test_design_motion_and_function(tmp_path, capsys):
    poses = _csv(tmp_path / "p.csv", "x,y,angle_deg", [[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80]])
    out = tmp_path / "m.json"
    assert main(["design", "motion", poses, "--out", str(out), "--candidates", "1"]) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith("1. candidate_1: fourbar, max deviation") and "°" in line
    assert main(["validate", str(out)]) == 0
    pairs = _csv(tmp_path / "f.csv", "input_deg,output_mm", [[0, 0], [45, 20], [90, 45]])
    out = tmp_path / "f.json"
    assert main(["design", "function", pairs, "--out", str(out), "--candidates", "1"]) == 0
    assert "slider_crank" in capsys.readouterr().out
    el = load_scene(out).elements[0]
    assert "output" in el.link_ids
    assert main(["validate", str(out)]) == 0
    # no header: the documented column order
    pairs = _csv(tmp_path / "g.csv", "0,0", [[40, 25], [90, 50]])
    assert main(["design", "function", pairs, "--out", str(tmp_path / "g.json"), "--candidates", "1"]) == 0


@pytest.mark.parametrize("args,content,message", [
    (["motion"], "x,y,angle_deg\n0,0,0\n1,1,10\n", "at least 3 poses"),
    (["motion"], "x,y,angle_deg\n0,0,0\n10,10,0\n20,20,0\n", "pure translation along a line"),
    (["motion"], "x,y,angle_deg\n0,0,0\n1,1,10\n0,0,0\n", "poses 1 and 3 are the same pose"),
    (["motion"], "x,y,angle_deg\n0,0,0\n1,nan,10\n2,2,30\n", "not a finite number"),
    (["motion"], "x,y\n0,0\n1,1\n2,2\n", "missing: angle_deg"),
    (["function"], "input_deg,output_deg\n0,0\n10,5\n", "at least 3"),
    (["function"], "input_deg,output_deg\n0,0\n10,5\nabc,7\n", "'abc' is not a number"),
    (["path"], "x,y\n0,0\n1,0\n1,1\n", "at least 6 points"),
    (["path", "--topology", "fourbar"], "x,y\n0,0\n1,0\n1,0\n1,1\n0,1\n0,2\n", "points 2 and 3 are the same point"),
    (["path"], "x,y\n0,0\n1,0\n1,1\nnan,1\n0,2\n3,3\n", "row 5, column x: 'nan' is not a finite number"),
    # reachable by a four-bar, but by none whose transmission angle stays above 89.9°
    (["path", "--topology", "fourbar", "--min-transmission", "89.9"],
     "x,y\n" + "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in _path_rows()),
     "lower the minimum transmission angle"),
    # a square: no four-bar traces it within 0.01 mm
    (["path", "--topology", "fourbar", "--max-deviation", "0.01"],
     "x,y\n" + "\n".join(f"{50 * float(np.clip(1.3 * math.cos(t), -1, 1))!r},"
                          f"{50 * float(np.clip(1.3 * math.sin(t), -1, 1))!r}"
                          for t in np.linspace(0, 2 * math.pi, 48, endpoint=False)), "raise the maximum deviation"),
    (["motion", "--max-deviation", "-1"], "x,y,angle_deg\n0,0,0\n30,10,20\n50,35,45\n",
     "maximum deviation must be a positive number"),
])
def test_bad_input_exit_1_nothing_written(atlas_cache, tmp_path, capsys, args, content, message):
    src = tmp_path / "in.csv"
    src.write_text(content)
    out = tmp_path / "out.json"
    assert main(["design", args[0], str(src), "--out", str(out)] + args[1:]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err
    assert not out.exists()


def test_unwritable_output_and_missing_file(tmp_path, capsys):
    poses = _csv(tmp_path / "p.csv", "x,y,angle_deg", [[0, 0, 0], [30, 10, 20], [50, 35, 45]])
    assert main(["design", "motion", poses, "--out", str(tmp_path / "nope" / "m.json")]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert main(["design", "motion", str(tmp_path / "missing.csv"), "--out", str(tmp_path / "m.json")]) == 1
    assert "cannot read" in capsys.readouterr().err
    if os.name == "posix" and os.geteuid() != 0:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        assert main(["design", "motion", poses, "--out", str(ro / "m.json")]) == 1
        assert "permission denied" in capsys.readouterr().err
        assert not (ro / "m.json").exists()
