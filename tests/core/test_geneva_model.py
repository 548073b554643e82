"""Geneva element: schema and meaning checks (every bad input names the limit and by how much it is
violated), defaults, exact round trips, and the closed-form wheel dimensions of the notes."""
from __future__ import annotations

import copy
import json
import math

import pytest

from mechsketch.core import GeometryError, SceneFormatError, load_scene, loads_scene
from mechsketch.core.analyses.geneva.geometry import geometry
from mechsketch.core.io.scene_file import dumps_scene, scene_from_dict
from mechsketch.core.model.geneva import (Clearances, Drawing, Geneva, require_valid,
                                          wheel_dimensions)

ISSUE_ELEMENT = {
    "type": "geneva", "id": "indexer", "slots": 6, "center_distance": 100.0,
    "roller_radius": 8.0, "roller_length": 10.0,
    "clearance": {"slot": 0.05, "bottom": 0.5, "lock": 0.1},
    "crank_center": [0, 0], "wheel_direction_deg": 0, "speed_rpm": 95.49,
    "load": {"wheel_inertia": 0.05, "external_moment": 0.0, "journal_friction": 0.05, "journal_radius": 15.0},
    "material": {"roller": {"E": 210000, "poisson": 0.3}, "wheel": {"E": 210000, "poisson": 0.3}},
    "wear": {"allowed_wear": 0.05, "specific_wear_rate": 1e-6},
    "samples": 3600,
}


def scene(*elements) -> dict:
    return {"format": "mechsketch.scene", "schema_version": 1, "units": "mm", "elements": list(elements)}


def problems_of(element: dict):
    sc, problems = scene_from_dict(scene(element))
    assert sc is None and problems
    return problems


def with_(path: str, value, base=None) -> dict:
    """A copy of the issue's element with ``path`` (dotted) set to ``value``."""
    el = copy.deepcopy(base or ISSUE_ELEMENT)
    *head, last = path.split(".")
    node = el
    for k in head:
        node = node.setdefault(k, {})
    node[last] = value
    return el


# -- the issue's element -----------------------------------------------------------------------
def test_issue_element_parses_with_its_values_and_round_trips_exactly():
    sc, problems = scene_from_dict(scene(ISSUE_ELEMENT))
    assert problems == []
    el = sc.element("indexer")
    assert el.type == "geneva" and el.slots == 6 and el.center_distance == 100.0
    assert el.crank_radius == pytest.approx(50.0, rel=1e-15)
    assert el.omega1 == pytest.approx(95.49 * math.pi / 30)
    assert el.to_dict() == ISSUE_ELEMENT
    assert json.loads(dumps_scene(sc))["elements"][0] == ISSUE_ELEMENT
    assert loads_scene(dumps_scene(sc)) == sc


def test_required_keys_only_get_the_notes_defaults_and_re_parse_equal():
    minimal = {"type": "geneva", "id": "g", "slots": 6, "center_distance": 100, "roller_radius": 8}
    el = loads_scene(json.dumps(scene(minimal))).element("g")
    assert el.roller_length == 10.0 and el.clearance == Clearances(0.05, 0.5, 0.1)
    assert el.omega1 == pytest.approx(10.0, rel=1e-15)  # n = 95.49... rpm
    assert el.load.wheel_inertia == 0.05 and el.load.journal_friction == 0.05 and el.load.journal_radius == 15.0
    assert el.roller_material.E == 210000.0 and el.wheel_material.poisson == 0.3
    assert el.samples == 3600 and el.contact_model is None and el.drawing is None
    again = loads_scene(json.dumps(scene(el.to_dict()))).element("g")
    assert again == el and again.to_dict() == el.to_dict()


def test_optional_groups_round_trip_and_keep_only_what_was_given():
    el = with_("drawing", {"wheel_bore_radius": 12.0, "pin_radius": 3.0})
    el = with_("contact_model", {"normal_force": "paper", "half_width": "hertz", "slip_radius": "undeformed"}, el)
    g = loads_scene(json.dumps(scene(el))).element("indexer")
    assert g.drawing == Drawing(wheel_bore_radius=12.0, pin_radius=3.0)
    assert g.model.normal_force == "paper" and g.model.half_width == "hertz"
    assert g.to_dict() == el


def test_wheel_dimensions_match_the_notes_default_scene():
    d = wheel_dimensions(6, 100.0, 8.0, Clearances(0.05, 0.5, 0.1))
    assert d.lock_arc_radius == pytest.approx(37.925, abs=1e-12)
    assert d.lock_disc_radius == pytest.approx(37.825, abs=1e-12)
    assert round(d.outer_radius, 3) == 86.976
    assert round(d.slot_depth, 2) == 45.15 and round(d.hub_max, 2) == 41.45
    assert d.x_c == pytest.approx(math.sqrt(100.0 ** 2 - 50.0 ** 2), rel=1e-15)  # a_w = √(A² − r²)
    z3 = wheel_dimensions(3, 100.0, 8.0, Clearances(0.05, 0.5, 0.1))
    assert round(z3.hub_max, 2) == 4.85  # "for z = 3, A = 100, r_p = 8 that leaves only 4.85"
    # the horn land closes exactly at the knife-edge locking arc R_arc = r − w
    knife = wheel_dimensions(6, 100.0, 8.0, Clearances(), d.crank_radius - d.w)
    assert abs(knife.land_angle) < 1e-12 and d.land_angle > 0


