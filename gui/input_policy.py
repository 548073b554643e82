"""Keyboard and wheel habits of a desktop CAD window (issue 24, items 1 and 2).

:class:`InputPolicy` is an application event filter the main window installs for itself:

- **Shortcuts work whatever has focus**, except while a text field is actually being edited: a
  line edit with focus whose text the user has not changed (``isModified()`` False: clicked into,
  or just committed) does not keep the window's shortcuts (Ctrl+E, Ctrl+S, F, Space, the tool
  keys) for itself — only the keys that start or move an edit of a number (digits, sign, point,
  exponent, Backspace, Delete, arrows, Home, End, Tab). Once the user types, every key is the
  field's until Enter or Esc.
- **The wheel never edits the design by accident**: a combo box or spin box that does not have
  the keyboard focus ignores the wheel, which scrolls the dock under it instead (and the wheel
  does not give it the focus: under X11 that happens before any event filter sees the wheel).

Only widgets of ``window`` are concerned (several windows can live in one process).
"""
from __future__ import annotations

from PySide6.QtCore import QEvent, QObject, Qt
from PySide6.QtGui import QKeyEvent, QKeySequence
from PySide6.QtWidgets import QAbstractSpinBox, QComboBox, QLineEdit, QWidget

from .qtsafe import qt_safe

#: keys an unchanged number field keeps: they start or move an edit
EDIT_KEYS = {Qt.Key.Key_Backspace, Qt.Key.Key_Delete, Qt.Key.Key_Left, Qt.Key.Key_Right, Qt.Key.Key_Home,
             Qt.Key.Key_End, Qt.Key.Key_Tab, Qt.Key.Key_Backtab, Qt.Key.Key_Return, Qt.Key.Key_Enter,
             Qt.Key.Key_Escape}
EDIT_TEXT = set("0123456789.,-+eE")
#: standard sequences that edit text (copy, paste, select all): the field's when it has a selection
TEXT_SEQUENCES = (QKeySequence.StandardKey.Copy, QKeySequence.StandardKey.Cut, QKeySequence.StandardKey.Paste,
                  QKeySequence.StandardKey.SelectAll)


def _line_edit(obj: QObject) -> QLineEdit | None:
    if isinstance(obj, QLineEdit):
        return obj
    if isinstance(obj, QAbstractSpinBox):
        return obj.findChild(QLineEdit)
    return None


def field_keeps(edit: QLineEdit, event: QKeyEvent) -> bool:
    """True if the focused line edit ``edit`` takes ``event`` before the window's shortcuts."""
    if edit.isModified():
        return True
    if edit.hasSelectedText() and any(event.matches(seq) for seq in TEXT_SEQUENCES):
        return True
    mods = event.modifiers() & ~(Qt.KeyboardModifier.KeypadModifier | Qt.KeyboardModifier.ShiftModifier)
    if mods:
        return False   # Ctrl/Alt/Meta + key: a window shortcut
    return Qt.Key(event.key()) in EDIT_KEYS or (event.text() != "" and event.text() in EDIT_TEXT)


@qt_safe
class InputPolicy(QObject):
    """The application event filter of one window (see the module docstring)."""

    def __init__(self, window: QWidget) -> None:
        super().__init__(window)
        self._window = window

    def _ours(self, obj: QObject) -> bool:
        return isinstance(obj, QWidget) and obj.window() is self._window

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt API
        kind = event.type()
        if kind == QEvent.Type.ShortcutOverride and self._ours(obj):
            edit = _line_edit(obj)
            if edit is not None and isinstance(event, QKeyEvent) and not field_keeps(edit, event):
                return True     # not accepted by the field: the window's shortcut (if any) runs
        elif kind == QEvent.Type.Polish and isinstance(obj, (QComboBox, QAbstractSpinBox)) and self._ours(obj):
            if obj.focusPolicy() == Qt.FocusPolicy.WheelFocus:   # a window server gives wheel focus
                obj.setFocusPolicy(Qt.FocusPolicy.StrongFocus)   # before any filter sees the wheel
        elif kind == QEvent.Type.Wheel and isinstance(obj, (QComboBox, QAbstractSpinBox)) and self._ours(obj):
            if not obj.hasFocus():
                event.ignore()   # passed on to the scroll area under it
                return True
        return False
