"""Assembly limits, singular poses and near-toggles of a swept linkage, found *between* samples
from each group's closed form, so that what the diagnostics report does not depend on where the
samples happen to fall (the same ranges and dead points at 360, 3,600 or 36,000 samples).

A sweep sees each group only at its samples. Per group, its kernel gives two smooth functions of
the input: the assembly margin ``gap`` (mm; below zero the group cannot be assembled; for PRP
and RPP, whose two lines always meet unless parallel, it is the conditioning itself, |sin| of the
angle between the guides) and the conditioning ``cond`` (|sin μ| for an RRR). Three searches:

- **limits**: where the linkage's assembly changes between two samples, the input is bisected
  (to ~2⁻⁴⁸ of a step);
- **pockets and singular poses**: a sampled local minimum ``f_k`` of the margin that could dip
  below zero between its neighbours is refined by golden-section search. It could whenever
  ``f_k < DIP · max(f_{k−1} − f_k, f_{k+1} − f_k)``: a parabola whose minimum lies below zero
  between the samples always has ``f_k < rise / 4`` at the nearer sample, and a V (|det| of a
  PRP whose guides turn through parallel) ``f_k ≤ rise / 2``. A minimum where the group cannot be
  assembled is a gap narrower than a step (a *pocket*), bisected to its two ends (two limits;
  guides turning through parallel give one, the blocks running off to infinity on either side);
  one where the group assembles but its outer joints meet is a singular pose;
- **toggles**: a sampled local minimum of the conditioning that could fall below
  :data:`~.tolerances.TOGGLE_COND` between its neighbours (``c_k − DIP · rise < TOGGLE_COND``) is
  refined the same way; below it, a toggle (near-miss or change point).

The golden-section searches of all candidates run together: one solve of the plan per step at
all candidate inputs (nothing runs when no candidate exists, the usual case). Inputs are the
driver's (rad for a crank, mm for an actuator); offsets ``u`` count from the first sample in the
direction of the samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .plan import Plan, Solution
from .structure import GroupKind
from .tolerances import TOGGLE_COND

BISECT_STEPS = 48
GOLDEN_STEPS = 60
#: a sampled local minimum is refined when it is below DIP times the larger rise to its neighbours
DIP = 1.0
#: two events of one kind and group closer than this fraction of a sample step are the same
SAME = 1e-6

__all__ = ["Boundary", "Events", "find_events", "golden_all"]


@dataclass(frozen=True)
class Boundary:
    """An end of an assembled input range: ``x`` the last assembled input (rad or mm), ``start``
    True where a range starts (it cannot be assembled just before, in the samples' direction),
    False where one ends; ``group`` the group that cannot be assembled just outside (None: not
    found); ``parallel``: that group is a PRP or RPP whose guides turn parallel there (its blocks
    run off to infinity as the input approaches it)."""

    x: float
    start: bool
    group: str | None
    parallel: bool = False


@dataclass
class Events:
    """What :func:`find_events` found: the range ``boundaries`` (sorted in the samples'
    direction), ``singular`` poses (input, group) and ``toggles`` (input, group, conditioning)."""

    boundaries: list[Boundary] = field(default_factory=list)
    singular: list[tuple[float, str]] = field(default_factory=list)
    toggles: list[tuple[float, str, float]] = field(default_factory=list)


def golden_all(f, a: np.ndarray, b: np.ndarray, steps: int = GOLDEN_STEPS) -> tuple[np.ndarray, np.ndarray]:
    """Golden-section searches for the minima of m functions on brackets [a, b] at once, (m,):
    ``f`` maps m points (one per search) to their m values. Returns the point of each search
    with the least value it met, and that value, (m,) each (a value of −inf — a point where a
    margin says the group cannot be assembled — is kept wherever it was met)."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = np.array(a, dtype=float), np.array(b, dtype=float)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    best, fbest = np.where(fd < fc, d, c), np.fmin(fc, fd)
    for _ in range(steps):
        left = fc < fd                                  # NaN compares False: go right
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        x = np.where(left, b - g * (b - a), a + g * (b - a))
        fx = f(x)
        d, fd, c, fc = (np.where(left, c, x), np.where(left, fc, fx),
                        np.where(left, x, d), np.where(left, fx, fd))
        better = fx < fbest
        best, fbest = np.where(better, x, best), np.where(better, fx, fbest)
    x = 0.5 * (a + b)
    fx = f(x)
    better = fx <= fbest
    return np.where(better, x, best), np.where(better, fx, fbest)


def _failing(sol: Solution, j: int) -> str | None:
    """The first group (solving order) that cannot be assembled at sample ``j`` of ``sol``."""
    for g in sol.groups:
        o = sol.group_output(g.name)
        if not o.ok[j] and not (o.singular is not None and o.singular[j]):
            return g.name
    return None


def _assembled(sol: Solution) -> np.ndarray:
    return sol.valid | sol.singular


def _bisect(plan: Plan, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, Solution]:
    """For pairs (a assembled, b not), the assembly's end between them: (a, b) within 2⁻⁴⁸ of
    |b − a| on either side of it, and the solve at the final b (for the group at fault)."""
    a, b = np.asarray(a, dtype=float).copy(), np.asarray(b, dtype=float).copy()
    for _ in range(BISECT_STEPS):
        m = 0.5 * (a + b)
        ok = _assembled(plan.evaluate(m, order=0))
        a = np.where(ok, m, a)
        b = np.where(ok, b, m)
    return a, b, plan.evaluate(b, order=0)


def _local_min(f: np.ndarray, prev: np.ndarray, nxt: np.ndarray, limit: float) -> np.ndarray:
    """Indices k where ``f`` has a sampled local minimum (neighbours at ``prev``, ``nxt``, all
    finite) that could fall below ``limit`` between its neighbours (module docstring)."""
    fp, fn = f[prev], f[nxt]
    with np.errstate(invalid="ignore"):
        rise = np.maximum(fp - f, fn - f)
        hit = (np.isfinite(f) & np.isfinite(fp) & np.isfinite(fn) & (f <= fp) & (f <= fn)
               & (f - DIP * rise < limit))
    return np.flatnonzero(hit)


def _values(plan: Plan, names: list[str], what: list[str]):
    """f(points) -> at point j, group ``names[j]``'s margin (``what[j]`` "gap"; −inf where it
    cannot be assembled) or conditioning ("cond"; 0 there), from one solve of all points."""
    def f(x: np.ndarray) -> np.ndarray:
        sol = plan.evaluate(x, order=0)
        out = np.empty(x.shape)
        for name in set(names):
            o = sol.group_output(name)
            sel = np.array([j for j, nm in enumerate(names) if nm == name])
            ok = np.broadcast_to(o.ok if o.singular is None else o.ok | o.singular, x.shape)[sel]
            gap = np.broadcast_to(o.gap, x.shape)[sel]
            cond = np.broadcast_to(o.cond, x.shape)[sel]
            is_gap = np.array([what[j] == "gap" for j in sel])
            v = np.where(is_gap, gap, cond)
            v = np.where(ok & np.isfinite(v), v, np.where(is_gap, -math.inf, 0.0))
            out[sel] = v
        return out
    return f


def _candidates(geo: Solution, prev: np.ndarray, nxt: np.ndarray, inner: np.ndarray
                ) -> tuple[list[int], list[str], list[str]]:
    """(sample, group, "gap" | "cond") of every sampled minimum of a moving group's margin that
    could dip below zero, or of its conditioning that could dip below TOGGLE_COND, between the
    sample's neighbours (all three assembled)."""
    n = len(geo)
    asm = _assembled(geo)
    around = asm & asm[prev] & asm[nxt] & inner
    ks: list[int] = []
    names: list[str] = []
    what: list[str] = []
    for g in geo.groups:
        if g.fixed:
            continue
        o = geo.group_output(g.name)
        m = np.where(asm, np.broadcast_to(o.gap, (n,)), np.nan)
        c = np.where(geo.valid, np.broadcast_to(o.cond, (n,)), np.nan)
        for arr, limit, kind in ((m, 0.0, "gap"), (c, TOGGLE_COND, "cond")):
            for k in _local_min(arr, prev, nxt, limit):
                if around[k]:
                    ks.append(int(k))
                    names.append(g.name)
                    what.append(kind)
    return ks, names, what


def find_events(plan: Plan, geo: Solution, periodic: bool) -> Events:
    """Limits, pockets, singular poses and toggles of the sweep ``geo`` of ``plan`` (order ≥ 0,
    equally spaced inputs; ``periodic``: they cover one turn of a crank, the last sample's
    successor is the first). See the module docstring."""
    x = np.asarray(geo.input, dtype=float)
    n = x.shape[0]
    ev = Events()
    if n < 2:
        return ev
    step = float(x[1] - x[0])
    h = abs(step)
    ring = np.arange(n)
    if periodic:
        prev, nxt, inner = np.roll(ring, 1), np.roll(ring, -1), np.ones(n, dtype=bool)
    else:
        prev, nxt, inner = np.maximum(ring - 1, 0), np.minimum(ring + 1, n - 1), (ring > 0) & (ring < n - 1)
    asm = _assembled(geo)
    # bisection pairs (assembled side, other side, the range starts there, sample)
    ends = np.flatnonzero(asm & ~asm[nxt] & (periodic | (ring < n - 1)))
    starts = np.flatnonzero(asm & ~asm[prev] & (periodic | (ring > 0)))
    pa = [x[ends], x[starts]]
    pb = [x[ends] + step, x[starts] - step]
    pstart = [np.zeros(ends.size, dtype=bool), np.ones(starts.size, dtype=bool)]
    for g in geo.groups:   # singular samples: at the sample itself
        o = geo.group_output(g.name)
        if o.singular is not None:
            ev.singular += [(float(x[k]), g.name) for k in np.flatnonzero(o.singular)]
    ks, names, what = _candidates(geo, prev, nxt, inner)
    if ks:
        kk = np.array(ks)
        xs, fs = golden_all(_values(plan, names, what), x[kk] - h, x[kk] + h)
        at = plan.evaluate(xs, order=0)
        bad = ~_assembled(at)
        pockets = _pockets(ev, at, bad, xs, names, what, x[kk] - h, x[kk] + h, h)
        for lo_j, hi_j, mid in pockets:   # bisect to both ends (the samples' direction says which ends)
            pa.append(np.array([lo_j, hi_j]))
            pb.append(np.array([mid, mid]))
            pstart.append(np.array([step < 0, step > 0]))
        for j, (name, kind) in enumerate(zip(names, what)):
            if (kind == "cond" and fs[j] < TOGGLE_COND and not bad[j]
                    and not any(lo <= xs[j] <= hi for lo, hi, _ in pockets)
                    and not _seen(ev.singular, xs[j], name, SAME * h)
                    and not _seen([(t, g) for t, g, _ in ev.toggles], xs[j], name, SAME * h)):
                ev.toggles.append((float(xs[j]), name, float(fs[j])))
    pa = np.concatenate(pa)
    if pa.size:
        a, _, at_b = _bisect(plan, pa, np.concatenate(pb))
        kinds = {g.name: g.kind for g in geo.groups}
        for j, is_start in enumerate(np.concatenate(pstart)):
            g = _failing(at_b, j)
            ev.boundaries.append(Boundary(float(a[j]), bool(is_start), g, g is not None and kinds[g] in _LINES))
    x0, sg = float(x[0]), math.copysign(1.0, step)
    period = n * h if periodic else math.inf
    ev.boundaries.sort(key=lambda bd: (sg * (bd.x - x0)) % period if periodic else sg * (bd.x - x0))
    return ev


def _pockets(ev: Events, at: Solution, bad: np.ndarray, xs: np.ndarray, names: list[str], what: list[str],
             lo: np.ndarray, hi: np.ndarray, h: float) -> list[tuple[float, float, float]]:
    """From the refined margin minima ``xs`` (solved in ``at``; ``bad``: not assembled there):
    the pockets (lo, hi, a point inside), one per gap; the singular poses go into ``ev``."""
    pockets: list[tuple[float, float, float]] = []
    for j, (name, kind) in enumerate(zip(names, what)):
        if kind != "gap":
            continue
        if bad[j]:
            if not any(a <= xs[j] <= b for a, b, _ in pockets):
                pockets.append((float(lo[j]), float(hi[j]), float(xs[j])))
            continue
        o = at.group_output(name)
        if o.singular is not None and o.singular[j] and not _seen(ev.singular, xs[j], name, h):
            ev.singular.append((float(xs[j]), name))
    return pockets


def _seen(events, x: float, name: str, tol: float) -> bool:
    """An event (input, group) of ``name`` within ``tol`` of ``x`` is in ``events`` already."""
    return any(abs(x - e) <= tol and g == name for e, g in events)


_LINES = (GroupKind.PRP, GroupKind.RPP)
