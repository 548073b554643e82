"""The registry of element kinds (core/model/kinds.py): every type a scene file may hold is there
with its schema file, its parser and its writer, and the three agree on every example."""
from __future__ import annotations

import json

import pytest

from mechsketch import resources
from mechsketch.core.io.scene_file import dump_element, dumps_scene, load_scene, loads_scene
from mechsketch.core.model.kinds import ELEMENT_KINDS, element_kind
from mechsketch.resources import example_paths

SCHEMA_DIR = resources.__path__[0] + "/schema"


def test_every_kind_names_its_own_schema_file_and_type():
    for name, kind in ELEMENT_KINDS.items():
        assert kind.type == name
        schema = json.loads(open(f"{SCHEMA_DIR}/{kind.schema}", encoding="utf-8").read())
        assert isinstance(schema, dict) and schema
    assert element_kind("no_such_type") is None


@pytest.mark.parametrize("path", example_paths(), ids=lambda p: p.stem)
def test_parse_then_dump_gives_back_the_file_and_the_same_records(path):
    scene = load_scene(path)
    for el, raw in zip(scene.elements, json.loads(path.read_text(encoding="utf-8"))["elements"]):
        kind = element_kind(el.type)
        again, problems = kind.parse(dump_element(el), "$")
        assert problems == [] and again == el
        assert kind.dump(el)["type"] == raw["type"] == el.type
    assert loads_scene(dumps_scene(scene)) == scene


def test_the_scene_schema_lists_exactly_the_registered_kinds():
    scene_schema = json.loads(open(f"{SCHEMA_DIR}/scene.schema.json", encoding="utf-8").read())
    enums = [v["enum"] for v in _walk(scene_schema) if isinstance(v, dict) and "enum" in v
             and "linkage" in v["enum"]]
    assert enums and all(e == list(ELEMENT_KINDS) for e in enums)


def _walk(node):
    yield node
    children = node.values() if isinstance(node, dict) else node if isinstance(node, list) else ()
    for child in children:
        yield from _walk(child)


def test_an_unknown_type_is_refused_by_name():
    doc = {"format": "mechsketch.scene", "schema_version": 2, "units": "mm",
           "elements": [{"type": "cam", "id": "c"}]}
    with pytest.raises(ValueError, match=r"\$\.elements\[0\]\.type \[c\]: 'cam' is not one of"):
        loads_scene(json.dumps(doc))
