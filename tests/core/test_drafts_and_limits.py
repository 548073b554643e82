"""A linkage saved while still being drawn reopens; validate also checks structure; size limits."""
from __future__ import annotations

import json

import pytest

from mechsketch.core import (Driver, Joint, JointKind, Link, Linkage, Scene, SceneFormatError,
                             StructureError, load_scene, save_scene)
from mechsketch.core.cli import main
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


def _draft() -> Linkage:
    joints = (Joint("A", JointKind.R, (0.0, 0.0)), Joint("B", JointKind.R, (40.0, 0.0)))
    # the tools give a draft a placeholder driver until the crank is drawn
    return Linkage("sketch", joints, (Link("ground", ("A",)), Link("bar", ("A", "B"))), "ground",
                   Driver("crank", "A", 60.0))


def test_a_draft_without_crank_saves_as_null_driver_and_reopens(tmp_path):
    path = tmp_path / "draft.json"
    save_scene(Scene((_draft(),)), path)
    assert json.loads(path.read_text())["elements"][0]["driver"] is None
    again = load_scene(path).element("sketch")
    assert not again.has_driver
    assert [j.at for j in again.joints] == [(0.0, 0.0), (40.0, 0.0)]
    with pytest.raises(StructureError, match="no driver yet.*crank"):
        compile_plan(again)
    save_scene(Scene((again,)), tmp_path / "again.json")
    assert (tmp_path / "again.json").read_text() == path.read_text()


def test_validate_reports_a_draft_and_a_wrong_mobility(tmp_path, capsys):
    path = tmp_path / "draft.json"
    save_scene(Scene((_draft(),)), path)
    assert main(["validate", str(path)]) == 1
    assert "no driver yet" in capsys.readouterr().out
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    doc["elements"][0]["links"].append({"id": "extra", "joints": ["B", "D"]})  # over-constrained
    bad = tmp_path / "stiff.json"
    bad.write_text(json.dumps(doc))
    assert main(["validate", str(bad)]) == 1
    out = capsys.readouterr().out
    assert "mobility 0" in out and "$.elements[0]" in out


def test_a_named_driver_that_does_not_exist_is_still_an_error(tmp_path):
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    doc["elements"][0]["driver"]["link"] = "nope"
    p = tmp_path / "x.json"
    p.write_text(json.dumps(doc))
    with pytest.raises(SceneFormatError, match=r"driver\.link.*unknown link 'nope'"):
        load_scene(p)


def test_coordinates_beyond_a_billion_mm_are_refused(tmp_path):
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    doc["elements"][0]["joints"][1]["at"] = [1e154, 0.0]
    p = tmp_path / "far.json"
    p.write_text(json.dumps(doc))
    with pytest.raises(SceneFormatError, match=r"joints\[1\]\.at \[B\]: position .* beyond"):
        load_scene(p)


def test_sample_counts_are_bounded(tmp_path, capsys):
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    doc["elements"][0]["samples"] = 10_000_000
    p = tmp_path / "many.json"
    p.write_text(json.dumps(doc))
    with pytest.raises(SceneFormatError, match=r"samples.*1000000"):
        load_scene(p)
    assert main(["analyze", str(example_path("fourbar_crank_rocker")), "--samples", "5000000"]) == 1
    assert "--samples must be from 2 to 1,000,000" in capsys.readouterr().err


def test_nearly_coincident_joints_far_from_the_origin_are_distinct():
    """Coincidence is judged against the link's own span, not against the coordinates' size."""
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    for j in doc["elements"][0]["joints"]:
        j["at"] = [j["at"][0] + 1e6, j["at"][1] + 1e6]
    from mechsketch.core import loads_scene

    lk = loads_scene(json.dumps(doc)).elements[0]
    assert compile_plan(lk).sweep(samples=90).valid.all()
