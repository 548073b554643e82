"""A live drag re-sweeps from the previous solution (core/solver/incremental.py), reusing the link
states of the groups the moved joint does not reach. Those states cache the points and rates the
kernels and the extraction read, keyed by drawn position: a joint dragged over a reused link (a
slider's guide point on the six-bar's rocker) must not leave one cache entry, (N,) arrays, per
move behind — a long drag would grow memory without bound — and the results must stay a fresh
solve's, bit for bit."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from mechsketch.core import load_scene
from mechsketch.core.solver import branches
from mechsketch.core.solver.incremental import resweep
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


def _moved(lk, jid: str, dx: float, dy: float):
    joints = tuple(j.moved((j.at[0] + dx, j.at[1] + dy)) if j.id == jid else j for j in lk.joints)
    return replace(lk, joints=joints)


def test_dragging_a_guide_point_keeps_the_reused_states_caches_bounded():
    lk = load_scene(example_path("sixbar_moving_guide")).elements[0]
    sol = compile_plan(lk).sweep(360, order=2)
    rocker = sol.link_state("rocker")
    for k in range(60):
        new = _moved(lk, "Q", 0.02 * (k + 1), 0.0)
        nxt = resweep(sol, compile_plan(new, sol.plan.groups), {"Q"})
        assert nxt is not None and nxt.link_state("rocker") is rocker    # the shortcut is taken
        for j in new.joint_ids:
            nxt.position(j), nxt.velocity(j), nxt.acceleration(j)        # the extraction reads too
        sol = nxt
    n_joints = len(lk.joint_ids)
    assert len(rocker._points or {}) <= n_joints and len(rocker._rates or {}) <= n_joints
    # and the branch-point search's states at its reference inputs, kept across the drag too
    ref = getattr(sol.plan.local(), branches.REF_STATES)
    assert "rocker" in ref
    for st in ref.values():
        assert len(st._points or {}) <= n_joints and len(st._rates or {}) <= n_joints
    fresh = compile_plan(new).sweep(360, order=2)
    for j in new.joint_ids:
        assert np.array_equal(sol.position(j), fresh.position(j))
        assert np.array_equal(sol.velocity(j), fresh.velocity(j))
        assert np.array_equal(sol.acceleration(j), fresh.acceleration(j))
