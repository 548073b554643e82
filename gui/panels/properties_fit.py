"""The Properties dock fits its width (issue 24, items 5 and the unit part of 24b).

At the dock's default width (300 px at 1024 and 1440 px windows) nothing in the panel may need a
sideways scroll bar or be cut: form rows put their field under the label when narrow, texts
wrap, choice boxes elide their longest entry, and a group box's title (which Qt never wraps and
which sets the box's minimum width: "Driver: crank crank on A (loaded_fourbar)") is elided to the
box's width with the whole title in its tooltip. No value is split from its unit and no unit is
split inside ("10 rad/ s"): unit labels beside fields never wrap, and wrapped texts keep each
number and unit together (:func:`..units.unbreakable`).
"""
from __future__ import annotations

from PySide6.QtCore import QEvent, QObject, Qt
from PySide6.QtWidgets import QComboBox, QFormLayout, QGroupBox, QLabel, QWidget

from .. import units
from ..qtsafe import qt_safe

#: the object name of the unit label beside a field (never wrapped)
UNIT_LABEL = "unit"
#: room of a group box's frame and title indent beside its title text, px
_TITLE_ROOM = 24


@qt_safe
class _TitleElider(QObject):
    """Elides the titles of the group boxes it watches to their width; their minimum width is what
    their rows need, not what their title needs."""

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt override
        if isinstance(watched, QGroupBox) and event.type() in (QEvent.Type.Resize, QEvent.Type.LayoutRequest):
            fit_title(watched)
        return False


def fit_title(box: QGroupBox) -> None:
    """Show as much of ``box``'s full title as its width allows; its minimum width from its rows."""
    full = box.property("full_title")
    if full is None:
        return
    layout = box.layout()
    need = layout.totalMinimumSize().width() if layout is not None else 0
    if box.minimumWidth() != need:
        box.setMinimumWidth(max(need, 1))
    shown = box.fontMetrics().elidedText(full, Qt.TextElideMode.ElideRight, max(box.width() - _TITLE_ROOM, 20))
    if box.title() != shown:
        box.setTitle(shown)


def fit_width(content: QWidget, elider: _TitleElider) -> None:
    """Let every row under ``content`` shrink to the dock's width (see the module docstring)."""
    for form in content.findChildren(QFormLayout):
        form.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
    for label in content.findChildren(QLabel):
        label.setWordWrap(label.objectName() != UNIT_LABEL)
    for box in content.findChildren(QComboBox):
        box.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        box.setMinimumContentsLength(8)
    for box in content.findChildren(QGroupBox):
        if box.property("full_title") is None:
            box.setProperty("full_title", box.title())
            if not box.toolTip():
                box.setToolTip(box.title())
            box.installEventFilter(elider)
        fit_title(box)


def keep_units_together(content: QWidget) -> None:
    """Every label under ``content`` keeps its numbers with their units on one line."""
    for label in content.findChildren(QLabel):
        if not label.wordWrap():   # a unit beside a field: one line anyway, its text left as it is
            continue
        text = label.text()
        fixed = units.unbreakable(text)   # in rich text too: a no-break space is a character there
        if fixed != text:
            label.setText(fixed)


def make_elider(parent: QObject) -> _TitleElider:
    """The title elider of one panel."""
    return _TitleElider(parent)
