"""Status-bar read-outs that change on every mouse move of a drag without laying the status bar
out again.

A QLabel whose text changes width asks its parent for a new layout (``updateGeometry``), and the
status bar then lays out and repaints every permanent widget and the window behind them, on every
move of a drag (the cursor position, the solve time). :class:`StatusLabel` keeps a fixed size
while a mouse button is held (a drag): its width only grows (to the text's size hint). Otherwise,
and at its first text change after the drag, it takes its text's own size as a plain QLabel
does. A fixed-size widget's text change repaints only the label (Qt skips the parent's layout
when its minimum and maximum sizes are equal). Setting the same text again does nothing at all.
"""
from __future__ import annotations

from PySide6.QtCore import QSize, Qt
from PySide6.QtWidgets import QApplication, QLabel, QWidget

from .qtsafe import qt_safe


@qt_safe
class StatusLabel(QLabel):
    """A QLabel for a status-bar read-out that changes often (see the module docstring)."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._probe = QLabel()   # never shown: the size hint of a plain label with the same text
        self.settle()

    def setText(self, text: str) -> None:  # noqa: N802 - Qt API
        if text == self.text():
            return
        super().setText(text)
        if QApplication.mouseButtons() == Qt.MouseButton.NoButton:
            self.settle()
            return
        hint = self.natural_size()
        if hint.width() > self.maximumWidth() or hint.height() > self.maximumHeight():
            self.setFixedSize(max(hint.width(), self.maximumWidth()), max(hint.height(), self.maximumHeight()))

    def natural_size(self) -> QSize:
        """The size hint a plain QLabel would have with this text, font, margins and indent."""
        p = self._probe
        p.setFont(self.font())
        p.setContentsMargins(self.contentsMargins())
        p.setMargin(self.margin())
        p.setIndent(self.indent())
        p.setText(self.text())
        return p.sizeHint()

    def settle(self) -> None:
        """Take the text's own size (what a plain QLabel would have); no layout if it has it."""
        hint = self.natural_size()
        if hint.width() != self.maximumWidth() or hint.height() != self.maximumHeight() \
                or self.minimumSize() != self.maximumSize():
            self.setFixedSize(hint)
