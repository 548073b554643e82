"""Graphics items of the canvas: a few items per linkage, each painting from arrays it is given.

- :class:`LinkageItem` - links (bars, ternary plates), joints, ground symbols, sliders and their
  guides, id labels, hover and selection highlight, and a note when the linkage is incomplete;
- :class:`TraceItem` - traced joint paths (coupler curves) and the driver's circle with its
  infeasible arcs in red, as QPainterPaths (NaN breaks a path);
- :class:`DeadPointItem` - dead points: the toggle pose of the group as a dashed ghost and a label;
- :class:`OverlayItem` - what the active tool will create (ghost lines, points, labels, rubber band).

World units are millimetres with y up (the view flips y). Sizes that should not scale with the
zoom (pen widths, joint radii, text) are given in screen pixels and converted with the painter's
current scale, so nothing here depends on the view except :meth:`set_px` for bounding boxes.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QBrush, QColor, QFont, QPainter, QPainterPath, QPen, QPolygonF
from PySide6.QtWidgets import QGraphicsItem, QStyleOptionGraphicsItem, QWidget

from mechsketch.core.model.drivers import input_text
from mechsketch.core.model.linkage import JointKind

from ..qpath import finite_path, xy_path as _path
from .events import XY, Hit
from .pose import ElementPose, SolutionArrays, link_outline, slider_roles
from .trace_path import TOLERANCE_PX, thin
from ..qtsafe import qt_safe

INK = QColor("#2b2f36")
MUTED = QColor("#6b7280")
LINK_FILL = QColor("#cfdcee")
LINK_EDGE = QColor("#3d5f8f")
DRIVER_FILL = QColor("#f5d9b8")
DRIVER_EDGE = QColor("#b3661a")
HOVER = QColor("#1e88e5")
SELECT = QColor("#ff8f00")
TRACE = QColor("#8e44ad")
BAD = QColor("#d62728")
NOTE = QColor("#9a6700")
GHOST = QColor("#1e88e5")
JOINT_R = 4.5          # px
LABEL_PX = 11          # px
TRACE_STEP_PX = 1.5    # traced paths keep about one point per this many pixels


def _pen(color: QColor, width: float, style: Qt.PenStyle = Qt.PenStyle.SolidLine,
         cap: Qt.PenCapStyle = Qt.PenCapStyle.RoundCap) -> QPen:
    pen = QPen(color, width, style, cap, Qt.PenJoinStyle.RoundJoin)
    pen.setCosmetic(True)
    return pen


def _px(painter: QPainter) -> float:
    """Millimetres per screen pixel for this painter."""
    s = abs(painter.worldTransform().m11()) or 1.0
    return 1.0 / s


def _text(painter: QPainter, at: XY, text: str, px: float, dx: float = 0.0, dy: float = 0.0,
          color: QColor = INK, size: int = LABEL_PX, bold: bool = False) -> None:
    """Draw ``text`` upright at world point ``at`` offset by (dx, dy) screen pixels (y up)."""
    painter.save()
    painter.translate(at[0], at[1])
    painter.scale(px, -px)
    font = QFont(painter.font())
    font.setPixelSize(size)
    font.setBold(bold)
    painter.setFont(font)
    painter.setPen(color)
    painter.drawText(QPointF(dx, -dy), text)
    painter.restore()


def short_error(error: str) -> str:
    """A one-line, polite summary of a solver error for the canvas."""
    m = re.search(r"mobility (-?\d+)", error)
    if m:
        return f"incomplete: mobility {m.group(1)} (a driven linkage needs 1)"
    if "no driver" in error:
        return "incomplete: no driver yet - add a crank (C)"
    if error.startswith("cannot be assembled at input"):
        return error
    first = error.split(". ")[0].split("\n")[0]
    return first if len(first) <= 90 else first[:87] + "..."


def draw_ground(painter: QPainter, at: XY, px: float) -> None:
    """A ground-pivot symbol (triangle on a hatched base) at ``at``; ``px`` is one pixel in mm."""
    x, y = at
    tri = QPolygonF([QPointF(x, y), QPointF(x - 8 * px, y - 13 * px), QPointF(x + 8 * px, y - 13 * px)])
    painter.setPen(_pen(INK, 1.4))
    painter.setBrush(QBrush(QColor("#e7e9ee")))
    painter.drawPolygon(tri)
    base = y - 13 * px
    painter.drawLine(QPointF(x - 13 * px, base), QPointF(x + 13 * px, base))
    painter.setPen(_pen(MUTED, 1.0))
    for k in range(-3, 4):
        x0 = x + k * 4 * px
        painter.drawLine(QPointF(x0 + 2 * px, base), QPointF(x0 - 2 * px, base - 5 * px))


@qt_safe
class _Item(QGraphicsItem):
    """Base: a cached bounding rect padded by a margin in screen pixels."""

    PAD_PX = 40.0

    def __init__(self) -> None:
        super().__init__()
        self._px = 0.5
        self._core = QRectF()
        self._rect = QRectF()
        # an item that did not change is blitted from a pixmap when the viewport repaints (a drag
        # of one linkage does not repaint the others' paths); a change re-renders it once
        self.setCacheMode(QGraphicsItem.CacheMode.DeviceCoordinateCache)

    def set_px(self, px: float) -> None:
        """Tell the item the current millimetres per pixel (for its bounding box only)."""
        if px != self._px:
            self._px = px
            self._bounds(self._core)

    def _bounds(self, core: QRectF) -> None:
        pad = self.PAD_PX * self._px
        rect = core.adjusted(-pad, -pad, pad, pad) if not core.isNull() else QRectF()
        if rect != self._rect:
            self.prepareGeometryChange()
            self._rect = rect
        self._core = core
        mode = self.cacheMode()
        if mode != QGraphicsItem.CacheMode.NoCache:
            # drop the cached pixmap: under X11 an update() alone could leave the old drawing on
            # screen (a linkage shown at an earlier frame and place; offscreen never showed it)
            self.setCacheMode(QGraphicsItem.CacheMode.NoCache)
            self.setCacheMode(mode)
        self.update()

    def boundingRect(self) -> QRectF:
        return self._rect


#: drawings anchored this far (px) outside the painted surface may still reach it (a label's text)
SURFACE_PAD_PX = 240.0


def _link_box(pose: ElementPose, link, px: float) -> QRectF:
    """The box of a link's joints at ``pose``, one pixel (``px`` mm) wider all round (a bar along
    an axis has a box of no area, which would intersect nothing)."""
    return _rect_of(pose.at[j] for j in link.joints if j in pose.at).adjusted(-px, -px, px, px)


def _surface(painter: QPainter, pad: float) -> QRectF | None:
    """The painter's surface (its device: the viewport, or an item's cache pixmap) in the painter's
    current coordinates, grown by ``pad`` in those units: a drawing anchored outside it cannot
    show. None when the painter has no device size to go by."""
    dev = painter.device()
    if dev is None or dev.width() <= 0 or dev.height() <= 0:
        return None
    inv, ok = painter.deviceTransform().inverted()
    if not ok:
        return None
    rect = inv.mapRect(QRectF(0.0, 0.0, float(dev.width()), float(dev.height())))
    return rect.adjusted(-pad, -pad, pad, pad)


def _rect_of(points) -> QRectF:
    pts = [p for p in points if math.isfinite(p[0]) and math.isfinite(p[1])]
    if not pts:
        return QRectF()
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return QRectF(min(xs), min(ys), max(max(xs) - min(xs), 1e-6), max(max(ys) - min(ys), 1e-6))


@qt_safe
class LinkageItem(_Item):
    """One linkage at one pose: links, joints, ground, sliders, labels, highlight."""

    PAD_PX = 60.0

    def __init__(self, pose: ElementPose) -> None:
        super().__init__()
        self.pose = pose
        self.hover: Hit | None = None
        self.selected: set[tuple[str, str]] = set()   # (kind, id) of this element
        self.show_labels = True
        self.setZValue(10)
        self.set_pose(pose)

    def set_pose(self, pose: ElementPose) -> None:
        self.pose = pose
        pts = list(pose.at.values()) + [e for g in pose.guide.values() for e in g]
        self._bounds(_rect_of(pts))

    def set_highlight(self, hover: Hit | None, selected: set[tuple[str, str]]) -> None:
        if hover != self.hover or selected != self.selected:
            self.hover, self.selected = hover, set(selected)
            self.update()

    def _state(self, kind: str, id_: str) -> QColor | None:
        if (kind, id_) in self.selected:
            return SELECT
        h = self.hover
        if h is not None and h.element == self.pose.element and h.kind == kind and h.id == id_:
            return HOVER
        return None

    # -- painting -------------------------------------------------------------------------
    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        lk = self.pose.linkage
        seen = _surface(painter, SURFACE_PAD_PX * px)   # what can reach the painted surface
        for jid in self.pose.guide:
            self._guide(painter, jid, px)
        # plates under bars, the driver on top: a crank is never hidden under a coupler plate
        order = sorted((k for k in lk.links if k.id != lk.ground),
                       key=lambda k: (k.id == lk.driver.link, len(k.joints) <= 2))
        for link in order:
            if seen is None or seen.intersects(_link_box(self.pose, link, px)):
                self._link(painter, link.id, px)
        grounded = set(lk.link(lk.ground).joints) if lk.ground in lk.link_ids else set()
        shown = [j for j in lk.joints if seen is None or seen.contains(QPointF(*self.pose.at[j.id]))]
        for j in shown:
            if j.id in grounded and j.kind is JointKind.R:
                draw_ground(painter, self.pose.at[j.id], px)
        for j in shown:
            if j.kind is JointKind.P:
                self._block(painter, j.id, px)
        for j in shown:
            if j.kind is JointKind.R:
                self._joint(painter, j.id, px)
        if self.show_labels:
            self._labels(painter, px, seen)
        if self.pose.error:
            self._badge(painter, px)

    def _link(self, painter: QPainter, link_id: str, px: float) -> None:
        lk = self.pose.linkage
        poly = link_outline(self.pose, link_id)
        if len(poly) < 2:
            return
        driver = link_id == lk.driver.link
        fill, edge = (DRIVER_FILL, DRIVER_EDGE) if driver else (LINK_FILL, LINK_EDGE)
        if len(poly) == 2:   # a bar: three strokes of one line (cheaper than paths)
            a, b = QPointF(poly[0].real, poly[0].imag), QPointF(poly[1].real, poly[1].imag)
            draw = lambda: painter.drawLine(a, b)  # noqa: E731
        else:
            shape = QPolygonF([QPointF(z.real, z.imag) for z in poly])
            draw = lambda: painter.drawPolygon(shape)  # noqa: E731
        state = self._state("link", link_id)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        if state is not None:
            halo = QColor(state)
            halo.setAlpha(110)
            painter.setPen(_pen(halo, 19))
            draw()
        painter.setPen(_pen(edge, 12))
        draw()
        painter.setPen(_pen(fill, 9))
        if len(poly) > 2:
            painter.setBrush(QBrush(fill))
        draw()
        painter.setBrush(Qt.BrushStyle.NoBrush)

    def _joint(self, painter: QPainter, jid: str, px: float) -> None:
        x, y = self.pose.at[jid]
        state = self._state("joint", jid)
        r = JOINT_R * px
        if state is not None:
            painter.setPen(_pen(state, 2.5))
            painter.setBrush(Qt.BrushStyle.NoBrush)
            painter.drawEllipse(QPointF(x, y), r + 3.5 * px, r + 3.5 * px)
        painter.setPen(_pen(INK, 1.6))
        painter.setBrush(QBrush(QColor("white")))
        painter.drawEllipse(QPointF(x, y), r, r)

    def _guide(self, painter: QPainter, jid: str, px: float) -> None:
        (x1, y1), (x2, y2) = self.pose.guide[jid]
        if not all(math.isfinite(v) for v in (x1, y1, x2, y2)):
            return
        guide, _ = slider_roles(self.pose.linkage, jid)
        d = complex(x2 - x1, y2 - y1)
        if abs(d) < 1e-12:
            return
        u = d / abs(d)
        n = u * 1j
        a, b = complex(x1, y1), complex(x2, y2)
        if guide == self.pose.linkage.ground:
            off = n * (-9 * px)
            painter.setPen(_pen(INK, 1.4, cap=Qt.PenCapStyle.FlatCap))
            painter.drawLine(QPointF((a + off).real, (a + off).imag), QPointF((b + off).real, (b + off).imag))
            painter.setPen(_pen(MUTED, 1.0))
            steps = int(abs(d) / (6 * px))
            for k in range(min(steps, 400) + 1):
                p = a + off + u * (k * 6 * px)
                q = p - n * (5 * px) - u * (4 * px)
                painter.drawLine(QPointF(p.real, p.imag), QPointF(q.real, q.imag))
        else:
            painter.setPen(_pen(LINK_EDGE, 1.4, cap=Qt.PenCapStyle.FlatCap))
            for s in (-1, 1):
                off = n * (s * 8 * px)
                painter.drawLine(QPointF((a + off).real, (a + off).imag), QPointF((b + off).real, (b + off).imag))
            painter.setPen(_pen(LINK_EDGE, 1.0, Qt.PenStyle.DashDotLine))
            painter.drawLine(QPointF(a.real, a.imag), QPointF(b.real, b.imag))

    def _block(self, painter: QPainter, jid: str, px: float) -> None:
        x, y = self.pose.at[jid]
        ang = self.pose.axis.get(jid, 0.0)
        state = self._state("joint", jid)
        painter.save()
        painter.translate(x, y)
        painter.rotate(ang)
        w, h = 15 * px, 8 * px
        if state is not None:
            painter.setPen(_pen(state, 2.5))
            painter.setBrush(Qt.BrushStyle.NoBrush)
            painter.drawRect(QRectF(-w - 3 * px, -h - 3 * px, 2 * w + 6 * px, 2 * h + 6 * px))
        painter.setPen(_pen(INK, 1.4))
        painter.setBrush(QBrush(QColor("#dfe6d2")))
        painter.drawRect(QRectF(-w, -h, 2 * w, 2 * h))
        painter.restore()

    def _labels(self, painter: QPainter, px: float, surface: QRectF | None = None) -> None:
        """Joint and link names; those anchored outside ``surface`` (item coordinates, None:
        everywhere) are left out."""
        lk = self.pose.linkage
        seen: dict[tuple[int, int], int] = {}
        for j in lk.joints:
            x, y = self.pose.at[j.id]
            key = (round(x / (4 * px)), round(y / (4 * px)))
            stack = seen.get(key, 0)
            seen[key] = stack + 1
            if surface is not None and not surface.contains(QPointF(x, y)):
                continue
            dx = 8.0 if j.kind is JointKind.R else 18.0
            _text(painter, (x, y), j.id, px, dx, 7.0 + 12.0 * stack, INK, LABEL_PX, True)
        for link in lk.links:
            if link.id == lk.ground:
                continue
            if surface is not None and not surface.intersects(_link_box(self.pose, link, px)):
                continue
            poly = link_outline(self.pose, link.id)
            if len(poly) < 2:
                continue
            c = sum(poly) / len(poly)
            dx, dy = 6.0, -14.0
            if len(poly) == 2 and abs(poly[1] - poly[0]) > 0:
                n = (poly[1] - poly[0]) / abs(poly[1] - poly[0]) * 1j
                n = n if n.imag >= 0 else -n
                dx, dy = 13.0 * n.real - 10.0, 13.0 * n.imag + 4.0
            _text(painter, (c.real, c.imag), link.id, px, dx, dy, MUTED, LABEL_PX - 1)

    def _badge(self, painter: QPainter, px: float) -> None:
        pts = list(self.pose.at.values())
        if not pts:
            return
        x = min(p[0] for p in pts)
        y = min(p[1] for p in pts)
        _text(painter, (x, y), f"{self.pose.element}: {short_error(self.pose.error or '')}", px,
              -8.0, -36.0, NOTE, LABEL_PX)


@qt_safe
class TraceItem(_Item):
    """Traced joint paths and the driver circle (red where the linkage cannot be assembled).

    Paths are decimated to about one point per :data:`TRACE_STEP_PX` screen pixels and then to the
    vertices that move the drawing by more than :data:`~mechsketch.gui.canvas.trace_path.TOLERANCE_PX`
    (rebuilt when the zoom changes much): Qt strokes the 1.6 px pen vertex by vertex, and thousands
    of sub-pixel segments cost paint time and show nothing.
    """

    PAD_PX = 6.0

    def __init__(self) -> None:
        super().__init__()
        self.traces: list[QPainterPath] = []
        self.circle_ok = QPainterPath()
        self.circle_bad = QPainterPath()
        self._data: tuple[ElementPose, list[str]] | None = None
        self._circle_of: tuple | None = None   # (key, valid mask, paths) of the driver circle
        self._built_px = 0.0
        self.setZValue(2)

    def set_px(self, px: float) -> None:
        super().set_px(px)
        if self._data is not None and not (0.67 < px / (self._built_px or px) < 1.5):
            self.set_data(*self._data)

    def set_data(self, pose: ElementPose, traced: list[str]) -> None:
        """Paths of ``traced`` joints over the cycle of ``pose.arrays`` (nothing if unsolved)."""
        arrays = pose.arrays
        self._data = (pose, list(traced))
        self._built_px = self._px
        step = TRACE_STEP_PX * self._px
        self.traces, self.circle_ok, self.circle_bad = [], QPainterPath(), QPainterPath()
        core = QRectF()
        if arrays is not None:
            for jid in traced:
                if jid in arrays.pos:
                    p = _trace(arrays.pos[jid], step, TOLERANCE_PX * self._px)
                    self.traces.append(p)
                    core = core.united(p.boundingRect())
            self._circle(pose, arrays, step)
            core = core.united(self.circle_ok.boundingRect()).united(self.circle_bad.boundingRect())
        self._bounds(core)

    def _circle(self, pose: ElementPose, arrays: SolutionArrays, step: float) -> None:
        lk = pose.linkage
        drv = lk.driver
        if not lk.has_driver or drv.pivot not in lk.joint_ids or drv.kind != "crank":
            return   # the crank's circle (an actuator has none: its input is a length)
        tip = next((j for j in lk.link(drv.link).joints if j != drv.pivot), None)
        if tip is None:
            return
        c = complex(*lk.joint(drv.pivot).at)
        r = abs(complex(*lk.joint(tip).at) - c)
        th = arrays.solution.input
        valid = arrays.valid
        # a drag of another joint leaves the circle as it was: same centre, radius, inputs, mask
        key = (c, r, th, step)
        old = self._circle_of
        if old is not None and old[0][:2] == key[:2] and old[0][2] is th and old[0][3] == step \
                and np.array_equal(old[1], valid):
            self.circle_ok, self.circle_bad = old[2]
            return
        xy = np.column_stack([c.real + r * np.cos(th), c.imag + r * np.sin(th)])
        ok = np.where(valid[:, None], xy, np.nan)
        self.circle_ok = _path(ok, close=bool(valid.all()), step=step)
        if not valid.all():
            bad = ~valid
            grown = bad | np.roll(bad, 1) | np.roll(bad, -1)
            self.circle_bad = _path(np.where(grown[:, None], xy, np.nan), step=step)
        self._circle_of = (key, valid.copy(), (self.circle_ok, self.circle_bad))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.setPen(_pen(QColor("#9aa3b2"), 1.0, Qt.PenStyle.DashLine))
        painter.drawPath(self.circle_ok)
        painter.setPen(_pen(BAD, 3.0, cap=Qt.PenCapStyle.FlatCap))
        painter.drawPath(self.circle_bad)
        painter.setPen(_pen(TRACE, 1.6))
        for p in self.traces:
            painter.drawPath(p)


def _trace(xy: np.ndarray, step: float, tol: float) -> QPainterPath:
    """A traced joint's closed path through the (N, 2) positions (mm; NaN breaks it), thinned to
    what the screen shows (:func:`~mechsketch.gui.canvas.trace_path.thin`: ``step`` arc length,
    ``tol`` deviation, mm)."""
    if len(xy) > 2 and np.isfinite(xy).all():
        xy = np.vstack([xy, xy[:1]])
    pts = thin(xy, step, tol)
    return finite_path(pts[:, 0], pts[:, 1])


@dataclass
class DeadMark:
    """A dead point to draw: ghost polyline (mm), marker point, label."""

    ghost: list[XY]
    at: XY
    label: str
    limit: bool


@qt_safe
class DeadPointItem(_Item):
    """Dead points and assembly limits of one linkage, drawn at their poses as red ghosts."""

    PAD_PX = 80.0

    def __init__(self) -> None:
        super().__init__()
        self.marks: list[DeadMark] = []
        self.setZValue(5)

    def set_data(self, pose: ElementPose) -> None:
        """Marks of the dead points of ``pose.arrays`` (the diagnostics', or during a drag those
        at the samples' resolution) at their nearest valid samples."""
        self.marks = []
        arrays = pose.arrays
        if arrays is not None:
            groups = {g.name: g for g in arrays.solution.groups}
            lk = pose.linkage
            tip = (next((j for j in lk.link(lk.driver.link).joints if j != lk.driver.pivot), None)
                   if lk.driver.kind == "crank" else None)
            for d, k in zip(arrays.dead_points, arrays.dead):
                g = groups.get(d.group)
                if g is None or not arrays.valid[k]:
                    continue
                pts = [tuple(arrays.pos[j][k]) for j in (g.outer_i, g.inner, g.outer_j)]
                if tip is not None:
                    pts = [tuple(arrays.pos[lk.driver.pivot][k]), tuple(arrays.pos[tip][k]), None] + pts
                what = "limit" if d.kind == "limit" else "dead point"
                self.marks.append(DeadMark(pts, tuple(arrays.pos[g.inner][k]),
                                           f"{what} {input_text(d.input, d.unit, 1)}",
                                           d.kind == "limit"))
        self._bounds(_rect_of([p for m in self.marks for p in m.ghost if p is not None]))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        ghost = QColor(BAD)
        ghost.setAlpha(150)
        for m in self.marks:
            painter.setPen(_pen(ghost, 1.4, Qt.PenStyle.DashLine))
            prev = None
            for p in m.ghost:
                if p is not None and prev is not None:
                    painter.drawLine(QPointF(*prev), QPointF(*p))
                prev = p
            painter.setPen(_pen(BAD, 2.0))
            x, y = m.at
            r = 6 * px
            painter.drawEllipse(QPointF(x, y), r, r)
            painter.drawLine(QPointF(x - r, y - r), QPointF(x + r, y + r))
            painter.drawLine(QPointF(x - r, y + r), QPointF(x + r, y - r))
            _text(painter, m.at, m.label, px, 10.0, -18.0, BAD, LABEL_PX - 1)


@dataclass
class Overlay:
    """A tool's preview, in world mm: what it will create, and why it cannot (``bad``)."""

    lines: list[tuple[XY, XY]] = field(default_factory=list)
    points: list[XY] = field(default_factory=list)
    circles: list[tuple[XY, float]] = field(default_factory=list)
    labels: list[tuple[XY, str]] = field(default_factory=list)
    rect: tuple[XY, XY] | None = None
    bad: bool = False
    picked: list[XY] = field(default_factory=list)    # joints the tool has picked so far

    def is_empty(self) -> bool:
        return not (self.lines or self.points or self.circles or self.labels or self.rect or self.picked)


@qt_safe
class OverlayItem(_Item):
    """Paints the active tool's :class:`Overlay` above everything else."""

    PAD_PX = 160.0

    def __init__(self) -> None:
        super().__init__()
        self.overlay = Overlay()
        self.setZValue(100)

    def set_overlay(self, overlay: Overlay) -> None:
        self.overlay = overlay
        pts = [p for ln in overlay.lines for p in ln] + list(overlay.points) + [p for p, _ in overlay.labels]
        pts += list(overlay.picked)
        pts += [(c[0] + s * r, c[1] + s * r) for c, r in overlay.circles for s in (-1, 1)]
        if overlay.rect:
            pts += list(overlay.rect)
        self._bounds(_rect_of(pts))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        ov = self.overlay
        color = BAD if ov.bad else GHOST
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        if ov.rect:
            (x1, y1), (x2, y2) = ov.rect
            fill = QColor(GHOST)
            fill.setAlpha(30)
            painter.setBrush(QBrush(fill))
            painter.setPen(_pen(GHOST, 1.0, Qt.PenStyle.DashLine))
            painter.drawRect(QRectF(QPointF(x1, y1), QPointF(x2, y2)).normalized())
            painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.setPen(_pen(color, 1.0, Qt.PenStyle.DotLine))
        for c, r in ov.circles:
            painter.drawEllipse(QPointF(*c), r, r)
        painter.setPen(_pen(color, 2.0, Qt.PenStyle.DashLine))
        for a, b in ov.lines:
            painter.drawLine(QPointF(*a), QPointF(*b))
        painter.setPen(_pen(color, 1.6))
        painter.setBrush(QBrush(QColor("white")))
        for p in ov.points:
            painter.drawEllipse(QPointF(*p), JOINT_R * px, JOINT_R * px)
        for p, text in ov.labels:
            _text(painter, p, text, px, 10.0, 10.0, color, LABEL_PX)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.setPen(_pen(GHOST, 2.5))
        for p in ov.picked:
            painter.drawEllipse(QPointF(*p), (JOINT_R + 4) * px, (JOINT_R + 4) * px)
