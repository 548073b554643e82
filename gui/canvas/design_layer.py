"""What the Study and Design docks show on the canvas: a tolerance band, a synthesis target and
an animated preview of a linkage that is not (yet) in the scene.

- :class:`BandItem` — the envelope of traced points: the strip between a lower and an upper
  curve (N, 2) mm, filled, with the nominal path dashed and a label (the band's confidence and
  how much it is magnified to be seen);
- :class:`TargetItem` — a path target (numbered points joined in order, closed or open) or
  rigid-body poses (a point and an arrow along its angle each), with the point being placed;
- :class:`GhostItem` — a candidate or a study variant, solved once over its cycle and drawn
  translucent at a frame that :meth:`DesignLayer.tick` advances (an animation of its own, so a
  candidate moves even on an empty canvas).

:class:`DesignLayer` owns the three and the preview's timer; the view makes one and tells it
the zoom. Everything here reads arrays and records handed to it; nothing imports a panel.
"""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import QObject, QPointF, QRectF, Qt, QTimer
from PySide6.QtGui import QBrush, QColor, QPainter, QPainterPath, QPen, QPolygonF
from PySide6.QtWidgets import QGraphicsItem, QGraphicsScene

from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.linkage import JointKind, Linkage
from mechsketch.core.solver.plan import compile_plan

from ..qpath import xy_path
from ..qtsafe import qt_safe
from .items import LinkageItem, TraceItem, _px, _text
from .pose import SolutionArrays, drawn_pose, sample_pose

BAND_FILL = QColor(230, 120, 20, 90)
BAND_EDGE = QColor("#c2571a")
NOMINAL = QColor("#5b3a8c")
TARGET = QColor("#0a8a5f")
PLACING = QColor("#0a8a5f")
GHOST_OPACITY = 0.6
#: frames per second of the preview animation, and samples of a previewed linkage's cycle
PREVIEW_FPS = 30
PREVIEW_SAMPLES = 180
ARROW_PX = 28.0


def _pen(color: QColor, width: float, style: Qt.PenStyle = Qt.PenStyle.SolidLine) -> QPen:
    pen = QPen(color, width, style, Qt.PenCapStyle.RoundCap, Qt.PenJoinStyle.RoundJoin)
    pen.setCosmetic(True)
    return pen


def _box(*arrays: np.ndarray) -> QRectF:
    pts = [a[np.isfinite(a).all(axis=1)] for a in arrays if a is not None and len(a)]
    pts = [p for p in pts if len(p)]
    if not pts:
        return QRectF()
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    return QRectF(float(lo[0]), float(lo[1]), max(float(hi[0] - lo[0]), 1e-6), max(float(hi[1] - lo[1]), 1e-6))


@qt_safe
class _LayerItem(QGraphicsItem):
    """Base: a bounding box of its data padded by a margin in screen pixels."""

    PAD_PX = 60.0

    def __init__(self) -> None:
        super().__init__()
        self._px = 0.5
        self._core = QRectF()
        self._rect = QRectF()
        self.setAcceptedMouseButtons(Qt.MouseButton.NoButton)

    def set_px(self, px: float) -> None:
        self._px = px
        self._bounds(self._core)

    def _bounds(self, core: QRectF) -> None:
        pad = self.PAD_PX * self._px
        self.prepareGeometryChange()
        self._core = core
        self._rect = core.adjusted(-pad, -pad, pad, pad) if not core.isNull() else QRectF()
        self.update()

    def boundingRect(self) -> QRectF:  # noqa: N802 - Qt override
        return self._rect


@qt_safe
class BandItem(_LayerItem):
    """The tolerance band: ``lower`` and ``upper`` (N, 2) mm around ``nominal`` (N, 2); NaN rows
    (samples the nominal cannot assemble) break it."""

    def __init__(self) -> None:
        super().__init__()
        self.setZValue(1.5)
        self.fill = QPainterPath()
        self.edges: list[QPainterPath] = []
        self.nominal = QPainterPath()
        self.label = ""
        self.anchor = (0.0, 0.0)
        self.data: tuple | None = None

    def set_band(self, nominal: np.ndarray, lower: np.ndarray, upper: np.ndarray, label: str = "",
                 closed: bool = True) -> None:
        nominal, lower, upper = (np.asarray(a, dtype=float) for a in (nominal, lower, upper))
        self.data = (nominal, lower, upper)
        self.label = label
        fill = QPainterPath()
        fill.setFillRule(Qt.FillRule.WindingFill)
        n = len(nominal)
        for k in range(n if closed else n - 1):
            j = (k + 1) % n
            quad = np.array([lower[k], lower[j], upper[j], upper[k]])
            if not np.isfinite(quad).all():
                continue
            x, y = quad[:, 0], quad[:, 1]
            if float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) < 0:   # one orientation:
                quad = quad[::-1]                                                     # overlaps stay filled
            fill.addPolygon(QPolygonF([QPointF(float(a), float(b)) for a, b in quad]))
            fill.closeSubpath()
        self.fill = fill
        self.edges = [xy_path(lower, close=closed), xy_path(upper, close=closed)]
        self.nominal = xy_path(nominal, close=closed)
        box = _box(lower, upper, nominal)
        self.anchor = (box.left(), box.bottom())   # above its top-left corner (y up): clear of the linkage
        self.setVisible(True)
        self._bounds(box)

    def clear(self) -> None:
        self.data = None
        self.fill, self.edges, self.nominal = QPainterPath(), [], QPainterPath()
        self.setVisible(False)
        self._bounds(QRectF())

    def paint(self, painter: QPainter, _option, _widget=None) -> None:
        if self.data is None:
            return
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        painter.setPen(Qt.PenStyle.NoPen)
        painter.setBrush(QBrush(BAND_FILL))
        painter.drawPath(self.fill)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.setPen(_pen(BAND_EDGE, 1.0))
        for e in self.edges:
            painter.drawPath(e)
        painter.setPen(_pen(NOMINAL, 1.2, Qt.PenStyle.DashLine))
        painter.drawPath(self.nominal)
        if self.label:
            _text(painter, self.anchor, self.label, px, 8, 8, BAND_EDGE)


