"""The records of cut-ready parts: :class:`Part` (an outline and its holes), :class:`Curve` (drawn,
not cut) and :class:`PartSet` (what a builder makes for one element). Geometry in millimetres.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Iterable, Sequence

import numpy as np
import shapely

from ...errors import GeometryError
from ..contour import Contour
from .outline import contour_bounds

#: chord sagitta of the polygons used by the checks (mm)
CHECK_TOL = 1e-4


@dataclass(frozen=True)
class Part:
    """One part to cut: a closed ``outer`` contour (CCW, mm) and its ``holes``; ``outer`` None is
    a drilling pattern (holes only, e.g. a frame's pivots). ``group``: parts of one group keep
    their relative places in the apart layout. ``deviation``: the largest distance (mm) of a
    fitted edge from the exact curve (0: exact lines and arcs). ``keys``: what the user can change
    when a check fails (canonical keys, see :mod:`.keys`). ``note``: one line for the report."""

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
    the curves drawn beside them, report lines (``notes``) and ``web_key``, the canonical key
    (see :mod:`.keys`) that sets the element's minimum web."""

    element_id: str
    parts: tuple[Part, ...]
    curves: tuple[Curve, ...] = ()
    notes: tuple[str, ...] = ()
    web_key: str = "option:min_web"

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
