"""The Study and Design docks of the main window, and their wiring to the canvas (issues 21, 22, 25).

The docks sit on the right, tabbed with the plots (View › Study, View › Design). Their panels
never import the canvas: what they want drawn goes out as signals, connected here to the canvas's
:class:`~mechsketch.gui.canvas.design_layer.DesignLayer` (the tolerance band, the synthesis
target, the animated preview of a candidate or a study variant). The Design dock's target is
picked on the canvas through :class:`TargetSession`, an event filter on the canvas that reads
clicks (one point each, snapped like every tool; for poses press at the point and drag along the
angle), a freehand stroke (resampled evenly along its length), or a click on an underlay's
polyline; Enter or a double click ends it, Esc cancels, Backspace removes the last point.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from PySide6.QtCore import QEvent, QObject, Qt
from PySide6.QtWidgets import QDockWidget, QMainWindow

from .panels.design_panel import DesignPanel
from .panels.study_panel import StudyPanel
from .qtsafe import qt_safe

XY = tuple[float, float]
#: points a freehand stroke or an underlay polyline is resampled to
STROKE_POINTS = 40
#: a stroke whose end comes back within this fraction of its length of its start is closed
CLOSE_FRACTION = 0.08


def resample(points: np.ndarray, n: int = STROKE_POINTS, closed: bool = False) -> np.ndarray:
    """``n`` points evenly spaced along the polyline ``points`` (M, 2) mm (a closed one: around the
    loop, the first point not repeated)."""
    pts = np.asarray(points, dtype=float)
    if closed:
        pts = np.vstack([pts, pts[:1]])
    seg = np.hypot(*np.diff(pts, axis=0).T)
    keep = np.concatenate(([True], seg > 1e-12))
    pts = pts[keep]
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))))
    if len(pts) < 2 or s[-1] <= 0:
        return pts[:1]
    t = np.linspace(0.0, s[-1], n, endpoint=not closed)
    return np.column_stack([np.interp(t, s, pts[:, 0]), np.interp(t, s, pts[:, 1])])


def stroke_target(points: list[XY]) -> tuple[np.ndarray, bool]:
    """A freehand stroke as a path target: evenly resampled, closed if it ends near its start."""
    pts = np.asarray(points, dtype=float)
    length = float(np.sum(np.hypot(*np.diff(pts, axis=0).T))) if len(pts) > 1 else 0.0
    closed = length > 0 and math.dist(pts[0], pts[-1]) <= CLOSE_FRACTION * length
    return resample(pts, STROKE_POINTS, closed), closed


@qt_safe
class TargetSession(QObject):
    """Reads a target from the canvas for the Design dock until it ends (see the module docstring).

    ``mode``: "click" (points of a path), "poses" (press at a point, release along its angle),
    "draw" (a freehand stroke) or "underlay" (click an underlay's polyline). ``on_points(points,
    angles, pending)`` gets what is placed so far (angles None for a path; ``pending`` the point under
    the pointer); ``on_end(keep)`` when it ends (then :attr:`points`, :attr:`angles`,
    :attr:`closed` hold the target)."""

    def __init__(self, view, mode: str, on_points, on_end) -> None:
        super().__init__(view)
        self.view, self.mode, self.on_points, self.on_end = view, mode, on_points, on_end
        self.points: list[XY] = []
        self.angles: list[float] = []
        self.pressed: XY | None = None
        self.stroke: list[XY] = []
        self.closed: bool | None = None
        view.viewport().installEventFilter(self)
        view.installEventFilter(self)

    def end(self, keep: bool = True) -> None:
        """Stop reading the canvas; ``keep``: hand the points over as the target."""
        self.view.viewport().removeEventFilter(self)
        self.view.removeEventFilter(self)
        self.on_end(keep)
        self.deleteLater()

    def _world(self, event, snap: bool = True) -> XY:
        p = self.view.mapToScene(event.position().toPoint())
        raw = (p.x(), p.y())
        return self.view.snap(raw) if snap else raw

    def _show(self, pending: XY | None = None) -> None:
        angles = list(self.angles) if self.mode == "poses" else None
        self.on_points(np.asarray(self.points, dtype=float).reshape(-1, 2), angles, pending)

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt override
        kind = event.type()
        if kind == QEvent.Type.KeyPress:
            return self._key(event.key())
        if obj is not self.view.viewport():
            return False
        left = getattr(event, "button", lambda: None)() == Qt.MouseButton.LeftButton
        if kind == QEvent.Type.MouseButtonPress and left:
            self._press(event)
            return True
        if kind == QEvent.Type.MouseMove:
            return self._move(event)
        if kind == QEvent.Type.MouseButtonRelease and left:
            self._release(event)
            return True
        if kind == QEvent.Type.MouseButtonDblClick:
            if self.mode in ("click", "poses") and self.points:
                self.end(True)
            return True
        return False

    def _key(self, key) -> bool:
        if key == Qt.Key.Key_Escape:
            self.end(False)
            return True
        if key in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
            self.end(bool(self.points))
            return True
        if key == Qt.Key.Key_Backspace and self.points:
            self.points.pop()
            if self.angles:
                self.angles.pop()
            self._show()
            return True
        return False

    def _press(self, event) -> None:
        if self.mode == "draw":
            self.stroke = [self._world(event, snap=False)]
        elif self.mode == "underlay":
            self._pick_underlay(self._world(event, snap=False))
        else:
            self.pressed = self._world(event)

    def _move(self, event) -> bool:
        if self.mode == "draw" and self.stroke:
            self.stroke.append(self._world(event, snap=False))
            self.on_points(np.asarray(self.stroke), None, None)
            return True
        if self.mode == "poses" and self.pressed is not None:
            tip = self._world(event, snap=False)
            angle = math.degrees(math.atan2(tip[1] - self.pressed[1], tip[0] - self.pressed[0]))
            self.on_points(np.asarray(self.points + [self.pressed]), self.angles + [angle], None)
            return True
        if self.mode == "click":
            self._show(pending=self._world(event))
        return False

    def _release(self, event) -> None:
        if self.mode == "draw" and self.stroke:
            self.stroke.append(self._world(event, snap=False))
            if len(self.stroke) >= 3:
                pts, closed = stroke_target(self.stroke)
                self.points = [tuple(p) for p in pts]
                self.closed = closed
                self.end(True)
            return
        if self.pressed is None:
            return
        at, self.pressed = self.pressed, None
        self.points.append(at)
        if self.mode == "poses":
            tip = self._world(event, snap=False)
            far = math.dist(tip, at) > 4.0 * self.view.px()
            self.angles.append(math.degrees(math.atan2(tip[1] - at[1], tip[0] - at[0])) if far else 0.0)
        self._show()

    def _pick_underlay(self, world: XY) -> None:
        """The underlay polyline nearest the click becomes the target (resampled)."""
        best, best_d = None, 12.0 * self.view.px()
        for item in self.view.underlays.items.values():
            u = item.underlay
            if not item.isVisible() or u is None or u.image is not None:
                continue
            for path in u.world_paths():
                pts = np.asarray(path, dtype=float)
                if len(pts) < 2:
                    continue
                d = float(np.min(np.hypot(pts[:, 0] - world[0], pts[:, 1] - world[1])))
                d = min(d, _polyline_distance(pts, world))
                if d < best_d:
                    best, best_d = pts, d
        if best is None:
            self.view.controller.message.emit("no underlay polyline there: click on a line of a visible underlay")
            return
        closed = len(best) > 2 and math.dist(best[0], best[-1]) <= 1e-6 * max(np.ptp(best, axis=0).max(), 1.0)
        pts = resample(best[:-1] if closed else best, STROKE_POINTS, closed)
        self.points = [tuple(p) for p in pts]
        self.closed = closed
        self.end(True)


def _polyline_distance(pts: np.ndarray, p: XY) -> float:
    """Distance (mm) from ``p`` to the polyline ``pts`` (M, 2)."""
    a, b = pts[:-1], pts[1:]
    d = b - a
    L2 = np.maximum((d * d).sum(axis=1), 1e-300)
    t = np.clip(((np.asarray(p) - a) * d).sum(axis=1) / L2, 0.0, 1.0)
    q = a + t[:, None] * d
    return float(np.min(np.hypot(q[:, 0] - p[0], q[:, 1] - p[1])))


class DesignDocks(QObject):
    """Makes the Study and Design docks of ``window``, adds them to ``docks`` (the window's, by
    name) tabbed with its plots, and wires them to its canvas."""

    def __init__(self, window: QMainWindow, docks: dict[str, QDockWidget]) -> None:
        super().__init__(window)
        self.window = window
        self.controller = window.controller
        self.layer = getattr(window.canvas, "design_layer", None)   # None with stand-in components
        self.study = StudyPanel(self.controller)
        self.design = DesignPanel(self.controller, self._ask_csv)
        self.docks: dict[str, QDockWidget] = {"study": self._dock("Study", self.study),
                                              "design": self._dock("Design", self.design)}
        self.session: TargetSession | None = None
        self.docks["study"].visibilityChanged.connect(self.study.set_on_screen)
        self.study.bandChanged.connect(self._band)
        self.study.previewChanged.connect(self._preview)
        self.design.previewChanged.connect(self._preview)
        self.design.targetChanged.connect(self._target)
        self.design.targetRequested.connect(self.pick_target)
        self.controller.documentReplaced.connect(self.stop_picking)
        docks.update(self.docks)
        if "plots" in docks:
            self.tabify(docks["plots"])

    def _dock(self, title: str, widget) -> QDockWidget:
        dock = QDockWidget(title, self.window)
        dock.setObjectName(f"dock:{title}")
        dock.setWidget(widget)
        self.window.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, dock)
        return dock

    def tabify(self, beside: QDockWidget) -> None:
        """Tab the docks with ``beside`` (the plots), which stays in front."""
        for dock in self.docks.values():
            self.window.tabifyDockWidget(beside, dock)
        beside.raise_()

    def _ask_csv(self) -> str | None:
        start = str(self.controller.path.parent) if self.controller.path else ""
        return self.window.dialogs.open_file_name("Read the target from CSV", start, "CSV files (*.csv);;All files (*)")

    # -- the target from the canvas ------------------------------------------------------------
    def pick_target(self, mode: str) -> bool:
        """Read the Design dock's target from the canvas (``mode``: see :class:`TargetSession`)."""
        self.stop_picking()
        view = self.window.canvas
        if self.layer is None or not hasattr(view, "viewport"):
            return False
        if mode == "underlay" and not any(it.isVisible() for it in view.underlays.items.values()):
            self.controller.message.emit("no visible underlay: File › Import Underlay… first (or show them)")
            return False
        view.cancel_tool()
        self.session = TargetSession(view, mode, self.design.target_placing, self._picked)
        view.setFocus()
        return True

    def _picked(self, keep: bool) -> None:
        session, self.session = self.session, None
        if session is None:
            return
        if keep and session.points:
            self.design.target_picked(np.asarray(session.points, dtype=float),
                                      session.angles if session.mode == "poses" else None, session.closed)
        else:
            self.design.target_cancelled()

    def stop_picking(self) -> None:
        """End a target being picked on the canvas, keeping the table as it was."""
        if self.session is not None:
            self.session.end(False)

    def _target(self, target: dict | None) -> None:
        if self.layer is not None:
            self.layer.set_target(target)

    def _band(self, band: dict | None) -> None:
        if self.layer is not None:
            self.layer.set_band(band)

    def _preview(self, linkage: Any) -> None:
        if self.layer is not None:
            self.layer.set_preview(linkage)

    def shutdown(self) -> None:
        """The window closes: stop the preview, cancel and wait for running work."""
        self.stop_picking()
        if self.layer is not None:
            self.layer.stop()
        self.study.shutdown()
        self.design.shutdown()


__all__ = ["DesignDocks", "TargetSession", "resample", "stroke_target"]
