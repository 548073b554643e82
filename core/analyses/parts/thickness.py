"""The necks of an outline: the thinnest material measured across the part along its normals.

From points every ≤ ``perimeter/samples`` along the outline (at least three on every segment, and
at every vertex) a ray along the inward normal is intersected exactly with every line and arc of
the outline; where it first meets the outline again head-on (the far side's normal within
:data:`HEAD_ON_DEG` of the ray, and not on the segment the ray starts from, the next one or the
previous one: that is a corner, not a web) the distance is a material thickness. A hole met
before the far side interrupts the ray (the material there is measured as the distance between
the hole and the outline instead). Around the :data:`REFINED` least local minima the rays are then
cast again, :data:`WINDOW` across one sample spacing, :data:`ROUNDS` times (each time 1/((WINDOW −
1)/2) the spacing), so a neck is found to within h/343 of its place (h the first pass's spacing) at
the cost of a few hundred rays.

The holes a ray may meet are found with a spatial index (shapely's STRtree over their segments'
exact boxes, queried with each ray cut at its first hit on the outline), so a part with many
holes costs what its few near holes cost.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np
import shapely

from ..contour import Contour
from .distance import pieces_of
from .outline import ccw

#: rays cast along the outline in the first pass (besides the vertices and 3 per segment)
NECK_SAMPLES = 48
#: local minima refined, rays across each window, rounds of refinement
REFINED = 6
WINDOW = 15
ROUNDS = 3
#: rays × hole segments above which the holes in a ray's way are found with the spatial index
BRUTE_HITS = 20000
#: a ray meets the far side head-on when their normals are within this angle (degrees)
HEAD_ON_DEG = 30.0


def _inward(sg, k: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points (M, 2) at parameters t of segments k of a CCW contour and their inward unit normals."""
    p0, p1 = sg.p0[k], sg.p1[k]
    arc = sg.is_arc[k]
    d = p1 - p0
    ln = np.hypot(d[:, 0], d[:, 1])
    ln = np.where(ln > 0, ln, 1.0)
    pt_line = p0 + t[:, None] * d
    n_line = np.stack([-d[:, 1], d[:, 0]], axis=1) / ln[:, None]
    ang = sg.a0[k] + t * sg.theta[k]
    rad = np.where(arc, sg.radius[k], 0.0)
    e = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    cen = np.where(arc[:, None], sg.centre[k], 0.0)
    pt_arc = cen + rad[:, None] * e
    n_arc = np.where((sg.theta[k] > 0)[:, None], -e, e)
    return np.where(arc[:, None], pt_arc, pt_line), np.where(arc[:, None], n_arc, n_line)


def _hits(q, u, a, b, arc, c, r, a0, th, smin: float) -> tuple[np.ndarray, np.ndarray]:
    """Rays q + s·u against segments (a→b; arcs: centre c, radius r, start a0, sweep th), all
    broadcast together (points (..., 2)): first distance s > smin (inf: none), inward normals."""
    with np.errstate(divide="ignore", invalid="ignore"):
        d = b - a
        den = u[..., 0] * d[..., 1] - u[..., 1] * d[..., 0]
        w = a - q
        sl = (w[..., 0] * d[..., 1] - w[..., 1] * d[..., 0]) / den
        ul = (w[..., 0] * u[..., 1] - w[..., 1] * u[..., 0]) / den
        ok = ~arc & (np.abs(den) > 1e-14) & (sl > smin) & (ul >= -1e-12) & (ul <= 1 + 1e-12)
        s = np.where(ok, sl, np.inf)
        ln = np.hypot(d[..., 0], d[..., 1])
        nl = np.stack([-d[..., 1], d[..., 0]], axis=-1) / np.where(ln > 0, ln, 1.0)[..., None]
        nrm = np.where(ok[..., None], nl, 0.0)
        pc = q - c
        bq = pc[..., 0] * u[..., 0] + pc[..., 1] * u[..., 1]
        disc = bq * bq - (pc[..., 0] ** 2 + pc[..., 1] ** 2 - r * r)
        root = np.sqrt(np.where(arc & (disc >= 0), disc, np.nan))
        for sgn in (1.0, -1.0):  # far root first, the near one overrides when valid
            sa = -bq + sgn * root
            x = pc + sa[..., None] * u
            rel = np.mod((np.arctan2(x[..., 1], x[..., 0]) - a0) * np.sign(th), 2 * np.pi)
            on = (rel <= np.abs(th) + 1e-12) | (rel >= 2 * np.pi - 1e-12)
            ok = (sa > smin) & on & (sa < s)
            s = np.where(ok, sa, s)
            nrm = np.where(ok[..., None], x * (-np.sign(th) / np.where(r > 0, r, 1.0))[..., None], nrm)
    return s, nrm


