"""The dead points a live drag marks (``sampled_dead_points``: the samples' resolution, no
re-solve) are those the refined diagnostics find: the same groups and kinds, each within one
sample of the refined input (mod 2π)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core import load_scene
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver.diagnostics import DeadPointKind, diagnose, sampled_dead_points
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path
from test_solver_hard import toggle_case


def _cases():
    yield pytest.param(load_scene(example_path("double_rocker")).element("double_rocker"), {DeadPointKind.LIMIT},
                       id="double_rocker-limits")
    yield pytest.param(LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0),
                       {DeadPointKind.CHANGE_POINT}, id="parallelogram-change-points")
    for kind in ("RRR", "RRP", "RPR"):   # passes 1e-6 mm from a toggle (tests/core/test_solver_hard.py)
        yield pytest.param(toggle_case(kind, 1e-6, 1)[0], {DeadPointKind.TOGGLE}, id=f"near-toggle-{kind}")
    yield pytest.param(load_scene(example_path("sixbar_moving_guide")).element("sixbar"), set(), id="sixbar-none")


@pytest.mark.parametrize("samples", [360, 3600])
@pytest.mark.parametrize("lk, kinds", list(_cases()))
def test_sampled_dead_points_are_the_refined_ones_within_a_sample(lk: Linkage, kinds, samples):
    sol = compile_plan(lk).sweep(samples=samples, order=2)
    refined = diagnose(sol).dead_points
    got = sampled_dead_points(sol)
    assert {d.kind for d in refined} == kinds          # the cases have what they are named for
    assert len(got) == len(refined)
    step = 2 * math.pi / samples
    for d in got:
        near = [r for r in refined if r.group == d.group and r.kind == d.kind
                and abs(math.remainder(r.input - d.input, 2 * math.pi)) <= step * (1 + 1e-9)]
        assert near, (d, refined)
    # each refined one has its sampled one (a one-to-one match)
    for r in refined:
        assert any(d.group == r.group and d.kind == r.kind
                   and abs(math.remainder(r.input - d.input, 2 * math.pi)) <= step * (1 + 1e-9) for d in got)
    assert all(np.isfinite(d.input) for d in got)
