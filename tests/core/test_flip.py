"""Flipping a group's assembly mode redraws the pose: lengths kept, mode reversed, involutive."""
from __future__ import annotations

import math

import pytest

from mechsketch.core import load_scene
from mechsketch.core.errors import GeometryError
from mechsketch.core.solver.flip import flip_group, group_modes
from mechsketch.resources import example_path


def _lengths(lk):
    out = {}
    for link in lk.links:
        pts = [lk.joint(j).at for j in link.joints if lk.joint(j).kind.value == "R"]  # a P point slides
        out[link.id] = [math.dist(p, q) for p in pts for q in pts]
    return out


@pytest.mark.parametrize("name", ["fourbar_crank_rocker", "slider_crank_offset", "inverted_slider_crank",
                                  "sixbar_moving_guide", "double_rocker"])
def test_flip_reverses_the_mode_keeps_lengths_and_undoes_itself(name):
    lk = load_scene(example_path(name)).elements[0]
    for group, mode in group_modes(lk).items():
        flipped = flip_group(lk, group)
        assert group_modes(flipped)[group] == -mode
        for link, ds in _lengths(lk).items():
            assert _lengths(flipped)[link] == pytest.approx(ds, abs=1e-8)
        back = flip_group(flipped, group)
        for a, b in zip(lk.joints, back.joints):
            assert a.at == pytest.approx(b.at, abs=1e-8)


def test_groups_without_a_mode_cannot_be_flipped():
    lk = load_scene(example_path("fourbar_crank_rocker")).elements[0]
    with pytest.raises(GeometryError, match="no group 'nope'"):
        flip_group(lk, "nope")
