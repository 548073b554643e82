"""Checks of cut-ready parts: closed, finite, a valid polygon, holes inside and apart, the thinnest
web at least a minimum (:func:`check_part`, :func:`require_checked`), and the report lines.

The thinnest web of a part is the smallest of
- the distances between its contours (each hole to the outline, each hole to each other hole),
  measured with shapely on polygons inscribed in the arcs (chord sagitta ≤ :data:`CHECK_TOL`, so
  each distance is exact to within 2·CHECK_TOL), and
- the necks of the outline: from points every ≤ ``perimeter/NECK_SAMPLES`` along the outline (and
  at every vertex) a ray along the inward normal is intersected exactly with every line and arc;
  where it first meets the outline again head-on (the far side's normal within
  :data:`HEAD_ON_DEG` of the ray, not on a neighbouring segment: that is a corner, not a web) the
  distance is a material thickness. Sampling can only miss a minimum, by O(h²·curvature).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np
import shapely
from shapely.validation import explain_validity

from ...errors import GeometryError
from ...model.drawing import DEFAULT_MIN_WEB  # noqa: F401  (re-exported: the default thinnest web, mm)
from ..contour import Contour
from .keys import API, Vocabulary, name_of, names_of
from .outline import ccw
from .records import CHECK_TOL, Part, PartSet

#: rays cast along the outline for the necks (at most)
NECK_SAMPLES = 3000
#: a ray meets the far side head-on when their normals are within this angle (degrees)
HEAD_ON_DEG = 30.0


@dataclass(frozen=True)
class PartCheck:
    """The check of one part: exact ``area`` (mm²), thinnest ``web`` (mm; inf when there is no
    web to measure) at ``web_at`` (mm), ``deviation`` (mm), ``problems`` (empty: fit to cut)."""

    name: str
    area: float
    web: float
    web_at: tuple[float, float] | None
    deviation: float
    problems: tuple[str, ...] = field(default=())

    @property
    def ok(self) -> bool:
        return not self.problems


def _ring(c: Contour, tol: float) -> shapely.LinearRing:
    return shapely.LinearRing(c.polyline(tol))


def _contour_problems(c: Contour, what: str, scale: float) -> list[str]:
    pts, bul = np.asarray(c.points, float), np.asarray(c.bulges, float)
    if len(bul) < 1 or pts.shape != (len(bul), 2):
        return [f"{what} is not a closed chain of segments"]
    if not (np.isfinite(pts).all() and np.isfinite(bul).all()):
        return [f"{what} has non-finite coordinates"]
    seg = np.hypot(*(np.roll(pts, -1, axis=0) - pts).T)
    if len(bul) > 1 and (seg <= 1e-12 * scale).any():
        k = int(np.argmin(seg))
        return [f"{what} has a zero-length segment at ({pts[k, 0]:.6g}, {pts[k, 1]:.6g})"]
    if len(bul) == 1:
        return [f"{what} has a single vertex"]
    return []


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


def _ray_hits(p: np.ndarray, n: np.ndarray, sg, smin: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """First hits of rays p + s·n (M rays) with segments sg (K): distance s (M, K) (inf: none) and
    the inward normals at the hits (M, K, 2)."""
    arc = sg.is_arc
    s = np.full((len(p), len(arc)), np.inf)
    nrm = np.zeros((len(p), len(arc), 2))
    with np.errstate(divide="ignore", invalid="ignore"):
        if (~arc).any():
            a, b = sg.p0[~arc], sg.p1[~arc]
            d = b - a
            den = n[:, None, 0] * d[None, :, 1] - n[:, None, 1] * d[None, :, 0]
            w = a[None, :, :] - p[:, None, :]
            sl = (w[..., 0] * d[None, :, 1] - w[..., 1] * d[None, :, 0]) / den
            ul = (w[..., 0] * n[:, None, 1] - w[..., 1] * n[:, None, 0]) / den
            ok = (np.abs(den) > 1e-14) & (sl > smin) & (ul >= -1e-12) & (ul <= 1 + 1e-12)
            s[:, ~arc] = np.where(ok, sl, np.inf)
            ln = np.hypot(d[:, 0], d[:, 1])
            nl = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.where(ln > 0, ln, 1.0)[:, None]
            nrm[:, ~arc] = nl[None, :, :]
        if arc.any():
            c, r = sg.centre[arc], sg.radius[arc]
            a0, th = sg.a0[arc], sg.theta[arc]
            pc = p[:, None, :] - c[None, :, :]
            bq = pc[..., 0] * n[:, None, 0] + pc[..., 1] * n[:, None, 1]
            cq = pc[..., 0] ** 2 + pc[..., 1] ** 2 - r[None, :] ** 2
            disc = bq * bq - cq
            root = np.sqrt(np.where(disc >= 0, disc, np.nan))
            best = np.full(bq.shape, np.inf)
            best_n = np.zeros(bq.shape + (2,))
            for sgn in (1.0, -1.0):  # far root first, the near one overrides when valid
                sa = -bq + sgn * root
                q = pc + sa[..., None] * n[:, None, :]
                ang = np.arctan2(q[..., 1], q[..., 0])
                rel = np.where(th > 0, np.mod(ang - a0, 2 * np.pi), np.mod(a0 - ang, 2 * np.pi))
                on = (rel <= np.abs(th) + 1e-12) | (rel >= 2 * np.pi - 1e-12)
                ok = (disc >= 0) & (sa > smin) & on & (sa < best)
                e = q / r[None, :, None]
                nq = np.where((th > 0)[None, :, None], -e, e)
                best = np.where(ok, sa, best)
                best_n = np.where(ok[..., None], nq, best_n)
            s[:, arc] = best
            nrm[:, arc] = best_n
    return s, nrm


def necks(outer: Contour, holes: Sequence[Contour] = (), samples: int = NECK_SAMPLES
          ) -> tuple[float, tuple[float, float] | None]:
    """The thinnest neck of an outline (see the module docstring): (thickness mm, midpoint) or
    (inf, None) when no ray meets the outline head-on."""
    oc = ccw(outer)
    sg = oc.segments()
    k_n = len(oc)
    per = float(sg.length.sum())
    h = per / samples
    ks, ts = [], []
    for k in range(k_n):
        m = max(1, int(math.ceil(sg.length[k] / h)))
        ks += [k] * (m + 1)
        ts += [0.0] + list((np.arange(m) + 0.5) / m)
    k_arr, t_arr = np.array(ks), np.array(ts)
    p, n = _inward(sg, k_arr, t_arr)
    scale = max(per, 1.0)
    s, nrm = _ray_hits(p, n, sg, 1e-9 * scale)
    first = np.argmin(s, axis=1)
    dist = s[np.arange(len(p)), first]
    if holes:
        hs = np.full(len(p), np.inf)
        for hole in holes:
            sh, _ = _ray_hits(p, n, hole.segments(), 1e-9 * scale)
            hs = np.minimum(hs, sh.min(axis=1))
        dist = np.where(hs < dist, np.inf, dist)
    src = k_arr
    prev = (src - 1) % k_n
    adjacent = (first == src) | (first == (src + 1) % k_n) | (first == prev)
    # a vertex sample (t = 0) also belongs to the previous segment
    adjacent |= (t_arr == 0.0) & (first == (prev - 1) % k_n)
    nh = nrm[np.arange(len(p)), first]
    head_on = -(nh * n).sum(axis=1) >= math.cos(math.radians(HEAD_ON_DEG))
    good = np.isfinite(dist) & ~adjacent & head_on
    if not good.any():
        return math.inf, None
    j = int(np.argmin(np.where(good, dist, np.inf)))
    mid = p[j] + 0.5 * dist[j] * n[j]
    return float(dist[j]), (float(mid[0]), float(mid[1]))


def thinnest_web(part: Part, tol: float = CHECK_TOL) -> tuple[float, tuple[float, float] | None]:
    """The part's thinnest web (mm) and where (see the module docstring); (inf, None) if none."""
    best, at = math.inf, None
    rings = [_ring(c, tol) for c in part.contours]
    for i in range(len(rings)):
        for j in range(i + 1, len(rings)):
            d = float(shapely.distance(rings[i], rings[j]))
            if d < best:
                line = shapely.shortest_line(rings[i], rings[j])
                mid = line.interpolate(0.5, normalized=True)
                best, at = d, (mid.x, mid.y)
    if part.outer is not None:
        d, where = necks(part.outer, part.holes)
        if d < best:
            best, at = d, where
    return best, at


