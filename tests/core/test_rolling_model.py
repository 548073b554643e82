"""The rolling-lever element: schema, meaning checks with their messages, round trip, examples."""
from __future__ import annotations

import json
import math

import pytest

import test_rolling_reference as ref
from mechsketch.core import SceneFormatError, dumps_scene, load_scene, loads_scene, save_scene
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.model.rolling_lever import RollingLever, parse
from mechsketch.resources import example_path


def _load(**changes):
    d = dict(ref.PRESS)
    d.update(changes)
    for k in [k for k, v in d.items() if v is None]:
        del d[k]
    return loads_scene(json.dumps(ref.scene_of(d)))


def _problems(**changes):
    with pytest.raises(SceneFormatError) as exc:
        _load(**changes)
    return [str(p) for p in exc.value.problems]


def test_loads_with_defaults_and_round_trips(tmp_path):
    minimal = {k: v for k, v in ref.PRESS.items() if k not in ("method", "points", "contact_branch", "slider_side",
                                                                "slider_axis_deg", "drive")}
    el = loads_scene(json.dumps(ref.scene_of(minimal))).element("press")
    assert isinstance(el, RollingLever) and el.type == "rolling_lever"
    assert (el.method, el.points, el.contact_branch, el.slider_side, el.drive) == ("exact", 200, "near", 1, None)
    assert el.rocker_length == pytest.approx(210.9502, abs=1e-4)
    full = _load().element("press")
    again = parse(full.to_dict(), "$")[0]
    assert again == full
    path = tmp_path / "s.json"
    save_scene(loads_scene(json.dumps(ref.scene_of(ref.PRESS))), path)
    assert load_scene(path).element("press") == full
    assert json.loads(dumps_scene(load_scene(path)))["elements"][0]["drive"] == {
        "crank_pivot": [-60.0, 120.0], "coupler_point": [30.0, 40.0]}


def test_drawn_contacts():
    p, p0 = _load().element("press").drawn_contacts()
    assert p == pytest.approx((-40.3298, -29.5552), abs=1e-4)
    assert p0 == pytest.approx((-40.3298, 52.5388), abs=1e-4)


@pytest.mark.parametrize("changes,fragment", [
    ({"rocker_pivot": [60, -20]}, "rocker_pivot [60.0, -20.0] coincides with the pin"),
    ({"pin": [60, 200]}, "misses the lever circle by"),
    ({"rocker_pivot": [10, 0]}, "lies behind rocker_pivot"),
    ({"lever_circle": {"center": [0, 0], "radius": 20}, "pin": [20, 9.797174393178826e-15], "rocker_pivot": [100, 0],
      "slider_circle": {"center": [0, 0], "radius": 30}},
     "lies on the lever circle (+0 mm from it) and is the near intersection of the rocker line, i.e. the contact "
     "itself: g = ℓ, so dα/dθ = 1 − g/ℓ = 0"),
    ({"rocker_pivot": [50 * math.cos(2.5), 50 * math.sin(2.5)],
      "pin": [50 * math.cos(2.5) + 120 * math.cos(-0.4), 50 * math.sin(2.5) + 120 * math.sin(-0.4)]},
     "lies on the lever circle and is the near intersection of the rocker line, i.e. the contact itself: g = 0"),
    ({"slider_circle": {"center": [200, 0], "radius": 20}}, "cannot reach the slider circle"),
    ({"stroke": {"from": 0.3, "to": 0.3}}, "the stroke is empty"),
    ({"drive": {"crank_pivot": [30, 40], "coupler_point": [30, 40]}}, "coincides with the crank pivot"),
    ({"lever_circle": {"center": [0, 0], "radius": -5}}, "lever_circle.radius"),
    ({"method": "graphical"}, "'graphical' is not one of"),
    ({"points": 1}, "points [press]: 1 is less than the minimum of 2"),
    ({"tolerance": 1e-14}, "tolerance"),
    ({"stroke": {"from": 0, "to": 7}}, "stroke.to"),
    ({"slider_side": 0}, "slider_side"),
    ({"contact_branch": "middle"}, "contact_branch"),
    ({"colour": "red"}, "unknown key(s)"),
])
def test_bad_elements_are_named(changes, fragment):
    problems = _problems(**changes)
    assert any(fragment in p for p in problems), problems
    assert all("[press]" in p for p in problems)


def test_far_branch_with_the_pivot_inside_is_accepted():
    el = _load(rocker_pivot=[10, 0], contact_branch="far").element("press")
    assert el.drawn_contacts()[0][0] > 10


@pytest.mark.parametrize("name,eid", [("rolling_lever_press", "press"), ("rolling_lever_inclined", "inclined")])
def test_examples_synthesise_without_slip(name, eid):
    el = load_scene(example_path(name)).element(eid)
    res = synthesize(el)
    assert res.slip.continuous.worst < 1e-9
    assert res.error_mm < el.tolerance
    assert res.drive is not None and res.drive.crank > 0
    if eid == "inclined":
        assert el.slider_axis_deg == 30.0
        # the slider moves along its inclined axis: Q = P0 − S5 d_s keeps P0 − Q parallel to the axis
        d = res.P0 - res.Q
        assert abs(d[-1, 1] / d[-1, 0] - 0.5773502691896258) < 1e-12
