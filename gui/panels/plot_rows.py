"""One row of the plots panel: a legend line above a plot, made once and re-used for ever.

A :class:`PlotRow` is a small widget: a rich-text legend (the curves' colours and names, with
their values at the read-out point) above a pyqtgraph plot at a readable height, with a dashed
cursor line. Its curves come from a pool that only grows: a curve no longer needed is emptied
and hidden, never deleted. The panel keeps every row it ever made, so no Qt object of the plots
is deleted while the panel lives: a pending pyqtgraph update (auto-range, hover, paint) never
meets a deleted plot (issue 20, item 9).
"""
from __future__ import annotations

import html
import math
from dataclasses import dataclass

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtGui import QFontMetrics
from PySide6.QtWidgets import QLabel, QSizePolicy, QVBoxLayout, QWidget

from ..qtsafe import qt_safe

#: the least height of a plot (px): tick labels, the axis title and the curves stay readable;
#: the panel's column scrolls rather than squeezing the plots below it
ROW_HEIGHT = 170
COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


@dataclass(frozen=True)
class Curve:
    """One curve to draw in a row: ``name`` (unique in the panel), ``unit``, x and y (N,)."""

    name: str
    unit: str
    x: np.ndarray
    y: np.ndarray


def _nowrap(text: str) -> str:
    """``text`` escaped for the legend with no place to break a line: its spaces non-breaking, a
    word joiner (U+2060) after each "|" and "/" (Unicode lets a line break after them: "|v C|",
    "mm/s" were split)."""
    return html.escape(text).replace(" ", "&nbsp;").replace("|", "|\u2060").replace("/", "/\u2060")


def _value_text(v: float) -> str:
    return "—" if not np.isfinite(v) else f"{v:.5g}"


