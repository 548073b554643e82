"""Diagnostics of a swept linkage: reachable input ranges, dead points, transmission angles.

Boundaries between assemblable and non-assemblable samples are refined by bisection on the
driver input (to ~1e-12 rad); near-toggle minima of a group's conditioning inside the reachable
range are refined by golden-section search. Angles are radians unless a name says ``_deg``.

They describe the geometry against the input, whatever the motion law: a crank over one full
turn (a crank driven by another law is diagnosed on a constant-speed turn), an actuator over its
stroke (inputs in mm; ``unit`` says which).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from ..model.drivers import input_text
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
    unit: str = "rad"    # of ``input``: "rad" (crank angle) or "mm" (actuator)

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
        return f"{input_text(self.input, self.unit, 6)} {self.group}: {what}"


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
    unit: str = "rad"                                 # of the inputs: "rad" (crank) or "mm" (actuator)
    stroke: tuple[float, float] | None = None         # an actuator's stroke, mm

    def lines(self) -> list[str]:
        out = [f"mobility: {self.mobility}"]
        for name, kind, mode in self.groups:
            out.append(f"group {name}: kind {kind}" + (f", mode {mode:+d}" if mode is not None else ""))
        for name in self.fixed:
            out.append(f"group {name} is fixed to the frame: it hangs on frame joints only, so it has "
                       f"zero mobility and its links do not move (solved once, in the drawn pose)")
        if self.full_turn:
            out.append("reachable: full revolution of the driver" if self.stroke is None else
                       f"reachable: the whole stroke, {self.stroke[0]:g} to {self.stroke[1]:g} mm")
        elif not self.reachable:
            out.append("reachable: none (the linkage cannot be assembled at any sampled input)")
        for a, b in self.reachable if not self.full_turn else []:
            out.append(f"reachable: input {input_text(a, self.unit, 6)} to {input_text(b, self.unit, 6)}")
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
    """Diagnostics of a full-cycle sweep (``plan.sweep``): a crank over one turn, an actuator
    over its stroke (see the module docstring)."""
    drv = sol.plan.linkage.driver
    if drv.linear:
        return _diagnose_stroke(sol)
    if not drv.law.is_constant:   # the geometry over one turn at constant speed
        n = len(sol)
        sg = 1.0 if drv.omega >= 0 else -1.0
        sol = sol.plan.evaluate(sol.plan.theta0 + sg * (2.0 * math.pi / n) * np.arange(n), order=min(sol.order, 2))
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


def sampled_dead_points(sol: Solution) -> list[DeadPoint]:
    """The dead points of a sweep at the resolution of its samples, with no re-solve (what a live
    drag marks; :func:`diagnose` refines them, and finds the same ones wherever the samples see
    them): an assembly limit at the last assemblable sample before a gap and the first one after
    it (the group that fails next door), each singular sample, and each sample where a group's
    conditioning has a local minimum below ``TOGGLE_COND`` (a change point when a branch point
    lies within a sample of it). Array work over (N,) per group; sorted by input (rad or mm)."""
    plan = sol.plan
    unit = plan.input_unit
    n = len(sol)
    x = np.asarray(sol.input, dtype=float)
    valid = _assembled(sol)
    outs = [(g, sol.group_output(g.name)) for g in sol.groups]
    dead: list[DeadPoint] = []
    if valid.any() and not valid.all():
        for k, nb in [(k, (k + 1) % n) for k in np.flatnonzero(valid & ~np.roll(valid, -1))] + \
                     [(k, (k - 1) % n) for k in np.flatnonzero(valid & ~np.roll(valid, 1))]:
            g = next((g for g, o in outs if not o.ok[nb] and not (o.singular is not None and o.singular[nb])), None)
            if g is not None:
                dead.append(DeadPoint(float(x[k]), g.name, DeadPointKind.LIMIT, 0.0, unit))
    branches = plan.branch_points() if unit == "rad" else {}   # found by the sweep already
    step = abs(x[1] - x[0]) if n > 1 else 2 * math.pi
    ring = np.arange(n)
    before, after = np.roll(ring, 1), np.roll(ring, -1)
    for g, o in outs:
        if o.singular is not None:
            dead += [DeadPoint(float(x[k]), g.name, DeadPointKind.SINGULAR, 0.0, unit) for k in np.flatnonzero(o.singular)]
        if g.fixed:
            continue
        low = np.flatnonzero(sol.valid & (o.cond < TOGGLE_COND))   # few samples, if any
        if low.size == 0:
            continue
        c = np.where(sol.valid, o.cond, np.inf)
        prev, nxt = c[before[low]], c[after[low]]
        bp = branches.get(g.name, np.empty(0))
        for k in low[(c[low] <= prev) & (c[low] <= nxt) & np.isfinite(prev) & np.isfinite(nxt)]:
            off = (plan.direction * (x[k] - plan.theta0)) % (2 * math.pi)
            near = bp.size and np.min(np.abs(np.remainder(bp - off + math.pi, 2 * math.pi) - math.pi)) <= step
            dead.append(DeadPoint(float(x[k]), g.name, DeadPointKind.CHANGE_POINT if near else DeadPointKind.TOGGLE,
                                  float(c[k]), unit))
    dead.sort(key=lambda d: d.input)
    return dead


def _diagnose_stroke(sol: Solution) -> Diagnostics:
    """Diagnostics of an actuator-driven linkage over its stroke (inputs in mm): the geometry is
    sampled uniformly over the stroke with the sweep's sample count; the solve time, residual and
    assemblable fraction are those of the sweep over the cycle."""
    plan = sol.plan
    lo, hi = plan.linkage.driver.stroke
    n = max(len(sol), 3)
    x = np.linspace(lo, hi, n)
    h = (hi - lo) / (n - 1)
    geo = plan.evaluate(x, order=0)
    valid = _assembled(geo)
    unit = "mm"
    groups = [(g.name, g.kind, geo.group_output(g.name).mode) for g in geo.groups]
    dead: list[DeadPoint] = []
    reachable: list[tuple[float, float]] = []
    full = bool(valid.all())
    if not full and valid.any():
        edges = np.flatnonzero(np.diff(np.concatenate(([0], valid.view(np.int8), [0]))))
        for s, e in zip(edges[::2], edges[1::2]):   # runs of valid samples [s, e)
            a = float(x[s]) if s == 0 else float(_bisect_valid(plan, x[s:s + 1], x[s - 1:s])[0])
            b = float(x[e - 1]) if e == n else float(_bisect_valid(plan, x[e - 1:e], x[e:e + 1])[0])
            reachable.append((a, b))
            for at, probe in ((a, a - 1e-9 * h), (b, b + 1e-9 * h)):
                if lo < at < hi:
                    p = plan.evaluate(np.array([probe]), order=0)
                    g = next((g for g in p.groups if not p.group_output(g.name).ok[0]), None)
                    if g is not None:
                        dead.append(DeadPoint(at, g.name, DeadPointKind.LIMIT, 0.0, unit))
    for g in geo.groups:
        o = geo.group_output(g.name)
        if o.singular is not None:
            dead += [DeadPoint(float(x[k]), g.name, DeadPointKind.SINGULAR, 0.0, unit) for k in np.flatnonzero(o.singular)]
    branches = plan.branch_points()
    for g in geo.groups:
        if g.fixed:
            continue
        c = np.where(geo.valid, geo.conditioning(g.name), np.inf)
        inner = np.zeros(n, dtype=bool)
        inner[1:-1] = (c[1:-1] < TOGGLE_COND) & (c[1:-1] <= c[:-2]) & (c[1:-1] <= c[2:]) & np.isfinite(c[:-2]) \
            & np.isfinite(c[2:])
        bp = branches.get(g.name, np.empty(0))
        for k in np.flatnonzero(inner):
            at, cmin = _golden_min(plan, g.name, float(x[k] - h), float(x[k] + h))
            near = bp.size and float(np.min(np.abs(bp - at))) < 1e-6 * max(hi - lo, 1.0)
            dead.append(DeadPoint(at, g.name, DeadPointKind.CHANGE_POINT if near else DeadPointKind.TOGGLE, cmin, unit))
    dead.sort(key=lambda d: d.input)
    trans = {}
    for g in geo.groups:
        if g.kind is GroupKind.RRR and valid.any():
            mu = np.degrees(geo.transmission_angle(g.name))
            mu = mu[np.isfinite(mu)]
            if mu.size:
                trans[g.name] = (float(mu.min()), float(mu.max()))
    return Diagnostics(plan.mobility, groups, len(sol), float(sol.valid.mean()), reachable, dead, trans,
                       sol.elapsed, sol.residual(), full, tuple(g.name for g in geo.groups if g.fixed), unit, (lo, hi))
