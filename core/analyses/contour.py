"""Closed contours made of exact lines and circular arcs (the bulge form of a DXF LWPOLYLINE).

A :class:`Contour` is K vertices (K, 2) mm and K bulges: segment k runs from vertex k to vertex
k + 1 (cyclically); bulge b = tan(θ/4) with θ the signed included angle of the arc (θ > 0
counter-clockwise), b = 0 a straight line. Exact area, arc centres and radii, a rigid motion, an
outward offset (for the relief computation) and a polyline for shapely (with the largest chord
error stated) are provided. A :class:`Part` is one closed outer contour with its holes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ..errors import GeometryError

if TYPE_CHECKING:  # pragma: no cover
    import shapely

#: turns smaller than this (rad) at a vertex count as tangent joins
TANGENT_TOL = 1e-9


def _rot(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class Segments:
    """Per-segment data of a contour, each (K,) or (K, 2): start ``p0`` and end ``p1`` (mm),
    ``theta`` signed included angle (rad, 0 for lines), ``is_arc``, arc ``centre`` (mm, NaN for
    lines), ``radius`` (mm, inf for lines), ``a0`` start angle seen from the centre (rad),
    ``length`` (mm)."""

    p0: np.ndarray
    p1: np.ndarray
    theta: np.ndarray
    is_arc: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    a0: np.ndarray
    length: np.ndarray


@dataclass(frozen=True)
class Contour:
    """A closed contour of lines and arcs; ``kinds`` optionally labels each segment."""

    points: np.ndarray
    bulges: np.ndarray
    kinds: tuple[str, ...] = ()

    @classmethod
    def circle(cls, centre: tuple[float, float], radius: float, kind: str = "circle") -> "Contour":
        """A full circle as two counter-clockwise semicircles (bulge 1)."""
        cx, cy = centre
        pts = np.array([[cx + radius, cy], [cx - radius, cy]])
        return cls(pts, np.array([1.0, 1.0]), (kind, kind))

    def __len__(self) -> int:
        return len(self.bulges)

    def segments(self) -> Segments:
        """Lines and arcs of the contour (see :class:`Segments`); computed once per contour (a
        contour is a value: its arrays are never changed in place)."""
        return self._segments

    @cached_property
    def _segments(self) -> Segments:
        p0 = np.asarray(self.points, float)
        p1 = np.roll(p0, -1, axis=0)
        b = np.asarray(self.bulges, float)
        theta = 4.0 * np.arctan(b)
        is_arc = b != 0.0
        chord = p1 - p0
        c = np.hypot(chord[:, 0], chord[:, 1])
        half = np.where(is_arc, theta / 2.0, 1.0)
        left = np.stack([-chord[:, 1], chord[:, 0]], axis=1)
        centre = np.where(is_arc[:, None], 0.5 * (p0 + p1) + left / (2.0 * np.tan(half))[:, None], np.nan)
        radius = np.where(is_arc, c / (2.0 * np.abs(np.sin(half))), np.inf)
        a0 = np.where(is_arc, np.arctan2(p0[:, 1] - centre[:, 1], p0[:, 0] - centre[:, 0]), 0.0)
        length = np.where(is_arc, np.where(is_arc, radius, 0.0) * np.abs(theta), c)
        return Segments(p0, p1, theta, is_arc, centre, radius, a0, length)

    def area(self) -> float:
        """Signed exact area (mm², positive for a counter-clockwise contour)."""
        return self._area

    @cached_property
    def _area(self) -> float:
        sg = self.segments()
        shoelace = 0.5 * np.sum(sg.p0[:, 0] * sg.p1[:, 1] - sg.p1[:, 0] * sg.p0[:, 1])
        r2 = np.where(sg.is_arc, sg.radius, 0.0) ** 2
        return float(shoelace + np.sum(0.5 * r2 * (sg.theta - np.sin(sg.theta))))

    @property
    def length(self) -> float:
        """Perimeter (mm)."""
        return float(self.segments().length.sum())

    def moved(self, angle: float, offset: tuple[float, float] = (0.0, 0.0)) -> "Contour":
        """Rotated by ``angle`` (rad, CCW, about the origin), then translated by ``offset`` (mm)."""
        pts = np.asarray(self.points, float) @ _rot(angle).T + np.asarray(offset, float)
        return Contour(pts, np.asarray(self.bulges, float).copy(), self.kinds)

    def polyline(self, tol: float) -> np.ndarray:
        """Vertices (M, 2) mm of a polygon inscribed in the contour: every arc is cut into chords
        whose sagitta is at most ``tol`` (mm); lines are kept whole. Not closed (no repeat)."""
        sg = self.segments()
        out = []
        for k in range(len(self)):
            if not sg.is_arc[k]:
                out.append(sg.p0[k:k + 1])
                continue
            r, th = sg.radius[k], sg.theta[k]
            step = 2.0 * math.acos(max(-1.0, 1.0 - tol / r)) if tol < r else math.pi / 2
            n = max(1, math.ceil(abs(th) / step))
            a = sg.a0[k] + th * np.arange(n) / n
            out.append(sg.centre[k] + r * np.stack([np.cos(a), np.sin(a)], axis=1))
        return np.vstack(out)

    def offset(self, d: float) -> "Contour":
        """The contour offset by ``d`` (mm) to the right of travel (outwards for a CCW outer contour).

        Lines move by d along their normal, arcs keep their centre and change radius by ±d, and a
        convex corner gets an arc of radius d about it (kind ``"corner"``). Concave corners are not
        supported (raises ValueError): the wheel outline has none.
        """
        sg = self.segments()
        k_n = len(self)

        def normal(k: int, at_end: bool) -> np.ndarray:
            if sg.is_arc[k]:
                p = sg.p1[k] if at_end else sg.p0[k]
                v = (p - sg.centre[k]) / sg.radius[k]
                return v if sg.theta[k] > 0 else -v
            t = (sg.p1[k] - sg.p0[k]) / sg.length[k]
            return np.array([t[1], -t[0]])

        pts, bul, kinds = [], [], []
        for k in range(k_n):
            j = (k + 1) % k_n
            pts.append(sg.p0[k] + d * normal(k, False))
            bul.append(self.bulges[k])
            kinds.append(self.kinds[k] if self.kinds else "")
            n_out, n_in = normal(k, True), normal(j, False)
            turn = math.atan2(n_out[0] * n_in[1] - n_out[1] * n_in[0], float(n_out @ n_in))
            if turn < -TANGENT_TOL:
                raise GeometryError(f"offset: concave corner at vertex {j} ({math.degrees(turn):.3g}°)")
            if turn > TANGENT_TOL:
                pts.append(sg.p1[k] + d * n_out)
                bul.append(math.tan(turn / 4.0))
                kinds.append("corner")
        return Contour(np.array(pts), np.array(bul), tuple(kinds))


@dataclass(frozen=True)
class Part:
    """One manufactured part: a closed ``outer`` contour (CCW) and its ``holes``, in mm."""

    name: str
    outer: Contour
    holes: tuple[Contour, ...] = ()

    @property
    def area(self) -> float:
        """Exact area of the material (mm²)."""
        return abs(self.outer.area()) - sum(abs(h.area()) for h in self.holes)

    def moved(self, angle: float, offset: tuple[float, float] = (0.0, 0.0)) -> "Part":
        """The part rotated by ``angle`` (rad) about the origin, then translated (mm)."""
        return Part(self.name, self.outer.moved(angle, offset), tuple(h.moved(angle, offset) for h in self.holes))

    def polygon(self, tol: float = 1e-3) -> shapely.Polygon:
        """A shapely polygon inscribed in the part, chord sagitta ≤ ``tol`` mm (shapely is imported
        here: drawing and analysing a drive do not need it)."""
        import shapely

        return shapely.Polygon(self.outer.polyline(tol), [h.polyline(tol) for h in self.holes])
