"""View -> Centrodes: the fixed and the moving centrode of a selected link, rolling on each other.

Select a link (and optionally a second link of the same linkage as the reference) and switch the
view on: the fixed centrode is drawn on the frame (or on the reference link, moving with it), the
moving centrode on the link, carried by the link's placement at each frame, so during the
animation it rolls on the fixed one and touches it at the instant centre (a dot). Where the
relative motion passes through a translation (centre at infinity) the curves break; each break is
marked "∞" at the last drawn point. The curves are built once per solution from
:func:`~mechsketch.core.analyses.centrodes.linkage_centrodes` (the core), a frame change only
sets two transforms. :meth:`CentrodeView.export_csv` and :meth:`CentrodeView.export_dxf` write the
core's table and arc-fitted DXF (:func:`mechsketch.core.io.dxf_centrodes.export_centrodes`).
"""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QBrush, QColor, QPainter, QPainterPath, QTransform
from PySide6.QtWidgets import QGraphicsItem, QGraphicsPathItem, QStyleOptionGraphicsItem, QWidget

from mechsketch.core.analyses.centrodes import Centrodes, linkage_centrodes, runs
from mechsketch.core.errors import MechsketchError
from mechsketch.core.io.dxf_centrodes import CentrodeExport, default_limit, export_centrodes
from mechsketch.core.io.table import write_csv
from mechsketch.core.model.linkage import Linkage

from .items import _pen, _px, _text
from ..frames import map_frame
from ..qtsafe import qt_safe

FIXED = QColor("#c2255c")
MOVING = QColor("#1971c2")


def _path(xy: np.ndarray, idx_runs: list[np.ndarray], closed_all: bool) -> QPainterPath:
    path = QPainterPath()
    for idx in idx_runs:
        pts = xy[idx]
        path.moveTo(float(pts[0, 0]), float(pts[0, 1]))
        for x, y in pts[1:]:
            path.lineTo(float(x), float(y))
        if closed_all:
            path.closeSubpath()
    return path


def body_transform(origin: tuple[float, float], at: np.ndarray, rotation: float) -> QTransform:
    """Drawn point x -> at + Rot(rotation)(x − origin), as a QTransform."""
    t = QTransform()
    t.translate(float(at[0]), float(at[1]))
    t.rotateRadians(float(rotation))
    t.translate(-origin[0], -origin[1])
    return t


@qt_safe
class _Marks(QGraphicsItem):
    """The contact (instant centre) dot and the break marks, painted per frame."""

    def __init__(self, owner: "CentrodeItem") -> None:
        super().__init__(owner)
        self.owner = owner
        self.setZValue(3)

    def boundingRect(self) -> QRectF:
        return self.owner.boundingRect()

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        o = self.owner
        for at, text in o.break_marks():
            _text(painter, at, text, px, 6.0, 6.0, FIXED, 12, True)
        ic = o.contact()
        if ic is not None:
            painter.setPen(Qt.PenStyle.NoPen)
            painter.setBrush(QBrush(QColor("#212529")))
            painter.drawEllipse(QPointF(*ic), 4.0 * px, 4.0 * px)
        _text(painter, o.label_at, o.label, px, 0.0, 0.0, MOVING, 11, True)


@qt_safe
class CentrodeItem(QGraphicsItem):
    """Both centrodes of one link for one solution (see the module docstring)."""

    def __init__(self, c: Centrodes, linkage: Linkage, limit: float) -> None:
        super().__init__()
        self.c, self.linkage = c, linkage
        self.setZValue(4)
        ok = c.drawable(limit)
        self.runs = [r for r in runs(ok) if len(r) >= 2]
        whole = len(self.runs) == 1 and len(self.runs[0]) == len(ok)
        self.fixed = QGraphicsPathItem(_path(c.P, self.runs, whole), self)
        self.moving = QGraphicsPathItem(_path(c.p, self.runs, whole), self)
        for item, colour in ((self.fixed, FIXED), (self.moving, MOVING)):
            item.setPen(_pen(colour, 2.2))
            item.setBrush(Qt.BrushStyle.NoBrush)
        self.ok = ok
        self.index = 0
        ends = [] if whole else [(r[0], r[-1]) for r in self.runs]
        self._ends = ends
        rel = "frame" if c.relative_to in (None, linkage.ground) else c.relative_to
        self.label = f"centrodes of {c.link} relative to {rel}"
        pts = np.concatenate([c.world[ok]] + ([c.at] if c.at is not None else []))
        lo, hi = (np.nanmin(pts, axis=0), np.nanmax(pts, axis=0)) if len(pts) else (np.zeros(2), np.zeros(2))
        self.label_at = (float(lo[0]), float(hi[1]))
        self._rect = QRectF(float(lo[0]), float(lo[1]), float(hi[0] - lo[0]), float(hi[1] - lo[1])).adjusted(-50, -50, 50, 50)
        self._marks = _Marks(self)

    def boundingRect(self) -> QRectF:
        return self._rect

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        pass

    def set_frame(self, k: int) -> None:
        """Place the moving centrode with the link, the fixed one with its body, at sample ``k``."""
        c = self.c
        self.index = k = int(k) % len(c.input)
        self.moving.setTransform(body_transform(c.origin, c.at[k], c.rotation[k]))
        if c.ref_at is not None:
            self.fixed.setTransform(body_transform(c.ref_origin, c.ref_at[k], c.ref_rotation[k]))
        self._marks.update()

    def contact(self) -> tuple[float, float] | None:
        """Where the centrodes touch now (the instant centre, world mm), None if not drawn."""
        k = self.index
        if not self.ok[k]:
            return None
        return (float(self.c.world[k, 0]), float(self.c.world[k, 1]))

    def break_marks(self) -> list[tuple[tuple[float, float], str]]:
        """'∞' at both ends of every drawn stretch, on the fixed centrode's body (world mm now)."""
        out = []
        t = self.fixed.transform()
        for a, b in self._ends:
            for j in (a, b):
                p = t.map(QPointF(float(self.c.P[j, 0]), float(self.c.P[j, 1])))
                out.append(((p.x(), p.y()), "∞"))
        return out


