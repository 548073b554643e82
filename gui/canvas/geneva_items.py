"""Canvas items of a Geneva drive, drawn from the core's exact geometry and animated by transforms.

:func:`contour_path` turns a core :class:`~mechsketch.core.analyses.contour.Contour` (lines
and arcs in bulge form) into a QPainterPath whose arcs are curves (:func:`arc_to`), never a dense
polyline.
:class:`GenevaItem` holds one path item per part, built once per solve in the part's own frame:
the wheel (stadium slots, horn lands, locking arcs, hub bore), and the driver - locking disc with
its relief, crank arm, roller - plus the centre marks and the line of centres. A frame only sets
two transforms read from the precomputed arrays of a
:class:`~mechsketch.core.workspace.results.GenevaResult`: the driver turns by the crank rotation
about the crank centre, the wheel by the kinematics' wheel angle about its centre (it holds still
in the dwell). World millimetres, y up (the view flips y).
"""
from __future__ import annotations

import math

from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QBrush, QColor, QPainter, QPainterPath, QPainterPathStroker, QPen, QTransform
from PySide6.QtWidgets import QGraphicsItem, QGraphicsPathItem, QStyleOptionGraphicsItem, QWidget

from mechsketch.core.analyses.contour import Contour, Part

from mechsketch.core.workspace import GenevaResult
from .items import INK, MUTED, NOTE, SELECT, _pen, _px, _text
from ..qtsafe import qt_safe

WHEEL_FILL = QColor("#cfdcee")
WHEEL_EDGE = QColor("#3d5f8f")
DISC_FILL = QColor("#f5d9b8")
DISC_EDGE = QColor("#b3661a")
ARM_FILL = QColor(214, 140, 69, 150)
ROLLER_FILL = QColor("#eef0f3")
CENTRE = QColor("#7b8494")
Z_WHEEL, Z_DISC, Z_ARM, Z_ROLLER, Z_MARKS = 1.0, 2.0, 3.0, 4.0, 5.0


#: largest sweep of one cubic piece of an arc (rad): radial error below 1e-7 of the radius
ARC_PIECE = math.pi / 8


def arc_to(path: QPainterPath, centre: tuple[float, float], radius: float, a0: float, sweep: float) -> None:
    """Continue ``path`` (whose current point is the arc's start) along the circular arc about
    ``centre`` from angle ``a0`` over ``sweep`` (rad, CCW positive, y-up world mm).

    The arc is a chain of cubic Bézier arcs - the curve ``QPainterPath.arcTo`` makes - but with
    every piece's end points on the circle and at most :data:`ARC_PIECE` wide, so the drawn arc
    deviates less than 1e-7·r from the true one (``arcTo``'s quarter-circle pieces are off by up
    to 2.7e-4·r: 0.02 mm on an 87 mm wheel, visible at the canvas's largest zoom).
    """
    n = max(1, math.ceil(abs(sweep) / ARC_PIECE - 1e-12))
    h = sweep / n
    k = 4.0 / 3.0 * math.tan(h / 4.0)
    cx, cy = centre
    a = a0
    for _ in range(n):
        b = a + h
        ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
        path.cubicTo(cx + radius * (ca - k * sa), cy + radius * (sa + k * ca),
                     cx + radius * (cb + k * sb), cy + radius * (sb - k * cb),
                     cx + radius * cb, cy + radius * sb)
        a = b


def contour_path(contour: Contour, path: QPainterPath | None = None) -> QPainterPath:
    """Append the closed ``contour`` to ``path`` (a new one if None): lines as ``lineTo``, arcs as
    curves (:func:`arc_to`), in world mm with y up."""
    path = QPainterPath() if path is None else path
    sg = contour.segments()
    path.moveTo(QPointF(float(sg.p0[0, 0]), float(sg.p0[0, 1])))
    for k in range(len(contour)):
        if sg.is_arc[k]:
            arc_to(path, (float(sg.centre[k, 0]), float(sg.centre[k, 1])), float(sg.radius[k]),
                   float(sg.a0[k]), float(sg.theta[k]))
        else:
            path.lineTo(QPointF(float(sg.p1[k, 0]), float(sg.p1[k, 1])))
    path.closeSubpath()
    return path


