"""Diagnostics of a swept linkage: reachable input ranges, dead points, transmission angles.

Boundaries between assemblable and non-assemblable samples are refined by bisection on the
driver angle (to ~1e-12 rad); near-toggle minima of a group's conditioning inside the reachable
range are refined by golden-section search. Angles are radians unless a name says ``_deg``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from .branches import golden_min
from .plan import Plan, Solution
from .structure import GroupKind
from .tolerances import TOGGLE_COND

BISECT_STEPS = 48
GOLDEN_STEPS = 60


class DeadPointKind(StrEnum):
    """What happens at a dead point; a ``str`` equal to (and printed as) its value."""

    LIMIT = "limit"
    TOGGLE = "toggle"
    CHANGE_POINT = "change point"
    SINGULAR = "singular"


@dataclass(frozen=True)
class DeadPoint:
    """A toggle: the driver angle (rad), the group, and whether the group stops being assemblable
    there (``"limit"``), passes close to it (``"toggle"``), passes through it where its two
    assembly modes meet (``"change point"``: the solution keeps to the smooth branch), or has its
    outer joints coincide at a sample, which leaves its pose undetermined there (``"singular"``:
    that sample is not solved, the motion continues on its smooth branch after it).
    ``kind`` is a :class:`DeadPointKind` (a string given here is converted)."""

    input: float
    group: str
    kind: DeadPointKind
    conditioning: float

    def __post_init__(self) -> None:
        if not isinstance(self.kind, DeadPointKind):
            object.__setattr__(self, "kind", DeadPointKind(self.kind))

    def __str__(self) -> str:
        what = {DeadPointKind.LIMIT: "assembly limit",
                DeadPointKind.CHANGE_POINT: "change point (the assembly modes meet; the motion keeps to the "
                                            "smooth branch)",
                DeadPointKind.SINGULAR: "singular sample (the outer joints coincide: the pose is undetermined "
                                        "there and not given; the motion keeps to the smooth branch)",
                }.get(self.kind, f"near toggle (conditioning {self.conditioning:.1e})")
        return f"{math.degrees(self.input):.6f}° {self.group}: {what}"


@dataclass
class Diagnostics:
    """What the summary and the GUI's diagnostics panel show."""

    mobility: int
    groups: list[tuple[str, GroupKind, int | None]]  # (name, kind, drawn mode ±1 or None)
    samples: int
    valid_fraction: float
    reachable: list[tuple[float, float]]              # input ranges (rad), sweep direction
    dead_points: list[DeadPoint]
    transmission_deg: dict[str, tuple[float, float]]  # RRR group -> (min, max) μ in degrees
    solve_time: float                                 # s
    residual: float                                   # mm
    full_turn: bool = field(default=False)
    fixed: tuple[str, ...] = ()                       # groups hung on the frame only (do not move)

    def lines(self) -> list[str]:
        out = [f"mobility: {self.mobility}"]
        for name, kind, mode in self.groups:
            out.append(f"group {name}: kind {kind}" + (f", mode {mode:+d}" if mode is not None else ""))
        for name in self.fixed:
            out.append(f"group {name} is fixed to the frame: it hangs on frame joints only, so it has "
                       f"zero mobility and its links do not move (solved once, in the drawn pose)")
        if self.full_turn:
            out.append("reachable: full revolution of the driver")
        elif not self.reachable:
            out.append("reachable: none (the linkage cannot be assembled at any sampled input)")
        for a, b in self.reachable if not self.full_turn else []:
            out.append(f"reachable: input {math.degrees(a):.6f}° to {math.degrees(b):.6f}°")
        for d in self.dead_points:
            out.append(f"dead point: {d}")
        if not self.dead_points:
            out.append("dead points: none")
        for g, (lo, hi) in self.transmission_deg.items():
            out.append(f"transmission angle {g}: {lo:.3f}° to {hi:.3f}°")
        per = self.solve_time / max(self.samples, 1) * 1e6
        out.append(f"solve: {self.samples} poses in {self.solve_time * 1e3:.3f} ms ({per:.3f} µs per pose), "
                   f"max loop-closure residual {self.residual:.1e} mm, {self.valid_fraction:.1%} assemblable")
        return out

    def __str__(self) -> str:
        return "\n".join(self.lines())


def _assembled(sol: Solution) -> np.ndarray:
    """(N,) bool: valid, or singular (assembled, pose undetermined at that one input)."""
    return sol.valid | sol.singular


