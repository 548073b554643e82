"""Every rolling-lever integration ends (issue 13, item 4): a stroke starting at 5e-324 rad (the
lead-in integration had a zero first step and never moved), a lever 1e9 mm long (round-off of
~2e-7 mm per step against a tolerance of 1e-10 mm: steps of 6e-11 rad, 1e10 of them) — each
integration has a step and a time budget and ends with a GeometryError naming the input to
change. The hang guards run the cases in a subprocess with a generous timeout."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from mechsketch.core import load_scene
from mechsketch.core.analyses.rolling import exact as RE
from mechsketch.core.analyses.rolling.exact import exact_path, integrate
from mechsketch.core.analyses.rolling.geometry import LeverGeometry
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.errors import GeometryError
from mechsketch.core.io.scene_file import scene_from_dict
from mechsketch.resources import example_path

MECHSKETCH = Path(sys.executable).with_name("mechsketch")


def _press(**changes) -> dict:
    d = json.loads(Path(example_path("rolling_lever_press")).read_text(encoding="utf-8"))
    el = d["elements"][0]
    for k, v in changes.items():
        if k.startswith("stroke_"):
            el["stroke"][k[len("stroke_"):]] = v
        else:
            el[k] = v
    return d


def _cli(tmp_path, doc: dict, *argv: str, timeout: float = 120.0):
    p = tmp_path / "s.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    return subprocess.run([str(MECHSKETCH), *argv, str(p), "--element", "press", *(() if argv[0] != "synthesize" else ("--csv", str(tmp_path / "o.csv")))],
                          capture_output=True, text=True, timeout=timeout)


def test_a_stroke_from_the_smallest_subnormal_is_the_stroke_from_zero():
    doc = _press(stroke_from=5e-324)
    scene, problems = scene_from_dict(doc)
    assert not problems
    el = scene.elements[0]
    geom = LeverGeometry.from_element(el)
    # the lead-in 0 -> 5e-324 and a few other degenerate spans end at once
    for span_end in (5e-324, -5e-324, 1e-300, 2.0 ** -1074 * 7):
        p = integrate(geom, span_end, 1e-10)
        assert p.theta[-1] == span_end and len(p.theta) <= 8
    res = synthesize(el, points=50)
    ref = synthesize(load_scene(example_path("rolling_lever_press")).elements[0], points=50)
    assert abs(res.alpha - ref.alpha).max() < 1e-13
    assert abs(res.P - ref.P).max() < 1e-10
    assert res.error_mm <= el.tolerance


def test_the_cli_ends_on_a_subnormal_stroke(tmp_path):
    r = _cli(tmp_path, _press(stroke_from=5e-324), "synthesize", timeout=120)
    assert r.returncode == 0, r.stderr


def test_a_lever_a_billion_millimetres_long_ends_with_the_inputs_to_change(tmp_path, monkeypatch):
    """The stroke of the press passes the end of this lever's working range (θ ≈ −0.0774 rad): the
    steps collapse (to 6e-11 rad) near the tangent; the budget ends the run and the message gives
    the reachable range and the input to change (it ran for hours)."""
    doc = _press(pin=[1e9 - 0.5, -20.0])
    scene, problems = scene_from_dict(doc)
    assert not problems
    with pytest.raises(GeometryError) as exc:
        synthesize(scene.elements[0], points=20, measures=False)
    msg = str(exc.value)
    assert "beyond the working range" in msg and "stroke" in msg and "-0.0774" in msg
    r = _cli(tmp_path, doc, "synthesize", timeout=120)
    assert r.returncode == 1 and "working range" in r.stderr and "Traceback" not in r.stderr
    # inside its range, a budget that runs out blames the tolerance against the lever's size
    el = scene.elements[0]
    monkeypatch.setattr(RE, "MAX_STEPS", 5)
    with pytest.raises(GeometryError) as exc:
        exact_path(LeverGeometry.from_element(el), 0.0, -0.05, 1e-10)
    msg = str(exc.value)
    assert "5 steps" in msg and "`tolerance`" in msg and "`pin`" in msg and "2.2e-07 mm" in msg


def test_the_step_budget_ends_an_integration_with_a_message(monkeypatch):
    el = load_scene(example_path("rolling_lever_press")).elements[0]
    geom = LeverGeometry.from_element(el)
    monkeypatch.setattr(RE, "MAX_STEPS", 20)
    with pytest.raises(GeometryError) as exc:
        exact_path(geom, 0.0, el.stroke.end, 1e-12)
    msg = str(exc.value)
    assert "20 steps" in msg and "tolerance" in msg and "stroke" in msg
    monkeypatch.setattr(RE, "MAX_STEPS", 10 ** 9)
    monkeypatch.setattr(RE, "MAX_SECONDS", 0.0)
    with pytest.raises(GeometryError, match="s of computing"):
        exact_path(geom, 0.0, el.stroke.end, 1e-12)
    monkeypatch.undo()
    assert math.isfinite(exact_path(geom, 0.0, el.stroke.end, 1e-12).error_mm)
