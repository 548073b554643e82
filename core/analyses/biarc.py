"""Arc fitting of smooth plane curves by biarcs, with the maximum deviation measured.

A biarc joins two points with given unit tangents by two circular arcs meeting with a common
tangent (G1). We use the equal-tangent-length biarc: with v = P1 − P0 and t = T0 + T1, the junction
is J = (P0 + P1)/2 + d (T0 − T1)/2 where d = v·v / (v·t + sqrt((v·t)² + 2(1 − T0·T1) v·v)). Each
arc is described by its start point, its signed sweep (counter-clockwise positive) and its centre;
its DXF bulge is tan(sweep/4). A chain of biarcs is G1-continuous since neighbouring spans share
their end tangents.

:func:`fit_biarcs` splits the parameter range until every span's biarc is within the tolerance:
the deviation is the distance from densely sampled curve points to the biarc (foot of the
perpendicular on the arcs, stable for nearly straight arcs). Curves are callables t (M,) -> (M, 2).

The chain never holds an arc or line shorter than :func:`shortest_segment` (relative to the
curve's size and below a tenth of the tolerance): where a traced point reverses (a cusp), the
biarc between two samples on either side of it is two half circles a few 1e-12 mm across, which
CAD readers refuse; such pieces are dropped, their neighbours meeting at the cusp, and the
reported deviation grows by at most their length.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..errors import GeometryError

Curve = Callable[[np.ndarray], np.ndarray]
#: the shortest segment (mm) a fit keeps, at least (FreeCAD's confusion distance is 1e-7 mm)
SHORTEST = 1e-6


def shortest_segment(tolerance: float, size: float) -> float:
    """The shortest arc or line (mm) a fit of a curve ``size`` mm across keeps: 1e-8 of its size
    (at least :data:`SHORTEST`), but at most a tenth of the ``tolerance`` (the fit keeps 10 %
    of it in hand: every span is within 0.9·tolerance)."""
    return min(0.1 * tolerance, max(SHORTEST, 1e-8 * size))


def drop_short(arcs: list["Arc"], shortest: float, closed: bool) -> tuple[list["Arc"], float]:
    """``arcs`` (a chain, each ending where the next starts) without the pieces shorter than
    ``shortest`` mm, and the longest one dropped (0 if none): the next piece starts where the
    dropped one started. A chain is never emptied."""
    out, dropped = [], 0.0
    for a in arcs:
        length = abs(a.sweep) * a.radius if a.center is not None else math.dist(a.start, a.end)
        if length < shortest and len(arcs) > 1:
            dropped = max(dropped, math.dist(a.start, a.end))
            if out:
                prev = out[-1]
                out[-1] = Arc(prev.start, a.end, prev.sweep, prev.center)
            continue
        out.append(a)
    if not closed and out and out[-1].end != arcs[-1].end:
        last = out[-1]
        out[-1] = Arc(last.start, arcs[-1].end, last.sweep, last.center)
    return out, dropped


@dataclass(frozen=True)
class Arc:
    """A circular arc from ``start`` to ``end`` (mm) with signed ``sweep`` (rad, CCW positive).

    ``center`` is None for a straight segment (sweep 0).
    """

    start: tuple[float, float]
    end: tuple[float, float]
    sweep: float
    center: tuple[float, float] | None

    @property
    def bulge(self) -> float:
        """DXF bulge of the segment: tan(sweep/4)."""
        return math.tan(self.sweep / 4.0)

    @property
    def radius(self) -> float:
        if self.center is None:
            return math.inf
        return math.dist(self.start, self.center)

    def points(self, m: int) -> np.ndarray:
        """m + 1 points along the arc (mm), start and end included."""
        s = np.linspace(0.0, 1.0, m + 1)
        a, b = np.asarray(self.start), np.asarray(self.end)
        if self.center is None:
            return a + s[:, None] * (b - a)
        c = np.asarray(self.center)
        r = np.linalg.norm(a - c)
        a0 = math.atan2(a[1] - c[1], a[0] - c[0])
        ang = a0 + s * self.sweep
        out = c + r * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        out[0], out[-1] = a, b
        return out


def _arc_from(p: np.ndarray, t: np.ndarray, q: np.ndarray) -> Arc:
    """The arc starting at p with unit tangent t and ending at q."""
    w = q - p
    cr = t[0] * w[1] - t[1] * w[0]
    dt = t[0] * w[0] + t[1] * w[1]
    sweep = 2.0 * math.atan2(cr, dt)
    ww = float(w @ w)
    if abs(cr) <= 1e-15 * ww ** 0.5 or ww == 0.0:
        return Arc((float(p[0]), float(p[1])), (float(q[0]), float(q[1])), 0.0, None)
    r = ww / (2.0 * cr)  # signed: > 0 centre on the left of t
    c = p + r * np.array([-t[1], t[0]])
    return Arc((float(p[0]), float(p[1])), (float(q[0]), float(q[1])), sweep, (float(c[0]), float(c[1])))


def biarc(p0: np.ndarray, t0: np.ndarray, p1: np.ndarray, t1: np.ndarray) -> tuple[Arc, Arc] | None:
    """The equal-tangent-length biarc from (p0, t0) to (p1, t1) (unit tangents), or None if degenerate."""
    v = p1 - p0
    t = t0 + t1
    vv = float(v @ v)
    vt = float(v @ t)
    c = 1.0 - float(t0 @ t1)
    den = vt + math.sqrt(max(vt * vt + 2.0 * c * vv, 0.0))
    if vv == 0.0 or den <= 0.0:
        return None
    d = vv / den
    j = 0.5 * (p0 + p1) + 0.5 * d * (t0 - t1)
    tj = (p1 - d * t1) - (p0 + d * t0)
    n = float(np.linalg.norm(tj))
    tj = tj / n if n > 0.0 else t0
    return _arc_from(p0, t0, j), _arc_from(j, tj, p1)


def arc_distance(x: np.ndarray, arc: Arc) -> np.ndarray:
    """Distance (M,) mm from points x (M, 2) to the arc (or segment), ends included."""
    a, b = np.asarray(arc.start), np.asarray(arc.end)
    xa = x - a
    d_end = np.minimum(np.linalg.norm(xa, axis=1), np.linalg.norm(x - b, axis=1))
    if arc.center is None:
        ab = b - a
        L2 = float(ab @ ab)
        s = np.clip(xa @ ab / L2, 0.0, 1.0) if L2 > 0 else np.zeros(len(x))
        return np.linalg.norm(xa - s[:, None] * ab, axis=1)
    c = np.asarray(arc.center)
    ac = a - c
    r = float(np.linalg.norm(ac))
    # |x − c|² − r² = |x − a|² + 2 (x − a)·(a − c): no cancellation for large radii
    q = np.einsum("ij,ij->i", xa, xa) + 2.0 * (xa @ ac)
    dist_circle = np.abs(q) / (np.sqrt(np.maximum(r * r + q, 0.0)) + r)
    sgn = 1.0 if arc.sweep > 0 else -1.0
    if abs(arc.sweep) < math.pi:
        xc = x - c
        c1 = sgn * (ac[0] * xa[:, 1] - ac[1] * xa[:, 0])  # cross(a − c, x − c) = cross(a − c, x − a)
        bc = b - c
        c2 = sgn * (xc[:, 0] * bc[1] - xc[:, 1] * bc[0])
        inside = (c1 >= 0.0) & (c2 >= 0.0)
    else:
        ang = np.arctan2(x[:, 1] - c[1], x[:, 0] - c[0]) - math.atan2(ac[1], ac[0])
        inside = np.mod(sgn * ang, 2.0 * math.pi) <= abs(arc.sweep)
    return np.where(inside, dist_circle, d_end)


@dataclass
class BiarcFit:
    """A G1 chain of arcs approximating a curve; ``max_deviation`` (mm) measured on
    ``samples_per_span`` curve points per span."""

    arcs: list[Arc]
    max_deviation: float
    spans: int
    samples_per_span: int

    def vertices_and_bulges(self) -> list[tuple[float, float, float]]:
        """(x, y, bulge) per vertex for an LWPOLYLINE; the last vertex has bulge 0."""
        out = [(a.start[0], a.start[1], a.bulge) for a in self.arcs]
        last = self.arcs[-1].end
        out.append((last[0], last[1], 0.0))
        return out


def tangents(curve: Curve, t: np.ndarray, scale: float) -> np.ndarray:
    """Unit tangents (M, 2) of ``curve`` at t (M,), fourth-order central differences, step 1e-4·scale."""
    h = 1e-4 * scale
    d = (curve(t - 2 * h) - 8.0 * curve(t - h) + 8.0 * curve(t + h) - curve(t + 2 * h)) / (12.0 * h)
    return d / np.linalg.norm(d, axis=1)[:, None]


def fit_biarcs(curve: Curve, t0: float, t1: float, tolerance: float, tangent: Callable[[np.ndarray], np.ndarray] | None = None,
               initial_spans: int = 4, samples_per_span: int = 48, max_spans: int = 20000) -> BiarcFit:
    """Fit biarcs to ``curve`` on [t0, t1] so that the sampled deviation is at most ``tolerance`` mm.

    ``tangent`` (optional) gives unit tangents dC/dt (M, 2) at t (M,); by default they come from
    :func:`tangents`; they are reversed when t1 < t0. Spans are halved (in t) until each span's biarc is within 0.9·tolerance.
    Raises ValueError if ``max_spans`` would be exceeded.
    """
    scale = abs(t1 - t0)
    raw = tangent if tangent is not None else (lambda t: tangents(curve, t, scale))
    sense = 1.0 if t1 > t0 else -1.0  # tangents along the direction of travel t0 -> t1

    def tan(t):
        return sense * raw(t)

    knots = np.linspace(t0, t1, initial_spans + 1)
    pts = {float(k): p for k, p in zip(knots, curve(knots))}
    tns = {float(k): v for k, v in zip(knots, tan(knots))}
    todo = [(float(knots[i]), float(knots[i + 1])) for i in range(initial_spans)]
    done: dict[float, tuple[float, tuple[Arc, Arc], float]] = {}
    s = np.linspace(0.0, 1.0, samples_per_span + 1)[1:-1]
    while todo:
        if len(done) + len(todo) > max_spans or abs(todo[0][1] - todo[0][0]) < 1e-12 * scale:
            raise GeometryError(f"more than {max_spans} biarcs would be needed for a tolerance of {tolerance:g} mm "
                             "(is the curve smooth?)")
        fits = []
        tq = np.concatenate([a + s * (b - a) for a, b in todo])
        xs = curve(tq).reshape(len(todo), len(s), 2)
        split = []
        for (a, b), x in zip(todo, xs):
            ba = biarc(pts[a], tns[a], pts[b], tns[b])
            dev = math.inf if ba is None else float(np.max(np.minimum(arc_distance(x, ba[0]), arc_distance(x, ba[1]))))
            if dev <= 0.9 * tolerance:
                fits.append((a, b, ba, dev))
            else:
                split.append((a, b))
        for a, b, ba, dev in fits:
            done[a] = (b, ba, dev)
        if split:
            mids = np.array([0.5 * (a + b) for a, b in split])
            for m, p, v in zip(mids, curve(mids), tan(mids)):
                pts[float(m)], tns[float(m)] = p, v
        todo = [half for a, b in split for half in ((a, 0.5 * (a + b)), (0.5 * (a + b), b))]
    order = sorted(done, reverse=t1 < t0)
    arcs = [arc for k in order for arc in done[k][1]]
    ends = np.array([a.start for a in arcs] + [arcs[-1].end])
    size = float(np.max(np.ptp(ends, axis=0))) if len(ends) > 1 else 0.0
    arcs, dropped = drop_short(arcs, shortest_segment(tolerance, size), closed=False)
    return BiarcFit(arcs, max(done[k][2] for k in order) + dropped, len(order), samples_per_span)
