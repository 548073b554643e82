"""Plots a designer can read (issue 24, item 4): the user chooses which plots show (remembered per
kind of element), legends sit outside the data, the legends read every curve at the hovered
input, and each plot keeps a readable height while the column scrolls."""
from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import QPoint
from PySide6.QtGui import QTextDocument
from PySide6.QtWidgets import QApplication

from app_fakes import DISCARD, shell  # noqa: F401 - fixture
from mechsketch.gui.panels.plot_rows import ROW_HEIGHT


def test_the_chosen_plots_are_remembered_per_kind_of_element(shell, tmp_path):
    parts = shell()
    w = parts.window
    plots = w.plots
    assert list(plots.plots) == ["position", "velocity", "acceleration", "transmission"]
    menu = {a.data(): a for a in plots.chooser_menu.actions()}
    menu["acceleration"].trigger()                       # the user unticks "acceleration"
    menu["transmission"].trigger()
    assert list(plots.plots) == ["position", "velocity"]
    assert not plots.rows["acceleration"].isVisible()
    w.actions["example:geneva_z6"].trigger()             # a Geneva drive has its own choice
    assert "alpha" in plots.plots and len(plots.plots) == 8
    {a.data(): a for a in plots.chooser_menu.actions()}["jerk"].trigger()
    assert "jerk" not in plots.plots and len(plots.plots) == 7
    w.actions["example:double_rocker"].trigger()         # back to a linkage: its choice again
    assert list(plots.plots) == ["position", "velocity"]
    settings = tmp_path / "settings.ini"
    parts.window.file_ops.settings.sync()
    again = shell(settings_path=settings)                # a new window reads the same settings
    assert list(again.window.plots.plots) == ["position", "velocity"]
    for a in plots.chooser_menu.actions():               # the last plot cannot be switched off
        if a.isChecked():
            a.trigger()
    assert len(plots.plots) == 1


def test_legends_are_outside_the_data_and_read_the_curves_at_the_hovered_input(shell, qtbot):
    parts = shell()
    ctl, plots = parts.controller, parts.window.plots
    ctl.set_selection([("fourbar", "joint", "C")])
    row = plots.rows["position"]
    assert row.legend.geometry().bottom() <= row.widget.geometry().top()   # above the plot, not on it
    assert not [i for i in row.plot.items if type(i).__name__ == "LegendItem"]
    sol = ctl.result("fourbar").solution
    vp = row.widget.viewport()
    for dx in (0, 7):                                    # the pointer over the middle of the plot
        qtbot.mouseMove(vp, QPoint(vp.width() // 2 + dx, vp.height() // 2))
    x = plots._hover_x
    assert x is not None and np.nanmin(np.degrees(sol.input)) <= x <= np.nanmax(np.degrees(sol.input))
    i = int(np.argmin(np.abs(np.degrees(sol.input) - x)))
    text = row.legend.text().replace("&nbsp;", " ")
    assert f"C.x = {sol.position('C')[i, 0]:.5g}" in text and f"C.y = {sol.position('C')[i, 1]:.5g}" in text
    vel = plots.rows["velocity"].legend.text().replace("&nbsp;", " ")           # every plot reads at the same input
    assert f"C.vx = {sol.velocity('C')[i, 0]:.5g}" in vel
    plots.read_out(None)                                  # off the plots: the animation cursor
    ctl.set_frame(7)
    assert f"C.x = {sol.position('C')[7, 0]:.5g}" in row.legend.text().replace("&nbsp;", " ")


@pytest.mark.parametrize("size", [(1024, 700), (1440, 900)])
def test_every_plot_keeps_a_readable_height_and_the_column_scrolls(shell, qtbot, size):
    parts = shell()
    w = parts.window
    w.resize(*size)
    w.size_docks()
    w.actions["example:fourbar_loaded"].trigger()        # 6 plots: kinematics and forces
    plots = w.plots
    qtbot.waitUntil(lambda: plots.isVisible())
    assert len(plots.plots) == 6
    for row in plots.shown_rows():
        assert row.widget.height() >= ROW_HEIGHT
    bar = plots.scroll.verticalScrollBar()
    assert bar.maximum() > 0                             # the column scrolls instead of squeezing
    assert plots.scroll.horizontalScrollBar().maximum() == 0


@pytest.mark.parametrize("size", [(1024, 700), (1440, 900)])
def test_a_legend_of_two_lines_does_not_cut_its_plot(shell, qtbot, size):
    """Issue 24 item 6: with a joint selected the velocity legend (C.vx, C.vy, |v C|) takes two
    lines at the default dock width; its plot (tick labels included) must still lie whole inside
    its row, and no curve's entry is broken between lines (``|v C|`` stays one piece)."""
    parts = shell()
    w = parts.window
    w.resize(*size)
    w.size_docks()
    w.actions["example:fourbar_crank_rocker"].trigger()
    parts.controller.set_selection([("fourbar", "joint", "C")])
    plots = w.plots
    qtbot.waitUntil(lambda: plots.isVisible())
    w.docks["plots"].resize(300, w.docks["plots"].height())

    def whole(row) -> bool:   # the legend shows all its lines and the plot lies inside its row
        need = row.legend.heightForWidth(row.legend.width())
        return row.legend.height() >= need and row.widget.geometry().bottom() <= row.rect().bottom()

    qtbot.waitUntil(lambda: all(whole(row) for row in plots.shown_rows()), timeout=5000)   # the layouts settle
    wrapped = 0
    for row in plots.shown_rows():
        legend = row.legend
        wrapped += legend.height() > legend.fontMetrics().lineSpacing() * 1.5
        assert row.widget.height() >= ROW_HEIGHT
        for width in range(200, 640, 8):                     # the legend laid out at many widths
            doc = QTextDocument()
            doc.setDefaultFont(legend.font())
            doc.setDocumentMargin(0)
            doc.setHtml(legend.text())
            doc.setTextWidth(width)
            doc.size()                                       # (lays it out)
            layout, text = doc.begin().layout(), doc.begin().text()
            lines = [text[ln.textStart():ln.textStart() + ln.textLength()].replace("\u2060", "")
                     for ln in (layout.lineAt(i) for i in range(layout.lineCount()))]
            for curve in row._shown:                         # each entry lies on one line
                entry = curve.name.replace(" ", "\xa0")
                assert any(entry in line for line in lines), (width, curve.name, lines)
    assert wrapped >= 1                                      # the case in question did arise
