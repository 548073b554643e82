"""The fast schema check (core/io/schema_check.py) accepts exactly what jsonschema accepts.

Differential: every example scene, and random mutations of them (hypothesis), checked against
each shipped schema by both; a disagreement would let a bad scene through or refuse a good one
(the messages users read always come from jsonschema: tests/core/test_scene_file.py).
"""
from __future__ import annotations

import copy
import json
from pathlib import Path

import jsonschema
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mechsketch.core.io import scene_file
from mechsketch.core.io.schema_check import Unsupported, compile_schema
from mechsketch.core.io.scene_file import _fast_check, _flat_schema, migrate

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "resources" / "examples").glob("*.json"))
ELEMENT_SCHEMAS = ("linkage.schema.json", "geneva.schema.json", "rolling_lever.schema.json")
SCHEMAS = ("scene.schema.json",) + ELEMENT_SCHEMAS


def _docs() -> list[dict]:
    return [migrate(json.loads(p.read_text())) for p in EXAMPLES]


DOCS = _docs()


def _jsonschema_ok(name: str, data) -> bool:
    return not list(jsonschema.Draft202012Validator(_flat_schema(name)).iter_errors(data))


def _agree(data_by_schema: list[tuple[str, object]]) -> None:
    for name, data in data_by_schema:
        fast = _fast_check(name)
        assert fast is not None, name
        assert fast(data) == _jsonschema_ok(name, data), (name, json.dumps(data)[:400])


def _cases(doc: dict) -> list[tuple[str, object]]:
    """The whole document against the scene schema, each element against every element schema."""
    out = [("scene.schema.json", doc)]
    elements = doc.get("elements") if isinstance(doc, dict) else None
    for el in elements if isinstance(elements, list) else []:
        out += [(name, el) for name in ELEMENT_SCHEMAS]
    return out


def test_every_shipped_schema_compiles():
    for name in SCHEMAS:
        assert _fast_check(name) is not None, name


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_accepted_by_both(path):
    doc = migrate(json.loads(path.read_text()))
    ok = [(n, d) for n, d in _cases(doc) if n == "scene.schema.json" or d["type"] + ".schema.json" == n]
    for name, data in ok:
        assert _fast_check(name)(data) and _jsonschema_ok(name, data), (path.name, name)
    _agree(_cases(doc))   # an element against the other types' schemas: both refuse


def test_jsonschema_semantics_kept():
    """The corner cases of JSON Schema the check must get as jsonschema does."""
    cases = [
        ({"type": "integer"}, 2.0, True), ({"type": "integer"}, 2.5, False), ({"type": "integer"}, True, False),
        ({"type": "number"}, True, False), ({"type": "number"}, 10**400, True),
        ({"enum": [1]}, True, False), ({"enum": [1]}, 1.0, True), ({"const": "a"}, "a", True),
        ({"const": False}, 0, False), ({"minimum": 0}, "x", True), ({"minimum": 0}, -1e-300, False),
        ({"maximum": 1}, 1, True), ({"minItems": 2}, {"a": 1}, True), ({"maxLength": 2}, "é€x", False),
        ({"pattern": "^a"}, "ba", False), ({"pattern": "a"}, "ba", True), ({"pattern": "^a"}, 3, True),
        ({"required": ["a"]}, [], True), ({"required": ["a"]}, {}, False),
        ({"properties": {"a": {"type": "string"}}, "additionalProperties": False}, {"a": "x", "b": 1}, False),
        ({"properties": {"a": {"type": "string"}}, "additionalProperties": False}, {"a": "x"}, True),
        ({"items": {"type": "number"}}, [1, "2"], False), ({"type": ["string", "null"]}, None, True),
    ]
    for schema, value, expected in cases:
        assert _jsonschema_ok_dict(schema, value) == expected, (schema, value)
        assert compile_schema(schema)(value) == expected, (schema, value)


def _jsonschema_ok_dict(schema: dict, value) -> bool:
    return not list(jsonschema.Draft202012Validator(schema).iter_errors(value))


def test_unsupported_keywords_refused():
    for schema in ({"oneOf": [{"type": "string"}]}, {"prefixItems": [], "items": {}}, {"format": "email"},
                   {"enum": [[1]]}, {"$ref": "#/$defs/x"}):
        with pytest.raises(Unsupported):
            compile_schema(schema)


REPLACEMENTS = [None, True, False, 0, 1, -1, 2, 2.0, 0.5, -0.5, 3.7, 1e9, -1e9, 1e300, 10**30, "", "x", " a",
                "a ", "a\nb", "linkage", "geneva", "rolling_lever", "crank", "mm", "R", "P", "x" * 70, [], {},
                [0, 0], [1.0, 2.0, 3.0], ["a"], {"id": "q"}]


def _paths(node, prefix=()):
    """Every (container path, key) in a JSON tree."""
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
def mutated(draw):
    doc = copy.deepcopy(draw(st.sampled_from(DOCS)))
    for _ in range(draw(st.integers(1, 3))):
        paths = list(_paths(doc))
        if not paths:
            break
        parent_path, key = draw(st.sampled_from(paths))
        parent = _get(doc, parent_path)
        op = draw(st.sampled_from(["replace", "replace", "replace", "delete", "add", "dup", "nudge"]))
        if op == "replace":
            parent[key] = copy.deepcopy(draw(st.sampled_from(REPLACEMENTS)))
        elif op == "delete":
            del parent[key]
        elif op == "add":
            if isinstance(parent, dict):
                parent[draw(st.sampled_from(["extra", "id", "type", "x", "units"]))] = draw(
                    st.sampled_from(REPLACEMENTS[:12]))
            else:
                parent.append(copy.deepcopy(parent[key]))
        elif op == "dup" and isinstance(parent, list):
            parent.insert(key, copy.deepcopy(parent[key]))
        elif op == "nudge" and isinstance(parent[key], (int, float)) and not isinstance(parent[key], bool):
            parent[key] = parent[key] * draw(st.sampled_from([-1, 0, 1e-9, 1e6, 1.5]))
    return doc


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated())
def test_fast_check_agrees_with_jsonschema_on_mutations(doc):
    _agree(_cases(doc))


def test_reader_messages_still_from_jsonschema():
    """A rejected document is explained by jsonschema, unchanged: same problems as jsonschema's own."""
    doc = copy.deepcopy(DOCS[0])
    doc["elements"][0]["samples"] = "many"
    doc["elements"][0]["bogus"] = 1
    problems = scene_file._schema_problems("linkage.schema.json", doc["elements"][0], "$.elements[0]",
                                           doc["elements"][0]["id"])
    errs = list(jsonschema.Draft202012Validator(_flat_schema("linkage.schema.json")).iter_errors(doc["elements"][0]))
    assert len(problems) == len(errs) == 2
    assert any("unknown key(s)" in p.message and "'bogus'" in p.message for p in problems)
    assert any("'many' is not of type" in p.message for p in problems)
