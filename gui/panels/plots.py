"""The plots dock: the selected joint's or link's kinematics against the driver's input (pyqtgraph).

A column of plots sharing the x axis (the input angle, °, or an actuator's mm): for a linkage
position (joint x, y in mm; link angle in °), velocity, acceleration and the transmission angle μ
of every RRR group, with the driving torque and a joint's reaction below when the linkage has
loads (:mod:`.linkage_plots`, :mod:`.force_plots`); a selected Geneva drive or rolling lever (or
the only element of a scene without linkages) brings its own rows, x axis and table
(:mod:`.element_plots`). NaN (a pose that cannot be assembled) breaks the line
(``connect="finite"``). Each plot keeps a readable height and the column scrolls; the legend of
each plot is a line above its data. A dashed cursor follows the animation frame, and a click on a
plot moves the frame there. The plotted data exports as CSV (a core :class:`Table`) and the plots
as one PNG.

Every plot row is made once and kept (:mod:`.plot_rows`): changing what is plotted shows, hides
and re-fills rows, it never deletes a Qt object a pending redraw could still hold (issue 20,
item 9).
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pyqtgraph as pg
from pyqtgraph.exporters import ImageExporter
from PySide6.QtCore import QRectF, QSettings, QSize, Qt
from PySide6.QtGui import QAction, QColor, QImage, QPainter, QTextDocument
from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QMenu, QScrollArea, QToolButton, QVBoxLayout, QWidget

from mechsketch.core import ExportError
from mechsketch.core.io.atomic import atomic_write
from mechsketch.core.io.table import write_csv

from ..controller import SceneController
from ..qtsafe import guard_library, qt_safe
from .lazy import LazyRefresh
from .linkage_plots import plot_data, robust_range  # noqa: F401 - re-exported
from .plot_rows import Curve, PlotRow, align_left_axes
from .plot_series import PLOTS, PlotData, in_display_units

pg.setConfigOptions(antialias=True, background="w", foreground="k")   # the app's look (set on import: the
# main window imports this module after its first frame, issue 14)
guard_library("pyqtgraph")   # an error in a pyqtgraph override is reported, not a segfault (qtsafe.py)

#: the panel's size hint (px): the main window's stand-in asks for the same before it is made
SIZE_HINT = (604, 511)


@qt_safe
class PlotsPanel(LazyRefresh, QWidget):
    """Docked plots with a cursor synced to ``controller.frame``.

    ``plots`` (row name -> PlotItem), ``cursors`` (row name -> InfiniteLine) and ``curves``
    (curve name -> PlotDataItem) describe what is shown now; ``rows`` keeps every row made.
    """

    def __init__(self, controller: SceneController, parent: QWidget | None = None,
                 settings: QSettings | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.settings = settings
        self.title = QLabel()
        self.title.setObjectName("plotTitle")
        self.title.setWordWrap(True)   # a long title wraps rather than widening the dock
        self.title.setMinimumWidth(1)   # and a long element id (one word) is cut, not the dock widened
        self.chooser = QToolButton()
        self.chooser.setObjectName("plotChooser")
        self.chooser.setText("Plots")
        self.chooser.setToolTip("Choose the plots to show (remembered for each kind of element)")
        self.chooser.setPopupMode(QToolButton.ToolButtonPopupMode.InstantPopup)
        self.chooser_menu = QMenu(self.chooser)
        self.chooser.setMenu(self.chooser_menu)
        self._choices: dict[str, QAction] = {}
        self._hidden_here: dict[str, list[str]] = {}   # the choices, without a settings file
        self._hover_x: float | None = None
        self._header = QHBoxLayout()
        self._header.addWidget(self.title, 1)
        self._header.addWidget(self.chooser)
        self.column = QWidget()
        self.column.setObjectName("plotColumn")
        self._column = QVBoxLayout(self.column)
        self._column.setContentsMargins(0, 0, 0, 0)
        self._column.setSpacing(4)
        self.scroll = QScrollArea()
        self.scroll.setObjectName("plotScroll")
        self.scroll.setWidgetResizable(True)
        self.scroll.setFrameShape(QFrame.Shape.NoFrame)
        self.scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.scroll.setWidget(self.column)
        self.rows: dict[str, PlotRow] = {}
        self.plots: dict[str, pg.PlotItem] = {}
        self.cursors: dict[str, pg.InfiniteLine] = {}
        self.curves: dict[str, pg.PlotDataItem] = {}
        self._rows: tuple[tuple[str, str], ...] = ()
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(self._header)
        layout.addWidget(self.scroll, 1)
        self.data = PlotData("")
        self._stale = True
        self._show_rows(PLOTS)
        controller.changed.connect(self._invalidate)
        controller.selectionChanged.connect(self._invalidate)
        controller.frameChanged.connect(self._move_cursor)
        self.refresh()

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt override
        """The width the dock asks for at first (the plots themselves take any width)."""
        return QSize(*SIZE_HINT)

    # -- rows ------------------------------------------------------------------------------------
    def _row(self, name: str) -> PlotRow:
        row = self.rows.get(name)
        if row is None:
            row = self.rows[name] = PlotRow(name)
            row.widget.scene().sigMouseClicked.connect(lambda ev, r=row: self._clicked(r, ev))
            row.widget.scene().sigMouseMoved.connect(lambda pos, r=row: self._hovered(r, pos))
            row.hide()
        return row

    # -- which plots show (remembered per kind of element) ---------------------------------------
    def hidden(self, kind: str) -> set[str]:
        """The plots the user switched off for elements of ``kind``."""
        if self.settings is None:
            return set(self._hidden_here.get(kind, ()))
        value = self.settings.value(f"plots/hidden/{kind}", "")
        return {v for v in (value if isinstance(value, list) else str(value).split(",")) if v}

    def set_shown(self, name: str, on: bool, kind: str | None = None) -> None:
        """Show (or hide) the plot ``name`` for elements of ``kind`` (default: the kind plotted
        now); remembered in the settings. The last shown plot cannot be hidden."""
        kind = kind or self.data.kind
        hidden = self.hidden(kind)
        hidden.discard(name) if on else hidden.add(name)
        if all(n in hidden for n, _ in self.data.rows) and kind == self.data.kind:
            hidden.discard(name)   # keep one plot: an empty dock says nothing
        if self.settings is None:
            self._hidden_here[kind] = sorted(hidden)
        else:
            self.settings.setValue(f"plots/hidden/{kind}", ",".join(sorted(hidden)))
        self.refresh()

    def _fill_chooser(self, data: PlotData) -> None:
        hidden = self.hidden(data.kind)
        names = [(n, label) for n, label in data.rows]
        if [a.data() for a in self._choices.values()] != [n for n, _ in names]:
            self.chooser_menu.clear()
            self._choices = {}
            for name, label in names:
                act = self.chooser_menu.addAction(label)
                act.setCheckable(True)
                act.setData(name)
                act.toggled.connect(lambda on, n=name: self.set_shown(n, on))
                self._choices[name] = act
        for name, act in self._choices.items():
            if act.isChecked() != (name not in hidden):
                act.blockSignals(True)
                act.setChecked(name not in hidden)
                act.blockSignals(False)

    def _show_rows(self, rows: tuple[tuple[str, str], ...]) -> None:
        """Show the rows ``rows`` (name, default y label), top to bottom, sharing their x axis;
        hide the others (kept for later)."""
        self._rows = rows
        names = [name for name, _ in rows]
        for row in self.rows.values():
            if row.name not in names:
                row.hide()
                row.plot.setXLink(None)
        first = None
        for k, name in enumerate(names):
            row = self._row(name)
            if self._column.indexOf(row) != k:
                self._column.removeWidget(row)
                self._column.insertWidget(k, row, 1)
            row.show()
            row.plot.setXLink(first)
            first = first or row.plot
        self.plots = {name: self.rows[name].plot for name in names}
        self.cursors = {name: self.rows[name].cursor for name in names}

    def shown_rows(self) -> list[PlotRow]:
        """The rows shown now, top to bottom."""
        return [self.rows[name] for name, _ in self._rows]

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
        self._fill_chooser(data)
        hidden = self.hidden(data.kind)
        rows = tuple(r for r in data.rows if r[0] not in hidden) or data.rows[:1]
        if rows != self._rows:  # another kind of element, or another choice: other plots
            self._show_rows(rows)
        by_row: dict[str, list[Curve]] = {name: [] for name, _ in data.rows}
        for s in data.series:
            by_row[s.plot].append(Curve(s.name, s.unit, data.x if s.x is None else s.x, s.y))
        defaults = dict(data.rows)
        rows = self.shown_rows()
        self._hover_x = None
        self.curves = {}
        for k, row in enumerate(rows):
            row.set_curves(by_row[row.name])
            self.curves.update(row.curves)
            row.set_labels(data.labels.get(row.name, defaults[row.name]), data.x_label,
                           last=k == len(rows) - 1, si_prefix=data.rows == PLOTS)
            lo_hi = robust_range([c.y for c in by_row[row.name]])
            if lo_hi is None:
                row.plot.enableAutoRange(axis="y")
            else:
                row.plot.setYRange(*lo_hi, padding=0.05)
        align_left_axes(rows)
        self._show_values()
        if data.x.size and np.isfinite(data.x).any():
            rows[0].plot.setXRange(float(np.nanmin(data.x)), float(np.nanmax(data.x)), padding=0.02)
        else:   # nothing to plot (New): one turn, not the axes of the document before
            for row in rows:
                row.plot.setXRange(0.0, 360.0, padding=0.02)
                row.plot.setYRange(0.0, 1.0, padding=0.02)
        self._move_cursor(self.controller.frame)

    def _move_cursor(self, frame: int) -> None:
        x = self.data.x if self.data.frame_x is None else self.data.frame_x
        visible = bool(x.size) and 0 <= frame < x.size
        for cursor in self.cursors.values():
            cursor.setVisible(visible)
            if visible:
                cursor.setValue(float(x[frame]))
        if self._hover_x is None:
            self._show_values()   # the legends read the curves at the animation cursor

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

    def _clicked(self, row: PlotRow, event) -> None:
        if event.button() != Qt.MouseButton.LeftButton or not row.isVisible():
            return
        vb = row.plot.vb
        if vb.sceneBoundingRect().contains(event.scenePos()):
            self.go_to(vb.mapSceneToView(event.scenePos()).x())

    def _hovered(self, row: PlotRow, pos) -> None:
        """The pointer over a plot: every plot's legend reads its curves at that input."""
        vb = row.plot.vb
        if row.isVisible() and vb.sceneBoundingRect().contains(pos):
            self.read_out(vb.mapSceneToView(pos).x())
        elif self._hover_x is not None:
            self.read_out(None)   # off the data (on an axis): back to the animation cursor

    def read_out(self, x: float | None) -> None:
        """Show every curve's value at the input ``x`` in the legends (None: at the animation
        cursor)."""
        self._hover_x = x
        self._show_values()

    def _show_values(self) -> None:
        x = self._hover_x
        if x is None:
            frame_x = self.data.x if self.data.frame_x is None else self.data.frame_x
            f = self.controller.frame
            x = float(frame_x[f]) if 0 <= f < frame_x.size else None
        unit = {"deg": "°"}.get(self.data.x_unit, self.data.x_unit)   # °, rad, mm or in
        for row in self.shown_rows():
            row.show_legend(x, f"at {x:.4g} {unit}:" if x is not None else "")

    def cursor_x(self) -> float:
        """Where the cursor is (input angle, °; or the element's x)."""
        return float(next(iter(self.cursors.values())).value())

    # -- export ------------------------------------------------------------------------------
    def export_csv(self, path: str | os.PathLike) -> None:
        """Write the plotted data as CSV (atomic); raises :class:`ExportError` naming the path."""
        write_csv(self.data.table(), path)

    def render_image(self, width: int = 1200) -> QImage:
        """The title, then each shown plot under its legend line, ``width`` px wide."""
        self.refresh_if_stale()
        parts: list[QImage] = [_text_image(f"<b>{self.data.title}</b>", width)]
        for row in self.shown_rows():
            parts.append(_text_image(row.legend.text(), width))
            exporter = ImageExporter(row.plot)
            exporter.parameters()["width"] = int(width)
            image = exporter.export(toBytes=True)
            if image is None:
                raise ExportError("the plots could not be drawn into an image")
            parts.append(image)
        out = QImage(width, sum(p.height() for p in parts), QImage.Format.Format_ARGB32)
        out.fill(QColor("white"))
        painter = QPainter(out)
        y = 0
        for p in parts:
            painter.drawImage(0, y, p)
            y += p.height()
        painter.end()
        return out

    def export_png(self, path: str | os.PathLike, width: int = 1200) -> None:
        """Write the plots as a PNG image (atomic); raises :class:`ExportError` naming the path."""
        target = Path(path)
        image = self.render_image(width)

        def write(tmp: str) -> None:
            if not image.save(tmp, "PNG"):
                raise OSError("the image could not be encoded")
        atomic_write(target, write)   # keeps an overwritten file's mode, writes through a symlink


def _text_image(rich: str, width: int) -> QImage:
    """``rich`` text laid out ``width`` px wide on white."""
    doc = QTextDocument()
    doc.setHtml(rich)
    doc.setTextWidth(width - 16)
    image = QImage(width, int(doc.size().height()) + 8, QImage.Format.Format_ARGB32)
    image.fill(QColor("white"))
    painter = QPainter(image)
    painter.translate(8, 4)
    doc.drawContents(painter, QRectF(0, 0, width - 16, doc.size().height()))
    painter.end()
    return image