def part_path(part: Part) -> QPainterPath:
    """A part's outline with its holes (odd-even fill: the holes show through)."""
    path = contour_path(part.outer)
    for hole in part.holes:
        contour_path(hole, path)
    path.setFillRule(Qt.FillRule.OddEvenFill)
    return path


def rotation_about(centre: tuple[float, float], angle: float) -> QTransform:
    """Rotate by ``angle`` (rad, CCW in the y-up world) about the origin, then move to ``centre``."""
    t = QTransform()
    t.translate(float(centre[0]), float(centre[1]))
    t.rotateRadians(float(angle))
    return t


def _cross(path: QPainterPath, c: tuple[float, float], half: float) -> None:
    path.moveTo(c[0] - half, c[1])
    path.lineTo(c[0] + half, c[1])
    path.moveTo(c[0], c[1] - half)
    path.lineTo(c[0], c[1] + half)


def _path_item(path: QPainterPath, parent: QGraphicsItem, fill: QColor | None, edge: QColor, width: float,
               z: float, name: str, style: Qt.PenStyle = Qt.PenStyle.SolidLine) -> QGraphicsPathItem:
    item = QGraphicsPathItem(path, parent)
    item.setPen(_pen(edge, width, style))
    item.setBrush(QBrush(fill) if fill is not None else Qt.BrushStyle.NoBrush)
    item.setZValue(z)
    item.setData(0, name)
    return item


@qt_safe
class _Container(QGraphicsItem):
    """A parent whose children draw the parts; it paints only its label (constant size on screen).

    The bounding box is the element's extent (``_core``, mm) padded by :attr:`PAD_PX` screen
    pixels; the view calls :meth:`set_px` when the zoom changes.
    """

    PAD_PX = 80.0

    def __init__(self) -> None:
        super().__init__()
        self._core = QRectF()
        self._rect = QRectF()
        self._px = 0.5
        self.label_at: tuple[float, float] | None = None
        self.label_text = ""
        self.label_color = MUTED

    def set_px(self, px: float) -> None:
        """Millimetres per screen pixel now (for the bounding box only)."""
        self._px = px
        self._set_core(self._core)

    def _set_core(self, core: QRectF) -> None:
        pad = self.PAD_PX * self._px
        rect = core.adjusted(-pad, -pad, pad, pad) if not core.isNull() else QRectF()
        if rect != self._rect:
            self.prepareGeometryChange()
            self._rect = rect
        self._core = QRectF(core)

    def boundingRect(self) -> QRectF:
        return self._rect

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        if self.label_at is not None and self.label_text:
            painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
            _text(painter, self.label_at, self.label_text, _px(painter), 0.0, 8.0, self.label_color, 11, True)


