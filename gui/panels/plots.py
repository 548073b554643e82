"""Kinematic plots of the selected joint or link against the driver's input angle (pyqtgraph).

Four stacked plots sharing the x axis (input angle, °): position (joint x, y in mm; link angle in °),
velocity (vx, vy, |v| in mm/s; ω in rad/s), acceleration (ax, ay, |a| in mm/s²; ε in rad/s²) and the
transmission angle μ (°) of every RRR group. A selected Geneva drive or rolling lever (or the only
element of a scene without linkages) brings its own rows, x axis and table, built in
:mod:`.element_plots`; the records they fill are in :mod:`.plot_series`. Plots read the controller's precomputed solution;
NaN (a pose that cannot be assembled) breaks the line (``connect="finite"``). A vertical cursor
follows the animation frame, and a click on a plot moves the frame there. The plotted data
exports as CSV (a core :class:`Table`) and the plots as a PNG.
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pyqtgraph as pg
from pyqtgraph.exporters import ImageExporter
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QHBoxLayout, QLabel, QToolButton, QVBoxLayout, QWidget

from mechsketch.core import ExportError, MechsketchError
from mechsketch.core.io.atomic import atomic_write
from mechsketch.core.io.table import write_csv
from mechsketch.core.model.linkage import Linkage

from ..controller import SceneController
from .element_plots import element_plot_data
from .force_plots import add_force_series
from .lazy import LazyRefresh
from .plot_series import COLORS, PLOTS, PlotData, Series, in_display_units

pg.setConfigOptions(antialias=True, background="w", foreground="k")   # the app's look (set on import: the
# main window imports this module after its first frame, issue 14)

def _target(controller: SceneController) -> tuple[Linkage, str, str] | None:
    """(linkage, "joint"|"link", id) to plot: the selection, else the last group's inner joint."""
    for eid, kind, ident in controller.selection:
        if eid not in controller.scene.ids:
            continue
        el = controller.scene.element(eid)
        if isinstance(el, Linkage) and ident in (el.joint_ids if kind == "joint" else el.link_ids):
            return el, kind, ident
    for lk in controller.linkages():
        res = controller.result(lk.id)
        if res is not None and res.plan is not None and res.plan.steps:
            return lk, "joint", res.plan.steps[-1].group.inner
        if lk.joints:
            return lk, "joint", lk.joint_ids[-1]
    return None


def plot_data(controller: SceneController) -> PlotData:
    """What to plot for the controller's current selection (pure: reads, never writes)."""
    element = element_plot_data(controller)
    if element is not None:
        return element
    target = _target(controller)
    if target is None:
        return PlotData("nothing to plot: the scene has no linkage")
    lk, kind, ident = target
    res = controller.result(lk.id)
    if res is None or res.solution is None:
        return PlotData(f"{lk.id} is not solved: {res.error if res else 'no result'}")
    sol = res.solution
    if sol.plan.input_unit == "mm":   # an actuator: its length (cylinder) or displacement (slider)
        what = "cylinder length" if str(lk.driver.kind) == "cylinder" else "slider displacement"
        data = PlotData(f"{kind} {ident} of {lk.id}", np.asarray(sol.input, dtype=float),
                        np.asarray(sol.valid, dtype=bool), x_label=f"input: {what} (mm)", x_unit="mm")
    else:
        data = PlotData(f"{kind} {ident} of {lk.id}", np.degrees(sol.input), np.asarray(sol.valid, dtype=bool))
    S = data.series
    try:
        if kind == "joint":
            p, v, a = sol.position(ident), sol.velocity(ident), sol.acceleration(ident)
            S += [Series("position", f"{ident}.x", "mm", p[:, 0]), Series("position", f"{ident}.y", "mm", p[:, 1]),
                  Series("velocity", f"{ident}.vx", "mm/s", v[:, 0]),
                  Series("velocity", f"{ident}.vy", "mm/s", v[:, 1]),
                  Series("velocity", f"|v {ident}|", "mm/s", np.hypot(v[:, 0], v[:, 1])),
                  Series("acceleration", f"{ident}.ax", "mm/s²", a[:, 0]),
                  Series("acceleration", f"{ident}.ay", "mm/s²", a[:, 1]),
                  Series("acceleration", f"|a {ident}|", "mm/s²", np.hypot(a[:, 0], a[:, 1]))]
            data.labels.update(position="position (mm)", velocity="velocity (mm/s)",
                               acceleration="acceleration (mm/s²)")
        elif ident == lk.ground:
            data.title += " (the frame does not move)"
        else:
            S += [Series("position", f"{ident}.angle", "°", np.degrees(sol.angle(ident))),
                  Series("velocity", f"{ident}.ω", "rad/s", sol.omega(ident)),
                  Series("acceleration", f"{ident}.ε", "rad/s²", sol.alpha(ident))]
            data.labels.update(position="angle (°)", velocity="ω (rad/s)", acceleration="ε (rad/s²)")
    except MechsketchError as exc:
        data.title += f" — {exc}"
    for g in sol.groups:
        if g.kind == "RRR":
            S.append(Series("transmission", f"μ {g.name}", "°", np.degrees(sol.transmission_angle(g.name))))
    data.labels["transmission"] = "μ (°)"
    add_force_series(controller, data, lk, kind, ident)
    return data


