"""Placing one scene inside another: translation of every element type (results move with it),
fresh ids where they collide."""
from __future__ import annotations

import numpy as np
import pytest

from mechsketch.core import load_scene
from mechsketch.core.errors import EditError
from mechsketch.core.model.transform import extent, fresh_id, placed, translated
from mechsketch.core.workspace import Workspace
from mechsketch.core.model.scene import Scene
from mechsketch.resources import example_path


def _el(name):
    return load_scene(example_path(name)).elements[0]


@pytest.mark.parametrize("name", ["fourbar_crank_rocker", "geneva_z6", "rolling_lever_press", "sixbar_moving_guide"])
def test_a_translated_element_moves_rigidly_with_its_results(name):
    el = _el(name)
    dx, dy = 123.5, -40.25
    moved = translated(el, dx, dy)
    a, b = Workspace(Scene((el,))).result(el.id), Workspace(Scene((moved,))).result(el.id)
    assert a.error is None and b.error is None
    if el.type == "linkage":
        for j in el.joint_ids:
            np.testing.assert_allclose(b.solution.position(j), a.solution.position(j) + [dx, dy], atol=1e-9)
    elif el.type == "geneva":
        assert moved.wheel_center == pytest.approx((el.wheel_center[0] + dx, el.wheel_center[1] + dy))
        np.testing.assert_array_equal(b.wheel_rotation, a.wheel_rotation)
    else:
        np.testing.assert_allclose(b.frames.P, a.frames.P + [dx, dy], atol=1e-7)
        np.testing.assert_allclose(b.frames.S5, a.frames.S5, atol=1e-7)
    x0, y0, x1, y1 = extent(el)
    assert extent(moved) == pytest.approx((x0 + dx, y0 + dy, x1 + dx, y1 + dy))


def test_placed_renames_only_colliding_ids_and_centres_on_the_click():
    els = [_el("fourbar_crank_rocker"), _el("geneva_z6")]
    out = placed(els, (500.0, 300.0), taken=["fourbar", "fourbar2", "press"])
    assert [e.id for e in out] == ["fourbar3", "indexer"]
    boxes = [extent(e) for e in out]
    cx = (min(b[0] for b in boxes) + max(b[2] for b in boxes)) / 2
    cy = (min(b[1] for b in boxes) + max(b[3] for b in boxes)) / 2
    assert (cx, cy) == pytest.approx((500.0, 300.0))
    assert fresh_id("a", []) == "a" and fresh_id("a", ["a", "a2"]) == "a3"


def test_an_unknown_element_type_is_refused_by_name():
    class Odd:
        id, type = "x", "odd"

    with pytest.raises(EditError, match="'odd'"):
        translated(Odd(), 1.0, 2.0)