class CentrodeView:
    """The centrodes view of one canvas: its target, its item, its exports."""

    def __init__(self, view) -> None:
        self.view = view
        self.controller = view.controller
        self.target: tuple[str, str, str | None] | None = None   # (element, link, relative_to)
        self.item: CentrodeItem | None = None
        self._built_for = None

    def set_enabled(self, on: bool) -> bool:
        """Show the centrodes of the selected link (a second selected link is the reference);
        returns whether they are shown (False, and a message, when no link is selected)."""
        if not on:
            self.target = None
            self._drop()
            return False
        links = [(el, i) for el, k, i in self.controller.selection if k == "link"]
        if not links:
            self.controller.message.emit("centrodes: select a link first (Shift-click a second link to see them "
                                         "relative to it), then View → Centrodes")
            return False
        el, link = links[0]
        rel = next((i for e, i in links[1:] if e == el and i != link), None)
        lk = self.controller.scene.element(el)
        if link == lk.ground:
            self.controller.message.emit(f"centrodes: {link} is the frame; select a moving link")
            return False
        self.target = (el, link, rel)
        self.refresh()
        if self.item is not None:
            self.controller.message.emit(f"centrodes of {link} relative to {rel or 'the frame'}: "
                                         "fixed (red) and moving (blue), rolling during the animation")
        return self.target is not None

    def _drop(self) -> None:
        if self.item is not None:
            self.view.scene().removeItem(self.item)
            self.item = None
        self._built_for = None

    def centrodes(self) -> Centrodes | None:
        """The core's centrodes of the target (from the linkage's current solution), or None."""
        return self.item.c if self.item is not None else None

    def refresh(self) -> None:
        """Rebuild for a new solution, or move to the displayed frame."""
        if self.target is None:
            return
        el, link, rel = self.target
        ctl = self.controller
        res = ctl.result(el) if el in ctl.scene.ids else None
        lk = ctl.scene.element(el) if res is not None else None
        if lk is None or link not in lk.link_ids or (rel is not None and rel not in lk.link_ids):
            self.target = None
            self._drop()
            return
        sol = res.solution
        if sol is None:
            self._drop()
            return
        if self._built_for is not sol:
            self._drop()
            try:
                c = linkage_centrodes(sol, lk, link, rel)
            except MechsketchError as exc:
                ctl.message.emit(f"centrodes: {exc}")
                self.target = None
                return
            self.item = CentrodeItem(c, lk, default_limit(lk))
            self.view.scene().addItem(self.item)
            self._built_for = sol
        self.item.set_frame(map_frame(self.view.ctx.display_frame(), ctl.sample_count(), len(sol)))

    def set_px(self, px: float) -> None:
        if self.item is not None:
            self.item.update()

    # -- exports ---------------------------------------------------------------------------------
    def export_csv(self, path: str) -> str:
        """Write the centrodes table (input, P, p, valid) as CSV; returns a one-line report."""
        c = self.centrodes()
        if c is None:
            raise MechsketchError("no centrodes shown: select a link and switch View → Centrodes on first")
        write_csv(c.table(), path)
        return f"wrote {path}: {len(c.input)} samples of the centrodes of {c.link}"

    def export_dxf(self, path: str, tolerance: float = 0.01) -> CentrodeExport:
        """Write both centrodes as arc-fitted DXF (see :func:`export_centrodes`)."""
        if self.target is None or self.item is None:
            raise MechsketchError("no centrodes shown: select a link and switch View → Centrodes on first")
        el, link, rel = self.target
        plan = self.controller.workspace.plan(el)
        n = max(720, len(self.item.c.input))
        return export_centrodes(plan, link, rel, path, tolerance, samples=n)

