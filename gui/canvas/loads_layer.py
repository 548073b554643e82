"""Loads on the canvas: each linkage's forces, torques, springs and dampers drawn where their links
are at the displayed frame, with handles that move them.

- :class:`LoadsItem` paints the records :class:`LoadLayer` builds: a force as an arrow ending at
  its point of application (fixed screen length, its size in N as a label), a torque as an arc
  with an arrowhead around its link's centre (counter-clockwise positive), a spring as a zigzag
  and a damper as a dashpot between their two ends, and a diamond on every point that can be
  dragged.
- :class:`LoadLayer` behaves like a tool (``handle(ev)``, ``overlay()``, ``busy``, ``cancel``):
  the view routes a press on a load's handle to it under the select tool. A force's handle is
  the tail of its arrow, a spring's or damper's a little inside each end (so that a load applied
  at a joint does not hide the joint's own grip); dragging a handle moves the load's point by the
  same displacement. A drag previews the moved load (the point shown at the displayed frame is
  mapped back to its link's drawn pose) and pushes one undo command on release. Moving a load
  never changes the kinematics: the preview re-sweeps nothing.

Everything is read from the solution the canvas already holds; nothing here solves.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from PySide6.QtCore import QPointF, Qt
from PySide6.QtGui import QBrush, QColor, QPainter, QPainterPath
from PySide6.QtWidgets import QStyleOptionGraphicsItem, QWidget

from mechsketch.core.model.edits import ReplaceElement
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.loads import End, PointForce

from .events import XY, CanvasEvent
from .arrows import arrow
from .items import Overlay, _Item, _pen, _px, _rect_of, _text
from .pose import ElementPose, to_drawn
from ..qtsafe import qt_safe

LOAD = QColor("#c2255c")
SPRING = QColor("#2f9e44")
DAMPER = QColor("#5f3dc4")
ARROW_PX = 46.0     # a force arrow's length on screen
TORQUE_PX = 20.0    # a torque arc's radius on screen
END_PX = 14.0       # a spring's or damper's handles sit this far inside its ends


@dataclass(frozen=True)
class LoadHandle:
    """A draggable grip of a load: ``element``, ``load`` id, ``end`` (0 for a force; 0 or 1 for
    a spring/damper), the grip's world position ``at`` (mm) at the displayed frame, the ``point``
    of the load it moves (world, mm) and that point's ``link``."""

    element: str
    load: str
    end: int
    link: str
    at: XY
    point: XY


def _centre(linkage: Linkage, link: str) -> XY:
    pts = [linkage.joint(j).at for j in linkage.link(link).joints]
    return (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))