def _bisect_valid(plan: Plan, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """For each pair (a valid, b invalid), the input where validity ends (vectorised bisection)."""
    a, b = a.astype(float).copy(), b.astype(float).copy()
    for _ in range(BISECT_STEPS):
        m = 0.5 * (a + b)
        ok = _assembled(plan.evaluate(m, order=0))
        a = np.where(ok, m, a)
        b = np.where(ok, b, m)
    return a


def _golden_min(plan: Plan, group: str, a: float, b: float) -> tuple[float, float]:
    """Input in [a, b] where ``group``'s conditioning is least, and that conditioning."""
    def f(x: float) -> float:
        c = plan.evaluate(np.array([x]), order=0).conditioning(group)[0]
        return float(c) if np.isfinite(c) else 0.0

    return golden_min(f, a, b, GOLDEN_STEPS)


def diagnose(sol: Solution) -> Diagnostics:
    """Diagnostics of a full-revolution sweep (``plan.sweep``)."""
    plan = sol.plan
    n = len(sol)
    valid = _assembled(sol)
    step = sol.input[1] - sol.input[0] if n > 1 else 2 * math.pi
    groups = []
    for g in sol.groups:
        groups.append((g.name, g.kind, sol.group_output(g.name).mode))
    dead: list[DeadPoint] = []
    reachable: list[tuple[float, float]] = []
    full = bool(valid.all())
    if not full and valid.any():
        nxt = np.roll(valid, -1)
        ends = np.flatnonzero(valid & ~nxt)        # last valid sample before a gap
        starts = np.flatnonzero(valid & ~np.roll(valid, 1))  # first valid sample after a gap
        th = sol.input
        end_at = _bisect_valid(plan, th[ends], th[ends] + step)
        start_at = _bisect_valid(plan, th[starts], th[starts] - step)
        for s in sorted(start_at):
            e = min((x for x in end_at if (x - s) * np.sign(step) >= 0), key=lambda x: abs(x - s),
                    default=end_at[0] + 2 * math.pi * np.sign(step))
            sg = float(np.sign(step))
            if (s - sol.input[0]) * sg > 0 and (e - sol.input[0]) * sg > 2 * math.pi - abs(step):
                s, e = s - 2 * math.pi * sg, e - 2 * math.pi * sg  # the range through the drawn pose
            reachable.append((float(s), float(e)))
        probe = plan.evaluate(np.concatenate([end_at + 1e-9 * np.sign(step), start_at - 1e-9 * np.sign(step)]),
                              order=0)
        for k, x in enumerate(np.concatenate([end_at, start_at])):
            for g in probe.groups:
                o = probe.group_output(g.name)
                if not o.ok[k] and not (o.singular is not None and o.singular[k]):
                    dead.append(DeadPoint(float(x), g.name, DeadPointKind.LIMIT, 0.0))
                    break
    for g in sol.groups:
        o = sol.group_output(g.name)
        if o.singular is not None:
            for k in np.flatnonzero(o.singular):
                dead.append(DeadPoint(float(sol.input[k]), g.name, DeadPointKind.SINGULAR, 0.0))
    # near-toggles inside the reachable range: local minima of conditioning below the threshold
    for g in sol.groups:
        if g.fixed:  # does not move: no toggle to pass through
            continue
        c = np.where(sol.valid, sol.conditioning(g.name), np.inf)
        prev, nxt = np.roll(c, 1), np.roll(c, -1)
        cand = np.flatnonzero((c < TOGGLE_COND) & (c <= prev) & (c <= nxt) & np.isfinite(prev) & np.isfinite(nxt))
        branches = plan.branch_points().get(g.name, np.empty(0))
        for k in cand:
            x, cmin = _golden_min(plan, g.name, sol.input[k] - step, sol.input[k] + step)
            off = (plan.direction * (x - plan.theta0)) % (2 * math.pi)
            near = branches.size and np.min(np.abs(np.remainder(branches - off + math.pi, 2 * math.pi) - math.pi)) < 1e-5
            dead.append(DeadPoint(float(x), g.name, DeadPointKind.CHANGE_POINT if near else DeadPointKind.TOGGLE, cmin))
    th0 = float(sol.input[0])
    ends = [x for r in reachable for x in r]

    def near_pose(x: float) -> float:
        """The angle congruent to x (mod 2π) as the reachable ranges state it, else nearest θ0."""
        for e in ends:
            if abs(math.remainder(x - e, 2 * math.pi)) < 1e-9:
                return e
        return th0 + math.remainder(x - th0, 2 * math.pi)

    dead = [DeadPoint(near_pose(d.input), d.group, d.kind, d.conditioning) for d in dead]
    dead.sort(key=lambda d: d.input)
    trans = {}
    for g in sol.groups:
        if g.kind is GroupKind.RRR and valid.any():
            mu = np.degrees(sol.transmission_angle(g.name))
            mu = mu[np.isfinite(mu)]
            if mu.size:
                trans[g.name] = (float(mu.min()), float(mu.max()))
    return Diagnostics(plan.mobility, groups, n, float(valid.mean()), reachable, dead, trans,
                       sol.elapsed, sol.residual(), full, tuple(g.name for g in sol.groups if g.fixed))
