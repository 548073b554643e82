"""Outline geometry of parts: exact contours of lines and arcs (mm), made and queried.

Constructors of closed, counter-clockwise contours (:func:`circle`, :func:`stadium`,
:func:`rectangle`, and :func:`disc_hull`, the exact convex hull of discs) and queries on any
:class:`~..contour.Contour` (:func:`reversed_contour`, :func:`ccw`, the exact
:func:`contour_bounds`, :func:`is_circle`). The part builders use them through :mod:`.parts`.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..contour import Contour


def circle(centre: Sequence[float], radius: float, kind: str = "bore") -> Contour:
    """A full circle (two counter-clockwise semicircles), mm."""
    return Contour.circle((float(centre[0]), float(centre[1])), float(radius), kind)


def stadium(p: Sequence[float], q: Sequence[float], radius: float, kind: str = "slot") -> Contour:
    """The counter-clockwise stadium around segment p–q (mm) with end radius ``radius``."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    d = q - p
    n = float(np.hypot(*d))
    if not n > 0.0:
        return circle(p, radius, kind)
    u = d / n
    left = np.array([-u[1], u[0]]) * radius
    pts = np.array([p - left, q - left, q + left, p + left])
    return Contour(pts, np.array([0.0, 1.0, 0.0, 1.0]), (kind,) * 4)


def rectangle(centre: Sequence[float], along: float, across: float, angle: float, kind: str = "block") -> Contour:
    """A counter-clockwise rectangle ``along`` × ``across`` mm centred at ``centre``, its long
    side at ``angle`` rad."""
    c, s = math.cos(angle), math.sin(angle)
    u, v = np.array([c, s]) * along / 2, np.array([-s, c]) * across / 2
    o = np.asarray(centre, float)
    pts = np.array([o - u - v, o + u - v, o + u + v, o - u + v])
    return Contour(pts, np.zeros(4), (kind,) * 4)


def disc_hull(centres: np.ndarray, radii: np.ndarray, kind: str = "plate",
              spans: Sequence[tuple[float, float] | None] | None = None) -> Contour:
    """The convex hull of discs (centres (K, 2) mm, radii (K,) mm ≥ 0; 0 is a point), exact.

    ``spans`` (optional, per disc): (a, b) rad makes disc k only the arc of its circle between
    the angles a < b (counter-clockwise), e.g. a working arc that must stay on the outline; its
    end points take part as points.

    The support function h(θ) = max_k (c_k·n(θ) + r_k) is the upper envelope of sinusoids; its
    breakpoints are the pairwise crossings, found in closed form (and the arcs' end normals). Each
    angle interval whose maximiser is disc k gives an arc of k (a vertex if r_k = 0); consecutive
    ones are joined by their common outer tangent. Counter-clockwise.
    """
    c = np.asarray(centres, float).reshape(-1, 2)
    r = np.asarray(radii, float).reshape(-1)
    span = list(spans) if spans is not None else [None] * len(c)
    crit = [0.0]
    for k, sp in enumerate(list(span)):
        if sp is not None:
            for ang in sp:
                c = np.vstack([c, c[k] + r[k] * np.array([math.cos(ang), math.sin(ang)])])
                r = np.append(r, 0.0)
                span.append(None)
                crit.append(ang % (2 * math.pi))
    scale = float(np.max(np.abs(c)) + np.max(r) + 1.0)
    if len(c) == 1:
        return circle(c[0], r[0], kind)
    for i in range(len(c)):
        for j in range(i + 1, len(c)):
            d = c[i] - c[j]
            rho = math.hypot(*d)
            if rho <= 1e-12 * scale:
                continue
            # d·n(θ) = r_j − r_i  ->  cos(θ − β) = (r_j − r_i)/ρ
            x = (r[j] - r[i]) / rho
            if abs(x) <= 1.0:
                beta, a = math.atan2(d[1], d[0]), math.acos(x)
                crit += [(beta + a) % (2 * math.pi), (beta - a) % (2 * math.pi)]
    crit = np.unique(np.round(np.sort(np.array(crit)), 14))
    crit = np.append(crit, crit[0] + 2 * math.pi)
    mids = 0.5 * (crit[:-1] + crit[1:])
    support = c @ np.stack([np.cos(mids), np.sin(mids)]) + r[:, None]
    for k, sp in enumerate(span):
        if sp is not None:
            rel = np.mod(mids - sp[0], 2 * math.pi)
            support[k] = np.where(rel <= (sp[1] - sp[0]) % (2 * math.pi), support[k], -np.inf)
    owner = np.argmax(support - 1e-12 * scale * np.arange(len(c))[:, None], axis=0)
    # merge runs of one owner (cyclically)
    runs: list[list] = []
    for k, (a, b) in enumerate(zip(crit[:-1], crit[1:])):
        if b - a <= 1e-15:
            continue
        if runs and runs[-1][0] == owner[k]:
            runs[-1][2] = b
        else:
            runs.append([int(owner[k]), a, b])
    if len(runs) > 1 and runs[0][0] == runs[-1][0]:
        runs[0][1] = runs[-1][1] - 2 * math.pi
        runs.pop()
    if len(runs) == 1:
        return circle(c[runs[0][0]], r[runs[0][0]], kind)
    pts, bul = [], []
    for k, a, b in runs:
        start = c[k] + r[k] * np.array([math.cos(a), math.sin(a)])
        end = c[k] + r[k] * np.array([math.cos(b), math.sin(b)])
        if r[k] > 0.0 and b - a > 1e-12:
            pts += [start, end]
            bul += [math.tan((b - a) / 4.0), 0.0]
        else:
            pts.append(start)
            bul.append(0.0)
    pts_a, bul_a = np.array(pts), np.array(bul)
    # drop zero-length tangents (discs touching the same support line at one point)
    keep = np.hypot(*(np.roll(pts_a, -1, axis=0) - pts_a).T) > 1e-12 * scale
    return Contour(pts_a[keep], bul_a[keep], (kind,) * int(keep.sum()))


