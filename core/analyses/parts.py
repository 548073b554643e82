"""Cut-ready parts: closed outlines of exact lines and arcs with their holes, checked, laid out.

Parts are derived data like solutions: the builders (:mod:`.parts_linkage`, :mod:`.parts_geneva`,
:mod:`.parts_rolling`) make them from the model, :func:`check_part` checks each one (closed,
finite, a valid polygon without self-intersection, holes inside and apart, the thinnest web at
least a minimum) and :func:`lay_out` places them on a sheet (``assembled`` in the mechanism's
frame, or ``apart``: side by side without overlap, each named). Writers (``core/io/dxf_parts.py``,
``core/io/svg_parts.py``) only serialise a :class:`Sheet`.

Geometry is in millimetres. A :class:`~.geneva_contour.Contour` is a closed chain of lines and
arcs (vertices and DXF bulges); outer contours are counter-clockwise.

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
from dataclasses import dataclass, field, replace
from typing import Iterable, Sequence

import numpy as np
import shapely
from shapely.validation import explain_validity

from ..errors import GeometryError
from .geneva_contour import Contour

#: default thinnest web (mm) a part must keep between its holes and its edges
DEFAULT_MIN_WEB = 1.0
#: chord sagitta of the polygons used by the checks (mm)
CHECK_TOL = 1e-4
#: rays cast along the outline for the necks (at most)
NECK_SAMPLES = 3000
#: a ray meets the far side head-on when their normals are within this angle (degrees)
HEAD_ON_DEG = 30.0
#: layouts
LAYOUTS = ("assembled", "apart")


# -- outlines -------------------------------------------------------------------------------
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
    xs, ys = list(sg.p0[:, 0]), list(sg.p0[:, 1])
    for k in np.nonzero(sg.is_arc)[0]:
        for q in range(4):
            ang = q * math.pi / 2
            rel = (ang - sg.a0[k]) % (2 * math.pi) if sg.theta[k] > 0 else (sg.a0[k] - ang) % (2 * math.pi)
            if rel <= abs(sg.theta[k]):
                xs.append(sg.centre[k, 0] + sg.radius[k] * math.cos(ang))
                ys.append(sg.centre[k, 1] + sg.radius[k] * math.sin(ang))
    return min(xs), min(ys), max(xs), max(ys)


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


# -- records ------------------------------------------------------------------------------
@dataclass(frozen=True)
class Part:
    """One part to cut: a closed ``outer`` contour (CCW, mm) and its ``holes``; ``outer`` None is
    a drilling pattern (holes only, e.g. a frame's pivots). ``group``: parts of one group keep
    their relative places in the apart layout. ``deviation``: the largest distance (mm) of a
    fitted edge from the exact curve (0: exact lines and arcs). ``keys``: what the user can change
    when a check fails (scene keys or export options). ``note``: one line for the report."""

    name: str
    outer: Contour | None
    holes: tuple[Contour, ...] = ()
    group: str = ""
    deviation: float = 0.0
    keys: tuple[str, ...] = ()
    note: str = ""

    @property
    def contours(self) -> tuple[Contour, ...]:
        return ((self.outer,) if self.outer is not None else ()) + tuple(self.holes)

    @property
    def area(self) -> float:
        """Exact area of the material (mm²); 0 for a drilling pattern."""
        if self.outer is None:
            return 0.0
        return abs(self.outer.area()) - sum(abs(h.area()) for h in self.holes)

    def moved(self, angle: float, offset: Sequence[float] = (0.0, 0.0)) -> "Part":
        """Rotated by ``angle`` rad about the origin, then shifted by ``offset`` mm."""
        off = (float(offset[0]), float(offset[1]))
        return replace(self, outer=None if self.outer is None else self.outer.moved(angle, off),
                       holes=tuple(h.moved(angle, off) for h in self.holes))

    def bounds(self) -> tuple[float, float, float, float]:
        """Exact bounding box (mm)."""
        b = np.array([contour_bounds(c) for c in self.contours])
        return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())

    def polygon(self, tol: float = CHECK_TOL) -> shapely.Geometry:
        """Inscribed polygon (chord sagitta ≤ ``tol`` mm); a drilling pattern gives its holes' union."""
        if self.outer is None:
            return shapely.union_all([shapely.Polygon(h.polyline(tol)) for h in self.holes])
        return shapely.Polygon(self.outer.polyline(tol), [h.polyline(tol) for h in self.holes])


@dataclass(frozen=True)
class Curve:
    """A curve that is drawn but not cut (a traced coupler curve): vertices (M, 2) mm and bulges
    (M,), the last bulge unused when open; ``deviation`` from the exact curve (mm) against
    ``tolerance``; ``group``: the part group it moves with in the apart layout."""

    name: str
    points: np.ndarray
    bulges: np.ndarray
    closed: bool
    deviation: float
    tolerance: float
    group: str = ""

    def moved(self, angle: float, offset: Sequence[float] = (0.0, 0.0)) -> "Curve":
        c = Contour(self.points, self.bulges).moved(angle, (float(offset[0]), float(offset[1])))
        return replace(self, points=c.points, bulges=c.bulges)

    def contour_like(self) -> Contour:
        """The curve as a contour (for bounds and sampling); open curves get a final zero bulge."""
        b = np.asarray(self.bulges, float).copy()
        if not self.closed:
            b[-1] = 0.0
        return Contour(np.asarray(self.points, float), b)

    def bounds(self) -> tuple[float, float, float, float]:
        c = self.contour_like()
        if not self.closed:  # the closing chord is not drawn but lies inside the vertices' box
            pass
        return contour_bounds(c)


@dataclass(frozen=True)
class PartSet:
    """What a builder makes for one element: its parts (in the element's frame, assembled),
    the curves drawn beside them, and report lines (``notes``)."""

    element_id: str
    parts: tuple[Part, ...]
    curves: tuple[Curve, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parts)

    def select(self, names: Iterable[str] | None) -> "PartSet":
        """Only the parts named (in the order given); :class:`GeometryError` names unknown ones.
        Curves stay with the groups that are kept."""
        if names is None:
            return self
        names = list(names)
        unknown = [n for n in names if n not in self.names]
        if unknown:
            raise GeometryError(f"{self.element_id!r} has no part {', '.join(map(repr, unknown))}; "
                                f"its parts are {', '.join(self.names)}")
        parts = tuple(next(p for p in self.parts if p.name == n) for n in dict.fromkeys(names))
        groups = {p.group or p.name for p in parts}
        return replace(self, parts=parts, curves=tuple(c for c in self.curves if c.group in groups))


# -- checks ---------------------------------------------------------------------------------
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


def require_checked(ps: PartSet, min_web: float = DEFAULT_MIN_WEB) -> list[PartCheck]:
    """Check every part of ``ps``; :class:`GeometryError` lists each failing part, what is wrong
    and what to change (its keys, or ``--min-web``)."""
    if not (math.isfinite(min_web) and min_web >= 0):
        raise GeometryError(f"the minimum web must be a number of millimetres >= 0, got {min_web}")
    checks = check_parts(ps.parts, min_web)
    bad = [(p, c) for p, c in zip(ps.parts, checks) if not c.ok]
    if bad:
        lines = []
        for p, c in bad:
            keys = ", ".join(p.keys) if p.keys else "the element's sizes"
            lines.append(f"part {p.name!r}: {'; '.join(c.problems)} (change {keys}, or the minimum web)")
        raise GeometryError(f"{ps.element_id!r} cannot be cut as drawn: " + " | ".join(lines))
    return checks


# -- layout ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class Label:
    """A part's name on the drawing: text, lower-left corner (mm), height (mm)."""

    text: str
    at: tuple[float, float]
    height: float


@dataclass(frozen=True)
class Sheet:
    """Parts placed for writing: ``layout`` ("assembled" | "apart"), the placed ``parts`` and
    ``curves``, ``labels`` (apart only), ``shared`` report lines for contours drawn once although
    two stacked parts have them (assembled only), and the exact ``bounds`` (mm)."""

    element_id: str
    layout: str
    parts: tuple[Part, ...]
    curves: tuple[Curve, ...]
    labels: tuple[Label, ...]
    shared: tuple[str, ...]
    bounds: tuple[float, float, float, float]


def _key(c: Contour, scale: float) -> frozenset:
    """A contour's geometry independent of where it starts and which way it runs."""
    q = 1e-9 * scale
    sg = c.segments()
    out = set()
    for a, b, th in zip(sg.p0, sg.p1, sg.theta):
        fa, fb = tuple(np.round(a / q).astype(np.int64)), tuple(np.round(b / q).astype(np.int64))
        t = round(float(th), 9)
        out.add((fa, fb, t) if fa <= fb else (fb, fa, -t))
    return frozenset(out)


def _dedupe(parts: Sequence[Part]) -> tuple[list[Part], list[str]]:
    """Drop every contour already drawn by an earlier part (stacked parts share bores)."""
    scale = max(1.0, max(float(np.max(np.abs(c.points))) for p in parts for c in p.contours))
    seen: dict[frozenset, str] = {}
    out, notes = [], []
    for p in parts:
        keep_holes = []
        for h in p.holes:
            k = _key(h, scale)
            if k in seen:
                notes.append(f"{p.name}: a hole is the same contour as one of {seen[k]} (drawn once, on {seen[k]})")
            else:
                seen[k] = p.name
                keep_holes.append(h)
        outer = p.outer
        if outer is not None:
            k = _key(outer, scale)
            if k in seen:
                notes.append(f"{p.name}: its outline is the same contour as one of {seen[k]} (drawn once)")
                outer = None
            else:
                seen[k] = p.name
        out.append(replace(p, outer=outer, holes=tuple(keep_holes)))
    return out, notes


def _sheet_bounds(parts, curves, labels) -> tuple[float, float, float, float]:
    boxes = [p.bounds() for p in parts if p.contours] + [c.bounds() for c in curves]
    boxes += [(lb.at[0], lb.at[1], lb.at[0] + 0.7 * lb.height * len(lb.text), lb.at[1] + lb.height) for lb in labels]
    if not boxes:
        return 0.0, 0.0, 0.0, 0.0
    b = np.array(boxes)
    return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())