def check_part(part: Part, min_web: float = DEFAULT_MIN_WEB, tol: float = CHECK_TOL) -> PartCheck:
    """Check one part: every contour closed and finite; the outline (with its holes) a valid
    polygon, no ring self-intersecting, holes inside and apart; thinnest web ≥ ``min_web`` mm."""
    problems: list[str] = []
    if not part.contours:
        return PartCheck(part.name, 0.0, math.inf, None, part.deviation, ("it has no contour",))
    scale = max(1.0, max(float(np.max(np.abs(c.points))) for c in part.contours if len(c.points)))
    for i, c in enumerate(part.contours):
        what = "the outline" if (part.outer is not None and i == 0) else f"hole {i if part.outer is not None else i + 1}"
        problems += _contour_problems(c, what, scale)
    if problems:
        return PartCheck(part.name, math.nan, math.nan, None, part.deviation, tuple(problems))
    for i, c in enumerate(part.contours):
        ring = _ring(c, tol)
        if not ring.is_simple:
            what = "the outline" if (part.outer is not None and i == 0) else "a hole"
            problems.append(f"{what} intersects itself ({explain_validity(shapely.Polygon(ring))})")
    if not problems:
        if part.outer is not None:
            poly = part.polygon(tol)
            if not poly.is_valid:
                problems.append(f"not a valid outline with holes: {explain_validity(poly)}")
        else:
            holes = [shapely.Polygon(h.polyline(tol)) for h in part.holes]
            for i in range(len(holes)):
                for j in range(i + 1, len(holes)):
                    if holes[i].intersects(holes[j]):
                        problems.append(f"holes {i + 1} and {j + 1} overlap")
    web, at = (math.nan, None) if problems else thinnest_web(part, tol)
    if not problems and not web >= min_web - 2 * tol:  # the measurement is exact to 2·tol
        where = f" at ({at[0]:.3f}, {at[1]:.3f}) mm" if at else ""
        problems.append(f"thinnest web {web:.4g} mm{where} is below the minimum web {min_web:g} mm")
    return PartCheck(part.name, part.area, web, at, part.deviation, tuple(problems))


