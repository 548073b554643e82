"""Issue 13 items 2 and 5: one validation for every entry path, and a stated physical range for
every quantity. An edit through the workspace (the API, the properties panel, a tool, the end of
a drag) is checked by the same schema and parser as a file; what the loader refuses never lands."""
from __future__ import annotations

import copy
import json
import sys
from dataclasses import replace

import pytest

from mechsketch.core import EditError, MoveJoint, ReplaceElement, load_scene
from mechsketch.core.io.scene_file import dumps_scene, element_problems, loads_scene, validate_file
from mechsketch.core.model.edits import AddElement
from mechsketch.core.workspace import Workspace
from mechsketch.resources import example_path

HUGE = sys.float_info.max


def _ws(name: str = "fourbar_crank_rocker") -> Workspace:
    return Workspace(load_scene(example_path(name)))


@pytest.mark.parametrize("y", [1e10, 1e308, -HUGE])
def test_a_coordinate_the_loader_refuses_is_refused_by_the_workspace(y):
    ws = _ws()
    before = ws.scene
    edit = MoveJoint("fourbar", "B", (20.0, y))
    for attempt in (ws.check, ws.apply):
        with pytest.raises(EditError, match=r"beyond ±1e\+09 mm") as info:
            attempt(edit)
        assert "fourbar" in str(info.value) and "B" in str(info.value)
    assert ws.scene is before
    # the same message as the loader's for the same value in a file
    doc = json.loads(dumps_scene(before))
    doc["elements"][0]["joints"][1]["at"] = [20.0, y]
    with pytest.raises(Exception, match=r"beyond ±1e\+09 mm"):
        loads_scene(json.dumps(doc))


def test_a_valid_edit_still_lands_and_undoes():
    ws = _ws()
    inverse = ws.apply(MoveJoint("fourbar", "B", (21.0, 35.0)))
    assert ws.scene.element("fourbar").joint("B").at == (21.0, 35.0)
    ws.apply(inverse)
    assert ws.scene == load_scene(example_path("fourbar_crank_rocker"))


def test_elements_of_every_type_are_checked_on_replace_and_add():
    ws = _ws("geneva_z4")
    g = ws.scene.elements[0]
    with pytest.raises(EditError, match="speed_rpm"):
        ws.apply(ReplaceElement(replace(g, speed_rpm=0.0)))
    with pytest.raises(EditError, match="slots"):
        ws.check(AddElement(replace(g, id="other", slots=2)))
    lever = load_scene(example_path("rolling_lever_press")).elements[0]
    bad = replace(lever, rocker_pivot=(HUGE, 0.0))
    with pytest.raises(EditError, match="rocker_pivot"):
        ws.apply(AddElement(bad))
    assert [e.id for e in ws.scene.elements] == [g.id]
    assert element_problems(g) == [] and element_problems(lever) == []


@pytest.mark.parametrize("key, value, limit", [("roller_length", 1e-300, "1e-06 mm"),
                                               ("center_distance", 1e-300, "1e-06 mm"),
                                               ("material.wheel.E", 1e-9, "0.001 MPa"),
                                               ("wear.specific_wear_rate", 1e-300, "1e-12 mm³/(N·m)"),
                                               ("wear.allowed_wear", 1e-300, "1e-06 mm")])
def test_positive_quantities_have_a_smallest_physical_value(key, value, limit):
    """A roller 1e-300 mm long passed as 'positive' and overflowed the contact pressure."""
    doc = json.loads(example_path("geneva_z8").read_text())
    node = doc["elements"][0]
    *parents, leaf = key.split(".")
    for part in parents:
        node = node.setdefault(part, {})
    node[leaf] = value
    with pytest.raises(Exception) as info:
        loads_scene(json.dumps(doc))
    assert f"at least {limit}" in str(info.value) and key in str(info.value), str(info.value)


def test_undo_back_to_the_documents_own_elements_is_never_refused():
    """A scene given by the API (not read from a file) may hold what a file may not; an edit of
    it and the undo of that edit both land: only values entering from outside are checked."""
    lk = load_scene(example_path("fourbar_crank_rocker")).element("fourbar")
    odd = lk.with_joints_moved({"E": (0.0, 5e9)})           # a coupler point beyond ±1e9 mm
    ws = Workspace(__import__("mechsketch.core.model.scene", fromlist=["Scene"]).Scene((odd,)))
    with pytest.raises(EditError, match="beyond"):
        ws.apply(MoveJoint("fourbar", "B", (21.0, 35.0)))   # the result still holds E: refused
    other = Workspace(load_scene(example_path("fourbar_crank_rocker")))
    other.reset(ws.scene)                                   # Open/restore-like replacement
    assert other.scene.element("fourbar") is odd
    inverse = other.apply(ReplaceElement(lk))               # a valid element replaces it
    other.apply(inverse)                                    # undo: the document's own element returns
    assert other.scene.element("fourbar") == odd


@pytest.mark.parametrize("key, value, limit", [("load.wheel_inertia", 1e-300, "1e-12 kg·m²"),
                                               ("load.external_moment", 1e-300, "1e-12 N·m"),
                                               ("load.external_moment", -1e-20, "1e-12 N·m"),
                                               ("clearance.slot", 1e-9, "1e-06 mm")])
def test_quantities_that_may_be_zero_are_zero_or_physical(key, value, limit):
    """A wheel inertia of 5e-324 kg·m² made a denormal normal force whose Hertz strip underflowed
    to 0 (divide by zero, nan in the contact columns)."""
    doc = json.loads(example_path("geneva_z4").read_text())
    node = doc["elements"][0]
    *parents, leaf = key.split(".")
    for part in parents:
        node = node.setdefault(part, {})
    node[leaf] = value
    with pytest.raises(Exception) as info:
        loads_scene(json.dumps(doc))
    assert f"0 or at least {limit}" in str(info.value) and key in str(info.value), str(info.value)
    node[leaf] = 0.0
    loads_scene(json.dumps(doc))


@pytest.mark.parametrize("name, key", [("fourbar_crank_rocker", "joints.1.at.0"),
                                       ("geneva_z4", "crank_center.1"),
                                       ("rolling_lever_press", "pin.0")])
def test_subnormal_coordinates_are_refused_everywhere(name, key):
    """A coordinate of 5e-324 mm (a subnormal float) made cmath.phase raise OverflowError in the
    dimensions panel (found by the monkey test): no coordinate may be subnormal, in a file or an
    edit (scalars have their own smallest values; a subnormal stroke start is read as given)."""
    doc = json.loads(example_path(name).read_text())
    node = doc["elements"][0]
    *parents, leaf = key.split(".")
    for part in parents:
        node = node[int(part)] if isinstance(node, list) else node.setdefault(part, {})
    node[int(leaf) if isinstance(node, list) else leaf] = -5e-324
    with pytest.raises(Exception) as info:
        loads_scene(json.dumps(doc))
    assert "subnormal" in str(info.value), str(info.value)
    ws = _ws()
    with pytest.raises(EditError, match="subnormal"):
        ws.apply(MoveJoint("fourbar", "E", (5e-324, 14000.0)))
