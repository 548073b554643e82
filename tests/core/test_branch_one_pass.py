"""The one-pass branch-point search (issue 14) finds exactly the offsets of the former per-group
search (each group's whole chain re-run: tests/core/reference_branches.py): on the examples, on
the branch tests' mechanisms and on hypothesis-generated chains of dyads, some of them
parallelograms (a branch point per group, whose flips the groups after it must see)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import linkage_builders as LB
from chains import dyad_chain
from mechsketch.core import load_scene
from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver import branches
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_paths
from reference_branches import per_group_branch_points


def _same(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for name in a:
        assert np.array_equal(a[name], b[name]), (name, a[name], b[name])


def _linkages():
    for path in example_paths():
        for el in load_scene(path).elements:
            # actuator inputs (mm along a stroke) have their own search, drive.find_linear_branch_points
            if isinstance(el, Linkage) and not el.driver.linear:
                yield pytest.param(el, id=f"{path.stem}:{el.id}")
    for theta0 in (30.0, 123.0):   # parallelograms: two branch points each
        yield pytest.param(LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=theta0,
                                      mode=1 if math.sin(math.radians(theta0)) > 0 else -1),
                           id=f"parallelogram{theta0:g}")
    yield pytest.param(LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=0.0, mode=1),
                       id="parallelogram-drawn-at-crossing")
    yield pytest.param(LB.sixbar_guide(), id="sixbar_guide")
    yield pytest.param(LB.two_dyads(), id="two_dyads")
    yield pytest.param(dyad_chain(12), id="chain12")


@pytest.mark.parametrize("lk", list(_linkages()))
def test_one_pass_gives_the_per_group_offsets(lk):
    plan = compile_plan(lk)
    assert not (plan.drive is not None and plan.drive.linear)
    ref = per_group_branch_points(plan)
    _same(compile_plan(lk).branch_points(), ref)


def test_the_parallelogram_offsets_are_found_at_all():
    """The comparison above has something to compare: the parallelogram's two crossings (at crank
    angles 0 and 180 deg, closed form) are found by both searches."""
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0, mode=1)
    got = np.degrees(compile_plan(lk).branch_points()["RRR(coupler,rocker)"])
    assert got == pytest.approx([150.0, 330.0], abs=1e-4)


def parallelogram_chain(kinds: list[bool], wobble: list[tuple[float, float]], heights: list[float] | None = None,
                        crank: float = 10.0, span: float = 100.0) -> Linkage:
    """A crank then dyads k = 1..n hanging on the previous coupler joint and on ground pivot Gk
    at (k·span, ``heights[k-1]``): a parallelogram of the previous moving link (``kinds[k-1]``
    True: two branch points, where the previous link is parallel to G(k-1)Gk, so whether the
    previous groups' flips were applied moves them) or a general dyad drawn ``wobble[k-1]`` (mm)
    away from the dyad_chain's shape."""
    heights = heights or [0.0] * len(kinds)
    a = 1.0
    prev_pivot, prev_pin = 0j, crank * complex(math.cos(a), math.sin(a))
    joints = [("A", "R", (0.0, 0.0)), ("P0", "R", LB.xy(prev_pin))]
    links: dict[str, list[str]] = {"ground": ["A"], "crank": ["A", "P0"]}
    for k, (para, (dx, dy), h) in enumerate(zip(kinds, wobble, heights), start=1):
        g = complex(k * span, h)
        if para:   # Pk - Gk parallel and equal to the previous link: a parallelogram
            p = g + (prev_pin - prev_pivot)
        else:
            p = complex(k * span - 0.5 * span + dx, 0.8 * span + dy)
        joints.append((f"G{k}", "R", LB.xy(g)))
        joints.append((f"P{k}", "R", LB.xy(p)))
        links["ground"].append(f"G{k}")
        links[f"c{k}"] = [f"P{k - 1}", f"P{k}"]
        links[f"r{k}"] = [f"P{k}", f"G{k}"]
        prev_pivot, prev_pin = g, p
    return LB.build("pchain", joints, links, "ground", "crank", "A")


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.booleans(), st.floats(-20.0, 20.0), st.floats(-20.0, 20.0), st.floats(-40.0, 40.0)),
                min_size=1, max_size=7))
def test_one_pass_matches_per_group_on_generated_chains(dyads):
    lk = parallelogram_chain([d[0] for d in dyads], [(d[1], d[2]) for d in dyads], [d[3] for d in dyads])
    try:
        plan = compile_plan(lk)
    except MechsketchError:
        assume(False)
    _same(plan.branch_points(), per_group_branch_points(compile_plan(lk)))