# -- every bad input, with its message ---------------------------------------------------------
BAD = [
    ("slots", 2, "$.elements[0].slots", ["at least 3 slots", "got 2", "1 short"]),
    ("slots", -4, "$.elements[0].slots", ["at least 3 slots", "got -4", "7 short"]),
    ("center_distance", -5.0, "$.elements[0].center_distance", ["must be > 0 mm", "got -5 mm", "5 mm below"]),
    ("center_distance", 0, "$.elements[0].center_distance", ["must be > 0 mm", "at the limit"]),
    ("roller_radius", 0.0, "$.elements[0].roller_radius", ["must be > 0 mm", "at the limit"]),
    ("roller_length", -1.0, "$.elements[0].roller_length", ["must be > 0 mm", "1 mm below"]),
    ("clearance.slot", -0.1, "$.elements[0].clearance.slot", ["must be >= 0 mm", "0.1 mm below"]),
    ("clearance.bottom", -2.0, "$.elements[0].clearance.bottom", ["must be >= 0 mm", "2 mm below"]),
    ("clearance.lock", -0.01, "$.elements[0].clearance.lock", ["must be >= 0 mm", "0.01 mm below"]),
    ("material.roller.E", 0, "$.elements[0].material.roller.E", ["must be > 0 MPa"]),
    ("material.wheel.poisson", 0.6, "$.elements[0].material.wheel.poisson", ["(−1, 0.5)", "got 0.6", "0.1 beyond the limit 0.5"]),
    ("material.roller.poisson", -1.5, "$.elements[0].material.roller.poisson", ["0.5 beyond the limit -1"]),
    ("speed_rpm", 0, "$.elements[0].speed_rpm", ["must not be zero"]),
    ("load.wheel_inertia", -0.1, "$.elements[0].load.wheel_inertia", ["must be >= 0 kg·m²", "0.1 kg·m² below"]),
    ("load.journal_friction", -0.2, "$.elements[0].load.journal_friction", ["must be >= 0;", "0.2 below"]),
    ("load.journal_radius", -3.0, "$.elements[0].load.journal_radius", ["must be >= 0 mm", "3 mm below"]),
    ("wear.allowed_wear", 0.0, "$.elements[0].wear.allowed_wear", ["must be > 0 mm"]),
    ("wear.specific_wear_rate", -1e-6, "$.elements[0].wear.specific_wear_rate", ["must be > 0 mm³/(N·m)"]),
    ("samples", 1, "$.elements[0].samples", ["at least 2", "1 short"]),
]


@pytest.mark.parametrize("key,value,where,words", BAD, ids=[f"{b[0]}={b[1]}" for b in BAD])
def test_bad_value_is_reported_with_its_limit(key, value, where, words):
    problems = problems_of(with_(key, value))
    hit = [p for p in problems if p.path == where]
    assert hit, problems
    assert hit[0].id == "indexer"
    for w in words:
        assert w in hit[0].message, hit[0].message


def test_roller_too_large_for_any_locking_arc():
    # a roller wider than the crank radius: r − w = −5.05 mm < A − R_o = −2.6 mm
    el = with_("roller_radius", 55.0)
    d = wheel_dimensions(6, 100.0, 55.0, Clearances())
    lo, hi = d.lock_arc_range
    assert hi <= lo
    (p,) = problems_of(el)
    assert p.path == "$.elements[0].roller_radius" and "no locking arc and no land" in p.message
    assert f"short by {lo - hi:.6g} mm" in p.message


def test_default_locking_arc_below_its_range():
    d = wheel_dimensions(6, 100.0, 27.5, Clearances())
    lo, hi = d.lock_arc_range
    assert lo < hi and d.lock_arc_radius <= lo
    (p,) = problems_of(with_("roller_radius", 27.5))
    assert "default locking arc radius r − 1.5·w" in p.message
    assert f"short by {lo - d.lock_arc_radius:.6g} mm" in p.message


def test_user_locking_arc_cutting_the_walls_and_the_knife_edge():
    d = wheel_dimensions(6, 100.0, 8.0, Clearances())
    (p,) = problems_of(with_("drawing", {"locking_arc_radius": d.crank_radius - d.w + 0.5}))
    assert p.path == "$.elements[0].drawing.locking_arc_radius"
    assert "exceeds r − w = 41.95 mm by 0.5 mm" in p.message
    (p,) = problems_of(with_("drawing", {"locking_arc_radius": d.crank_radius - d.w}))
    assert "no land between slots" in p.message and "must be > 0°" in p.message


