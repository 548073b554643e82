"""Checks of cut-ready parts: closed, finite, each contour simple, holes inside the outline and
apart, the thinnest web at least a minimum (:func:`check_part`, :func:`require_checked`), and the
report lines.

The thinnest web of a part is the smallest of
- the distances between its contours (each hole to the outline, each hole to each other hole),
  exact: segment against segment in closed form, the pairs found through a spatial index
  (:mod:`.distance`), so the cost grows as n log n with the number of holes and the result does
  not depend on a polygon's resolution; and
- the necks of the outline, measured along its normals (:mod:`.thickness`); a convex outline without
  corners whose smallest arc radius is R is at least 2R thick everywhere (a disc of radius R rolls
  freely inside it), so when 2R is not below the distance between the contours the necks cannot
  be the thinnest web and are not cast.

Whether each contour crosses itself is judged on a polygon inscribed in its arcs whose chord
sagitta is relative to the part (:func:`check_tolerance`: at most 1e-5 of the part's size and a
fiftieth of the minimum web), so a 50 m frame plate costs what a 50 mm one does; two contours that
touch or cross are found exactly (their distance is 0), a hole outside the outline or inside
another hole by the position of one of its points.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Sequence

import numpy as np
import shapely

from ...errors import GeometryError
from ...model.drawing import DEFAULT_MIN_WEB  # noqa: F401  (re-exported: the default thinnest web, mm)
from ..contour import Contour
from .distance import discs_of, nearest_between_contours, pieces_of
from .keys import API, Vocabulary, name_of, names_of
from .thickness import HEAD_ON_DEG, NECK_SAMPLES, necks  # noqa: F401  (re-exported)
from .outline import is_convex, rolling_radius
from .records import Part, PartSet

#: the web is compared with the minimum to this relative rounding (of the part's size)
WEB_ROUNDING = 1e-12
#: chord sagitta of the self-intersection test, relative to the part's size and to the minimum web
SIZE_FRACTION = 1e-5
WEB_FRACTION = 0.02


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


def part_size(part: Part) -> float:
    """The larger side of the part's exact bounding box (mm; at least 1e-300)."""
    x0, y0, x1, y1 = part.bounds()
    return max(x1 - x0, y1 - y0, 1e-300)


def check_tolerance(part: Part, min_web: float, size: float | None = None) -> float:
    """The chord sagitta (mm) of the self-intersection test of ``part`` (see the module docstring;
    ``size``: :func:`part_size` if known)."""
    size = part_size(part) if size is None else size
    web = WEB_FRACTION * min_web if min_web > 0 else math.inf
    return max(min(SIZE_FRACTION * size, web), 1e-9 * size)


def thinnest_web(part: Part, guess: float = 1.0) -> tuple[float, tuple[float, float] | None]:
    """The part's thinnest web (mm) and where (see the module docstring); (inf, None) if none.
    ``guess``: the first search radius of the spatial index (mm)."""
    best, at, _ = nearest_between_contours(part.contours, guess)
    if part.outer is not None and not 2.0 * rolling_radius(part.outer) >= best:
        d, where = necks(part.outer, part.holes, above=best)
        if d < best:
            best, at = d, where
    return best, at


def _names(part: Part) -> list[str]:
    """How the problems name each contour of ``part`` (the outline, hole 1, …)."""
    first = 1 if part.outer is not None else 0
    return (["the outline"] if part.outer is not None else []) + [f"hole {k + 1}" for k in range(len(part.contours) - first)]


