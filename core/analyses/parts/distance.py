"""Exact distances between the contours of a part, found through a spatial index.

The contours of a part are lines and circular arcs (:class:`~..contour.Contour`). The distance
between two of them is the smallest distance between a segment of one and a segment of the other,
and the distance between two segments has a closed form: its minimum is reached at an end point of
one segment (the distance from a point to a line or an arc), at a common point (an intersection,
distance 0), or where both points lie on a common normal (the foot of an arc's centre on a line;
the line of two arcs' centres). :func:`segment_distance` evaluates every such candidate for whole
arrays of segment pairs and keeps the least, so the result is exact to rounding, whatever the
size of the part; no polygon is made.

Pairs are found with a spatial index (shapely's STRtree over the segments' exact bounding
boxes): only pairs whose boxes lie within a distance D are evaluated, and D grows (doubling from
a guess) until the least distance found is within D, so a part with n holes costs O(n log n),
not O(n²).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
import shapely

from ..contour import Contour

TWO_PI = 2.0 * math.pi
#: slack of the angular test "this direction lies on the arc" (rad)
ANGLE_SLACK = 1e-12


@dataclass(frozen=True)
class Pieces:
    """The segments of several contours as arrays (S segments): ``owner`` (S,) contour index,
    ``p0`` ``p1`` (S, 2) mm, ``is_arc`` (S,), ``centre`` (S, 2) mm, ``radius`` (S,) mm, ``a0``
    (S,) start angle and ``theta`` (S,) signed sweep (rad; 0 for lines), ``box`` (S, 4) exact
    bounds (xmin, ymin, xmax, ymax) mm."""

    owner: np.ndarray
    p0: np.ndarray
    p1: np.ndarray
    is_arc: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    a0: np.ndarray
    theta: np.ndarray
    box: np.ndarray

    def __len__(self) -> int:
        return len(self.owner)


def pieces_of(contours: Sequence[Contour]) -> Pieces:
    """Every segment of ``contours`` (see :class:`Pieces`)."""
    parts = [c.segments() for c in contours]
    owner = np.concatenate([np.full(len(sg.p0), k) for k, sg in enumerate(parts)])
    cat = {f: np.concatenate([getattr(sg, f) for sg in parts]) for f in ("p0", "p1", "is_arc", "centre", "radius",
                                                                          "a0", "theta")}
    arc = cat["is_arc"]
    cen = np.where(arc[:, None], cat["centre"], 0.0)
    rad = np.where(arc, cat["radius"], 0.0)
    lo = np.minimum(cat["p0"], cat["p1"])
    hi = np.maximum(cat["p0"], cat["p1"])
    for q in range(4):  # the arc's extreme points along ±x, ±y where the arc passes them
        ang = q * math.pi / 2
        on = arc & _on_arc(np.full(len(arc), ang), cat["a0"], cat["theta"])
        pt = cen + rad[:, None] * np.array([math.cos(ang), math.sin(ang)])
        lo = np.where(on[:, None], np.minimum(lo, pt), lo)
        hi = np.where(on[:, None], np.maximum(hi, pt), hi)
    return Pieces(owner, cat["p0"], cat["p1"], arc, cen, rad, np.where(arc, cat["a0"], 0.0),
                  np.where(arc, cat["theta"], 0.0), np.column_stack([lo, hi]))


def _on_arc(ang: np.ndarray, a0: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Does direction ``ang`` (rad) lie on the arc from ``a0`` sweeping ``theta``? (elementwise)"""
    rel = np.where(theta > 0, np.mod(ang - a0, TWO_PI), np.mod(a0 - ang, TWO_PI))
    return (rel <= np.abs(theta) + ANGLE_SLACK) | (rel >= TWO_PI - ANGLE_SLACK)


