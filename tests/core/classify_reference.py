"""The output motions as classify.py computed them before issue 14 (one whole-linkage solve per
golden-section step and search): kept as the reference the vectorised version is compared with
(tests/core/test_classify_vectorised.py, benchmarks/bench_classify.py)."""
from __future__ import annotations

import math

import numpy as np

from mechsketch.core.analyses.classify import GOLDEN, OutputMotion, _outputs
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver.branches import golden_min
from mechsketch.core.solver.motion_law import at_times
from mechsketch.core.solver.plan import Plan, Solution


def _value(sol: Solution, lk: Linkage, link: str, kind: str, joint: str) -> np.ndarray:
    if kind == "rocker":
        return sol.angle(link)
    j = lk.joint(joint)
    u = np.array([math.cos(math.radians(j.axis_deg or 0.0)), math.sin(math.radians(j.axis_deg or 0.0))])
    return sol.point(link, j.at) @ u


def output_motions_reference(lk: Linkage, plan: Plan, sol: Solution) -> list[OutputMotion]:
    """classify.output_motions as of commit 99a3eee (verbatim but for the names)."""
    drv = lk.driver
    T = drv.period
    n = len(sol)
    out = []
    for link, kind, joint in _outputs(lk, plan):
        y = _value(sol, lk, link, kind, joint)
        if not np.all(np.isfinite(y)):
            out.append(OutputMotion(link, kind, joint, note="the cycle stops at assembly limits (no stroke over a "
                                                            "full cycle)"))
            continue
        if kind == "rocker" and abs(y[-1] + (y[1] - y[0]) - y[0]) > math.pi:   # unwrapped: it gained a turn
            out.append(OutputMotion(link, kind, joint, note=f"turns fully about {joint}"))
            continue

        def at(t: float) -> float:
            if drv.linear or not drv.law.is_constant:
                q = at_times(drv, plan.theta0, np.array([t])).q
            else:
                q = np.array([plan.theta0 + math.copysign(2 * math.pi / T, drv.speed_rpm) * t])   # fixed as in classify.py: t < 0 was mirrored
            return float(_value(plan.evaluate(q, order=0), lk, link, kind, joint)[0])

        dt = T / n
        k_lo, k_hi = int(np.argmin(y)), int(np.argmax(y))
        t_lo, y_lo = golden_min(at, sol.t[k_lo] - dt, sol.t[k_lo] + dt, GOLDEN)
        t_hi, neg = golden_min(lambda t: -at(t), sol.t[k_hi] - dt, sol.t[k_hi] + dt, GOLDEN)
        fwd = (t_hi - t_lo) % T
        out.append(OutputMotion(link, kind, joint, y_lo, -neg, fwd, T - fwd))
    return out