def reversed_contour(c: Contour) -> Contour:
    """The same contour traversed the other way."""
    pts = np.asarray(c.points, float)[::-1]
    bul = -np.roll(np.asarray(c.bulges, float)[::-1], -1)
    kinds = tuple(reversed(c.kinds[:len(c)])) if c.kinds else ()
    kinds = (kinds[1:] + kinds[:1]) if kinds else ()
    return Contour(pts, bul, kinds)


def ccw(c: Contour) -> Contour:
    """``c`` made counter-clockwise."""
    return c if c.area() > 0 else reversed_contour(c)


def contour_bounds(c: Contour) -> tuple[float, float, float, float]:
    """Exact bounding box (xmin, ymin, xmax, ymax) mm: vertices and the arcs' extreme points."""
    sg = c.segments()
    lo, hi = sg.p0.min(axis=0), sg.p0.max(axis=0)
    k = np.nonzero(sg.is_arc)[0]
    if len(k):
        ang = np.arange(4) * (math.pi / 2)                                  # +x, +y, −x, −y
        a0, th = sg.a0[k][:, None], sg.theta[k][:, None]
        rel = np.where(th > 0, np.mod(ang - a0, 2 * math.pi), np.mod(a0 - ang, 2 * math.pi))
        on = rel <= np.abs(th)
        r = sg.radius[k][:, None]
        x = np.where(on[:, [0, 2]], sg.centre[k, 0:1] + r * np.array([1.0, -1.0]), np.nan)
        y = np.where(on[:, [1, 3]], sg.centre[k, 1:2] + r * np.array([1.0, -1.0]), np.nan)
        if np.isfinite(x).any():
            lo[0], hi[0] = min(lo[0], np.nanmin(x)), max(hi[0], np.nanmax(x))
        if np.isfinite(y).any():
            lo[1], hi[1] = min(lo[1], np.nanmin(y)), max(hi[1], np.nanmax(y))
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


def _turning(c: Contour) -> tuple[np.ndarray, np.ndarray, float]:
    """Each segment's sweep (K,), the turn at each vertex from segment k to k + 1 (K,), and
    the total turning (rad)."""
    sg = c.segments()
    chord = np.arctan2(sg.p1[:, 1] - sg.p0[:, 1], sg.p1[:, 0] - sg.p0[:, 0])
    start, end = chord - sg.theta / 2, chord + sg.theta / 2          # tangent directions (rad)
    turn = np.mod(np.roll(start, -1) - end + math.pi, 2 * math.pi) - math.pi
    return sg.theta, turn, float(sg.theta.sum() + turn.sum())


def is_convex(c: Contour) -> bool:
    """True if ``c`` is a simple convex closed curve (either way round): every arc and every turn
    at a vertex bends the same way and they add up to one turn (so it cannot cross itself)."""
    if len(c) < 2:
        return False
    theta, turn, total = _turning(c)
    sign = 1.0 if total > 0 else -1.0
    return (abs(abs(total) - 2 * math.pi) <= 1e-9 and bool((sign * theta >= 0).all())
            and bool((sign * turn >= -1e-12).all()))


def rolling_radius(c: Contour) -> float:
    """For a convex contour without corners (every vertex a tangent join: a stadium, the hull of
    discs), its smallest arc radius R: a disc of radius R rolls freely inside it (Blaschke), so
    every chord along an inward normal is at least 2R long. 0 for any other contour."""
    if not is_convex(c):
        return 0.0
    _, turn, _ = _turning(c)
    sg = c.segments()
    if not (np.abs(turn) <= 1e-9).all() or not sg.is_arc.any():
        return 0.0
    return float(np.min(sg.radius[sg.is_arc]))


def is_circle(c: Contour) -> tuple[tuple[float, float], float] | None:
    """(centre, radius) if ``c`` is a full circle (two half-circle arcs about one centre), else None."""
    if len(c) != 2:
        return None
    sg = c.segments()
    if not sg.is_arc.all() or abs(abs(sg.theta[0]) - math.pi) > 1e-12 or np.sign(sg.theta[0]) != np.sign(sg.theta[1]):
        return None
    if abs(abs(sg.theta[1]) - math.pi) > 1e-12:
        return None
    cen = 0.5 * (sg.p0[0] + sg.p1[0])  # the diameter's midpoint: exact where tan(π/2) is not
    return (float(cen[0]), float(cen[1])), 0.5 * float(np.hypot(*(sg.p1[0] - sg.p0[0])))