def _to_segment(x: np.ndarray, pc: Pieces, k: np.ndarray) -> np.ndarray:
    """The point of segment k nearest to x (both (P, ...)): (P, 2) mm."""
    a, b = pc.p0[k], pc.p1[k]
    d = b - a
    dd = np.einsum("ij,ij->i", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(np.einsum("ij,ij->i", x - a, d) / dd, 0.0, 1.0)
    on_line = a + np.where(dd > 0, t, 0.0)[:, None] * d
    c, r = pc.centre[k], pc.radius[k]
    v = x - c
    nv = np.hypot(v[:, 0], v[:, 1])
    ang = np.arctan2(v[:, 1], v[:, 0])
    inside = _on_arc(ang, pc.a0[k], pc.theta[k]) & (nv > 0)
    radial = c + r[:, None] * v / np.where(nv > 0, nv, 1.0)[:, None]
    da = np.hypot(*(x - a).T)
    db = np.hypot(*(x - b).T)
    end = np.where((da <= db)[:, None], a, b)
    on_arc = np.where(inside[:, None], radial, end)
    return np.where(pc.is_arc[k][:, None], on_arc, on_line)


def _circle_line_points(c, r, a, d) -> list[np.ndarray]:
    """Points of the circle (c, r) on the infinite lines a + t·d, NaN where none: the two
    intersections and the two points of the circle on the normal through c ((P, 2) each)."""
    dd = np.einsum("ij,ij->i", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t0 = np.einsum("ij,ij->i", c - a, d) / dd
        foot = a + t0[:, None] * d
        h = np.hypot(*(foot - c).T)
        half = np.sqrt(np.maximum(r * r - h * h, 0.0) / dd)
        half = np.where(h <= r, half, np.nan)
        u = (foot - c) / h[:, None]
    u = np.where((h > 0)[:, None], u, np.stack([-d[:, 1], d[:, 0]], axis=1) / np.sqrt(dd)[:, None])
    return [a + (t0 - half)[:, None] * d, a + (t0 + half)[:, None] * d, c + r[:, None] * u, c - r[:, None] * u, foot]


def _on_segment(x: np.ndarray, pc: Pieces, k: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Is point x (found on segment k's line or circle) within the segment? (P,) bool."""
    ok = np.isfinite(x).all(axis=1)
    a, d = pc.p0[k], pc.p1[k] - pc.p0[k]
    dd = np.einsum("ij,ij->i", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.einsum("ij,ij->i", x - a, d) / dd
    slack = 1e-12 * scale / np.sqrt(np.where(dd > 0, dd, 1.0))
    line_ok = (t >= -slack) & (t <= 1 + slack)
    v = x - pc.centre[k]
    arc_ok = _on_arc(np.arctan2(v[:, 1], v[:, 0]), pc.a0[k], pc.theta[k])
    return ok & np.where(pc.is_arc[k], arc_ok, line_ok)


def _interior(pc: Pieces, i: np.ndarray, j: np.ndarray, scale: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Candidates where the nearest points are inside both segments (see the module docstring),
    as (point on i, point on j) (P, 2) pairs, NaN where a candidate does not apply."""
    out = []
    arc_i, arc_j = pc.is_arc[i], pc.is_arc[j]
    nan = np.full((len(i), 2), np.nan)
    # a line and a circle: the intersections, and the circle's points on the normal through its centre
    for li, ci, flip in ((i, j, False), (j, i, True)):
        use = ~pc.is_arc[li] & pc.is_arc[ci]
        if not use.any():
            continue
        a, d = pc.p0[li], pc.p1[li] - pc.p0[li]
        pts = _circle_line_points(pc.centre[ci], pc.radius[ci], a, d)
        for q, pt in enumerate(pts[:4]):
            on_line = pt if q < 2 else pts[4]
            ok = use & _on_segment(on_line, pc, li, scale) & _on_segment(pt, pc, ci, scale)
            pair = (on_line, pt) if not flip else (pt, on_line)
            out.append((np.where(ok[:, None], pair[0], nan), np.where(ok[:, None], pair[1], nan)))
    lines = ~arc_i & ~arc_j
    if lines.any():   # two lines: their crossing
        a, d, b, e = pc.p0[i], pc.p1[i] - pc.p0[i], pc.p0[j], pc.p1[j] - pc.p0[j]
        den = d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            t = ((b - a)[:, 0] * e[:, 1] - (b - a)[:, 1] * e[:, 0]) / den
            x = a + t[:, None] * d
        ok = lines & (den != 0) & _on_segment(x, pc, i, scale) & _on_segment(x, pc, j, scale)
        out.append((np.where(ok[:, None], x, nan), np.where(ok[:, None], x, nan)))
    c1, r1, c2, r2 = pc.centre[i], pc.radius[i], pc.centre[j], pc.radius[j]
    w = c2 - c1
    dist = np.hypot(w[:, 0], w[:, 1])
    both = arc_i & arc_j & (dist > 0)
    if not both.any():
        return out
    # two arcs: the points on the line of centres, and the circles' intersections
    with np.errstate(invalid="ignore", divide="ignore"):
        u = w / dist[:, None]
        along = (dist * dist + r1 * r1 - r2 * r2) / (2 * dist)
        across = np.sqrt(r1 * r1 - along * along)
    nrm = np.stack([-u[:, 1], u[:, 0]], axis=1)
    for s1 in (1.0, -1.0):
        for s2 in (1.0, -1.0):
            p, q = c1 + s1 * r1[:, None] * u, c2 + s2 * r2[:, None] * u
            ok = both & _on_segment(p, pc, i, scale) & _on_segment(q, pc, j, scale)
            out.append((np.where(ok[:, None], p, nan), np.where(ok[:, None], q, nan)))
        x = c1 + along[:, None] * u + s1 * across[:, None] * nrm
        ok = both & np.isfinite(across) & _on_segment(x, pc, i, scale) & _on_segment(x, pc, j, scale)
        out.append((np.where(ok[:, None], x, nan), np.where(ok[:, None], x, nan)))
    return out


def segment_distance(pc: Pieces, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact distances (P,) mm between segments i and j (index arrays (P,)) of ``pc`` and the
    nearest points on each ((P, 2) mm): the least over the candidates of the module docstring."""
    scale = 1.0 + np.maximum(np.abs(pc.p0[i]).max(axis=1), np.abs(pc.p0[j]).max(axis=1))
    cands = [(ends, _to_segment(ends, pc, j)) for ends in (pc.p0[i], pc.p1[i])]
    cands += [(_to_segment(ends, pc, i), ends) for ends in (pc.p0[j], pc.p1[j])]
    cands += _interior(pc, i, j, scale)
    pa = np.stack([c[0] for c in cands])          # (C, P, 2)
    pb = np.stack([c[1] for c in cands])
    dd = np.hypot(*(pa - pb).transpose(2, 0, 1))
    dd = np.where(np.isfinite(dd), dd, np.inf)
    best = np.argmin(dd, axis=0)
    cols = np.arange(len(i))
    return dd[best, cols], pa[best, cols], pb[best, cols]


#: contours with fewer segment pairs than this are measured pair by pair without an index
BRUTE_PAIRS = 4096


@dataclass(frozen=True)
class Discs:
    """Which contours are full circles (the bores, most holes of a part): ``is_circle`` (C,),
    ``centre`` (C, 2) mm, ``radius`` (C,) mm (0 where not a circle)."""

    is_circle: np.ndarray
    centre: np.ndarray
    radius: np.ndarray


def discs_of(contours: Sequence[Contour]) -> Discs:
    """The full circles among ``contours`` (two half-circle arcs about one centre)."""
    flags, cen, rad = [], [], []
    for c in contours:
        circ = None
        if len(c) == 2:
            b = np.asarray(c.bulges, float)
            if b[0] == b[1] and abs(abs(b[0]) - 1.0) <= 1e-15:
                p = np.asarray(c.points, float)
                circ = (0.5 * (p[0] + p[1]), 0.5 * float(np.hypot(*(p[1] - p[0]))))
        flags.append(circ is not None)
        cen.append(circ[0] if circ else (0.0, 0.0))
        rad.append(circ[1] if circ else 0.0)
    return Discs(np.array(flags), np.array(cen, float).reshape(-1, 2), np.array(rad, float))


def _far_from(x: np.ndarray, pc: Pieces, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The largest distance (P,) from points x to segments k and where it is reached ((P, 2): an
    end point, or an arc's far point)."""
    d0, d1 = np.hypot(*(x - pc.p0[k]).T), np.hypot(*(x - pc.p1[k]).T)
    far = np.maximum(d0, d1)
    at = np.where((d0 >= d1)[:, None], pc.p0[k], pc.p1[k])
    v = pc.centre[k] - x
    nv = np.hypot(v[:, 0], v[:, 1])
    ang = np.arctan2(v[:, 1], v[:, 0])
    opposite = pc.is_arc[k] & (nv > 0) & _on_arc(ang, pc.a0[k], pc.theta[k]) & (nv + pc.radius[k] > far)
    u = v / np.where(nv > 0, nv, 1.0)[:, None]
    return (np.where(opposite, nv + pc.radius[k], far),
            np.where(opposite[:, None], pc.centre[k] + pc.radius[k][:, None] * u, at))


def _disc_to_segment(c: np.ndarray, r: np.ndarray, pc: Pieces, k: np.ndarray):
    """Distances (P,) between circles (c (P, 2), r (P,)) and segments k, with the nearest points
    (on the circle, on the segment): outside it, inside it, or crossing it (0)."""
    q = _to_segment(c, pc, k)
    v = q - c
    dn = np.hypot(v[:, 0], v[:, 1])
    df, qf = _far_from(c, pc, k)
    outside, inside = dn >= r, df <= r
    d = np.where(outside, dn - r, np.where(inside, r - df, 0.0))
    on_seg = np.where(inside[:, None] & ~outside[:, None], qf, q)
    w = on_seg - c
    nw = np.hypot(w[:, 0], w[:, 1])
    u = np.where((nw > 0)[:, None], w / np.where(nw > 0, nw, 1.0)[:, None], np.array([1.0, 0.0]))
    on_circle = np.where((d > 0)[:, None], c + r[:, None] * u, on_seg)
    return d, on_circle, on_seg


def _disc_to_disc(c1, r1, c2, r2):
    """Distances (P,) between two circles as curves (apart, nested, or crossing: 0) and the
    nearest points."""
    v = c2 - c1
    dc = np.hypot(v[:, 0], v[:, 1])
    u = np.where((dc > 0)[:, None], v / np.where(dc > 0, dc, 1.0)[:, None], np.array([1.0, 0.0]))  # concentric: any
    apart = dc >= r1 + r2
    nested = dc <= np.abs(r1 - r2)
    d = np.where(apart, dc - r1 - r2, np.where(nested, np.abs(r1 - r2) - dc, 0.0))
    sign2 = np.where(apart, -1.0, np.where(r1 >= r2, 1.0, -1.0))
    sign1 = np.where(apart, 1.0, np.where(r1 >= r2, 1.0, -1.0))
    pa = c1 + (sign1 * r1)[:, None] * u
    pb = c2 + (sign2 * r2)[:, None] * u
    return d, pa, np.where((d > 0)[:, None], pb, pa)


def nearest_between_contours(contours: Sequence[Contour], guess: float = 1.0, pc: Pieces | None = None,
                             discs: Discs | None = None
                             ) -> tuple[float, tuple[float, float] | None, tuple[int, int] | None]:
    """The least distance (mm) between two different contours of ``contours``, the midpoint of
    the two nearest points, and the two contours' indices; (inf, None, None) with fewer than two.
    ``guess`` (mm): the first search radius of the spatial index (see the module docstring);
    ``pc``, ``discs``: :func:`pieces_of` and :func:`discs_of` of ``contours`` if made already.
    Full circles are measured as circles (centre and radius: one formula instead of a pair of arcs)."""
    if len(contours) < 2:
        return math.inf, None, None
    pc = pieces_of(contours) if pc is None else pc
    discs = discs_of(contours) if discs is None else discs
    if len(pc) * len(pc) <= 2 * BRUTE_PAIRS:
        i, j = np.triu_indices(len(pc), 1)
        keep = pc.owner[i] != pc.owner[j]
        return _least(pc, discs, i[keep], j[keep], math.inf)
    b = pc.box
    size = float(max(np.max(b[:, 2:] - b[:, :2]), 1e-300))
    tree = shapely.STRtree(shapely.box(b[:, 0], b[:, 1], b[:, 2], b[:, 3]))
    reach = max(float(guess), 1e-9 * size)
    span = float(np.max(b[:, 2:]) - np.min(b[:, :2]))
    while True:
        i, j = tree.query(tree.geometries, predicate="dwithin", distance=reach)
        keep = (i < j) & (pc.owner[i] != pc.owner[j])
        found = _least(pc, discs, i[keep], j[keep], reach)
        if found[1] is not None or reach > 2.0 * span:
            return found
        reach *= 2.0


def _least(pc: Pieces, discs: Discs, i: np.ndarray, j: np.ndarray, reach: float):
    """The least distance among segment pairs (i, j) if it is within ``reach`` (else (inf, None,
    None)): (distance, midpoint of the nearest points, the two contours' indices)."""
    if not len(i):
        return math.inf, None, None
    oi, oj = pc.owner[i], pc.owner[j]
    ci, cj = discs.is_circle[oi], discs.is_circle[oj]
    found = []   # (d, pa, pb, owner a, owner b)
    both = ci & cj
    if both.any():   # one pair of contours, once
        pairs = np.unique(np.stack([oi[both], oj[both]], axis=1), axis=0)
        a, b = pairs[:, 0], pairs[:, 1]
        found.append((*_disc_to_disc(discs.centre[a], discs.radius[a], discs.centre[b], discs.radius[b]), a, b))
    for sel, circ, seg in ((ci & ~cj, oi, j), (cj & ~ci, oj, i)):
        if sel.any():
            o, k = circ[sel], seg[sel]
            found.append((*_disc_to_segment(discs.centre[o], discs.radius[o], pc, k), o, pc.owner[k]))
    rest = ~ci & ~cj
    if rest.any():
        found.append((*segment_distance(pc, i[rest], j[rest]), oi[rest], oj[rest]))
    d, pa, pb, a, b = (np.concatenate([f[q] for f in found]) for q in range(5))
    k = int(np.argmin(d))
    if not d[k] <= reach:
        return math.inf, None, None
    mid = 0.5 * (pa[k] + pb[k])
    return float(d[k]), (float(mid[0]), float(mid[1])), (int(a[k]), int(b[k]))
