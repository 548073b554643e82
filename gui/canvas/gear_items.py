"""Canvas items of non-circular gear pairs (issue 25, items 3-4): the pitch curves drawn from the
core's precomputed curves and turned per frame by transforms, nothing solved per frame.

:class:`GearPairItem` draws a ``gear_pair``: both pitch curves (closed paths in their body frames),
a spoke on each so the turning shows, the pivots and the line of centres, the pitch point marked
where the curves touch. :class:`GearedGenevaItem` is a :class:`~.geneva_items.GenevaItem` (the drive,
whose crank already follows the gears' output in the result's rotations) with the gear pair drawn
beside it on the crank shaft, turning on the same frames.
"""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QPainterPath, QPainterPathStroker, QPen

from mechsketch.core.workspace import GearedGenevaResult, GearResult
from .geneva_items import CENTRE, GenevaItem, _Container, _cross, _path_item, rotation_about
from .items import INK, NOTE, SELECT

GEAR_IN_FILL = QColor(120, 170, 120, 110)
GEAR_OUT_FILL = QColor(200, 150, 90, 110)
GEAR_EDGE = QColor("#3f6f3f")
GEAR_OUT_EDGE = QColor("#8a5a1e")
PITCH = QColor("#c0392b")
Z_GEARS = 6.0


def _curve_path(points: np.ndarray) -> QPainterPath:
    """A closed path through a polyline (M, 2) mm, in its body frame, with a spoke to the centre."""
    path = QPainterPath(QPointF(float(points[0, 0]), float(points[0, 1])))
    for x, y in points[1:]:
        path.lineTo(float(x), float(y))
    path.closeSubpath()
    return path


class _Gears:
    """The two gear bodies of a :class:`GearResult` as children of ``parent`` (in world mm)."""

    def __init__(self, parent: _Container, res: GearResult) -> None:
        self.res = res
        self.input = _Container()
        self.output = _Container()
        self.input.setParentItem(parent)
        self.output.setParentItem(parent)
        self.input.setZValue(Z_GEARS)
        self.output.setZValue(Z_GEARS)
        self.items = {
            "input_gear": _path_item(_curve_path(res.input_curve), self.input, GEAR_IN_FILL, GEAR_EDGE, 1.6, Z_GEARS,
                                     "input_gear"),
            "output_gear": _path_item(_curve_path(res.output_curve), self.output, GEAR_OUT_FILL, GEAR_OUT_EDGE, 1.6,
                                      Z_GEARS, "output_gear"),
        }
        for body, curve in ((self.input, res.input_curve), (self.output, res.output_curve)):
            spoke = QPainterPath(QPointF(0.0, 0.0))
            spoke.lineTo(float(curve[0, 0]), float(curve[0, 1]))
            _cross(spoke, (0.0, 0.0), 0.05 * float(np.max(np.hypot(*curve.T))))
            _path_item(spoke, body, None, INK, 1.2, Z_GEARS + 0.1, "spoke")
        marks = QPainterPath()
        a, b = res.input_center, res.output_center
        marks.moveTo(*a)
        marks.lineTo(*b)
        self.line = _path_item(marks, parent, None, CENTRE, 1.0, Z_GEARS + 0.2, "gear_centres", Qt.PenStyle.DashDotLine)
        self.pitch = _path_item(QPainterPath(), parent, None, PITCH, 2.0, Z_GEARS + 0.3, "pitch_point")

    def extent(self) -> QRectF:
        rect = QRectF()
        for c, curve in ((self.res.input_center, self.res.input_curve), (self.res.output_center, self.res.output_curve)):
            r = float(np.max(np.hypot(*curve.T)))
            rect = rect.united(QRectF(c[0] - r, c[1] - r, 2 * r, 2 * r))
        return rect

    def set_frame(self, k: int) -> None:
        res = self.res
        self.input.setTransform(rotation_about(res.input_center, float(res.input_rotation[k])))
        self.output.setTransform(rotation_about(res.output_center, float(res.output_rotation[k])))
        a, b = np.asarray(res.input_center), np.asarray(res.output_center)
        r1 = float(res.kinematics.r1[k])
        p = a + r1 * (b - a) / np.linalg.norm(b - a)
        ring = QPainterPath()
        ring.addEllipse(QPointF(float(p[0]), float(p[1])), 0.02 * float(np.linalg.norm(b - a)),
                        0.02 * float(np.linalg.norm(b - a)))
        self.pitch.setPath(ring)

    def set_selected(self, on: bool) -> None:
        for name, item in self.items.items():
            pen = QPen(item.pen())
            pen.setColor(SELECT if on else (GEAR_EDGE if name == "input_gear" else GEAR_OUT_EDGE))
            pen.setWidthF(2.6 if on else 1.6)
            item.setPen(pen)

    def hit(self, pos: tuple[float, float], tol: float) -> bool:
        stroker = QPainterPathStroker()
        stroker.setWidth(2 * tol)
        for item in self.items.values():
            local = item.mapFromScene(QPointF(*pos))
            if item.path().contains(local) or stroker.createStroke(item.path()).contains(local):
                return True
        return False