def _orientation(parts: Sequence[Part]) -> float:
    """The rotation (rad) that lays a group's smallest enclosing rectangle flat, long side along x."""
    hull = shapely.union_all([p.polygon(1e-2) for p in parts]).convex_hull
    if hull.area <= 0:
        return 0.0
    rect = np.asarray(hull.minimum_rotated_rectangle.exterior.coords)[:4]
    e1, e2 = rect[1] - rect[0], rect[2] - rect[1]
    e = e1 if np.hypot(*e1) >= np.hypot(*e2) else e2
    return -math.atan2(e[1], e[0])


def lay_out(ps: PartSet, layout: str = "apart", gap: float | None = None) -> Sheet:
    """Place the parts: ``assembled`` (as built, contours shared by stacked parts drawn once) or
    ``apart`` (each group turned flat and packed in rows, ``gap`` mm apart (default: 5 % of the
    largest part, 3…20 mm), named underneath)."""
    if layout not in LAYOUTS:
        raise GeometryError(f"layout must be one of {', '.join(LAYOUTS)}; got {layout!r}")
    if layout == "assembled":
        parts, notes = _dedupe(ps.parts)
        return Sheet(ps.element_id, layout, tuple(parts), ps.curves, (), tuple(notes),
                     _sheet_bounds(parts, ps.curves, ()))
    groups: dict[str, list[Part]] = {}
    for p in ps.parts:
        groups.setdefault(p.group or p.name, []).append(p)
    boxes = []
    for g, members in groups.items():
        ang = _orientation(members)
        moved = [p.moved(ang) for p in members]
        curves = [c.moved(ang) for c in ps.curves if c.group == g]
        b = np.array([p.bounds() for p in moved] + [c.bounds() for c in curves])
        boxes.append((g, moved, curves, float(b[:, 0].min()), float(b[:, 1].min()),
                      float(b[:, 2].max()), float(b[:, 3].max())))
    size = max(max(x1 - x0, y1 - y0) for *_, x0, y0, x1, y1 in boxes)
    gap = float(gap) if gap is not None else min(20.0, max(3.0, 0.05 * size))
    text_h = min(10.0, max(2.5, 0.04 * size))
    band = text_h + gap
    total = sum((x1 - x0 + gap) * (y1 - y0 + gap + band) for *_, x0, y0, x1, y1 in boxes)
    width = max(max(x1 - x0 for *_, x0, y0, x1, y1 in boxes), 1.5 * math.sqrt(total))
    boxes.sort(key=lambda b: -(b[6] - b[4]))
    placed, curves, labels = [], [], []
    x = y_top = 0.0
    row_h = 0.0
    for g, members, crv, x0, y0, x1, y1 in boxes:
        w, h = x1 - x0, y1 - y0
        if x > 0 and x + w > width:
            y_top -= row_h + gap
            x, row_h = 0.0, 0.0
        dx, dy = x - x0, y_top - h - y0
        placed += [p.moved(0.0, (dx, dy)) for p in members]
        curves += [c.moved(0.0, (dx, dy)) for c in crv]
        labels.append(Label(", ".join(p.name for p in members) if len(members) > 1 else members[0].name,
                            (x, y_top - h - gap / 2 - text_h), text_h))
        x += w + gap
        row_h = max(row_h, h + band)
    return Sheet(ps.element_id, layout, tuple(placed), tuple(curves), tuple(labels), (),
                 _sheet_bounds(placed, curves, labels))


def report_lines(checks: Sequence[PartCheck], min_web: float) -> list[str]:
    """One line per part: area, thinnest web, curve deviation (what the export report lists)."""
    out = []
    for c in checks:
        web = "—" if not math.isfinite(c.web) else f"{c.web:.4f} mm"
        dev = "exact lines and arcs" if c.deviation == 0 else f"fitted edges within {c.deviation:.3e} mm of the exact curve"
        out.append(f"  {c.name}: area {c.area:.3f} mm², thinnest web {web} (minimum {min_web:g} mm), {dev}")
    return out