def check_parts(parts: Iterable[Part], min_web: float = DEFAULT_MIN_WEB) -> list[PartCheck]:
    """:func:`check_part` for each part."""
    return [check_part(p, min_web) for p in parts]


def failures(ps: PartSet, checks: Sequence[PartCheck], vocab: Vocabulary = API) -> list[str]:
    """One line per part of ``ps`` that failed its check (``checks`` in the same order): what is
    wrong and what to change, named as the front end ``vocab`` names it."""
    web = name_of(ps.web_key, vocab)
    out = []
    for p, c in zip(ps.parts, checks):
        if not c.ok:
            keys = names_of(p.keys, vocab) if p.keys else "the element's sizes"
            out.append(f"part {p.name!r}: {'; '.join(c.problems)} (change {keys}, or {web})")
    return out


def require_checked(ps: PartSet, min_web: float = DEFAULT_MIN_WEB, vocab: Vocabulary = API) -> list[PartCheck]:
    """Check every part of ``ps``; :class:`GeometryError` lists each failing part, what is wrong
    and what to change (its keys and the minimum web, named as the front end ``vocab`` does)."""
    if not (math.isfinite(min_web) and min_web >= 0):
        raise GeometryError(f"the minimum web must be a number of millimetres >= 0, got {min_web}")
    checks = check_parts(ps.parts, min_web)
    bad = failures(ps, checks, vocab)
    if bad:
        raise GeometryError(f"{ps.element_id!r} cannot be cut as drawn: " + " | ".join(bad))
    return checks


def report_lines(checks: Sequence[PartCheck], min_web: float) -> list[str]:
    """One line per part: area, thinnest web, curve deviation (what the export report lists)."""
    out = []
    for c in checks:
        web = "—" if not math.isfinite(c.web) else f"{c.web:.4f} mm"
        dev = "exact lines and arcs" if c.deviation == 0 else f"fitted edges within {c.deviation:.3e} mm of the exact curve"
        out.append(f"  {c.name}: area {c.area:.3f} mm², thinnest web {web} (minimum {min_web:g} mm), {dev}")
    return out
