"""Diagnostics of a swept linkage: reachable input ranges, dead points, transmission angles.

Assembly limits, pockets narrower than a sample step, singular poses and near-toggles are found
between the samples from each group's closed form (:mod:`.limits`: bisection of the assembly,
golden-section search of the margins' and conditionings' sampled minima that could dip below
their thresholds), so the ranges and dead points are the same at any number of samples.
Angles are radians unless a name says ``_deg``.

They describe the geometry against the input, whatever the motion law: a crank over one full
turn (a crank driven by another law is diagnosed on a constant-speed turn), an actuator over its
stroke (inputs in mm; ``unit`` says which).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import StrEnum

import numpy as np

from ..model.drivers import input_text
from .limits import Events, find_events
from .plan import Plan, Solution
from .structure import GroupKind
from .tolerances import TOGGLE_COND

#: what a limit of a PRP or RPP group means (its guides turn parallel there)
PARALLEL_NOTE = "the guides turn parallel: the blocks run off to infinity as the input approaches it"


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
    note: str = ""       # why, where the kind alone does not say (a PRP's guides turning parallel)

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
        if self.note:
            what = f"{what} ({self.note})"
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


def _ranges(ev: Events, x: np.ndarray, asm: np.ndarray, periodic: bool) -> list[tuple[float, float]]:
    """The assembled input ranges (start, end), in the samples' direction, from the boundaries
    of ``ev`` (sorted that way): on a turn (``periodic``) the range through the first sample (the
    drawn pose) starts before it; over a stroke a range may start or end at a stroke end."""
    bs = ev.boundaries
    if not bs:   # assembled everywhere (a full turn, the whole stroke) or nowhere
        return []
    step = float(x[1] - x[0])
    turn = math.copysign(2 * math.pi, step)
    out = []
    if periodic:
        first = next((i for i, b in enumerate(bs) if b.start), None)
        if first is None:
            return []
        order = bs[first:] + bs[:first]
        start = None
        for b in order:
            if b.start:
                start = b.x
            elif start is not None:
                end = b.x
                while (end - start) * step < 0:
                    end += turn
                out.append((start, end))
                start = None
        x0 = float(x[0])
        # the range through the drawn pose (the first sample) is stated from before it
        sg = math.copysign(1.0, step)
        out = [(s - turn, e - turn) if (s - x0) * sg > 0 and (e - x0) * sg > 2 * math.pi else (s, e)
               for s, e in out]
        return sorted(((float(s), float(e)) for s, e in out), key=lambda r: r[0] * sg)
    start = float(x[0]) if asm[0] else None
    for b in bs:
        if b.start:
            start = b.x
        elif start is not None:
            out.append((start, b.x))
            start = None
    if start is not None:
        out.append((start, float(x[-1])))
    return [(float(s), float(e)) for s, e in out]


def _dead_points(ev: Events, plan: Plan, unit: str, span: float) -> list[DeadPoint]:
    """The dead points of the events: each boundary's limit, the singular poses, the toggles
    (change points where a branch point lies within 1e-5 rad, or 1e-6 of the stroke)."""
    dead = [DeadPoint(b.x, b.group, DeadPointKind.LIMIT, 0.0, unit, PARALLEL_NOTE if b.parallel else "")
            for b in ev.boundaries if b.group is not None]
    dead += [DeadPoint(x, g, DeadPointKind.SINGULAR, 0.0, unit) for x, g in ev.singular]
    branches = plan.branch_points()
    for x, g, c in ev.toggles:
        bp = branches.get(g, np.empty(0))
        if unit == "rad":
            off = (plan.direction * (x - plan.theta0)) % (2 * math.pi)
            near = bp.size and np.min(np.abs(np.remainder(bp - off + math.pi, 2 * math.pi) - math.pi)) < 1e-5
        else:
            near = bp.size and float(np.min(np.abs(bp - x))) < 1e-6 * max(span, 1.0)
        dead.append(DeadPoint(x, g, DeadPointKind.CHANGE_POINT if near else DeadPointKind.TOGGLE, c, unit))
    return dead


def _transmission(sol: Solution) -> dict[str, tuple[float, float]]:
    trans = {}
    for g in sol.groups:
        if g.kind is GroupKind.RRR and _assembled(sol).any():
            mu = np.degrees(sol.transmission_angle(g.name))
            mu = mu[np.isfinite(mu)]
            if mu.size:
                trans[g.name] = (float(mu.min()), float(mu.max()))
    return trans


def diagnose(sol: Solution) -> Diagnostics:
    """Diagnostics of a full-cycle sweep (``plan.sweep``): a crank over one turn, an actuator
    over its stroke (see the module docstring). Limits, singular poses and toggles are found
    between the samples from each group's closed form (:mod:`.limits`), so they do not depend on
    the number of samples."""
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
    step = float(sol.input[1] - sol.input[0]) if n > 1 else 2 * math.pi
    periodic = n > 1 and abs(n * abs(step) - 2 * math.pi) <= 1e-9 * 2 * math.pi
    groups = [(g.name, g.kind, sol.group_output(g.name).mode) for g in sol.groups]
    ev = find_events(plan, sol, periodic)
    reachable = _ranges(ev, sol.input, valid, periodic) if valid.any() else []
    full = bool(valid.all()) and not ev.boundaries
    dead = _dead_points(ev, plan, "rad", 2 * math.pi)
    th0 = float(sol.input[0])
    ends = [x for r in reachable for x in r]

    def near_pose(x: float) -> float:
        """The angle congruent to x (mod 2π) as the reachable ranges state it, else nearest θ0."""
        for e in ends:
            if abs(math.remainder(x - e, 2 * math.pi)) < 1e-9:
                return e
        return th0 + math.remainder(x - th0, 2 * math.pi)

    dead = [replace(d, input=near_pose(d.input)) for d in dead]
    dead.sort(key=lambda d: d.input)
    return Diagnostics(plan.mobility, groups, n, float(valid.mean()), reachable, dead, _transmission(sol),
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
    sampled uniformly over the stroke with the sweep's sample count and searched between the
    samples (:mod:`.limits`); the solve time, residual and assemblable fraction are those of the
    sweep over the cycle."""
    plan = sol.plan
    lo, hi = plan.linkage.driver.stroke
    n = max(len(sol), 3)
    x = np.linspace(lo, hi, n)
    geo = plan.evaluate(x, order=0)
    valid = _assembled(geo)
    groups = [(g.name, g.kind, geo.group_output(g.name).mode) for g in geo.groups]
    ev = find_events(plan, geo, periodic=False)
    reachable = _ranges(ev, x, valid, periodic=False) if valid.any() else []
    full = bool(valid.all()) and not ev.boundaries
    dead = sorted(_dead_points(ev, plan, "mm", hi - lo), key=lambda d: d.input)
    return Diagnostics(plan.mobility, groups, len(sol), float(sol.valid.mean()), reachable, dead,
                       _transmission(geo), sol.elapsed, sol.residual(), full,
                       tuple(g.name for g in geo.groups if g.fixed), "mm", (lo, hi))
