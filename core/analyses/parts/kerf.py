"""Kerf compensation: the tool paths of a part, offset from its edges by half the kerf (issue 23,
item 6).

A cutter (laser, plasma, water jet, wire) removes a strip ``kerf`` mm wide centred on its path, so
to leave the part as drawn the path runs ``kerf/2`` outside the outline and ``kerf/2`` inside every
hole. :func:`offset_contour` offsets a contour of lines and arcs exactly, keeping arcs as arcs:

- a line moves along its normal, an arc keeps its centre and its radius grows or shrinks by the
  offset (an arc that would shrink to nothing is refused);
- where neighbouring offset segments part (the outline's convex corners, a hole's reflex ones)
  they are joined by a true arc of radius ``kerf/2`` about the corner (a round join, as the cutter
  itself turns round the corner);
- where they cross (the outline's reflex corners, a hole's convex ones) both are cut back to their
  crossing (a mitre: the corner stays sharp, as cut).

The offset part (:func:`kerf_part`) is checked again like any part: every path closed and not
crossing itself, the paths apart. A hole smaller than the kerf cannot be cut and is refused, and
so is an offset that would make paths cross (a slot narrower than the kerf).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import GeometryError
from ..contour import Contour
from .outline import ccw
from .records import Part
from .thickness import necks

#: turns smaller than this (rad) at a vertex are tangent joins (the offset segments meet)
TANGENT = 1e-9


def _line_circle(a: np.ndarray, b: np.ndarray, c: np.ndarray, r: float) -> list[np.ndarray]:
    d = b - a
    dd = float(d @ d)
    t0 = float((c - a) @ d) / dd
    foot = a + t0 * d
    h2 = r * r - float((foot - c) @ (foot - c))
    if h2 < 0:
        return []
    s = math.sqrt(h2 / dd)
    return [a + (t0 - s) * d, a + (t0 + s) * d]


def _circle_circle(c1: np.ndarray, r1: float, c2: np.ndarray, r2: float) -> list[np.ndarray]:
    w = c2 - c1
    dist = math.hypot(*w)
    if dist == 0 or dist > r1 + r2 or dist < abs(r1 - r2):
        return []
    along = (dist * dist + r1 * r1 - r2 * r2) / (2 * dist)
    across = math.sqrt(max(r1 * r1 - along * along, 0.0))
    u = w / dist
    n = np.array([-u[1], u[0]])
    return [c1 + along * u + across * n, c1 + along * u - across * n]


class _Seg:
    """One offset segment: a line (p0 → p1) or an arc (centre, radius, sweep sign) whose ends
    are moved as the joins are made."""

    def __init__(self, p0, p1, arc: bool, centre=None, radius: float = 0.0, sign: float = 0.0):
        self.p0, self.p1, self.arc = np.asarray(p0, float), np.asarray(p1, float), arc
        self.centre, self.radius, self.sign = centre, radius, sign

    def meet(self, other: "_Seg", near: np.ndarray) -> np.ndarray | None:
        """The crossing of this segment's line or circle with the other's nearest to ``near``."""
        if not self.arc and not other.arc:
            d, e = self.p1 - self.p0, other.p1 - other.p0
            den = d[0] * e[1] - d[1] * e[0]
            if den == 0:
                return None
            t = ((other.p0 - self.p0)[0] * e[1] - (other.p0 - self.p0)[1] * e[0]) / den
            return self.p0 + t * d
        if self.arc and other.arc:
            pts = _circle_circle(self.centre, self.radius, other.centre, other.radius)
        else:
            line, circ = (other, self) if self.arc else (self, other)
            pts = _line_circle(line.p0, line.p1, circ.centre, circ.radius)
        return min(pts, key=lambda q: float((q - near) @ (q - near))) if pts else None

    def bulge(self) -> float:
        if not self.arc:
            return 0.0
        a0 = math.atan2(*(self.p0 - self.centre)[::-1])
        a1 = math.atan2(*(self.p1 - self.centre)[::-1])
        sweep = (a1 - a0) % (2 * math.pi) if self.sign > 0 else -((a0 - a1) % (2 * math.pi))
        return math.tan(sweep / 4.0)


def offset_contour(c: Contour, d: float, what: str = "the contour") -> Contour:
    """``c`` offset by ``d`` mm to the right of its travel (outwards for a CCW contour; a negative
    ``d`` goes left), with round joins where segments part and mitres where they cross (see the
    module docstring). Raises :class:`GeometryError` naming ``what`` when an arc would vanish."""
    if d == 0:
        return c
    sg = c.segments()
    k_n = len(c)
    segs: list[_Seg] = []
    for k in range(k_n):
        if sg.is_arc[k]:
            sign = 1.0 if sg.theta[k] > 0 else -1.0
            r = sg.radius[k] + sign * d            # CCW arc: its centre is on the left
            if not r > 1e-9 * max(1.0, sg.radius[k]):
                raise GeometryError(f"{what}: an arc of radius {sg.radius[k]:.4g} mm at ({sg.p0[k, 0]:.4g}, "
                                    f"{sg.p0[k, 1]:.4g}) mm vanishes offset by {abs(d):.4g} mm")
            u0 = (sg.p0[k] - sg.centre[k]) / sg.radius[k]
            u1 = (sg.p1[k] - sg.centre[k]) / sg.radius[k]
            segs.append(_Seg(sg.centre[k] + r * u0, sg.centre[k] + r * u1, True, sg.centre[k], r, sign))
        else:
            t = (sg.p1[k] - sg.p0[k]) / sg.length[k]
            n = np.array([t[1], -t[0]])            # right of travel
            segs.append(_Seg(sg.p0[k] + d * n, sg.p1[k] + d * n, False))
    chord = np.arctan2(sg.p1[:, 1] - sg.p0[:, 1], sg.p1[:, 0] - sg.p0[:, 0])
    start, end = chord - sg.theta / 2, chord + sg.theta / 2
    pts, bul = [], []
    joins = []   # per vertex k+1: (kind, data)
    for k in range(k_n):
        j = (k + 1) % k_n
        turn = (start[j] - end[k] + math.pi) % (2 * math.pi) - math.pi
        vertex = sg.p1[k]
        if abs(turn) <= TANGENT:
            joins.append(("meet", None))
        elif turn * d > 0:       # the segments part: a round join about the corner
            joins.append(("round", (vertex, turn)))
        else:                     # they cross: cut both back to the crossing
            x = segs[k].meet(segs[j], vertex)
            if x is None:
                raise GeometryError(f"{what}: the offset of {abs(d):.4g} mm cannot turn the corner at "
                                    f"({vertex[0]:.4g}, {vertex[1]:.4g}) mm")
            segs[k].p1, segs[j].p0 = x.copy(), x.copy()
            joins.append(("mitre", None))
    for k in range(k_n):
        pts.append(segs[k].p0)
        bul.append(segs[k].bulge())
        kind, data = joins[k]
        if kind == "round":
            vertex, turn = data
            pts.append(segs[k].p1)
            bul.append(math.tan(turn / 4.0))
    out = Contour(np.array(pts), np.array(bul))
    keep = np.hypot(*(np.roll(out.points, -1, axis=0) - out.points).T) > 1e-12 * (1.0 + float(np.max(np.abs(out.points))))
    return Contour(out.points[keep], out.bulges[keep])


def kerf_part(part: Part, kerf: float) -> Part:
    """The tool paths of ``part`` for a cut ``kerf`` mm wide: the outline offset outwards by
    kerf/2, every hole inwards by kerf/2 (see the module docstring). Raises
    :class:`GeometryError` naming the part when a hole is too small for the kerf."""
    if kerf == 0:
        return part
    half = 0.5 * kerf
    outer = None if part.outer is None else offset_contour(ccw(part.outer), half, f"part {part.name!r}, its outline")
    holes = []
    for k, h in enumerate(part.holes):
        hc = ccw(h)
        what = f"part {part.name!r}, hole {k + 1}"
        sg = hc.segments()
        inradius = _inradius_bound(hc)
        if not inradius > half:
            x0, y0 = sg.p0[0]
            raise GeometryError(f"{what} (at ({x0:.4g}, {y0:.4g}) mm) is too small for a kerf of {kerf:g} mm: "
                                f"it is {2 * inradius:.4g} mm across at its narrowest")
        holes.append(offset_contour(hc, -half, what))
    return replace(part, outer=outer, holes=tuple(holes))


def _inradius_bound(c: Contour) -> float:
    """Half the narrowest width across a CCW hole (mm): for a circle its radius, else half the
    least distance across it measured along its inward normals."""
    sg = c.segments()
    if len(c) == 2 and sg.is_arc.all() and abs(abs(sg.theta[0]) - math.pi) < 1e-12:
        return float(sg.radius[0])
    width, _ = necks(c)
    radii = sg.radius[sg.is_arc]
    small = float(np.min(radii)) if len(radii) and (sg.theta[sg.is_arc] > 0).any() else math.inf
    return 0.5 * min(width, 2 * small) if math.isfinite(width) else small
