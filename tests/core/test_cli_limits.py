"""Issue 13 item 5: extreme numbers are messages, never tracebacks; ``--samples`` is checked the
same way by every command that takes it."""
from __future__ import annotations

import copy
import json
import sys

import pytest

from mechsketch.core.cli import main
from mechsketch.resources import example_path

HUGE = sys.float_info.max
TINY = 5e-324


def _doc(name: str) -> dict:
    return json.loads(example_path(name).read_text())


def _set(doc: dict, key: str, value) -> dict:
    doc = copy.deepcopy(doc)
    node = doc["elements"][0]
    *parents, leaf = key.split(".")
    for part in parents:
        node = node.setdefault(part, {})
    node[leaf] = value
    return doc


CASES = [  # (example, key, value, command, what the message names)
    ("geneva_z4", "speed_rpm", 1e300, "analyze", "speed_rpm"),
    ("geneva_z4", "speed_rpm", TINY, "analyze", "speed_rpm"),
    ("geneva_z4", "speed_rpm", -TINY, "analyze", "speed_rpm"),
    ("geneva_z4", "load.external_moment", HUGE, "analyze", "external_moment"),
    ("geneva_z4", "material.wheel.E", 1e308, "analyze", "E"),
    ("geneva_z4", "load.wheel_inertia", 1e308, "analyze", "wheel_inertia"),
    ("geneva_z4", "wear.specific_wear_rate", 1e308, "analyze", "specific_wear_rate"),
    ("geneva_z4", "crank_center", [1e300, 0.0], "analyze", "crank_center"),
    ("geneva_z4", "center_distance", 1e300, "analyze", "center_distance"),
    ("fourbar_crank_rocker", "driver.speed_rpm", TINY, "analyze", "speed_rpm"),
    ("fourbar_crank_rocker", "driver.speed_rpm", 1e300, "analyze", "speed_rpm"),
    ("rolling_lever_press", "rocker_pivot", [HUGE, 0.0], "synthesize", "rocker_pivot"),
    ("rolling_lever_press", "lever_circle.radius", 1e300, "synthesize", "radius"),
    ("rolling_lever_press", "slider_axis_deg", 1e300, "synthesize", "slider_axis_deg"),
]


@pytest.mark.parametrize("name, key, value, command, named", CASES,
                         ids=[f"{c[0]}:{c[1]}={c[2]}" for c in CASES])
def test_extreme_numbers_are_refused_with_a_message(tmp_path, capsys, name, key, value, command, named):
    p = tmp_path / "s.json"
    p.write_text(json.dumps(_set(_doc(name), key, value)))
    for cmd in ("validate", command):
        code = main([cmd, str(p)])
        out, err = capsys.readouterr()
        assert code == 1, (cmd, out, err)
        assert named in out + err and "Traceback" not in out + err


@pytest.mark.parametrize("n", [0, 1, -5, 1_000_001])
def test_centrodes_checks_samples_like_analyze(tmp_path, capsys, n):
    target = tmp_path / "c.csv"
    code = main(["centrodes", str(example_path("fourbar_crank_rocker")), "--link", "coupler",
                 "--samples", str(n), "--csv", str(target)])
    _, err = capsys.readouterr()
    assert code == 1 and "--samples must be from 2 to 1,000,000" in err, err
    assert not target.exists()