class LoadLayer:
    """Records to draw and handle dragging for the loads of every linkage (module docstring)."""

    def __init__(self, ctx, px=lambda: 0.5) -> None:
        self.ctx = ctx
        self.px = px   # mm per screen pixel now (handles sit a fixed screen distance from points)
        self._cache: dict[tuple, tuple] = {}
        self._overlay = Overlay()
        self._grab: LoadHandle | None = None
        self._started = False
        self._base: Linkage | None = None
        self._good: Linkage | None = None

    # -- where things are -------------------------------------------------------------------
    def _world(self, pose: ElementPose, link: str, p0: XY) -> XY:
        """Where the point of ``link`` drawn at ``p0`` is shown (the drawn point without a solution)."""
        lk = pose.linkage
        if link == lk.ground or pose.arrays is None or pose.index is None:
            return (float(p0[0]), float(p0[1]))
        sol = pose.arrays.solution
        key = (id(sol), link, p0)
        hit = self._cache.get(key)
        if hit is None or hit[0] is not sol:
            if len(self._cache) > 512:
                self._cache.clear()
            hit = (sol, sol.point(link, p0))
            self._cache[key] = hit
        p = hit[1][pose.index]
        return (float(p[0]), float(p[1]))

    def records(self) -> tuple[list[dict], list[XY], list[LoadHandle]]:
        """(drawing records, their points for the bounding box, the handles) at the displayed frame."""
        records: list[dict] = []
        points: list[XY] = []
        handles: list[LoadHandle] = []
        px = self.px()
        for pose in self.ctx.poses():
            lk = pose.linkage
            for ld in lk.loads:
                if ld.kind == "force":
                    at = self._world(pose, ld.link, ld.at)
                    mag = math.hypot(*ld.force)
                    u = (ld.force[0] / mag, ld.force[1] / mag) if mag else (0.0, -1.0)
                    records.append({"kind": "force", "at": at, "dir": u, "label": f"{ld.id} {mag:.4g} N"})
                    tail = (at[0] - u[0] * ARROW_PX * px, at[1] - u[1] * ARROW_PX * px)
                    handles.append(LoadHandle(lk.id, ld.id, 0, ld.link, tail, at))
                    points.append(at)
                elif ld.kind == "torque":
                    at = self._world(pose, ld.link, _centre(lk, ld.link))
                    records.append({"kind": "torque", "at": at, "ccw": ld.torque >= 0,
                                    "label": f"{ld.id} {ld.torque:.4g} N·m"})
                    points.append(at)
                else:
                    ends = [self._world(pose, e.link, e.at) for e in ld.ends]
                    text = f"{ld.id} {ld.stiffness:.4g} N/mm" if ld.kind == "spring" else f"{ld.id} {ld.damping:.4g} N·s/mm"
                    records.append({"kind": ld.kind, "ends": ends, "label": text})
                    d = complex(ends[1][0] - ends[0][0], ends[1][1] - ends[0][1])
                    inward = min(END_PX * px, 0.3 * abs(d)) * (d / abs(d) if abs(d) > 0 else 1.0)
                    for m, e in enumerate(ld.ends):
                        g = complex(*ends[m]) + (inward if m == 0 else -inward)
                        handles.append(LoadHandle(lk.id, ld.id, m, e.link, (g.real, g.imag), ends[m]))
                    points += ends
        return records, points, handles

    def at(self, pos: XY, tol: float) -> LoadHandle | None:
        best, dist = None, tol
        for h in self.records()[2]:
            d = math.hypot(h.at[0] - pos[0], h.at[1] - pos[1])
            if d <= dist:
                best, dist = h, d
        return best

    # -- tool protocol ----------------------------------------------------------------------
    @property
    def busy(self) -> bool:
        return self._grab is not None and self._started

    def overlay(self) -> Overlay:
        return self._overlay

    def route(self, ev: CanvasEvent, tool):
        """This layer while it drags, or for a press on a load handle under the select tool when
        no joint is under the cursor; else ``tool``."""
        if self._grab is not None:
            return self
        if (ev.kind == "press" and ev.button == "left" and getattr(tool, "name", "") == "select"
                and self.at(ev.raw, ev.tolerance) is not None):
            return self
        return tool

    def handle(self, ev: CanvasEvent) -> None:
        if self._grab is not None and self.stale():
            self.cancel()
            self.ctx.say("the load drag was interrupted (an edit, undo or another document): drag again")
            return
        getattr(self, f"_on_{ev.kind}", lambda _ev: None)(ev)

    def stale(self) -> bool:
        """The drag under way lost its ground (its linkage or load gone or changed by something
        else, or its preview ended by an edit)."""
        ctl, h = self.ctx.controller, self._grab
        if h is None:
            return False
        if not self.ctx.has_linkage(h.element):
            return True
        if self._started:
            return not ctl.workspace.previewing
        return ctl.scene.element(h.element) is not self._base

    def forget(self, gone=None) -> bool:
        """Abandon the drag if its linkage is in ``gone`` (None: the document was replaced)."""
        if self._grab is not None and (gone is None or self._grab.element in gone):
            self.cancel()
            return True
        return False

    def moved(self, linkage: Linkage, h: LoadHandle, pos: XY) -> Linkage:
        """``linkage`` with handle ``h`` dragged to world ``pos`` at the displayed frame (its load's
        point moves by the same displacement)."""
        pose = self.ctx.pose(h.element)
        arrays, k = (pose.arrays, pose.index) if pose is not None else (None, None)
        world = (h.point[0] + pos[0] - h.at[0], h.point[1] + pos[1] - h.at[1])
        p0 = to_drawn(arrays, linkage, h.link, k, world)
        p0 = (float(p0[0]), float(p0[1]))
        ld = linkage.load(h.load)
        if isinstance(ld, PointForce):
            return linkage.with_load(replace(ld, at=p0))
        ends = list(ld.ends)
        ends[h.end] = End(ends[h.end].link, p0)
        return linkage.with_load(replace(ld, ends=(ends[0], ends[1])))

    def _on_press(self, ev: CanvasEvent) -> None:
        h = self.at(ev.raw, ev.tolerance)
        if h is None:
            return
        self._grab, self._started = h, False
        self._base = self._good = self.ctx.linkage(h.element)
        self.ctx.say(f"{h.element}: drag load {h.load}" + ("" if h.end == 0 and self._base.load(h.load).kind == "force"
                                                            else f" (end {h.end + 1})"))

    def _on_move(self, ev: CanvasEvent) -> None:
        h = self._grab
        if h is None:
            return
        ctl = self.ctx.controller
        if not self._started:
            if math.hypot(ev.raw[0] - h.at[0], ev.raw[1] - h.at[1]) < 0.4 * ev.tolerance:
                return
            self._started = True
            ctl.begin_preview()
        cand = self.moved(self._base, h, ev.pos)
        if ctl.preview(ReplaceElement(cand, f"move load {h.load}")):
            self._good = cand

    def _on_release(self, ev: CanvasEvent) -> None:
        h = self._grab
        if h is None:
            return
        if self._started:
            text = f"move load {h.load}"
            good = self._good if self._good is not None and self._good != self._base else None
            self.ctx.controller.end_preview(ReplaceElement(good, text) if good is not None else None, text)
        self._grab, self._started = None, False
        self._base = self._good = None

    def cancel(self) -> None:
        if self._grab is not None and self._started:
            self.ctx.controller.end_preview(None)
        self._grab, self._started = None, False
        self._base = self._good = None