def test_lock_clearance_eating_the_locking_disc():
    (p,) = problems_of(with_("clearance.lock", 40.0))
    assert p.path == "$.elements[0].clearance.lock"
    assert "R_arc − c_l = -2.075 mm" in p.message and "2.075 mm too large" in p.message


def test_no_hub_around_the_bore():
    el = with_("slots", 3)  # hub limit 4.847 mm < journal radius 15 mm
    (p,) = problems_of(el)
    assert p.path == "$.elements[0].load.journal_radius"
    hub = wheel_dimensions(3, 100.0, 8.0, Clearances()).hub_max
    assert "no hub" in p.message and f"x_b − w = {hub:.6g} mm" in p.message
    assert f"short by {15.0 - hub:.6g} mm" in p.message
    (p,) = problems_of(with_("drawing", {"wheel_bore_radius": 42.0}))
    assert p.path == "$.elements[0].drawing.wheel_bore_radius" and "short by 0.55 mm" in p.message
    assert scene_from_dict(scene(with_("drawing", {"wheel_bore_radius": 3.8}, el)))[1] == []
    # a hub thinner than the minimum web (1 mm by default; drawing.min_web changes it)
    (p,) = problems_of(with_("drawing", {"wheel_bore_radius": 4.0}, el))
    assert p.path.endswith("drawing.wheel_bore_radius") and "the hub is too thin" in p.message
    assert scene_from_dict(scene(with_("drawing", {"wheel_bore_radius": 4.0, "min_web": 0.8}, el)))[1] == []


def test_self_locking_journal():
    el = with_("load", {"journal_friction": 1.0, "journal_radius": 60.0})
    el = with_("drawing", {"wheel_bore_radius": 10.0}, el)
    (p,) = problems_of(el)
    assert p.path == "$.elements[0].load.journal_friction"
    assert "f02·r02 = 60 mm" in p.message and "A − r = 50 mm" in p.message and "over by 10 mm" in p.message


def test_pin_and_crank_bore_limits():
    (p,) = problems_of(with_("drawing", {"pin_radius": 8.5}))
    assert "over by 0.5 mm" in p.message and p.path.endswith("drawing.pin_radius")
    (p,) = problems_of(with_("drawing", {"crank_bore_radius": 20.0}))
    assert p.path.endswith("drawing.crank_bore_radius") and "A − R_o − c_l" in p.message
    # inside the necessary bound but beyond the exact relief: caught when the geometry is built
    g = loads_scene(json.dumps(scene(with_("drawing", {"crank_bore_radius": 11.5})))).element("indexer")
    with pytest.raises(GeometryError, match=r"crank_bore_radius = 11.5 mm must be below A − relief radius − min_web = 11.398"):
        geometry(g)


def test_schema_problems_unknown_key_wrong_type_bad_enum():
    problems = problems_of(with_("colour", "red"))
    assert "unknown key" in problems[0].message and problems[0].id == "indexer"
    problems = problems_of(with_("slots", 6.5))
    assert problems[0].path == "$.elements[0].slots" and "integer" in problems[0].message
    problems = problems_of(with_("contact_model", {"normal_force": "guess"}))
    assert problems[0].path == "$.elements[0].contact_model.normal_force"


def test_geometry_is_checked_even_when_unrelated_values_are_bad():
    el = with_("slots", 3, with_("wear.allowed_wear", -1.0))
    paths = {p.path for p in problems_of(el)}
    assert paths == {"$.elements[0].wear.allowed_wear", "$.elements[0].load.journal_radius"}  # + no hub


def test_all_problems_of_one_element_are_listed_together():
    el = with_("center_distance", -1.0, with_("speed_rpm", 0, with_("wear.allowed_wear", -1.0)))
    paths = {p.path for p in problems_of(el)}
    assert paths == {"$.elements[0].center_distance", "$.elements[0].speed_rpm", "$.elements[0].wear.allowed_wear"}


def test_bad_file_raises_scene_format_error_naming_the_file(tmp_path):
    f = tmp_path / "bad.json"
    f.write_text(json.dumps(scene(with_("slots", 2))), encoding="utf-8")
    with pytest.raises(SceneFormatError, match=r"(?s)bad.json: 1 problem\(s\).*\[indexer\]: a Geneva drive needs at least 3 slots"):
        load_scene(f)


def test_elements_built_in_code_are_checked_too():
    assert require_valid(Geneva("ok", 6, 100.0, 8.0)).slots == 6
    with pytest.raises(GeometryError, match=r"geneva 'g3'.*no hub"):
        geometry(Geneva("g3", 3, 100.0, 8.0))
    with pytest.raises(GeometryError, match="at least 3 slots"):
        require_valid(Geneva("g2", 2, 100.0, 8.0))