def _segs(sg, k=None):
    """The arrays :func:`_hits` takes, of every segment of ``sg`` (or of segments ``k``)."""
    pick = (lambda v: v) if k is None else (lambda v: v[k])
    arc = pick(sg.is_arc)
    return (pick(sg.p0), pick(sg.p1), arc, np.where(arc[:, None], pick(sg.centre), 0.0),
            np.where(arc, pick(sg.radius), 0.0), np.where(arc, pick(sg.a0), 0.0), np.where(arc, pick(sg.theta), 0.0))


def ray_hits(p: np.ndarray, n: np.ndarray, sg, m: np.ndarray | None = None, k: np.ndarray | None = None,
             smin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Hits of rays p + s·n ((M, 2) mm each) with the segments of ``sg`` (a contour's
    :class:`~..contour.Segments` or :class:`~.distance.Pieces`): the first distance s > smin along
    each ray and the segment's inward normal there. Without ``m``, ``k``: every ray against every
    segment, (M, K) and (M, K, 2); with them, the pairs (ray m, segment k), (P,) and (P, 2)."""
    if m is None:
        a, b, arc, c, r, a0, th = _segs(sg)
        return _hits(p[:, None, :], n[:, None, :], a[None], b[None], arc[None], c[None], r[None], a0[None],
                     th[None], smin)
    return _hits(p[m], n[m], *_segs(sg, k), smin)


def _samples(sg, k_n: int, samples: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segment indices, parameters and half-spacings (in t) of the ray origins: every vertex, and
    points every ≤ perimeter/samples along each segment (at least 3)."""
    h = float(sg.length.sum()) / samples
    m = np.maximum(3, np.ceil(sg.length / h).astype(int))
    k_arr = np.repeat(np.arange(k_n), m + 1)
    starts = np.cumsum(np.r_[0, m + 1])[:-1]
    pos = np.arange(len(k_arr)) - np.repeat(starts, m + 1)          # 0 … m within each segment
    t_arr = np.where(pos == 0, 0.0, (pos - 0.5) / np.repeat(m, m + 1))
    return k_arr, t_arr, 1.0 / np.repeat(m, m + 1)


def _hole_hits(p: np.ndarray, n: np.ndarray, reach: np.ndarray, holes: Sequence[Contour], smin: float) -> np.ndarray:
    """The first distance (M,) along each ray at which it meets a hole, if within ``reach`` (the
    ray's first hit on the outline; inf: no hole in the way)."""
    out = np.full(len(p), np.inf)
    pc = pieces_of(holes)
    if len(p) * len(pc) <= BRUTE_HITS:
        return ray_hits(p, n, pc, smin=smin)[0].min(axis=1)
    tree = shapely.STRtree(shapely.box(pc.box[:, 0], pc.box[:, 1], pc.box[:, 2], pc.box[:, 3]))
    span = float(np.max(pc.box[:, 2:]) - np.min(pc.box[:, :2])) + float(np.max(np.abs(p))) + 1.0
    far = np.where(np.isfinite(reach), reach, 2.0 * span)
    rays = shapely.linestrings(np.stack([p, p + far[:, None] * n], axis=1))
    m, k = tree.query(rays, predicate="intersects")
    if len(m):
        s, _ = ray_hits(p, n, pc, m, k, smin)
        np.minimum.at(out, m, s)
    return out


def _cast(sg, k_n: int, k_arr: np.ndarray, t_arr: np.ndarray, holes: Sequence[Contour], smin: float):
    """Rays from (k, t): origins (M, 2), inward normals (M, 2), the thickness met head-on (M,) mm
    (inf where the ray meets a corner, a neighbouring segment, a hole or nothing) and, for a ray
    from a vertex that meets the neighbour of the vertex's other segment head-on (a corner: not a
    web), that distance (M,) (inf elsewhere): the rays just beside such a vertex may be webs, a
    run narrower than the rays' spacing, so it seeds a refinement."""
    p, n = _inward(sg, k_arr, t_arr)
    s, nrm = ray_hits(p, n, sg, smin=smin)
    first = np.argmin(s, axis=1)
    rows = np.arange(len(p))
    dist = s[rows, first]
    if holes:
        dist = np.where(_hole_hits(p, n, dist, holes, smin) < dist, np.inf, dist)
    prev = (k_arr - 1) % k_n
    adjacent = (first == k_arr) | (first == (k_arr + 1) % k_n) | (first == prev)
    # a vertex sample (t = 0) also belongs to the previous segment, one at t = 1 to the next
    corner = ((t_arr == 0.0) & (first == (prev - 1) % k_n)) | ((t_arr == 1.0) & (first == (k_arr + 2) % k_n))
    head_on = -(nrm[rows, first] * n).sum(axis=1) >= math.cos(math.radians(HEAD_ON_DEG))
    seen = np.isfinite(dist) & head_on
    return (p, n, np.where(seen & ~adjacent & ~corner, dist, np.inf),
            np.where(seen & ~adjacent & corner, dist, np.inf))


def _windows(d: np.ndarray, seed: np.ndarray, k_arr: np.ndarray, t_arr: np.ndarray, dt: np.ndarray):
    """Rays across the windows around the least local minima of ``d`` (sample order) and the
    least vertex seeds (``seed``, see :func:`_cast`): (k, t, dt), or None if there is neither."""
    left, right = np.roll(d, 1), np.roll(d, -1)
    minima = np.nonzero(np.isfinite(d) & (d <= left) & (d <= right))[0]
    seeds = np.nonzero(np.isfinite(seed))[0]
    pick = np.r_[minima[np.argsort(d[minima], kind="stable")[:REFINED]],
                 seeds[np.argsort(seed[seeds], kind="stable")[:REFINED]]].astype(int)
    if not len(pick):
        return None
    off = np.linspace(-1.0, 1.0, WINDOW)
    k = np.repeat(k_arr[pick], WINDOW)
    t = np.clip((t_arr[pick][:, None] + dt[pick][:, None] * off).ravel(), 0.0, 1.0)
    return k, t, np.repeat(dt[pick] * 2.0 / (WINDOW - 1), WINDOW)


def _sampling_error(sg, dt: np.ndarray, k_arr: np.ndarray, least: float) -> float:
    """A bound (mm) on how much the first pass can overstate the thinnest neck, whose rays are h
    apart along the outline (h its largest spacing, κ its largest curvature): along a side the
    head-on thickness L changes at most as tan 30°·(1 + L·κ) per mm (the far side's normal is
    within 30° of the ray, and the ray turns with the side's curvature), so a minimum between two
    rays, or at the end of a run of rays (where they begin to meet a neighbouring segment), is
    missed by at most h·tan 30°·(1 + L·κ) + h²·κ/4."""
    h = float(np.max(dt * sg.length[k_arr]))
    kappa = float(np.max(np.where(sg.is_arc, 1.0 / np.where(sg.is_arc, sg.radius, 1.0), 0.0)))
    return h * math.tan(math.radians(HEAD_ON_DEG)) * (1.0 + least * kappa) + h * h * kappa / 4.0


def necks(outer: Contour, holes: Sequence[Contour] = (), samples: int = NECK_SAMPLES, above: float = math.inf
          ) -> tuple[float, tuple[float, float] | None]:
    """The thinnest neck of an outline (see the module docstring): (thickness mm, midpoint) or
    (inf, None) when no ray meets the outline head-on. ``above`` (mm): a web already known (the
    distance between the part's contours); when the first pass shows that no neck can be thinner
    (its least thickness less the sampling error :func:`_sampling_error` is above it), the
    refinement is skipped and the first pass's value returned (it is only used if it is the less)."""
    oc = ccw(outer)
    sg = oc.segments()
    k_n = len(oc)
    smin = 1e-9 * max(float(sg.length.sum()), 1.0)
    k_arr, t_arr, dt = _samples(sg, k_n, samples)
    p, n, d, seed = _cast(sg, k_n, k_arr, t_arr, holes, smin)
    found = [(p, n, d)]
    least = float(min(np.min(d), np.min(seed)))
    rounds = ROUNDS if not least - _sampling_error(sg, dt, k_arr, least) > above else 0
    for _ in range(rounds):
        win = _windows(d, seed, k_arr, t_arr, dt)
        if win is None:
            break
        k_arr, t_arr, dt = win
        p, n, d, seed = _cast(sg, k_n, k_arr, t_arr, holes, smin)
        found.append((p, n, d))
    p, n, d = (np.concatenate([f[q] for f in found]) for q in range(3))
    if not np.isfinite(d).any():
        return math.inf, None
    j = int(np.argmin(d))
    mid = p[j] + 0.5 * d[j] * n[j]
    return float(d[j]), (float(mid[0]), float(mid[1]))