class GenevaItem(_Container):
    """One Geneva drive: wheel and driver parts as exact paths, turned per frame by transforms.

    ``wheel``, ``driver`` are the two moving groups; ``parts`` maps part names ("wheel",
    "locking_disc", "crank_arm", "roller") to their path items (paths in the part's own frame).
    """

    def __init__(self, result: GenevaResult) -> None:
        super().__init__()
        self.setZValue(5)
        self.result = result
        self.parts: dict[str, QGraphicsPathItem] = {}
        self.wheel = _Container()
        self.driver = _Container()
        self.wheel.setParentItem(self)
        self.driver.setParentItem(self)
        self.index = 0
        self.selected = False
        self.marks: QGraphicsPathItem | None = None
        self._build()
        self.set_frame(0)

    @property
    def element_id(self) -> str:
        return self.result.element_id

    @property
    def n_frames(self) -> int:
        return self.result.n_frames

    def _build(self) -> None:
        res = self.result
        geo = res.geometry
        el = res.element
        if geo is None:
            self._set_core(QRectF(el.crank_center[0] - 10, el.crank_center[1] - 10, 20, 20))
            self.label_at, self.label_color = el.crank_center, NOTE
            self.label_text = f"{el.id}: {res.error or 'not solved'}"
            return
        specs = (("wheel", self.wheel, WHEEL_FILL, WHEEL_EDGE, 1.6, Z_WHEEL),
                 ("locking_disc", self.driver, DISC_FILL, DISC_EDGE, 1.4, Z_DISC),
                 ("crank_arm", self.driver, ARM_FILL, DISC_EDGE, 1.4, Z_ARM),
                 ("roller", self.driver, ROLLER_FILL, INK, 1.4, Z_ROLLER))
        for name, parent, fill, edge, width, z in specs:
            self.parts[name] = _path_item(part_path(getattr(geo, name)), parent, fill, edge, width, z, name)
        d = geo.dims
        half = 0.6 * el.roller_radius
        cc, wc = geo.crank_center, geo.wheel_center
        static = QPainterPath()
        for c in (cc, wc):
            _cross(static, c, half)
        static.moveTo(*cc)
        static.lineTo(*wc)
        self.marks = _path_item(static, self, None, CENTRE, 1.0, Z_MARKS, "centre_marks", Qt.PenStyle.DashDotLine)
        roller_mark = QPainterPath()
        _cross(roller_mark, (d.crank_radius, 0.0), 0.5 * half)
        _path_item(roller_mark, self.driver, None, CENTRE, 1.0, Z_MARKS, "roller_mark")
        ro, reach = d.outer_radius, d.lock_disc_radius + d.crank_radius
        self._set_core(QRectF(wc[0] - ro, wc[1] - ro, 2 * ro, 2 * ro).united(
            QRectF(cc[0] - reach, cc[1] - reach, 2 * reach, 2 * reach)))
        self.label_at = (self._core.left(), self._core.bottom())
        self.label_text = f"{el.id}  (Geneva drive, z = {el.slots})"

    # -- animation --------------------------------------------------------------------------
    def set_frame(self, index: int) -> None:
        """Show sample ``index`` of the precomputed rotations (no solving)."""
        res = self.result
        if res.geometry is None or res.n_frames == 0:
            return
        self.index = int(index) % res.n_frames
        geo = res.geometry
        self.driver.setTransform(rotation_about(geo.crank_center, float(res.crank_rotation[self.index])))
        self.wheel.setTransform(rotation_about(geo.wheel_center, float(res.wheel_rotation[self.index])))

    def wheel_rotation(self) -> float:
        """The wheel's rotation shown now (rad, from its built frame, world CCW)."""
        t = self.wheel.transform()
        return math.atan2(t.m12(), t.m11())

    def crank_rotation(self) -> float:
        """The driver's rotation shown now (rad)."""
        t = self.driver.transform()
        return math.atan2(t.m12(), t.m11())

    # -- selection and picking --------------------------------------------------------------
    def set_selected(self, on: bool) -> None:
        """Outline the parts in the selection colour."""
        if on == self.selected:
            return
        self.selected = on
        for name, item in self.parts.items():
            pen = QPen(item.pen())
            pen.setColor(SELECT if on else (WHEEL_EDGE if name == "wheel" else INK if name == "roller" else DISC_EDGE))
            pen.setWidthF(2.6 if on else (1.6 if name == "wheel" else 1.4))
            item.setPen(pen)

    def hit(self, pos: tuple[float, float], tol: float) -> bool:
        """True if the world point ``pos`` is on a part (within ``tol`` mm of its outline)."""
        p = QPointF(*pos)
        stroker = QPainterPathStroker()
        stroker.setWidth(2 * tol)
        for item in self.parts.values():
            local = item.mapFromScene(p)
            if item.path().contains(local) or stroker.createStroke(item.path()).contains(local):
                return True
        return False

    def extent(self) -> QRectF:
        """The area swept by the drive (mm)."""
        return QRectF(self._core)
