"""The Study dock's results (pyqtgraph, made on the first result): the histogram of the deviation
of the traced point over the builds, the sensitivity bars (each variable's and pin's share of the
first-order variance), and for an optimisation the Pareto front as a scatter whose points can be
clicked (``pointPicked(int)``: the index into the front, best first by the first objective).

Only :mod:`.study_panel` imports this module, when a study has finished, so the app's first frame
does not wait for pyqtgraph.
"""
from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QLabel, QVBoxLayout, QWidget

from ..qtsafe import guard_library

pg.setConfigOptions(antialias=True, background="w", foreground="k")
guard_library("pyqtgraph")

BAR = QColor("#4f7cc0")
FRONT = QColor("#1f5fbf")
CHOSEN = QColor("#ff8f00")
OTHERS = QColor(150, 150, 150, 120)
BINS = 40


def _plot(title: str, x: str, y: str, height: int = 170) -> pg.PlotWidget:
    w = pg.PlotWidget()
    w.setMinimumHeight(height)
    w.setMaximumHeight(height + 60)
    item = w.getPlotItem()
    item.setTitle(title, size="9pt")
    item.setLabel("bottom", x)
    item.setLabel("left", y)
    item.showGrid(x=True, y=True, alpha=0.2)
    w.setMenuEnabled(False)
    return w


def short_key(key: str) -> str:
    """A variable's key as a bar label: ``length:crank:A:B`` -> ``crank A–B``, ``clearance:B`` ->
    ``pin B (fit)``, ``x:D`` -> ``D x``."""
    p = key.split(":")
    if p[0] == "length" and len(p) == 4:
        return f"{p[1]} {p[2]}–{p[3]}"
    if p[0] == "angle" and len(p) == 5:
        return f"{p[1]} ∠{p[3]}{p[2]}{p[4]}"
    if p[0] == "clearance":
        return f"pin {p[1]} (fit)"
    if p[0] in ("x", "y") and len(p) == 2:
        return f"{p[1]} {p[0]}"
    return key


class ToleranceView(QWidget):
    """Histogram of the deviation and the sensitivity bars of one tolerance run."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        lay = QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.histogram = _plot("deviation over the builds", "largest deviation over the cycle (mm)", "builds")
        self.histogram.setObjectName("studyHistogram")
        self.sensitivity = _plot("sensitivity (first-order share of the variance)", "share (%)", "")
        self.sensitivity.setObjectName("studySensitivity")
        lay.addWidget(self.histogram)
        lay.addWidget(self.sensitivity)
        self.counts = np.zeros(0)
        self.edges = np.zeros(0)
        self.shares: list[tuple[str, float]] = []

    def show_result(self, deviation: np.ndarray, marks: dict[str, float], shares: dict[str, float],
                    joint: str) -> None:
        """``deviation`` (B,) mm (inf: a build that fails), ``marks`` label -> mm drawn as lines,
        ``shares`` key -> share (sum 1)."""
        fin = deviation[np.isfinite(deviation)]
        hp = self.histogram.getPlotItem()
        hp.clear()
        hp.setTitle(f"largest deviation of {joint} over {len(deviation):,} builds", size="9pt")
        if fin.size:
            lo, hi = float(fin.min()), float(fin.max())
            if hi <= lo:
                hi = lo + max(abs(lo), 1e-9) * 1e-3
            self.counts, self.edges = np.histogram(fin, bins=BINS, range=(lo, hi))
            width = self.edges[1] - self.edges[0]
            hp.addItem(pg.BarGraphItem(x0=self.edges[:-1], width=width, height=self.counts, brush=BAR, pen=None))
            for k, (label, x) in enumerate(marks.items()):
                if np.isfinite(x):
                    line = pg.InfiniteLine(x, angle=90, pen=pg.mkPen(CHOSEN, width=1.5, style=Qt.PenStyle.DashLine),
                                           label=label, labelOpts={"position": 0.92 - 0.12 * k, "color": CHOSEN})
                    hp.addItem(line)
        sp = self.sensitivity.getPlotItem()
        sp.clear()
        self.shares = sorted(shares.items(), key=lambda kv: -kv[1])
        if self.shares:
            y = np.arange(len(self.shares))
            w = np.array([100.0 * s for _, s in self.shares])
            sp.addItem(pg.BarGraphItem(x0=np.zeros_like(w), y=y, height=0.6, width=w, brush=BAR, pen=None))
            sp.getAxis("left").setTicks([[(float(k), short_key(name)) for k, (name, _) in enumerate(self.shares)]])
            sp.invertY(True)
            sp.setXRange(0, max(100.0, float(w.max())) if w.size else 100.0, padding=0.02)
            self.sensitivity.setMinimumHeight(60 + 22 * len(self.shares))


class ParetoView(QWidget):
    """The Pareto front of an optimisation as a scatter; a click on a front point picks it."""

    pointPicked = Signal(int)

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        lay = QVBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.plot = _plot("Pareto front", "", "", 230)
        self.plot.setObjectName("studyPareto")
        self.note = QLabel()
        self.note.setWordWrap(True)
        lay.addWidget(self.plot)
        lay.addWidget(self.note)
        self.front = pg.ScatterPlotItem(size=11, brush=pg.mkBrush(FRONT), pen=pg.mkPen("w"), hoverable=True,
                                        hoverBrush=pg.mkBrush(CHOSEN), tip=None)
        self.others = pg.ScatterPlotItem(size=6, brush=pg.mkBrush(OTHERS), pen=None)
        self.chosen = pg.ScatterPlotItem(size=16, brush=pg.mkBrush(None), pen=pg.mkPen(CHOSEN, width=2.5))
        self.front.sigClicked.connect(self._clicked)
        self.xy = np.zeros((0, 2))

    def show_front(self, front_xy: np.ndarray, others_xy: np.ndarray, x_label: str, y_label: str) -> None:
        """Front points (F, 2) in the order of the front, the other feasible evaluations (E, 2)."""
        p = self.plot.getPlotItem()
        p.clear()
        for item in (self.others, self.front, self.chosen):
            p.addItem(item)
        p.setLabel("bottom", x_label)
        p.setLabel("left", y_label)
        self.xy = np.asarray(front_xy, dtype=float).reshape(-1, 2)
        self.others.setData(pos=np.asarray(others_xy, dtype=float).reshape(-1, 2))
        self.front.setData(pos=self.xy, data=np.arange(len(self.xy)))
        self.chosen.setData(pos=np.zeros((0, 2)))
        p.setTitle(f"Pareto front: {len(self.xy)} designs (click one to preview it)", size="9pt")
        # fit the view to the points now, not at the next paint: a click that comes first (or a
        # point mapped to the screen) meets the range the user will see
        p.getViewBox().updateAutoRange()

    def choose(self, index: int | None) -> None:
        """Ring the front point ``index`` (None: none)."""
        self.chosen.setData(pos=self.xy[index:index + 1] if index is not None and 0 <= index < len(self.xy)
                            else np.zeros((0, 2)))

    def _clicked(self, _item, points, _event=None) -> None:
        if len(points):
            self.pointPicked.emit(int(points[0].data()))

    def scene_point(self, index: int):
        """The front point ``index`` in the plot's scene coordinates (tests click there)."""
        vb = self.plot.getPlotItem().getViewBox()
        return vb.mapViewToScene(pg.Point(*self.xy[index]))


__all__ = ["ParetoView", "ToleranceView", "short_key"]