def test_a_chain_of_parallelograms_has_branch_points_in_every_group():
    """The generated chains exercise flips: in a chain of parallelograms on tilted frames every
    group has its two crossings, where its input link is parallel to its frame G(k-1)Gk — at
    crank offsets that follow from the closed form only if every earlier group stayed a
    parallelogram through its own crossings (all links then keep the crank's direction)."""
    heights = [0.0, 30.0, -20.0, 10.0]
    lk = parallelogram_chain([True] * 4, [(0.0, 0.0)] * 4, heights)
    got = compile_plan(lk).branch_points()
    assert len(got) == 4 and all(v.size == 2 for v in got.values())
    pts = [0j] + [complex(100.0 * k, h) for k, h in enumerate(heights, start=1)]
    for k in range(1, 5):
        frame = math.atan2((pts[k] - pts[k - 1]).imag, (pts[k] - pts[k - 1]).real)
        expect = sorted(((frame - 1.0) % math.pi + m * math.pi) % (2 * math.pi) for m in (0, 1))
        assert got[f"RRR(c{k},r{k})"] == pytest.approx(expect, abs=1e-6), k
    _same(got, per_group_branch_points(compile_plan(lk)))


def test_one_pass_runs_each_group_once_at_the_reference_samples(monkeypatch):
    """Linear in the number of groups: on a 24-dyad chain (no candidate touches) each group runs
    once at the reference samples, against n(n+1)/2 group runs for the per-group search."""
    lk = dyad_chain(24)
    plan = compile_plan(lk)
    runs = []
    real = type(plan).run_steps

    def counting(self, inputs, order, idx, *a, **kw):
        idx = list(idx)
        runs.append(len(idx) if np.size(inputs) == branches.REF_SAMPLES else 0)
        return real(self, inputs, order, idx, *a, **kw)

    monkeypatch.setattr(type(plan), "run_steps", counting)
    plan.branch_points()
    assert sum(runs) == 24
    runs.clear()
    per_group_branch_points(compile_plan(lk))
    assert sum(runs) == 24 * 25 // 2


def _moved(lk: Linkage, joint: str, dx: float, dy: float) -> Linkage:
    from dataclasses import replace
    return replace(lk, joints=tuple(j.moved((j.at[0] + dx, j.at[1] + dy)) if j.id == joint else j
                                    for j in lk.joints))


@pytest.mark.parametrize("joint, dirty", [("P24", 1), ("P20", 5), ("P1", 24)])
def test_a_drag_searches_only_the_groups_it_reaches(monkeypatch, joint, dirty):
    """After a move, the re-sweep keeps the branch offsets and the reference-sample link states of
    the groups the moved joint does not reach: only the dirty groups run at the reference samples,
    and the offsets and the solution are a fresh plan's, bit for bit."""
    from mechsketch.core.solver.incremental import resweep

    lk = dyad_chain(24)
    old = compile_plan(lk).sweep(samples=720)
    new_lk = _moved(lk, joint, 0.7, -0.4)
    plan = compile_plan(new_lk, old.plan.groups)
    runs = []
    real = type(plan).run_steps

    def counting(self, inputs, order, idx, *a, **kw):
        idx = list(idx)
        if np.size(inputs) == branches.REF_SAMPLES:
            runs.extend(idx)
        return real(self, inputs, order, idx, *a, **kw)

    monkeypatch.setattr(type(plan), "run_steps", counting)
    sol = resweep(old, plan, {joint})
    assert len(runs) == dirty and len(set(runs)) == dirty
    fresh = compile_plan(new_lk)
    _same(plan.branch_points(), fresh.branch_points())
    full = fresh.sweep(samples=720)
    for j in new_lk.joint_ids:
        assert np.array_equal(sol.position(j), full.position(j), equal_nan=True)


def test_kept_reference_states_carry_the_flips_of_a_parallelogram_chain():
    """A chain of parallelograms on tilted frames then a general dyad: moving the last joint keeps
    every parallelogram's states (with their flips) and finds the last group's offsets, equal to
    a fresh search's and to the per-group reference."""
    from mechsketch.core.solver.incremental import resweep

    lk = parallelogram_chain([True, True, True, False], [(0.0, 0.0)] * 3 + [(5.0, -3.0)], [0.0, 30.0, -20.0, 10.0])
    old = compile_plan(lk).sweep(samples=720)
    new_lk = _moved(lk, "P4", 1.5, 0.5)
    plan = compile_plan(new_lk, old.plan.groups)
    sol = resweep(old, plan, {"P4"})
    fresh = compile_plan(new_lk)
    _same(plan.branch_points(), fresh.branch_points())
    _same(plan.branch_points(), per_group_branch_points(compile_plan(new_lk)))
    full = fresh.sweep(samples=720)
    for j in new_lk.joint_ids:
        assert np.array_equal(sol.position(j), full.position(j), equal_nan=True)
