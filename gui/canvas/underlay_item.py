"""Underlays on the canvas: a drawing's polylines or a picture, under everything else, and their
points to snap to.

:class:`UnderlayLayer` keeps one :class:`UnderlayItem` per visible underlay element of the scene
(:meth:`UnderlayLayer.sync`, cheap when the records did not change), answers the nearest vertex of
a visible drawing within a distance (:meth:`UnderlayLayer.snap`) and the box of everything shown
(:meth:`UnderlayLayer.extent`). The view calls these three (gui/canvas/view.py).
"""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QImage, QPainter, QPainterPath, QPen, QTransform
from PySide6.QtWidgets import QGraphicsItem, QGraphicsScene

from mechsketch.core.model.underlay import Underlay

from .events import XY
from ..qtsafe import qt_safe

Z_UNDERLAY = -100.0
LINE = QColor("#5b6f99")


def world_array(u: Underlay, source: np.ndarray) -> np.ndarray:
    """(N, 2) source points of ``u`` -> (N, 2) world points, mm (its placement, with numpy)."""
    a, b = u.placement.linear()
    ox, oy = u.placement.offset
    x, y = source[:, 0], source[:, 1]
    return np.column_stack([ox + a * x - b * y, oy + b * x + a * y])


def image_transform(u: Underlay) -> QTransform:
    """Maps a picture's pixel (i, j), j down from its top row, to world mm."""
    pl = u.placement
    h = u.image.height
    a, b = pl.linear()
    ox, oy = pl.offset
    # source (i, h - j) -> world: x = ox + a·i − b·(h − j), y = oy + b·i + a·(h − j)
    return QTransform(a, b, b, -a, ox - b * h, oy + a * h)


@qt_safe
class UnderlayItem(QGraphicsItem):
    """One underlay: its polylines (cosmetic lines) or its picture, at the record's opacity."""

    def __init__(self, underlay: Underlay) -> None:
        super().__init__()
        self.setZValue(Z_UNDERLAY)
        self.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
        self.underlay: Underlay | None = None
        self._path = QPainterPath()
        self._image: QImage | None = None
        self._image_key: object = None
        self._rect = QRectF()
        self._source: tuple[object, list[np.ndarray]] = (None, [])   # the paths as arrays, by identity
        self.points = np.zeros((0, 2))
        self.set_underlay(underlay)

    def set_underlay(self, u: Underlay) -> None:
        """Show ``u`` (rebuilt only where it changed)."""
        if u is self.underlay:
            return
        self.prepareGeometryChange()
        self.underlay = u
        x0, y0, x1, y1 = u.world_bounds()
        self._rect = QRectF(x0, y0, x1 - x0, y1 - y0).adjusted(-1, -1, 1, 1)
        if u.image is not None:
            if self._image_key != u.image.data:
                self._image = QImage.fromData(u.image.raw())
                self._image_key = u.image.data
            self.points = np.zeros((0, 2))
        else:
            if self._source[0] is not u.paths:      # a move or a scale keeps the paths: arrays kept
                self._source = (u.paths, [np.asarray(p, dtype=float) for p in u.paths])
            world = [world_array(u, src) for src in self._source[1]]
            path = QPainterPath()
            for pts in world:
                path.moveTo(QPointF(*pts[0]))
                for x, y in pts[1:]:
                    path.lineTo(QPointF(x, y))
            self._path = path
            self.points = np.concatenate(world) if world else np.zeros((0, 2))
        self.setVisible(u.visible)
        self.update()

    def boundingRect(self) -> QRectF:  # noqa: N802 - Qt override
        return self._rect

    def paint(self, painter: QPainter, _option, _widget=None) -> None:
        u = self.underlay
        if u is None:
            return
        painter.save()
        painter.setOpacity(u.opacity)
        if self._image is not None and u.image is not None:
            painter.setRenderHint(QPainter.RenderHint.SmoothPixmapTransform, True)
            painter.setTransform(image_transform(u), combine=True)
            painter.drawImage(0, 0, self._image)
        else:
            pen = QPen(LINE, 1.2)
            pen.setCosmetic(True)
            painter.setPen(pen)
            painter.drawPath(self._path)
        painter.restore()


class UnderlayLayer:
    """The underlay items of one canvas scene."""

    def __init__(self, scene: QGraphicsScene) -> None:
        self.scene = scene
        self.items: dict[str, UnderlayItem] = {}

    def sync(self, document) -> None:
        """Match the items to the underlay elements of ``document`` (a Scene)."""
        present = {e.id: e for e in document.elements if isinstance(e, Underlay)}
        for gone in set(self.items) - set(present):
            self.scene.removeItem(self.items.pop(gone))
        for eid, u in present.items():
            item = self.items.get(eid)
            if item is None:
                item = self.items[eid] = UnderlayItem(u)
                self.scene.addItem(item)
            else:
                item.set_underlay(u)

    def snap(self, raw: XY, tol: float) -> XY | None:
        """The vertex of a visible drawing nearest ``raw`` within ``tol`` mm, else None."""
        best, best_d = None, tol
        for item in self.items.values():
            if not item.isVisible() or not len(item.points):
                continue
            d = np.hypot(item.points[:, 0] - raw[0], item.points[:, 1] - raw[1])
            k = int(np.argmin(d))
            if d[k] <= best_d:
                best, best_d = (float(item.points[k, 0]), float(item.points[k, 1])), float(d[k])
        return best

    def extent(self) -> QRectF:
        """The box of every visible underlay (mm); empty if none."""
        rect = QRectF()
        for item in self.items.values():
            if item.isVisible():
                rect = rect.united(item.boundingRect())
        return rect
