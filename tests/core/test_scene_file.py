"""Scene files: every bad input gets a message naming its JSON path and the id involved (never a
traceback), saving is atomic, load → save → load round-trips exactly."""
from __future__ import annotations

import copy
import json
import os
from pathlib import Path

import pytest

import linkage_builders as LB
from mechsketch.core import (ExportError, SceneFormatError, dumps_scene, load_scene, loads_scene,
                             save_scene, validate_file)
from mechsketch.core.cli import main as cli_main
from mechsketch.core.io import scene_file
from mechsketch.core.model.scene import SCHEMA_VERSION
from mechsketch.resources import example_path, example_paths

BASE = json.loads(example_path("slider_crank_offset").read_text(encoding="utf-8"))
# joints A B C S (S is P); links ground(A,S) crank(A,B) rod(B,C) slider(C,S)
EL = "$.elements[0]"


def el(doc):
    return doc["elements"][0]


def joint(doc, jid):
    return next(j for j in el(doc)["joints"] if j["id"] == jid)


def link(doc, lid):
    return next(k for k in el(doc)["links"] if k["id"] == lid)


class NewDoc:
    """Returned by a mutation that replaces the whole document."""

    def __init__(self, value):
        self.value = value


def mutated(f):
    doc = copy.deepcopy(BASE)
    out = f(doc)
    return out.value if isinstance(out, NewDoc) else doc