def robust_range(arrays: list[np.ndarray], tail: float = 0.5) -> tuple[float, float] | None:
    """A y range showing the curves without letting a spike near a toggle (ω, ε → ∞) flatten
    everything else: the full range, or the central 100 − 2·``tail`` percent of the values
    widened by half its span when a few extreme values lie beyond that. None: no finite value."""
    if not arrays:
        return None
    values = np.concatenate([np.asarray(a, dtype=float).ravel() for a in arrays])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return None
    lo, hi = float(values.min()), float(values.max())
    plo, phi = (float(v) for v in np.percentile(values, [tail, 100.0 - tail]))
    span = phi - plo
    if span > 0 and (hi - lo) > 4.0 * span:
        return plo - 0.5 * span, phi + 0.5 * span
    return lo, hi if hi > lo else lo + 1.0


class PlotsPanel(LazyRefresh, QWidget):
    """Docked kinematic plots with a cursor synced to ``controller.frame``."""

    def __init__(self, controller: SceneController, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.title = QLabel()
        self.title.setObjectName("plotTitle")
        self.title.setWordWrap(True)   # a long title wraps rather than widening the dock
        self._header = QHBoxLayout()
        self._header.addWidget(self.title, 1)
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setBackground("w")
        self.plots: dict[str, pg.PlotItem] = {}
        self.cursors: dict[str, pg.InfiniteLine] = {}
        self.curves: dict[str, pg.PlotDataItem] = {}
        self._rows: tuple[tuple[str, str], ...] = ()
        self._build_rows(PLOTS, "input angle (°)")
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(self._header)
        layout.addWidget(self.graphics, 1)
        self.data = PlotData("")
        self._keys: list[tuple[str, str, str]] | None = None
        self._stale = True
        controller.changed.connect(self._invalidate)
        controller.selectionChanged.connect(self._invalidate)
        controller.frameChanged.connect(self._move_cursor)
        self.graphics.scene().sigMouseClicked.connect(self._clicked)
        self.refresh()

    def _build_rows(self, rows: tuple[tuple[str, str], ...], x_label: str) -> None:
        """(Re)make the stacked plots: one per row, sharing the x axis, each with a cursor."""
        self.graphics.clear()
        self.plots.clear()
        self.cursors.clear()
        self.curves.clear()
        self._rows = rows
        first = None
        for row, (name, label) in enumerate(rows):
            plot = self.graphics.addPlot(row=row, col=0)
            plot.showGrid(x=True, y=True, alpha=0.25)
            for axis in ("left", "bottom"):  # major ticks only: the minor grid halves the drag frame rate
                plot.getAxis(axis).setStyle(maxTickLevel=0)
            if rows != PLOTS:  # an element's rows carry their unit in the label: no "(x0.001)" rescaling
                plot.getAxis("left").enableAutoSIPrefix(False)
            plot.setLabel("left", label)
            plot.addLegend(offset=(-10, 5), labelTextSize="8pt", brush=pg.mkBrush(255, 255, 255, 210),
                           pen=pg.mkPen("#ccc"))
            plot.setMenuEnabled(False)
            if first is not None:
                plot.setXLink(first)
            first = first or plot
            cursor = pg.InfiniteLine(angle=90, movable=False, pen=pg.mkPen("#555", width=1, style=pg.QtCore.Qt.PenStyle.DashLine))
            plot.addItem(cursor, ignoreBounds=True)
            self.plots[name], self.cursors[name] = plot, cursor
        self.plots[rows[-1][0]].setLabel("bottom", x_label)

    def add_header_actions(self, actions) -> None:
        """Put buttons for ``actions`` (e.g. Export PNG / CSV) next to the title, labelled short
        ("PNG…", "CSV…": the menu and the tooltip give the full text) so the dock fits a small screen."""
        for action in actions:
            button = QToolButton()
            button.setDefaultAction(action)
            short = "PNG…" if "PNG" in action.text() else "CSV…" if "CSV" in action.text() else None
            if short:
                button.setText(short)
                button.setToolTip(action.text().replace("&", ""))
            self._header.addWidget(button)

    # -- updating ----------------------------------------------------------------------------
    def refresh(self) -> None:
        """Re-read the controller and redraw every curve."""
        self._stale = False
        self.data = data = in_display_units(plot_data(self.controller))   # Edit › Preferences units
        self.title.setText(data.title)
        keys = [(x.plot, x.name, x.unit) for x in data.series]
        if data.rows != self._rows:  # another kind of element: other stacked plots
            self._build_rows(data.rows, data.x_label)
            self._keys = None
        bottom = self.plots[data.rows[-1][0]]
        if bottom.getAxis("bottom").labelText != data.x_label:   # a crank's angle or an actuator's mm
            bottom.setLabel("bottom", data.x_label)
        if keys != self._keys:  # other curves: rebuild them (and the legends)
            self._keys = keys
            for plot in self.plots.values():
                for item in list(plot.listDataItems()):
                    plot.removeItem(item)
            self.curves.clear()
            counts: dict[str, int] = {}
            for s in data.series:
                k = counts.get(s.plot, 0)
                counts[s.plot] = k + 1
                self.curves[s.name] = self.plots[s.plot].plot(
                    data.x if s.x is None else s.x, s.y, pen=pg.mkPen(COLORS[k % len(COLORS)], width=1),
                    name=f"{s.name} ({s.unit})", connect="finite")
            for name, plot in self.plots.items():
                plot.setLabel("left", data.labels.get(name, dict(data.rows)[name]))
        else:  # same curves, new numbers (a drag): only the data changes
            for s in data.series:
                self.curves[s.name].setData(data.x if s.x is None else s.x, s.y, connect="finite")
        ranges: dict[str, list[np.ndarray]] = {}
        for s in data.series:
            ranges.setdefault(s.plot, []).append(s.y)
        for name, plot in self.plots.items():
            lo_hi = robust_range(ranges.get(name, []))
            if lo_hi is None:
                plot.enableAutoRange(axis="y")
            else:
                plot.setYRange(*lo_hi, padding=0.05)
        self._move_cursor(self.controller.frame)

    def _move_cursor(self, frame: int) -> None:
        x = self.data.x if self.data.frame_x is None else self.data.frame_x
        visible = bool(x.size) and 0 <= frame < x.size
        for cursor in self.cursors.values():
            cursor.setVisible(visible)
            if visible:
                cursor.setValue(float(x[frame]))

    def frame_at(self, x: float) -> int | None:
        """The assemblable sample whose input angle (°) is nearest ``x``; None if there is none."""
        data = self.data
        if data.frame_x is not None:
            fin = np.isfinite(data.frame_x)
            return int(np.argmin(np.where(fin, np.abs(data.frame_x - x), np.inf))) if fin.any() else None
        if not data.x.size or not data.valid.any():
            return None
        distance = np.where(data.valid, np.abs(data.x - x), np.inf)
        return int(np.argmin(distance))

    def go_to(self, x: float) -> None:
        """Move the animation frame to the input angle ``x`` (°), as a click on a plot does."""
        frame = self.frame_at(x)
        if frame is not None:
            self.controller.set_frame(frame)

    def _clicked(self, event) -> None:
        if event.button() != Qt.MouseButton.LeftButton:
            return
        for plot in self.plots.values():
            if plot.vb.sceneBoundingRect().contains(event.scenePos()):
                self.go_to(plot.vb.mapSceneToView(event.scenePos()).x())
                return

    def cursor_x(self) -> float:
        """Where the cursor is (input angle, °; or the element's x)."""
        return float(next(iter(self.cursors.values())).value())

    # -- export ------------------------------------------------------------------------------
    def export_csv(self, path: str | os.PathLike) -> None:
        """Write the plotted data as CSV (atomic); raises :class:`ExportError` naming the path."""
        write_csv(self.data.table(), path)

    def export_png(self, path: str | os.PathLike, width: int = 1200) -> None:
        """Write the plots as a PNG image (atomic); raises :class:`ExportError` naming the path."""
        self.refresh_if_stale()
        target = Path(path)
        exporter = ImageExporter(self.graphics.scene())
        exporter.parameters()["width"] = int(width)
        image = exporter.export(toBytes=True)
        if image is None:
            raise ExportError(f"cannot write {target}: the image could not be encoded")

        def write(tmp: str) -> None:
            if not image.save(tmp, "PNG"):
                raise OSError("the image could not be encoded")
        atomic_write(target, write)   # keeps an overwritten file's mode, writes through a symlink