class GearPairItem(_Container):
    """One ``gear_pair``: both pitch curves turning by the precomputed rotations."""

    def __init__(self, result: GearResult) -> None:
        super().__init__()
        self.setZValue(5)
        self.result = result
        self.index = 0
        self.selected = False
        self.gears: _Gears | None = None
        el = result.element
        if result.kinematics is None or not len(result.input_curve):
            c = el.input_center
            self._set_core(QRectF(c[0] - 10, c[1] - 10, 20, 20))
            self.label_at, self.label_color = c, NOTE
            self.label_text = f"{el.id}: {result.error or 'not solved'}"
            return
        self.gears = _Gears(self, result)
        self._set_core(self.gears.extent())
        self.label_at = (self._core.left(), self._core.bottom())
        self.label_text = f"{el.id}  (non-circular gears)"
        self.set_frame(0)

    @property
    def element_id(self) -> str:
        return self.result.element_id

    @property
    def n_frames(self) -> int:
        return self.result.n_frames

    def set_frame(self, index: int) -> None:
        if self.gears is None or not self.result.n_frames:
            return
        self.index = int(index) % self.result.n_frames
        self.gears.set_frame(self.index)

    def input_rotation(self) -> float:
        t = self.gears.input.transform()
        return math.atan2(t.m12(), t.m11())

    def output_rotation(self) -> float:
        t = self.gears.output.transform()
        return math.atan2(t.m12(), t.m11())

    def set_selected(self, on: bool) -> None:
        if on != self.selected and self.gears is not None:
            self.selected = on
            self.gears.set_selected(on)

    def hit(self, pos: tuple[float, float], tol: float) -> bool:
        return self.gears is not None and self.gears.hit(pos, tol)

    def extent(self) -> QRectF:
        return QRectF(self._core)


class GearedGenevaItem(GenevaItem):
    """A Geneva drive driven through gears: the drive as :class:`GenevaItem` draws it (its crank
    turning by the geared rotations of the result) and the gear pair on the crank shaft."""

    def __init__(self, result: GearedGenevaResult) -> None:
        self.gears: _Gears | None = None
        super().__init__(result)
        gres = result.gears
        if result.geometry is not None and gres is not None and gres.kinematics is not None:
            self.gears = _Gears(self, gres)
            self._set_core(self._core.united(self.gears.extent()))
            self.label_at = (self._core.left(), self._core.bottom())
            self.label_text = f"{result.element.id}  (smooth Geneva drive, z = {result.element.slots}, geared crank)"
            self.set_frame(self.index)

    def set_frame(self, index: int) -> None:
        super().set_frame(index)
        if self.gears is not None and self.gears.res.n_frames:
            self.gears.set_frame(int(index) % self.gears.res.n_frames)

    def set_selected(self, on: bool) -> None:
        was = self.selected
        super().set_selected(on)
        if self.gears is not None and on != was:
            self.gears.set_selected(on)

    def hit(self, pos: tuple[float, float], tol: float) -> bool:
        return super().hit(pos, tol) or (self.gears is not None and self.gears.hit(pos, tol))


def element_item(res):
    """The canvas item for a gear result (a ``gear_pair`` or a ``geared_geneva``), or None."""
    if isinstance(res, GearedGenevaResult):
        return GearedGenevaItem(res)
    if isinstance(res, GearResult):
        return GearPairItem(res)
    return None