@qt_safe
class TargetItem(_LayerItem):
    """A synthesis target: ``points`` (M, 2) mm of a path (``angles`` None) or of poses (``angles``
    (M,) degrees), and the point being placed (``pending``)."""

    def __init__(self) -> None:
        super().__init__()
        self.setZValue(30)
        self.points = np.zeros((0, 2))
        self.angles: np.ndarray | None = None
        self.closed = True
        self.pending: tuple[float, float] | None = None

    def set_target(self, points, angles=None, closed: bool = True, pending=None) -> None:
        self.points = np.asarray(points, dtype=float).reshape(-1, 2)
        self.angles = None if angles is None else np.asarray(angles, dtype=float).reshape(-1)
        self.closed = bool(closed)
        self.pending = None if pending is None else (float(pending[0]), float(pending[1]))
        extra = [np.array([self.pending])] if self.pending is not None else []
        self.setVisible(len(self.points) > 0 or self.pending is not None)
        self._bounds(_box(self.points, *extra))

    def clear(self) -> None:
        self.set_target(np.zeros((0, 2)))

    def paint(self, painter: QPainter, _option, _widget=None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        pts = self.points
        if self.angles is None and len(pts) > 1:
            painter.setPen(_pen(TARGET, 1.6, Qt.PenStyle.DashLine))
            painter.drawPath(xy_path(pts, close=self.closed and len(pts) > 2))
        painter.setPen(_pen(TARGET, 1.4))
        painter.setBrush(QBrush(QColor(255, 255, 255)))
        r = 3.5 * px
        step = max(1, len(pts) // 12)   # numbers on a dozen points at most
        for k, (x, y) in enumerate(pts):
            painter.drawEllipse(QPointF(x, y), r, r)
            if self.angles is not None and k < len(self.angles):
                self._arrow(painter, (x, y), self.angles[k], px)
            if k % step == 0 or k == len(pts) - 1:
                _text(painter, (x, y), str(k + 1), px, 6, 6, TARGET)
        if self.pending is not None:
            painter.setPen(_pen(PLACING, 1.0, Qt.PenStyle.DotLine))
            if len(pts) and self.angles is None:
                painter.drawLine(QPointF(*pts[-1]), QPointF(*self.pending))
            painter.drawEllipse(QPointF(*self.pending), r, r)

    def _arrow(self, painter: QPainter, at, angle_deg: float, px: float) -> None:
        a = math.radians(angle_deg)
        L = ARROW_PX * px
        tip = QPointF(at[0] + L * math.cos(a), at[1] + L * math.sin(a))
        painter.drawLine(QPointF(*at), tip)
        for turn in (2.6, -2.6):
            painter.drawLine(tip, QPointF(tip.x() + 8 * px * math.cos(a + turn), tip.y() + 8 * px * math.sin(a + turn)))


class GhostItem:
    """A linkage that is not in the scene, drawn translucent at a frame of its own cycle with the
    paths of its coupler points (joints on one moving link only)."""

    def __init__(self, scene: QGraphicsScene) -> None:
        self.scene = scene
        self.linkage: Linkage | None = None
        self.arrays: SolutionArrays | None = None
        self.frame = 0
        self.error = ""
        self.item: LinkageItem | None = None
        self.trace = TraceItem()
        self.trace.setOpacity(GHOST_OPACITY)
        self.trace.setZValue(3)
        self.trace.setVisible(False)
        scene.addItem(self.trace)

    @property
    def frames(self) -> int:
        return self.arrays.n if self.arrays is not None else 0

    def set_linkage(self, linkage: Linkage | None, px: float) -> None:
        """Show ``linkage`` (None: nothing); solved here once over its cycle."""
        self.linkage, self.arrays, self.frame, self.error = linkage, None, 0, ""
        if linkage is None:
            if self.item is not None:
                self.scene.removeItem(self.item)
                self.item = None
            self.trace.setVisible(False)
            return
        try:
            sol = compile_plan(linkage).sweep(PREVIEW_SAMPLES, order=0)
            self.arrays = SolutionArrays(linkage, sol)
        except MechsketchError as exc:
            self.error = str(exc)
        pose = drawn_pose(linkage, self.error or None)
        pose.arrays = self.arrays
        if self.item is None:
            self.item = LinkageItem(pose)
            self.item.setOpacity(GHOST_OPACITY)
            self.item.setZValue(25)
            self.item.show_labels = False
            self.scene.addItem(self.item)
        self.item.set_px(px)
        self.trace.set_px(px)
        self.trace.set_data(pose, traced_points(linkage))
        self.trace.setVisible(True)
        self.show_frame(0)

    def show_frame(self, k: int) -> None:
        if self.linkage is None or self.item is None:
            return
        self.frame = k % max(self.frames, 1)
        pose = sample_pose(self.arrays, self.linkage, self.frame) if self.arrays is not None else None
        if pose is None:
            pose = drawn_pose(self.linkage, self.error or None)
            pose.arrays = self.arrays
        self.item.set_pose(pose)

    def set_px(self, px: float) -> None:
        if self.item is not None:
            self.item.set_px(px)
        self.trace.set_px(px)


def traced_points(linkage: Linkage) -> list[str]:
    """The joints whose paths a preview draws: revolute joints on one moving link only (coupler
    points), else every joint of the coupler."""
    ground = linkage.ground
    out = [j.id for j in linkage.joints if j.kind is JointKind.R and len(linkage.links_of(j.id)) == 1
           and linkage.links_of(j.id)[0] != ground]
    if not out and "coupler" in linkage.link_ids:
        out = list(linkage.link("coupler").joints)
    return out


class DesignLayer(QObject):
    """The band, the target and the preview of one canvas (see the module docstring).

    ``tick()`` advances the preview one frame (the timer calls it while a preview shows and
    :attr:`animate` is on; tests call it instead of waiting)."""

    def __init__(self, scene: QGraphicsScene, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.scene = scene
        self.band = BandItem()
        self.target = TargetItem()
        for item in (self.band, self.target):
            item.setVisible(False)
            scene.addItem(item)
        self.ghost = GhostItem(scene)
        self.timer = QTimer(self)
        self.timer.setObjectName("designPreviewTimer")
        self.timer.setInterval(int(1000 / PREVIEW_FPS))
        self.timer.timeout.connect(self.tick)
        self.animate = True
        self._px = 0.5

    def set_px(self, px: float) -> None:
        self._px = px
        self.band.set_px(px)
        self.target.set_px(px)
        self.ghost.set_px(px)

    # -- band ------------------------------------------------------------------------------
    def set_band(self, band: dict | None) -> None:
        """``band``: {"nominal", "lower", "upper": (N, 2) mm, "label": str, "closed": bool}, or None."""
        if band is None:
            self.band.clear()
        else:
            self.band.set_px(self._px)
            self.band.set_band(band["nominal"], band["lower"], band["upper"], band.get("label", ""),
                               band.get("closed", True))

    # -- target ----------------------------------------------------------------------------
    def set_target(self, target: dict | None) -> None:
        """``target``: {"points": (M, 2) mm, "angles": (M,) ° or None, "closed": bool, "pending": (x, y)
        or None}, or None."""
        if target is None:
            self.target.clear()
        else:
            self.target.set_px(self._px)
            self.target.set_target(target.get("points", np.zeros((0, 2))), target.get("angles"),
                                   target.get("closed", True), target.get("pending"))

    # -- preview ---------------------------------------------------------------------------
    def set_preview(self, linkage: Linkage | None) -> None:
        """Show ``linkage`` animated (None: stop and hide the preview)."""
        self.ghost.set_linkage(linkage, self._px)
        if linkage is not None and self.animate and self.ghost.frames > 1:
            self.timer.start()
        else:
            self.timer.stop()

    def tick(self) -> None:
        """Advance the preview one frame."""
        if self.ghost.linkage is not None:
            self.ghost.show_frame(self.ghost.frame + 1)

    def stop(self) -> None:
        """Stop the preview's animation (closing the window)."""
        self.timer.stop()

    def extent(self) -> QRectF:
        """What the layer shows (mm), for zoom to fit."""
        rect = QRectF()
        for item in (self.band, self.target):
            if item.isVisible():
                rect = rect.united(item._core)
        if self.ghost.item is not None and self.ghost.arrays is not None:
            ext = self.ghost.arrays.extent()
            if ext:
                rect = rect.united(QRectF(ext[0], ext[1], ext[2] - ext[0], ext[3] - ext[1]))
        return rect


__all__ = ["BandItem", "DesignLayer", "GhostItem", "TargetItem", "traced_points"]