def _placement_problems(part: Part, names: list[str], touch: tuple[int, int] | None, at, discs, tol: float
                        ) -> list[str]:
    """Contours that touch or cross (``touch``: the pair found at distance 0), holes outside
    the outline or inside another hole. The contours are apart by more than 2·``tol`` (mm), so a
    hole's first point is classified exactly against polygons of sagitta ``tol``; circles are
    compared as circles."""
    if touch is not None:
        a, b = sorted(touch)
        where = f" at ({at[0]:.6g}, {at[1]:.6g}) mm" if at else ""
        if a == 0 and part.outer is not None:
            return [f"{names[b]} crosses or touches the outline{where}"]
        return [f"{names[a]} and {names[b]} overlap or touch{where}"]
    out = []
    holes = list(part.holes)
    if not holes:
        return out
    first = 1 if part.outer is not None else 0
    probe = np.array([np.asarray(h.points, float)[0] for h in holes])
    if part.outer is not None:
        outline = shapely.Polygon(part.outer.polyline(tol))
        inside = shapely.contains_xy(outline, probe[:, 0], probe[:, 1])
        out += [f"{names[k + first]} lies outside the outline" for k in np.nonzero(~inside)[0]]
    if len(holes) < 2:
        return out
    circ = discs.is_circle[first:]
    if circ.all():   # circle a inside circle b: |ca − cb| + ra < rb
        c, r = discs.centre[first:], discs.radius[first:]
        gap = np.hypot(*(c[:, None, :] - c[None, :, :]).transpose(2, 0, 1)) + r[:, None] - r[None, :]
        i, j = np.nonzero(gap < 0)
    else:
        polys = [shapely.Polygon(h.polyline(tol)) for h in holes]
        if len(holes) <= 8:
            i, j = np.nonzero(shapely.contains_xy(np.array(polys)[None, :], probe[:, 0:1], probe[:, 1:2]))
        else:
            i, j = shapely.STRtree(polys).query(shapely.points(probe), predicate="within")
    out += [f"{names[a + first]} lies inside {names[b + first]}" for a, b in zip(i, j) if a != b]
    return out


def check_part(part: Part, min_web: float = DEFAULT_MIN_WEB, tol: float | None = None) -> PartCheck:
    """Check one part: every contour closed and finite and not crossing itself; contours apart,
    holes inside the outline and not inside each other; thinnest web ≥ ``min_web`` mm (to
    rounding). ``tol``: the sagitta of the self-intersection test (default :func:`check_tolerance`)."""
    problems: list[str] = []
    if not part.contours:
        return PartCheck(part.name, 0.0, math.inf, None, part.deviation, ("it has no contour",))
    finite = [np.abs(np.asarray(c.points, float)) for c in part.contours]
    scale = max([1.0] + [float(a[np.isfinite(a)].max()) for a in finite if np.isfinite(a).any()])
    names = _names(part)
    for c, what in zip(part.contours, names):
        problems += _contour_problems(c, what, scale)
    if problems:
        return PartCheck(part.name, math.nan, math.nan, None, part.deviation, tuple(problems))
    pc = pieces_of(part.contours)
    size = max(float(np.max(pc.box[:, 2:].max(axis=0) - pc.box[:, :2].min(axis=0))), 1e-300)
    tol = check_tolerance(part, min_web, size) if tol is None else tol
    discs = discs_of(part.contours)
    for c, what, circular in zip(part.contours, names, discs.is_circle):
        if not circular and not is_convex(c) and not shapely.LinearRing(c.polyline(tol)).is_simple:
            problems.append(f"{what} intersects itself")
    if problems:
        return PartCheck(part.name, part.area, math.nan, None, part.deviation, tuple(problems))
    web, at, pair = nearest_between_contours(part.contours, max(min_web, 1e-6 * size), pc, discs)
    touch = pair if web <= WEB_ROUNDING * scale else None
    problems += _placement_problems(part, names, touch, at, discs, min(0.5 * web, check_tolerance(part, 0.0, size)))
    if problems:
        return PartCheck(part.name, part.area, math.nan, None, part.deviation, tuple(problems))
    # a convex outline without corners is at least 2R thick along its normals (outline.rolling_radius)
    if part.outer is not None and not 2.0 * rolling_radius(part.outer) >= web:
        d, where = necks(part.outer, part.holes, above=web)
        if d < web:
            web, at = d, where
    if not web >= min_web - WEB_ROUNDING * scale:
        where = f" at ({at[0]:.3f}, {at[1]:.3f}) mm" if at else ""
        problems.append(f"thinnest web {web:.4g} mm{where} is below the minimum web {min_web:g} mm")
    return PartCheck(part.name, part.area, web, at, part.deviation, tuple(problems))


