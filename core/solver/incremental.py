"""Re-solve a linkage after some of its joints moved, running only the groups that depend on them.

A drag moves one joint (or a few) of a linkage whose topology stays the same. The groups that do
not use a moved joint, and do not hang on a group that does, see exactly the same inputs as
before: their link states, outputs and branch points are reused from the previous solution, and
only the *dirty* groups — those with a moved joint, and everything downstream of them — run again.

The result is the solution a full :meth:`~mechsketch.core.solver.plan.Plan.evaluate` of the new
plan would give, bit for bit, or ``None`` when the shortcut does not apply (the topology or the
driver changed; the old solution was partial). The caller then solves in full. A group whose
rounding tolerance changed (it follows the coordinates of the group and of the links it hangs on)
runs again like a moved one.
"""
from __future__ import annotations

import time
from typing import Iterable

import numpy as np

from ..model.linkage import Linkage
from .branches import keep_reference_states
from .plan import Plan, Solution


def topology_key(linkage: Linkage) -> tuple:
    """What the structural decomposition depends on: joint ids and kinds, links, ground, driver
    (its link, pivot and kind).

    Two linkages with equal keys decompose into the same groups (only drawn positions differ).
    """
    drv = linkage.driver
    return (tuple((j.id, j.kind) for j in linkage.joints), tuple((k.id, k.joints) for k in linkage.links),
            linkage.ground, drv.link, drv.pivot, drv.kind)


def moved_joints(old: Linkage, new: Linkage) -> frozenset[str] | None:
    """Ids of the joints whose drawn position or slide axis differ between ``old`` and ``new``;
    None when the two differ in anything else (topology, driver speed, samples)."""
    if (topology_key(old) != topology_key(new) or old.driver != new.driver
            or old.samples != new.samples):
        return None
    return frozenset(a.id for a, b in zip(old.joints, new.joints) if a != b)


def dirty_steps(plan: Plan, moved: Iterable[str], extra: Iterable[int] = ()) -> set[int]:
    """Indices of the steps of ``plan`` that use a joint of ``moved`` (or are in ``extra``) and of
    the steps that depend on those."""
    moved = set(moved)
    extra = set(extra)
    dirty: set[int] = set()
    changed_links: set[str] = set()
    for k, step in enumerate(plan.steps):
        g = step.group
        if k in extra or moved.intersection(g.joints) or changed_links.intersection(step.needs):
            dirty.add(k)
            changed_links.update((g.link_i, g.link_j))
    return dirty


def resweep(old: Solution, plan: Plan, moved: Iterable[str]) -> Solution | None:
    """Solve ``plan`` (the linkage after a move) at ``old``'s inputs and order, re-running only the
    groups that use a joint of ``moved`` and those downstream of them.

    ``old`` must be a solution of every group of the linkage before the move. Returns None when
    the shortcut does not apply (see the module docstring); the caller then solves in full.
    Arrays keep the shapes of :class:`Solution`: (N,) samples on the leading axis.
    """
    before = old.plan
    if (topology_key(before.linkage) != topology_key(plan.linkage) or len(old.groups) != len(plan.steps)
            or before.theta0 != plan.theta0 or before.pivot != plan.pivot or before.omega != plan.omega):
        return None
    dirty = dirty_steps(plan, moved)
    # a group's rounding tolerance follows the coordinates of its joints and of the links it hangs
    # on: a clean group whose tolerance changed must run again too (and everything after it)
    tol_changed = {k for k, (a, b) in enumerate(zip(before.steps, plan.steps)) if a.coord != b.coord}
    if tol_changed - dirty:
        dirty = dirty_steps(plan, moved, extra=tol_changed)
    # branch points of the clean groups are those of the old plan (same inputs all the way up)
    clean_names = {plan.steps[k].group.name for k in range(len(plan.steps)) if k not in dirty}
    old_branches = before._branches or {}
    plan._branches = {name: b for name, b in old_branches.items() if name in clean_names}
    # and so are their link states at the search's reference inputs: only the dirty groups run
    clean_links = {link for k, s in enumerate(plan.steps) if k not in dirty for link in (s.group.link_i, s.group.link_j)}
    if dirty:
        keep_reference_states(before, plan, clean_links)
    branches = plan.branch_points(sorted(dirty))
    start = time.perf_counter()
    states = dict(old._states)
    # the reused states cache points by drawn position: drop the moved joints' old positions, or
    # a long drag leaves (N,) arrays behind at every move
    drawn = {at for _, at in plan.joint_at.values()}
    for link in clean_links:
        st = states.get(link)
        if st is not None:
            st.keep_only(drawn)
    outs = dict(old._outs)
    fresh = plan.run_steps(old.input, old.order, sorted(dirty), branches, old.omega_driver, old.alpha_driver,
                           states)
    outs.update(fresh)
    valid = np.ones(old.input.shape, dtype=bool)
    for out in outs.values():
        valid &= out.ok
    elapsed = time.perf_counter() - start
    return Solution(plan, old.input, old.order, states, outs, valid, old.omega_driver, old.t, elapsed,
                    old.alpha_driver)
