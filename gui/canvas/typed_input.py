"""Typed input while a tool places a point, and angle/length snapping (issue 24, item 7).

While a placing tool is active, typing a number opens :class:`TypedBox`, a small inline box on the
canvas beside the pointer: the point's coordinates x, y (mm), or, when the tool measures from a
point it already has (a crank's pivot, a Geneva drive's crank centre, a guide's start, the first
point of a measure), the length (mm) and angle (°) from there. The typed character starts the
first field; Tab and Shift+Tab move between the fields; Enter places the point as a click there
would (snapping aside); Esc closes the box. A tool names the point it measures from with
``anchor()``.

Snapping with a modifier: with Shift held, a point placed from an anchor snaps to a multiple of
15° and of the grid step in length (:func:`snap_polar`).
"""
from __future__ import annotations

import math

from PySide6.QtCore import QPoint, Qt, Signal
from PySide6.QtGui import QKeyEvent
from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QLineEdit, QWidget

from ..qtsafe import qt_safe
from .events import XY

#: angle step (°) of Shift-snapping from an anchor
ANGLE_STEP = 15.0
#: characters that open the box
STARTS = set("0123456789.-")


def snap_polar(anchor: XY, pos: XY, length_step: float, angle_step: float = ANGLE_STEP) -> XY:
    """``pos`` moved to the nearest multiple of ``angle_step`` degrees and of ``length_step`` mm
    (at least one step) from ``anchor``."""
    dx, dy = pos[0] - anchor[0], pos[1] - anchor[1]
    length = max(round(math.hypot(dx, dy) / length_step), 1) * length_step
    angle = math.radians(round(math.degrees(math.atan2(dy, dx)) / angle_step) * angle_step)
    return (anchor[0] + length * math.cos(angle), anchor[1] + length * math.sin(angle))


def polar_point(anchor: XY, length: float, angle_deg: float) -> XY:
    """The point ``length`` mm from ``anchor`` at ``angle_deg`` degrees (counter-clockwise from +x)."""
    a = math.radians(angle_deg)
    return (anchor[0] + length * math.cos(a), anchor[1] + length * math.sin(a))


@qt_safe
class TypedBox(QFrame):
    """The inline box: two number fields; ``placed(x, y)`` (world mm) on Enter."""

    placed = Signal(float, float)
    closed = Signal()

    def __init__(self, parent: QWidget) -> None:
        super().__init__(parent)
        self.setObjectName("typedBox")
        self.setFrameShape(QFrame.Shape.StyledPanel)
        self.setAutoFillBackground(True)
        self.labels = (QLabel(), QLabel())
        self.fields = (QLineEdit(), QLineEdit())
        row = QHBoxLayout(self)
        row.setContentsMargins(4, 2, 4, 2)
        for label, field in zip(self.labels, self.fields):
            field.setFixedWidth(70)
            field.installEventFilter(self)
            row.addWidget(label)
            row.addWidget(field)
        self.anchor: XY | None = None
        self.hide()

    def open(self, first: str, at: QPoint, anchor: XY | None, start: XY) -> None:
        """Show the box at ``at`` (view pixels) with ``first`` typed into its first field; the
        fields are length and angle from ``anchor`` if given, else x and y (``start`` fills the
        second field: the pointer's current place)."""
        self.anchor = anchor
        if anchor is None:
            names, second = ("x", "y (mm)"), start[1]
        else:
            names = ("length (mm)", "angle (°)")
            second = math.degrees(math.atan2(start[1] - anchor[1], start[0] - anchor[0]))
        for label, text in zip(self.labels, names):
            label.setText(text)
        self.fields[0].setText(first)
        self.fields[1].setText(f"{second:.4g}")
        self.adjustSize()
        self.move(at + QPoint(16, 16))
        self.show()
        self.raise_()
        self.fields[0].setFocus()
        self.fields[0].deselect()
        self.fields[0].setCursorPosition(len(first))

    def point(self) -> XY | None:
        """The typed point (world mm), or None if a field is not a number."""
        try:
            a, b = (float(f.text().replace(",", ".")) for f in self.fields)
        except ValueError:
            return None
        if not (math.isfinite(a) and math.isfinite(b)):
            return None
        return (a, b) if self.anchor is None else polar_point(self.anchor, a, b)

    def close_box(self) -> None:
        self.hide()
        self.closed.emit()

    def eventFilter(self, obj, event) -> bool:  # noqa: N802 - Qt API
        if isinstance(event, QKeyEvent) and event.type() == QKeyEvent.Type.KeyPress and obj in self.fields:
            key = event.key()
            if key in (Qt.Key.Key_Tab, Qt.Key.Key_Backtab):
                other = self.fields[1] if obj is self.fields[0] else self.fields[0]
                other.setFocus()
                other.selectAll()
                return True
            if key in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
                p = self.point()
                if p is not None:
                    self.close_box()
                    self.placed.emit(p[0], p[1])
                return True
            if key == Qt.Key.Key_Escape:
                self.close_box()
                return True
        return False