#: two parts are congruent when their contours, in the frame of their first segment, agree to this
#: fraction of their size (rounding of the rigid motions that placed them is ~1e-16 of it)
CONGRUENT = 1e-12


def _frame_key(part: Part) -> tuple[np.ndarray, float, tuple] | None:
    """The part's contours in the frame of its first contour's first segment (origin, angle),
    rounded to :data:`CONGRUENT` of its size, as a hashable key; None if degenerate."""
    first = part.contours[0]
    pts0 = np.asarray(first.points, float)
    if len(pts0) < 2:
        return None
    d = pts0[1] - pts0[0]
    if not (np.isfinite(pts0).all() and np.hypot(*d) > 0):
        return None
    ang = math.atan2(d[1], d[0])
    rot = np.array([[math.cos(ang), math.sin(ang)], [-math.sin(ang), math.cos(ang)]])
    local = [(np.asarray(c.points, float) - pts0[0]) @ rot.T for c in part.contours]
    size = max(float(max(np.abs(q).max() for q in local)), 1e-300)
    q = CONGRUENT * size
    key = tuple((np.round(loc / q).astype(np.int64).tobytes(), np.asarray(c.bulges, float).tobytes())
                for loc, c in zip(local, part.contours))
    return pts0[0], ang, (part.outer is None, key)


def check_parts(parts: Iterable[Part], min_web: float = DEFAULT_MIN_WEB) -> list[PartCheck]:
    """:func:`check_part` for each part. A part congruent to one already checked and found fit to
    cut (the same contours moved rigidly, to :data:`CONGRUENT` of its size: a chain's identical
    links) takes that check, its web's place moved with it."""
    seen: dict[tuple, tuple[PartCheck, np.ndarray, float]] = {}
    out = []
    for p in parts:
        frame = _frame_key(p) if p.contours else None
        hit = seen.get(frame[2]) if frame is not None else None
        if hit is not None:
            c0, o0, a0 = hit
            at = None
            if c0.web_at is not None:   # back to the first part's frame, then into this one's
                da = frame[1] - a0
                v = np.asarray(c0.web_at) - o0
                w = np.array([v[0] * math.cos(da) - v[1] * math.sin(da), v[0] * math.sin(da) + v[1] * math.cos(da)])
                at = (float(frame[0][0] + w[0]), float(frame[0][1] + w[1]))
            out.append(PartCheck(p.name, p.area, c0.web, at, p.deviation, ()))
            continue
        c = check_part(p, min_web)
        if c.ok and frame is not None:
            seen[frame[2]] = (c, frame[0], frame[1])
        out.append(c)
    return out


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


def report_lines(checks: Sequence[PartCheck], min_web: float, written: Sequence[Part] | None = None,
                 kerf: float = 0.0) -> list[str]:
    """One line per part: area, thinnest web, curve deviation (what the export report lists) and,
    given the parts as ``written`` (the edges, or the tool paths for a ``kerf``), the length of
    their contours (the cut length) and the area they enclose (outline less holes), mm and mm²."""
    out = []
    for k, c in enumerate(checks):
        web = "—" if not math.isfinite(c.web) else f"{c.web:.4f} mm"
        dev = "exact lines and arcs" if c.deviation == 0 else f"fitted edges within {c.deviation:.3e} mm of the exact curve"
        cut = ""
        if written is not None:
            w = written[k]
            length = sum(ct.length for ct in w.contours)
            enclosed = abs(w.outer.area()) - sum(abs(h.area()) for h in w.holes) if w.outer is not None else \
                sum(abs(h.area()) for h in w.holes)
            what = f"tool paths (kerf {kerf:g} mm)" if kerf else "as written"
            cut = f", {what}: cut length {length:.6f} mm enclosing {enclosed:.6f} mm²"
        out.append(f"  {c.name}: area {c.area:.6f} mm²{cut}, thinnest web {web} (minimum {min_web:g} mm), {dev}")
    return out
