"""An edit's element check that looks only at what changed (core/io/schema_delta.py,
``element_problems_since``) gives exactly the scene reader's answer and messages.

Differential: each example element mutated at random (hypothesis: leaves replaced, keys added or
deleted, items duplicated, numbers nudged, NaN and subnormals put in), checked knowing the
original object and the whole way; and a workspace that refuses a bad edit with the same message
as before, and accepts a drag's edit checking only the moved joint against the schema.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mechsketch.core import EditError, MoveJoint, Workspace
from mechsketch.core.io import scene_file
from mechsketch.core.io.scene_file import _data_problems, _data_problems_since, dump_element, migrate

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "resources" / "examples").glob("*.json"))
ELEMENTS = [el for p in EXAMPLES for el in migrate(json.loads(p.read_text()))["elements"]]
REPLACEMENTS = [None, True, False, 0, 1, -1, 2.0, 0.5, -0.5, 1e9, -1e9, 1e300, 10**400, math.nan, math.inf,
                5e-324, "", "x", "R", "P", "crank", [], {}, [0, 0], [1.0, 2.0, 3.0], {"id": "q"}]


def _paths(node, prefix=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield prefix, k
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield prefix, i
            yield from _paths(v, prefix + (i,))


def _get(node, path):
    for k in path:
        node = node[k]
    return node


@st.composite
def edited(draw):
    known = draw(st.sampled_from(ELEMENTS))
    data = copy.deepcopy(known)
    for _ in range(draw(st.integers(1, 3))):
        parent_path, key = draw(st.sampled_from(list(_paths(data))))
        parent = _get(data, parent_path)
        op = draw(st.sampled_from(["replace", "replace", "nudge", "nudge", "delete", "add"]))
        if op == "replace":
            parent[key] = copy.deepcopy(draw(st.sampled_from(REPLACEMENTS)))
        elif op == "nudge" and isinstance(parent[key], float):
            parent[key] = parent[key] + draw(st.sampled_from([-1e6, -10.0, -1.0, 0.25, 3.0, 1e6]))
        elif op == "delete":
            del parent[key]
        elif op == "add":
            if isinstance(parent, dict):
                parent[draw(st.sampled_from(["extra", "x", "units", "label"]))] = draw(st.sampled_from(REPLACEMENTS[:10]))
            else:
                parent.append(copy.deepcopy(parent[key]))
    return known, data


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(edited())
def test_checking_what_changed_gives_the_readers_answer(case):
    known, data = case
    assert _data_problems(known) == []
    assert _data_problems_since(copy.deepcopy(data), known) == _data_problems(copy.deepcopy(data))


def test_every_example_element_unchanged_or_nudged_is_accepted():
    for known in ELEMENTS:
        assert _data_problems_since(copy.deepcopy(known), known) == []


@pytest.fixture
def sixbar():
    ws = Workspace.open(next(p for p in EXAMPLES if p.stem == "sixbar_moving_guide"))
    return ws, next(e for e in ws.scene.elements if e.type == "linkage")


def test_a_bad_edit_is_refused_with_the_same_message(sixbar, monkeypatch):
    ws, lk = sixbar
    joint = lk.joints[-1].id
    ws.apply(MoveJoint(lk.id, joint, (12.0, 34.0)))   # its object is now kept with it
    with pytest.raises(EditError) as fast:
        ws.apply(MoveJoint(lk.id, joint, (math.nan, 1.0)))
    monkeypatch.setattr(ws, "_valid_data", lambda el: None)   # the whole way, as before
    with pytest.raises(EditError) as whole:
        ws.apply(MoveJoint(lk.id, joint, (math.nan, 1.0)))
    assert str(fast.value) == str(whole.value) and "finite" in str(fast.value)


def test_a_drag_edit_checks_only_the_moved_joint(sixbar, monkeypatch):
    ws, lk = sixbar
    joint = lk.joints[-1].id
    ws.apply(MoveJoint(lk.id, joint, (12.0, 34.0)))
    seen = []
    monkeypatch.setattr(scene_file, "_nonfinite", lambda node, path, out, id=None: seen.append(path))
    monkeypatch.setattr(scene_file, "_data_problems", lambda data: pytest.fail("checked the whole element"))
    ws.apply(MoveJoint(lk.id, joint, (13.0, 35.0)))
    new = ws.element(lk.id)
    assert seen and all(".joints[" in p for p in seen), seen
    assert dump_element(new)["joints"][-1]["at"] == [13.0, 35.0]
