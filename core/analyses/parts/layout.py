"""Layout of cut-ready parts on a sheet: ``assembled`` in the mechanism's frame (contours that
stacked parts share drawn once) or ``apart`` (each group turned flat, packed in rows, named).
The writers (``core/io/dxf_parts.py``, ``core/io/svg_parts.py``) only serialise a :class:`Sheet`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np
import shapely

from ...errors import GeometryError
from ..contour import Contour
from .records import Curve, Part, PartSet

#: layouts
LAYOUTS = ("assembled", "apart")


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