def _zigzag(a: XY, b: XY, px: float) -> QPainterPath:
    za, zb = complex(*a), complex(*b)
    d = zb - za
    path = QPainterPath(QPointF(*a))
    if abs(d) < 1e-12:
        return path
    n = 1j * d / abs(d)
    turns, amp = 8, 5.0 * px
    lead = 0.15
    pts = [za + lead * d]
    for m in range(turns):
        t = lead + (1 - 2 * lead) * (m + 0.5) / turns
        pts.append(za + t * d + (amp if m % 2 == 0 else -amp) * n)
    pts += [za + (1 - lead) * d, zb]
    for p in pts:
        path.lineTo(p.real, p.imag)
    return path


@qt_safe
class LoadsItem(_Item):
    """Draws the records of :meth:`LoadLayer.records` (forces, torques, springs, dampers, handles)."""

    PAD_PX = 90.0

    def __init__(self) -> None:
        super().__init__()
        self.records: list[dict] = []
        self.handles: list[LoadHandle] = []
        self.setZValue(55)
        self.setCacheMode(_Item.CacheMode.NoCache)

    def set_records(self, records: list[dict], points: list[XY], handles: list[LoadHandle]) -> None:
        self.records, self.handles = records, handles
        self._bounds(_rect_of(points))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for r in self.records:
            kind = r["kind"]
            if kind == "force":
                (x, y), (ux, uy) = r["at"], r["dir"]
                tail = (x - ux * ARROW_PX * px, y - uy * ARROW_PX * px)
                painter.setPen(_pen(LOAD, 2.2))
                painter.setBrush(QBrush(LOAD))
                arrow(painter, tail, (x, y), px)
                _text(painter, tail, r["label"], px, 4.0, 6.0, LOAD, 10, True)
            elif kind == "torque":
                x, y = r["at"]
                rad = TORQUE_PX * px
                path = QPainterPath()
                a0, a1 = (-0.6, 3.9) if r["ccw"] else (3.9, -0.6)
                for m, t in enumerate(np.linspace(a0, a1, 28)):
                    q = (x + rad * math.cos(t), y + rad * math.sin(t))
                    path.moveTo(*q) if m == 0 else path.lineTo(*q)
                painter.setPen(_pen(LOAD, 2.0))
                painter.setBrush(Qt.BrushStyle.NoBrush)
                painter.drawPath(path)
                end = (x + rad * math.cos(a1), y + rad * math.sin(a1))
                tang = (-math.sin(a1), math.cos(a1)) if r["ccw"] else (math.sin(a1), -math.cos(a1))
                painter.setBrush(QBrush(LOAD))
                arrow(painter, (end[0] - tang[0] * px, end[1] - tang[1] * px), end, px)
                _text(painter, (x, y), r["label"], px, rad / px + 4.0, rad / px, LOAD, 10, True)
            else:
                a, b = r["ends"]
                colour = SPRING if kind == "spring" else DAMPER
                painter.setBrush(Qt.BrushStyle.NoBrush)
                painter.setPen(_pen(colour, 1.8))
                if kind == "spring":
                    painter.drawPath(_zigzag(a, b, px))
                else:
                    za, zb = complex(*a), complex(*b)
                    mid, d = 0.5 * (za + zb), zb - za
                    if abs(d) > 1e-12:
                        u, n = d / abs(d), 1j * d / abs(d)
                        w = 5.0 * px
                        painter.drawLine(QPointF(*a), QPointF((mid - 4 * w * u).real, (mid - 4 * w * u).imag))
                        piston = mid + 2 * w * u
                        painter.drawLine(QPointF(piston.real, piston.imag), QPointF(*b))
                        for s in (-1, 1):   # the cylinder's walls and bottom
                            p1, p2 = mid - 4 * w * u + s * w * n, mid + 4 * w * u + s * w * n
                            painter.drawLine(QPointF(p1.real, p1.imag), QPointF(p2.real, p2.imag))
                        p1, p2 = mid - 4 * w * u - w * n, mid - 4 * w * u + w * n
                        painter.drawLine(QPointF(p1.real, p1.imag), QPointF(p2.real, p2.imag))
                        p1, p2 = piston - 0.8 * w * n, piston + 0.8 * w * n
                        painter.drawLine(QPointF(p1.real, p1.imag), QPointF(p2.real, p2.imag))
                mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
                _text(painter, mid, r["label"], px, 8.0, -14.0, colour, 10)
        for h in self.handles:
            x, y = h.at
            s = 4.5 * px
            if h.at != h.point:   # a thin line from the grip to the point it moves
                painter.setPen(_pen(LOAD, 1.0, Qt.PenStyle.DotLine))
                painter.drawLine(QPointF(*h.at), QPointF(*h.point))
            diamond = QPainterPath(QPointF(x, y - s))
            for q in ((x + s, y), (x, y + s), (x - s, y), (x, y - s)):
                diamond.lineTo(*q)
            painter.setPen(_pen(LOAD, 1.4))
            painter.setBrush(QBrush(QColor("white")))
            painter.drawPath(diamond)
