"""The branch-point search as it was before the one-pass search (issue 14): each group's whole
chain of steps re-run at the reference samples, group by group (quadratic in the number of
groups). Kept as the reference the one-pass :func:`mechsketch.core.solver.branches.find_branch_points`
must agree with, offset for offset."""
from __future__ import annotations

import math

import numpy as np

from mechsketch.core.solver.branches import (CANDIDATE, DRAWN_NEAR, REF_SAMPLES, TWO_PI, _apart,
                                             _leaves_flipped, golden_min)
from mechsketch.core.solver.structure import MODAL_KINDS
from mechsketch.core.solver.tolerances import BRANCH_REL


def per_group_branch_points(plan, steps=None) -> dict[str, np.ndarray]:
    """Branch offsets (rad, sorted) of every group of ``plan`` (or of ``steps``), found group by
    group on each group's own closure, as ``find_branch_points`` did before issue 14."""
    known: dict[str, np.ndarray] = {}
    lp = plan.local()
    sg = lp.direction
    delta = np.arange(REF_SAMPLES) * (TWO_PI / REF_SAMPLES)
    inputs = lp.theta0 + sg * delta
    step_h = TWO_PI / REF_SAMPLES
    for k in sorted(range(len(lp.steps)) if steps is None else steps):
        step = lp.steps[k]
        name = step.group.name
        if name in known:
            continue
        if step.group.kind not in MODAL_KINDS or step.group.fixed:
            known[name] = np.empty(0)
            continue
        idx = lp.closure(k)
        out = lp.run_steps(inputs, 0, idx, known)[name]
        ok = out.ok if out.singular is None else out.ok | out.singular
        gap = np.where(ok, out.gap, -np.inf)
        good = ok & np.roll(ok, 1) & np.roll(ok, -1)
        cand = np.flatnonzero(good & (gap <= np.roll(gap, 1)) & (gap <= np.roll(gap, -1))
                              & (gap < CANDIDATE * step.scale))
        thr = BRANCH_REL * (step.scale + step.coord)

        def margin(d: float) -> float:
            o = lp.run_steps(np.array([lp.theta0 + sg * d]), 0, idx, known)[name]
            return float(o.gap[0]) if np.isfinite(o.gap[0]) else math.inf

        found: list[float] = []
        for c in cand:
            d, f = golden_min(margin, delta[c] - step_h, delta[c] + step_h)
            d %= TWO_PI
            if abs(f) <= thr and all(_apart(d, e) for e in found):
                found.append(d)
        if abs(margin(0.0)) <= thr:
            found = [d for d in found if min(d, TWO_PI - d) > DRAWN_NEAR]
            found.append(0.0 if _leaves_flipped(lp, k, idx, known, found) else TWO_PI)
        known[name] = np.array(sorted(found))
    return known
