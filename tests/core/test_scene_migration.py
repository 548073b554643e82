"""Scene format versions: version 1 files (kept as fixtures in tests/fixtures/scenes_v1, copies of
the examples as they shipped before version 2) and version 2 files (tests/fixtures/scenes_v2, the
examples as they shipped before version 3) load unchanged, re-save as the current version and load
back equal; the migrations leave their input alone and leave malformed documents to the schema."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

from mechsketch.core import dumps_scene, load_scene, loads_scene, save_scene
from mechsketch.core.io.scene_file import migrate, scene_from_dict
from mechsketch.core.model.drivers import DriverKind
from mechsketch.core.model.scene import SCHEMA_VERSION
from mechsketch.resources import example_path

V1 = sorted((Path(__file__).parent.parent / "fixtures" / "scenes_v1").glob("*.json"))
V2 = sorted((Path(__file__).parent.parent / "fixtures" / "scenes_v2").glob("*.json"))


def test_there_are_version_1_and_2_fixtures():
    assert len(V1) >= 11 and len(V2) >= 14
    assert SCHEMA_VERSION == 3


@pytest.mark.parametrize("path", V2, ids=lambda p: p.stem)
def test_a_version_2_file_loads_and_resaves_as_version_3_with_the_same_elements(tmp_path, path):
    """Version 3 only adds optional content: the migration changes the number and nothing else."""
    raw = json.loads(path.read_text(encoding="utf-8"))
    assert raw["schema_version"] == 2
    before = copy.deepcopy(raw)
    assert migrate(raw) == {**before, "schema_version": 3} and raw == before
    scene = load_scene(path)
    out = tmp_path / path.name
    save_scene(scene, out)
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["schema_version"] == 3
    assert doc["elements"] == json.loads(dumps_scene(load_scene(path)))["elements"]
    assert load_scene(out) == scene == load_scene(example_path(path.stem))


@pytest.mark.parametrize("path", V1, ids=lambda p: p.stem)
def test_a_version_1_file_loads_resaves_as_the_current_version_and_loads_back_equal(tmp_path, path):
    raw = json.loads(path.read_text(encoding="utf-8"))
    assert raw["schema_version"] == 1
    scene = load_scene(path)
    out = tmp_path / path.name
    save_scene(scene, out)
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["schema_version"] == SCHEMA_VERSION
    for ed, old in zip(doc["elements"], raw["elements"]):
        if ed["type"] == "linkage":
            assert ed["driver"]["kind"] == "crank"
            assert {k: v for k, v in ed["driver"].items() if k != "kind"} == old["driver"]
            assert ed["joints"] == old["joints"] and ed["links"] == old["links"]
        else:
            assert ed == old
    again = load_scene(out)
    assert again == scene
    assert dumps_scene(again) == out.read_text(encoding="utf-8")


@pytest.mark.parametrize("path", V1, ids=lambda p: p.stem)
def test_the_shipped_example_is_the_version_1_file_migrated(path):
    """The examples in resources/ (version 2) hold what their version 1 files held."""
    assert load_scene(example_path(path.stem)) == load_scene(path)


def test_every_version_1_linkage_is_a_constant_speed_crank():
    for path in V1:
        for el in load_scene(path).elements:
            if el.type == "linkage":
                assert el.driver.kind is DriverKind.CRANK and el.driver.law.is_constant
                assert el.driver.stroke is None


def test_migration_does_not_change_its_input():
    doc = json.loads(V1[0].read_text(encoding="utf-8"))
    before = copy.deepcopy(doc)
    out = migrate(doc)
    assert doc == before
    assert out["schema_version"] == SCHEMA_VERSION


@pytest.mark.parametrize("elements", [
    "not a list", [1, 2], [{"type": "linkage", "driver": "crank"}], [{"type": "linkage"}],
    [{"type": "linkage", "id": "x", "driver": None}],
], ids=["string", "numbers", "driver-string", "no-driver", "null-driver"])
def test_a_malformed_version_1_document_gets_problems_not_a_traceback(elements):
    doc = {"format": "mechsketch.scene", "schema_version": 1, "units": "mm", "elements": elements}
    scene, problems = scene_from_dict(doc)
    assert scene is None and problems
    assert all(p.path.startswith("$") for p in problems)


def test_a_version_2_driver_must_say_its_kind():
    doc = json.loads(example_path("fourbar_crank_rocker").read_text(encoding="utf-8"))
    doc = migrate(doc)
    del doc["elements"][0]["driver"]["kind"]
    scene, problems = scene_from_dict(doc)
    assert scene is None
    assert any(p.path == "$.elements[0].driver" and "'kind' is a required property" in p.message for p in problems)


def test_a_version_2_text_round_trips():
    scene = load_scene(example_path("sixbar_moving_guide"))
    assert loads_scene(dumps_scene(scene)) == scene


#: the examples as they shipped in version 2 (copies, so they stay version 2 files)
V2 = sorted((Path(__file__).parent.parent / "fixtures" / "scenes_v2").glob("*.json"))


def test_there_are_version_2_fixtures():
    assert len(V2) >= 14


@pytest.mark.parametrize("path", V2, ids=lambda p: p.stem)
def test_a_version_2_file_migrates_to_3_unchanged_and_resaves_as_3(tmp_path, path):
    raw = json.loads(path.read_text(encoding="utf-8"))
    assert raw["schema_version"] == 2
    out = migrate(raw)
    assert out == {**raw, "schema_version": 3} and raw["schema_version"] == 2
    scene = load_scene(path)
    save_scene(scene, tmp_path / path.name)
    assert json.loads((tmp_path / path.name).read_text(encoding="utf-8"))["schema_version"] == 3
    assert load_scene(tmp_path / path.name) == scene