# (label, mutation returning a doc or raw text, expected path, expected id, message fragment)
BAD = [
    ("link names an unknown joint", lambda d: link(d, "rod")["joints"].__setitem__(1, "Z"),
     f"{EL}.links[2].joints[1]", "rod", "unknown joint 'Z'"),
    ("unknown ground", lambda d: el(d).__setitem__("ground", "floor"), f"{EL}.ground", "floor", "unknown link"),
    ("unknown driver link", lambda d: el(d)["driver"].__setitem__("link", "motor"), f"{EL}.driver.link", "motor",
     "unknown link"),
    ("unknown pivot", lambda d: el(d)["driver"].__setitem__("pivot", "O"), f"{EL}.driver.pivot", "O", "unknown joint"),
    ("duplicate joint id", lambda d: joint(d, "C").__setitem__("id", "B"), f"{EL}.joints[1].id", "B",
     "duplicate joint id 'B'"),
    ("duplicate link id", lambda d: link(d, "slider").__setitem__("id", "rod"), f"{EL}.links[2].id", "rod",
     "duplicate link id 'rod'"),
    ("duplicate element id", lambda d: d["elements"].append(copy.deepcopy(el(d))), "$.elements[1].id",
     "slider_crank", "duplicate element id"),
    ("joint on no link", lambda d: el(d)["joints"].append({"id": "X", "kind": "R", "at": [1, 2]}),
     f"{EL}.joints[4]", "X", "on no link"),
    ("P joint on one link", lambda d: link(d, "ground").__setitem__("joints", ["A"]), f"{EL}.joints[3]", "S",
     "exactly two links"),
    ("link lists a joint twice", lambda d: link(d, "rod").__setitem__("joints", ["B", "C", "B"]),
     f"{EL}.links[2].joints", "rod", "twice"),
    ("at is a string", lambda d: joint(d, "B").__setitem__("at", "40,0"), f"{EL}.joints[1].at", "B",
     "not of type 'array'"),
    ("at has three numbers", lambda d: joint(d, "B").__setitem__("at", [1, 2, 3]), f"{EL}.joints[1].at", "B",
     "too long"),
    ("coordinate is a string", lambda d: joint(d, "C").__setitem__("at", ["1", 2]), f"{EL}.joints[2].at[0]", "C",
     "not of type 'number'"),
    ("coordinate is a boolean", lambda d: joint(d, "C").__setitem__("at", [True, 2]), f"{EL}.joints[2].at[0]",
     "C", "not of type 'number'"),
    ("unknown joint kind", lambda d: joint(d, "B").__setitem__("kind", "H"), f"{EL}.joints[1].kind", "B",
     "is not one of"),
    ("missing at", lambda d: joint(d, "B").pop("at"), f"{EL}.joints[1]", "B", "'at' is a required property"),
    ("unknown key", lambda d: joint(d, "B").__setitem__("colour", "red"), f"{EL}.joints[1]", "B", "colour"),
    ("id is a number", lambda d: link(d, "rod").__setitem__("id", 7), f"{EL}.links[2].id", "slider_crank",
     "not of type 'string'"),
    ("joints is an object", lambda d: el(d).__setitem__("joints", {"A": [0, 0]}), f"{EL}.joints", "slider_crank",
     "not of type 'array'"),
    ("samples not an integer", lambda d: el(d).__setitem__("samples", 12.5), f"{EL}.samples", "slider_crank",
     "not of type 'integer'"),
    ("speed is text", lambda d: el(d)["driver"].__setitem__("speed_rpm", "fast"), f"{EL}.driver.speed_rpm",
     "slider_crank", "not of type 'number'"),
    ("P joint without axis", lambda d: joint(d, "S").pop("axis_deg"), f"{EL}.joints[3]", "S", "axis_deg"),
    ("R joint with an axis", lambda d: joint(d, "B").__setitem__("axis_deg", 30), f"{EL}.joints[1].axis_deg", "B",
     "only a P joint"),
    ("two revolute joints of a link at one point", lambda d: joint(d, "C").__setitem__("at", [40, 0]),
     f"{EL}.links[2]", "rod", "same point"),
    ("crank with only its pivot", lambda d: link(d, "crank").__setitem__("joints", ["A"]), f"{EL}.driver.link",
     "crank", "besides its pivot"),
    ("cylinder on a revolute joint", lambda d: el(d)["driver"].update(kind="cylinder", stroke=[10, 20]),
     f"{EL}.driver.pivot", "A", "prismatic"),
    ("actuator without a stroke", lambda d: el(d)["driver"].update(kind="slider", link="slider", pivot="S"),
     f"{EL}.driver", "slider", "needs a 'stroke'"),
    ("stroke that does not increase", lambda d: el(d)["driver"].update(kind="slider", link="slider", pivot="S",
                                                                         stroke=[20, -10]),
     f"{EL}.driver.stroke", "slider", "must increase"),
    ("crank with a stroke", lambda d: el(d)["driver"].__setitem__("stroke", [0, 10]), f"{EL}.driver.stroke", "crank",
     "no stroke"),
    ("slider guide off the frame", lambda d: el(d)["driver"].update(kind="slider", link="rod", pivot="B",
                                                                      stroke=[0, 10]),
     f"{EL}.driver.pivot", "B", "prismatic"),
    ("table law with two points", lambda d: el(d)["driver"].__setitem__("law", {"kind": "table",
                                                                                "points": [[0, 0], [0.5, 9]]}),
     f"{EL}.driver.law.points", "crank", "at least 3 points"),
    ("table law going back in time", lambda d: el(d)["driver"].__setitem__(
        "law", {"kind": "table", "points": [[0, 0], [0.5, 9], [0.25, 3]]}), f"{EL}.driver.law.points[2]", "crank",
     "must increase"),
    ("crank table closing on a part turn", lambda d: el(d)["driver"].__setitem__(
        "law", {"kind": "table", "points": [[0, 0], [0.5, 90], [1, 300]]}), f"{EL}.driver.law.points", "crank",
     "multiple of 360"),
    ("unknown motion law", lambda d: el(d)["driver"].__setitem__("law", {"kind": "sinusoid"}),
     f"{EL}.driver.law.kind", "slider_crank", "is not one of"),
    ("unknown driver kind", lambda d: el(d)["driver"].__setitem__("kind", "motor"), f"{EL}.driver.kind",
     "slider_crank", "is not one of"),
    ("driver pivot off the ground", lambda d: el(d)["driver"].__setitem__("pivot", "B"), f"{EL}.driver.pivot", "B",
     "not on the ground link"),
    ("driver pivot not on the driver", lambda d: el(d)["driver"].__setitem__("pivot", "C"), f"{EL}.driver.pivot",
     "C", "not a joint of driver"),
    ("driver pivot prismatic", lambda d: (link(d, "crank").__setitem__("joints", ["S", "B"]),
                                          el(d)["driver"].__setitem__("pivot", "S")),
     f"{EL}.driver.pivot", "S", "revolute"),
    ("driver is the ground", lambda d: el(d)["driver"].__setitem__("link", "ground"), f"{EL}.driver.link", "ground",
     "cannot be the ground"),
    ("zero speed", lambda d: el(d)["driver"].__setitem__("speed_rpm", 0), f"{EL}.driver.speed_rpm", "crank",
     "must not be zero"),
    ("unknown element type", lambda d: el(d).__setitem__("type", "gearbox"), "$.elements[0].type", "slider_crank",
     "gearbox"),
    ("newer file", lambda d: d.__setitem__("schema_version", SCHEMA_VERSION + 1), "$.schema_version", None, "newer"),
    ("version as text", lambda d: d.__setitem__("schema_version", "1"), "$.schema_version", None, "whole number"),
    ("version zero", lambda d: d.__setitem__("schema_version", 0), "$.schema_version", None, "whole number"),
    ("not a scene", lambda d: d.__setitem__("format", "dxf"), "$.format", None, "not a mechsketch scene"),
    ("no format tag", lambda d: d.pop("format"), "$.format", None, "not a mechsketch scene"),
    ("top level is a list", lambda d: NewDoc([d]), "$", None, "JSON object"),
    ("wrong units", lambda d: d.__setitem__("units", "inch"), "$.units", None, "'mm'"),
]