@qt_safe
class PlotRow(QWidget):
    """A legend line above one plot; see the module docstring. ``plot`` is the PlotItem,
    ``cursor`` its InfiniteLine, ``curves`` name -> the PlotDataItem drawing it now."""

    def __init__(self, name: str, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.name = name
        self.setObjectName(f"plotRow:{name}")
        self.legend = QLabel()
        self.legend.setObjectName("plotLegend")
        self.legend.setTextFormat(Qt.TextFormat.RichText)
        self.legend.setWordWrap(True)
        policy = QSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Fixed)
        policy.setHeightForWidth(False)   # its height is set by fit_legend: the column's layout
        self.legend.setSizePolicy(policy)  # then gives each row what its lines and plot take
        self.widget = pg.PlotWidget(background="w")
        self.widget.setMinimumHeight(ROW_HEIGHT)
        # its size hint (640 x 480) is not a wish: each plot takes ROW_HEIGHT and shares what is left
        self.widget.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Ignored)
        self.plot: pg.PlotItem = self.widget.getPlotItem()
        self.plot.showGrid(x=True, y=True, alpha=0.25)
        for axis in ("left", "bottom"):   # major ticks only: the minor grid halves the drag frame rate
            self.plot.getAxis(axis).setStyle(maxTickLevel=0)
        self.plot.setMenuEnabled(False)
        self.plot.hideButtons()
        self.cursor = pg.InfiniteLine(angle=90, movable=False,
                                      pen=pg.mkPen("#555", width=1, style=Qt.PenStyle.DashLine))
        self.plot.addItem(self.cursor, ignoreBounds=True)
        self._pool: list[pg.PlotDataItem] = []
        self.curves: dict[str, pg.PlotDataItem] = {}
        self._shown: list[Curve] = []
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 2, 0, 2)
        layout.setSpacing(0)
        layout.addWidget(self.legend)
        layout.addWidget(self.widget, 1)

    # -- curves ------------------------------------------------------------------------------
    def set_curves(self, curves: list[Curve]) -> None:
        """Draw ``curves`` (the pool's first items take them, in order; the rest are emptied)."""
        same_names = [c.name for c in curves] == [c.name for c in self._shown]
        self.curves = {}
        for k, c in enumerate(curves):
            if k == len(self._pool):
                item = pg.PlotDataItem()
                self.plot.addItem(item)
                self._pool.append(item)
            item = self._pool[k]
            if not same_names:
                item.setPen(pg.mkPen(COLORS[k % len(COLORS)], width=1))
            item.setData(c.x, c.y, connect="finite")
            item.setVisible(True)
            self.curves[c.name] = item
        for item in self._pool[len(curves):]:
            if item.isVisible():
                item.setData([], [])
                item.setVisible(False)
        self._shown = list(curves)

    def set_labels(self, y_label: str, x_label: str, last: bool, si_prefix: bool) -> None:
        """The y-axis title; the x-axis title (shown on the last row only)."""
        left, bottom = self.plot.getAxis("left"), self.plot.getAxis("bottom")
        if left.autoSIPrefix != si_prefix:   # (each call re-renders the axis title)
            left.enableAutoSIPrefix(si_prefix)
        if left.labelText != y_label:
            self.plot.setLabel("left", y_label)
        if bottom.labelText != x_label:
            self.plot.setLabel("bottom", x_label)
        if bottom.label.isVisible() != last:
            bottom.showLabel(last)

    # -- legend and read-out ------------------------------------------------------------------
    def show_legend(self, at: float | None = None, x_text: str = "") -> None:
        """The legend line: each curve's colour, name and unit; with ``at`` (an x value), each
        curve's value there (the nearest sample of its own x), after ``x_text``."""
        parts = []
        for k, c in enumerate(self._shown):
            swatch = f'<span style="color:{COLORS[k % len(COLORS)]}">&#9632;</span>'
            text = f"{swatch}&nbsp;{_nowrap(c.name)}"
            if at is not None and c.x.size:
                i = int(np.nanargmin(np.abs(c.x - at))) if np.isfinite(c.x).any() else 0
                text += f"&nbsp;=&nbsp;{_value_text(float(c.y[i]))}"
            parts.append(f"{text}&nbsp;{_nowrap(c.unit)}")
        lead = f"<b>{_nowrap(x_text)}</b>&nbsp;&nbsp; " if at is not None and x_text else ""
        # a line may break between entries only ("|v C| = 176 mm/s" stays one piece)
        self.legend.setText(lead + "&nbsp;&nbsp; ".join(parts))
        self.fit_legend()

    def fit_legend(self) -> None:
        """Give the legend the height its lines take at its width, so that a legend wrapped onto
        a second line pushes its plot down (the row grows) instead of cutting the plot's tick
        labels off at the row's bottom (issue 24 item 6)."""
        need = self.legend.heightForWidth(max(1, self.legend.width()))
        if need > 0 and need != self.legend.minimumHeight():
            self.legend.setFixedHeight(need)
            top, bottom = self.layout().contentsMargins().top(), self.layout().contentsMargins().bottom()
            self.setMinimumHeight(need + ROW_HEIGHT + top + bottom)   # the column's layout reads it now

    def resizeEvent(self, event) -> None:  # noqa: N802 - Qt override
        super().resizeEvent(event)
        self.fit_legend()   # another width wraps the legend onto another number of lines


def align_left_axes(rows: list[PlotRow]) -> None:
    """Give every row's left axis one width, that of the longest tick label (at the y range each
    has now) plus the title: the plots then span the same pixels and their linked x range is the
    same. With widths of their own pyqtgraph aligned the linked plots pixel by pixel, and a plot
    whose tick labels were wider ("-5000") lost the start of its data off its left edge."""
    widths = []
    for row in rows:
        ax = row.plot.getAxis("left")
        font = ax.style["tickFont"] or ax.font()
        metrics = QFontMetrics(font)
        lo, hi = ax.range
        levels = ax.tickValues(lo, hi, max(ax.size().height(), ROW_HEIGHT))[: ax.style["maxTickLevel"] + 1]
        texts = [t for spacing, values in levels for t in ax.tickStrings(values, ax.scale, spacing)]
        text = max((metrics.boundingRect(t).width() for t in texts if t), default=metrics.horizontalAdvance("0.0"))
        label = ax.label.boundingRect().height() * 0.8 if ax.label.isVisible() else 0.0
        widths.append(text + 4 + ax.style["tickTextOffset"][0] + max(0, ax.style["tickLength"]) + label)
    width = math.ceil(max(widths, default=0.0))
    for row in rows:
        ax = row.plot.getAxis("left")
        if ax.fixedWidth != width:
            ax.setWidth(width)
