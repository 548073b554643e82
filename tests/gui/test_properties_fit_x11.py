"""The Properties dock at its default width, for every element kind, after a rolling lever was
shown (issue 24 items 5 and the unit part): nothing needs a sideways scroll bar, and no value is
split from its unit nor a unit inside itself ("10 rad/ s").

Found in a real X11 window (docs/screenshots/check_fit_x11.py): a group box's title sets its
minimum width and Qt never wraps it, so "Driver: crank crank on A (loaded_fourbar)" made the
content 2 px wider than the dock at 1024 x 700 (and a user's long element id any wider). Offscreen
fonts are narrower than X11's, so here the ids are long, as a user may name them.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtGui import QTextLayout
from PySide6.QtWidgets import QAbstractButton, QComboBox, QGroupBox, QLabel, QLineEdit, QScrollArea, QWidget

from mechsketch.gui import units
from mechsketch.gui.panels.properties_fit import UNIT_LABEL

from app_fakes import shell  # noqa: F401 - fixture

EXAMPLES = Path(__file__).resolve().parents[2] / "resources" / "examples"
LONG = "a_designers_long_element_name_for_the_press_line_{}"
#: every unit string the panels show beside a field or in a value label
UNITS = ("mm", "in", "°", "deg", "rad", "rad/s", "rad/s²", "°/s", "rpm", "s", "N", "N·m", "N/mm", "N·s/mm",
         "mm/s", "mm/s²", "mm/rad", "in/s", "kg", "kg·m²", "MPa", "µm", "%")


def _open_long(parts, tmp_path: Path, example: str) -> list[str]:
    """Open ``example`` with its elements renamed to long ids (as the user may name them)."""
    data = json.loads((EXAMPLES / f"{example}.json").read_text())
    ids = []
    for i, el in enumerate(data["elements"]):
        el["id"] = LONG.format(i)
        ids.append(el["id"])
    path = tmp_path / f"{example}.json"
    path.write_text(json.dumps(data))
    parts.dialogs.save_changes.append("discard")
    parts.dialogs.open_names.append(str(path))
    parts.window.actions["open"].trigger()
    assert parts.controller.scene.ids == tuple(ids) or list(parts.controller.scene.ids) == ids
    return ids


def _pick(qtbot, props, wanted) -> None:
    """Choose ``wanted`` (element id, kind, ident) in the panel's selector, with the keyboard."""
    box = props.selector
    index = next(i for i in range(box.count()) if box.itemData(i) == wanted)
    box.setFocus()
    while box.currentIndex() != index:
        qtbot.keyClick(box, Qt.Key.Key_Down if box.currentIndex() < index else Qt.Key.Key_Up)


def _misfits(props) -> list[str]:
    content = props._content
    scroll = props.findChild(QScrollArea)
    width = scroll.viewport().width()
    out = []
    need = content.layout().totalMinimumSize().width()
    if need > width or content.width() > width:
        out.append(f"content needs {need} px, is {content.width()} px > {width}")
    if scroll.horizontalScrollBar().maximum() > 0:
        out.append("sideways scroll bar")
    for w in content.findChildren(QWidget):
        if isinstance(w, (QLineEdit, QAbstractButton, QLabel, QComboBox, QGroupBox)) and w.isVisibleTo(content):
            right = w.mapTo(content, QPoint(w.width(), 0)).x()
            if right > width + 1:
                out.append(f"{type(w).__name__} {w.objectName()!r} ends at {right} > {width}")
    return out


def _selections(ctl) -> list[tuple[str, str, str]]:
    picks = []
    for el in ctl.scene.elements:
        if el.type == "linkage":
            picks += [(el.id, "joint", el.joint_ids[-1]), (el.id, "link", el.link_ids[-1])]
        else:
            picks.append((el.id, "element", el.id))
    return picks


@pytest.mark.parametrize("size", [(1024, 700), (1440, 900)])
def test_every_kind_fits_the_dock_after_a_rolling_lever(shell, qtbot, tmp_path, size):
    parts = shell()
    w, props = parts.window, parts.window.properties
    w.resize(*size)
    qtbot.waitUntil(lambda: w.width() <= size[0])
    w.size_docks()
    qtbot.waitUntil(lambda: abs(w.docks["properties"].width() - 300) <= 2)   # the default width
    problems = {}
    for example in ("rolling_lever_press", "rolling_lever_law", "fourbar_loaded", "sixbar_moving_guide",
                    "geneva_z6", "gears_elliptic", "smooth_geneva_z5", "excavator_arm"):
        _open_long(parts, tmp_path, example)
        qtbot.waitUntil(lambda: props.selector.count() > 1)
        for pick in _selections(parts.controller):
            _pick(qtbot, props, pick)
            layout = props._content.layout()
            shown = [layout.itemAt(i).widget() for i in range(layout.count())]
            qtbot.waitUntil(lambda: all(b.isVisible() for b in shown if b is not None))
            qtbot.wait(0)    # one turn of the event loop: the layout settles
            bad = _misfits(props)
            if bad:
                problems[f"{example} {pick[1]} {pick[2][-12:]}"] = bad
    assert abs(w.docks["properties"].width() - 300) <= 2, "the dock kept its default width"
    assert not problems, problems


def _lines(label: QLabel, text: str, width: int) -> list[str]:
    """The lines a word-wrapped label of ``width`` px shows ``text`` in (Qt's own line breaking)."""
    layout = QTextLayout(text, label.font())
    layout.beginLayout()
    lines = []
    while True:
        line = layout.createLine()
        if not line.isValid():
            break
        line.setLineWidth(width)
        lines.append(text[line.textStart():line.textStart() + line.textLength()])
    layout.endLayout()
    return lines


@pytest.mark.parametrize("unit", UNITS)
def test_no_unit_wraps_inside_itself_or_off_its_value(qtbot, unit):
    label = QLabel()
    label.setWordWrap(True)
    qtbot.addWidget(label)
    fm = label.fontMetrics()
    before = "crank speed ω1 = 12.5"
    text = units.unbreakable(f"{before} {unit} at the drawn pose")
    # every width at which the line must break somewhere between the value and the end of its unit
    widths = range(fm.horizontalAdvance(before) - 2, fm.horizontalAdvance(f"{before} {unit}") + 3)
    for width in widths:
        label.setText(text)
        lines = [units.plain(x).strip() for x in _lines(label, text, width)]
        joined = [ln for ln in lines if f"12.5 {unit}" in ln]
        assert joined, f"{unit!r} at {width} px: {lines}"


def test_the_unit_beside_a_field_never_wraps(shell, qtbot):
    parts = shell()
    w = parts.window
    w.actions["example:geneva_z6"].trigger()
    parts.controller.set_selection([("indexer", "element", "indexer")])
    qtbot.waitUntil(lambda: bool(w.properties.fields))
    labels = [lb for lb in w.properties._content.findChildren(QLabel) if lb.objectName() == UNIT_LABEL]
    assert {units.plain(lb.text()) for lb in labels} >= {"mm", "rpm"}
    for lb in labels:
        assert not lb.wordWrap(), lb.text()
        assert lb.minimumSizeHint().width() >= lb.fontMetrics().horizontalAdvance(lb.text()), lb.text()
