"""Arrows and their scales: what the vector, force and load overlays draw with."""
from __future__ import annotations

import math

from PySide6.QtCore import QPointF
from PySide6.QtGui import QPainter, QPolygonF


def nice_scale(value: float) -> float:
    """The 1-2-5 number nearest above ``value`` (> 0)."""
    if not (value > 0 and math.isfinite(value)):
        return 1.0
    e = math.floor(math.log10(value))
    for m in (1, 2, 5, 10):
        if m * 10.0 ** e >= value * (1 - 1e-12):
            return m * 10.0 ** e
    return 10.0 ** (e + 1)  # pragma: no cover


def arrow(painter: QPainter, a: tuple[float, float], b: tuple[float, float], px: float) -> None:
    """A line a -> b with an arrowhead of constant screen size."""
    pa, pb = QPointF(*a), QPointF(*b)
    painter.drawLine(pa, pb)
    d = complex(b[0] - a[0], b[1] - a[1])
    if abs(d) < 1e-12:
        return
    u = d / abs(d)
    h = 9 * px
    tip = complex(*b)
    left, right = tip - h * u * complex(math.cos(0.4), math.sin(0.4)), tip - h * u * complex(math.cos(0.4), -math.sin(0.4))
    painter.drawPolygon(QPolygonF([pb, QPointF(left.real, left.imag), QPointF(right.real, right.imag)]))