# raw text (not representable as a Python dict → json.dumps)
TEXT = json.dumps(BASE)
B_AT = '"at": [40, 0]'
assert B_AT in TEXT
BAD_TEXT = [
    ("NaN coordinate", TEXT.replace(B_AT, '"at": [NaN, 0]'), f"{EL}.joints[1].at[0]", "B", "finite"),
    ("Infinity coordinate", TEXT.replace(B_AT, '"at": [40, Infinity]'), f"{EL}.joints[1].at[1]", "B", "finite"),
    ("-Infinity speed", TEXT.replace('"speed_rpm": 95.4929658551372', '"speed_rpm": -Infinity'),
     f"{EL}.driver.speed_rpm", "slider_crank", "finite"),
    ("1e999 coordinate", TEXT.replace(B_AT, '"at": [1e999, 0]'), f"{EL}.joints[1].at[0]", "B", "finite"),
    ("integer too large for a float", TEXT.replace(B_AT, '"at": [1' + "0" * 400 + ', 0]'),
     f"{EL}.joints[1].at[0]", "B", "finite"),
    ("integer too large as speed", TEXT.replace('"speed_rpm": 95.4929658551372', '"speed_rpm": 9' + "9" * 330),
     f"{EL}.driver.speed_rpm", "slider_crank", "finite"),
    ("truncated JSON", TEXT[: len(TEXT) // 2], "$", None, "not valid JSON (line"),
    ("trailing comma", TEXT.replace('"units": "mm"', '"units": "mm",,'), "$", None, "not valid JSON"),
    ("empty file", "", "$", None, "not valid JSON"),
    ("not JSON at all", "PK\x03\x04 this is a zip", "$", None, "not valid JSON"),
    ("deeply nested", "[" * 100000 + "]" * 100000, "$", None, "JSON"),
    ("huge integer literal", '{"format": "mechsketch.scene", "schema_version": ' + "9" * 5000 + "}", "$", None,
     "not valid JSON"),
    ("nested just below the parser's limit", '{"format": "mechsketch.scene", "schema_version": 1, "elements": '
     '[{"type": "linkage", "id": "x", "joints": ' + "[" * 800 + "]" * 800 + "}]}", f"{EL}.joints[0]", "x",
     "not of type 'object'"),
]


def _problems_of_text(tmp_path, text: str | bytes):
    p = tmp_path / "bad.json"
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding="utf-8")
    return p, validate_file(p)


def _check(problems, path, id, fragment):
    hits = [p for p in problems if p.path == path]
    assert hits, f"no problem at {path}; got {[str(p) for p in problems]}"
    p = next((p for p in hits if fragment in p.message), None)
    assert p is not None, f"no message with {fragment!r} at {path}: {[str(p) for p in hits]}"
    assert p.id == id, f"{p!r}: expected id {id!r}"
    text = str(p)
    assert path in text and (id is None or f"[{id}]" in text)
    assert all(len(q.message) < 400 for q in problems), "messages quote at most a short excerpt"


@pytest.mark.parametrize("label,mutate,path,id,fragment", BAD, ids=[b[0] for b in BAD])
def test_bad_input_is_reported_with_path_and_id(tmp_path, label, mutate, path, id, fragment):
    doc = mutated(mutate)
    f, problems = _problems_of_text(tmp_path, json.dumps(doc))
    _check(problems, path, id, fragment)
    with pytest.raises(SceneFormatError) as info:
        load_scene(f)
    assert info.value.problems == problems
    assert isinstance(info.value, ValueError)
    with pytest.raises(SceneFormatError):
        loads_scene(json.dumps(doc))


@pytest.mark.parametrize("label,text,path,id,fragment", BAD_TEXT, ids=[b[0] for b in BAD_TEXT])
def test_bad_text_is_reported_with_path_and_id(tmp_path, label, text, path, id, fragment):
    f, problems = _problems_of_text(tmp_path, text)
    _check(problems, path, id, fragment)
    with pytest.raises(SceneFormatError) as info:
        load_scene(f)
    assert info.value.problems == problems
    with pytest.raises(SceneFormatError) as info:
        loads_scene(text)
    _check(info.value.problems, path, id, fragment)


def test_not_utf8(tmp_path):
    f, problems = _problems_of_text(tmp_path, b"\xff\xfe\x00{not utf8")
    _check(problems, "$", None, "not UTF-8")


def test_a_50_MB_file_is_refused_before_reading(tmp_path, monkeypatch):
    f = tmp_path / "huge.json"
    with open(f, "wb") as fh:          # sparse: no 50 MB written to disk
        fh.truncate(50 * 1024 * 1024)
    monkeypatch.setattr(Path, "read_bytes", lambda self: pytest.fail("a huge file must not be read"))
    problems = validate_file(f)
    _check(problems, "$", None, "MB")
    assert "52.4 MB" in problems[0].message and "limited to 10 MB" in problems[0].message


def test_missing_file_and_folder(tmp_path):
    _check(validate_file(tmp_path / "nope.json"), "$", None, "no such file")
    _check(validate_file(tmp_path), "$", None, "folder")


def test_every_problem_is_reported_not_just_the_first(tmp_path):
    doc = copy.deepcopy(BASE)
    link(doc, "rod")["joints"][1] = "Z"
    el(doc)["ground"] = "floor"
    joint(doc, "S").pop("axis_deg")
    problems = _problems_of_text(tmp_path, json.dumps(doc))[1]
    paths = {p.path for p in problems}
    assert {f"{EL}.links[2].joints[1]", f"{EL}.ground", f"{EL}.joints[3]"} <= paths


@pytest.mark.parametrize("argv_tail", [[], ["--summary"]])
def test_cli_never_shows_a_traceback_on_bad_files(tmp_path, capsys, argv_tail):
    cases = [json.dumps(mutated(b[1])) for b in BAD] + [b[1] for b in BAD_TEXT]
    for k, text in enumerate(cases):
        f = tmp_path / f"bad{k}.json"
        f.write_text(text, encoding="utf-8")
        for cmd in (["validate", str(f)], ["analyze", str(f)] + argv_tail):
            assert cli_main(cmd) == 1, (k, cmd)
            out, err = capsys.readouterr()
            assert "Traceback" not in out + err
            assert out + err


# -- examples and round trips --------------------------------------------------------------------
def test_every_example_validates():
    paths = example_paths()
    assert len(paths) >= 5
    for p in paths:
        assert validate_file(p) == [], p


@pytest.mark.parametrize("path", example_paths(), ids=lambda p: p.stem)
def test_round_trip_load_save_load(tmp_path, path):
    a = load_scene(path)
    out = tmp_path / "copy.json"
    save_scene(a, out)
    b = load_scene(out)
    assert b == a
    assert dumps_scene(b) == out.read_text(encoding="utf-8")
    save_scene(b, out)
    assert load_scene(out) == a


def test_round_trip_keeps_every_float_bit(tmp_path):
    lk = LB.slider_crank(xi=-90.0, pin=1e-300 + 3j, theta0=1e-7, offset=-0.0)
    lk = lk.with_joint(lk.joint("S").__class__("S", lk.joint("S").kind, lk.joint("S").at, 1 / 3))
    from mechsketch.core import Scene
    scene = Scene((LB.translated(lk, 0.1, 1e6),))
    out = tmp_path / "s.json"
    save_scene(scene, out)
    back = load_scene(out)
    assert back == scene
    for a, b in zip(back.elements[0].joints, scene.elements[0].joints):
        assert a.at == b.at and a.axis_deg == b.axis_deg


def test_derived_data_is_not_saved():
    text = dumps_scene(load_scene(example_path("fourbar_crank_rocker")))
    doc = json.loads(text)
    assert set(doc) == {"format", "schema_version", "units", "elements"}
    assert set(el(doc)) == {"type", "id", "joints", "links", "ground", "driver", "samples"}


# -- atomic save --------------------------------------------------------------------------------
def _scene():
    return load_scene(example_path("slider_crank_offset"))


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "scene.json"
    target.write_text("OLD CONTENT", encoding="utf-8")

    def full(fd):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(scene_file.os, "fsync", full)
    with pytest.raises(ExportError) as info:
        save_scene(_scene(), target)
    assert isinstance(info.value, OSError)
    assert str(target) in str(info.value) and "No space left" in str(info.value)
    assert target.read_text(encoding="utf-8") == "OLD CONTENT"
    assert sorted(os.listdir(tmp_path)) == ["scene.json"]


def test_failed_rename_keeps_the_old_file(tmp_path, monkeypatch):
    target = tmp_path / "scene.json"
    target.write_text("OLD", encoding="utf-8")

    def nope(a, b):
        raise PermissionError(13, "Permission denied")
    monkeypatch.setattr(scene_file.os, "replace", nope)
    with pytest.raises(ExportError, match="Permission denied"):
        save_scene(_scene(), target)
    assert target.read_text(encoding="utf-8") == "OLD"
    assert sorted(os.listdir(tmp_path)) == ["scene.json"]


def test_unwritable_paths(tmp_path):
    with pytest.raises(ExportError, match="nowhere"):
        save_scene(_scene(), tmp_path / "nowhere" / "scene.json")
    folder = tmp_path / "a_folder"
    folder.mkdir()
    (folder / "keep.txt").write_text("x")
    with pytest.raises(ExportError, match="a_folder"):
        save_scene(_scene(), folder)
    assert (folder / "keep.txt").read_text() == "x"
    assert sorted(os.listdir(folder)) == ["keep.txt"]
    with pytest.raises(ExportError):
        save_scene(_scene(), "/proc/mechsketch-cannot-write-here.json")


def test_successful_save_replaces_the_old_file(tmp_path):
    target = tmp_path / "scene.json"
    target.write_text("OLD", encoding="utf-8")
    save_scene(_scene(), target)
    assert load_scene(target) == _scene()
    assert sorted(os.listdir(tmp_path)) == ["scene.json"]
