"""The canvas's background grid and scale bar, painted in world millimetres with y up.

:func:`grid_steps` chooses the grid spacing for the zoom (1-2-5 steps, at least
:data:`GRID_MIN_PX` pixels apart); :func:`paint_grid` fills the background and draws the minor
grid, the major grid and the axes; :func:`paint_scale_bar` draws a labelled scale bar in the
bottom-left corner of the viewport. :class:`~mechsketch.gui.canvas.view.CanvasView` calls them
from ``drawBackground`` / ``drawForeground``.
"""
from __future__ import annotations

import math

from PySide6.QtCore import QLineF, QPointF, QRectF
from PySide6.QtGui import QColor, QPainter, QPen

GRID_MIN_PX = 12.0            # the minor grid is at least this far apart on screen
BACKGROUND = QColor("#fbfbfc")
GRID_MINOR = QColor("#eceef2")
GRID_MAJOR = QColor("#d9dde4")
GRID_AXES = QColor("#b4bac5")


def grid_steps(px: float) -> tuple[float, float]:
    """(minor, major) grid spacing in mm for ``px`` mm per pixel: 1-2-5 steps, major a power of
    ten or five times one, at least five minors apart."""
    raw = GRID_MIN_PX * px
    e = math.floor(math.log10(raw))
    for m in (1, 2, 5, 10):
        if m * 10.0 ** e >= raw * (1 - 1e-9):
            minor = m * 10.0 ** e
            break
    lead = round(minor / 10.0 ** math.floor(math.log10(minor) + 1e-9))
    major = minor * (10 if lead in (1, 5) else 5)
    return minor, major


def paint_grid(painter: QPainter, rect: QRectF, px: float) -> None:
    """Fill ``rect`` (scene mm) with the background, then draw the minor and major grid for ``px``
    mm per pixel (cosmetic one-pixel lines, none in a direction with 2,000 or more) and the axes."""
    painter.fillRect(rect, BACKGROUND)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing, False)
    minor, major = grid_steps(px)
    for step, color in ((minor, GRID_MINOR), (major, GRID_MAJOR)):
        pen = QPen(color, 0)
        pen.setCosmetic(True)
        painter.setPen(pen)
        lines = []
        k0, k1 = math.floor(rect.left() / step), math.ceil(rect.right() / step)
        if k1 - k0 < 2000:
            lines += [QLineF(k * step, rect.top(), k * step, rect.bottom()) for k in range(k0, k1 + 1)]
        k0, k1 = math.floor(rect.top() / step), math.ceil(rect.bottom() / step)
        if k1 - k0 < 2000:
            lines += [QLineF(rect.left(), k * step, rect.right(), k * step) for k in range(k0, k1 + 1)]
        painter.drawLines(lines)
    pen = QPen(GRID_AXES, 0)
    pen.setCosmetic(True)
    painter.setPen(pen)
    painter.drawLines([QLineF(0, rect.top(), 0, rect.bottom()), QLineF(rect.left(), 0, rect.right(), 0)])


def paint_scale_bar(painter: QPainter, px: float, height: int) -> None:
    """A scale bar in the bottom-left corner of a viewport ``height`` pixels high, ``px`` mm per
    pixel: a major grid step halved or doubled until it is 60-160 pixels long, labelled in mm."""
    _minor, major = grid_steps(px)
    length = major
    while length / px > 160:
        length /= 2
    while length / px < 60:
        length *= 2
    painter.save()
    painter.resetTransform()
    painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
    x0, y0, w = 16.0, height - 18.0, length / px
    pen = QPen(QColor("#4b5563"), 1.5)
    painter.setPen(pen)
    painter.drawLine(QPointF(x0, y0), QPointF(x0 + w, y0))
    for x in (x0, x0 + w):
        painter.drawLine(QPointF(x, y0 - 5), QPointF(x, y0 + 1))
    font = painter.font()
    font.setPixelSize(11)
    painter.setFont(font)
    label = f"{length:g} mm"
    painter.drawText(QPointF(x0 + w + 6, y0 + 4), label)
    painter.restore()
