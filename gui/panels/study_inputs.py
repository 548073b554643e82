"""The inputs of a study in the Study dock: the linkage's variables — the rows of its Dimensions
table and its frame pivots' coordinates — each with a tolerance (± half-width) or a range, and its
pins with an ISO 286 fit each.

Defaults are scaled to the part: a length's tolerance is ±(0.02 mm + 0.02 % of the length) (a
100 mm link: ±0.04 mm), an angle's ±0.05°, a pivot's ±(0.02 mm + 0.02 % of the linkage's size);
a range is the nominal ±15 % (lengths) or ±15° (angles), a pivot ±15 % of the linkage's size. Values
are shown and typed in the display units (Edit › Preferences) and kept in the model's. What the
user typed is kept per element and key while the dock lives (switching elements loses nothing).
A bad entry raises :class:`EntryError` naming the row and what to type.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QAbstractItemView, QComboBox, QHeaderView, QTableWidget, QTableWidgetItem

from mechsketch.core.errors import MechsketchError, RequestError
from mechsketch.core.model.linkage import JointKind, Linkage
from mechsketch.core.solver.dimensions import dimensions

from .. import units

#: fits offered for a pin (any other ISO 286 fit may be typed)
FITS = ("H7/g6", "H7/h6", "H7/f7", "H8/f7", "H8/e8", "H9/d9", "H7/js6", "H7/k6")
DEFAULT_FIT = "H7/g6"
USE, LINK, NAME, NOMINAL, TOL, LOW, HIGH, UNIT = range(8)
HEADERS = ["use", "link", "dimension", "nominal", "±", "from", "to", "unit"]


class EntryError(ValueError):
    """A study input that cannot be used: ``row`` and ``column`` of the table at fault."""

    def __init__(self, message: str, table: QTableWidget | None = None, row: int = -1, column: int = -1) -> None:
        super().__init__(message)
        self.table, self.row, self.column = table, row, column


@dataclass(frozen=True)
class Row:
    """One variable: its study ``key``, ``link``, ``label`` (as the Dimensions table says it),
    model ``unit`` ("mm" or "°") and ``nominal`` value."""

    key: str
    link: str
    label: str
    unit: str
    nominal: float


def size_of(linkage: Linkage) -> float:
    """The linkage's size: the diagonal of its joints' box, mm (at least 1)."""
    xs = [j.at[0] for j in linkage.joints]
    ys = [j.at[1] for j in linkage.joints]
    return max(math.hypot(max(xs) - min(xs), max(ys) - min(ys)), 1.0) if xs else 1.0


def variable_rows(linkage: Linkage) -> list[Row]:
    """The Dimensions table's rows, then the x and y of each revolute joint of the frame."""
    rows = [Row(d.key, d.link, d.label, d.unit, d.value) for d in dimensions(linkage)]
    frame = linkage.link(linkage.ground).joints if linkage.ground in linkage.link_ids else ()
    for j in frame:
        joint = linkage.joint(j)
        if joint.kind is JointKind.R:
            rows += [Row(f"x:{j}", "frame", f"{j} x", "mm", float(joint.at[0])),
                     Row(f"y:{j}", "frame", f"{j} y", "mm", float(joint.at[1]))]
    return rows


def _round(x: float, digits: int = 2) -> float:
    return float(f"{x:.{digits}g}") if x > 0 else 0.0


def default_tolerance(row: Row, size: float) -> float:
    """± half-width scaled to the part (see the module docstring), in the row's unit."""
    if row.unit == "°":
        return 0.05
    base = size if row.key.startswith(("x:", "y:")) else abs(row.nominal)
    return _round(0.02 + 2e-4 * base)


def default_range(row: Row, size: float) -> tuple[float, float]:
    """(from, to) around the nominal value, in the row's unit."""
    v = row.nominal
    if row.unit == "°":
        return v - 15.0, v + 15.0
    if row.key.startswith(("x:", "y:")):
        return v - 0.15 * size, v + 0.15 * size
    return 0.85 * v, 1.15 * v


def default_use(row: Row, linkage: Linkage) -> bool:
    """Rows used by default: every link's lengths and angles from its first joint (a ternary link by
    its polar dimensions, not over-described), not the frame's pivot coordinates."""
    if row.key.startswith(("x:", "y:")):
        return False
    parts = row.key.split(":")
    if parts[0] == "length" and len(parts) == 4:
        first = linkage.link(parts[1]).joints[0] if parts[1] in linkage.link_ids else parts[2]
        return parts[2] == first
    return parts[0] in ("angle", "offset")


def pins(linkage: Linkage) -> list[str]:
    """Revolute joints on two or more links: the pins a clearance applies to."""
    return [j.id for j in linkage.joints if j.kind is JointKind.R and len(linkage.links_of(j.id)) >= 2]


def _model(text: str, unit: str, shown: units.Units | None = None) -> float | str:
    """What a cell holds, in the model's unit (the text itself where it is not a number); ``shown``:
    the display units it was typed in (default the current ones)."""
    try:
        return units.parse(text, unit, shown)
    except ValueError:
        return text


def _shown(value: float | str, unit: str) -> str:
    return units.format_value(value, unit, digits=4) if isinstance(value, float) else value


def _item(text: str, editable: bool = False) -> QTableWidgetItem:
    item = QTableWidgetItem(text)
    item.setToolTip(text)
    if not editable:
        item.setFlags(item.flags() & ~Qt.ItemFlag.ItemIsEditable)
    return item


def _check(on: bool) -> QTableWidgetItem:
    item = QTableWidgetItem()
    item.setFlags((item.flags() | Qt.ItemFlag.ItemIsUserCheckable) & ~Qt.ItemFlag.ItemIsEditable)
    item.setCheckState(Qt.CheckState.Checked if on else Qt.CheckState.Unchecked)
    return item


def _table(columns: list[str], name: str) -> QTableWidget:
    t = QTableWidget(0, len(columns))
    t.setObjectName(name)
    t.setHorizontalHeaderLabels(columns)
    t.verticalHeader().setVisible(False)
    head = t.horizontalHeader()
    head.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
    t.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
    t.setEditTriggers(QAbstractItemView.EditTrigger.DoubleClicked | QAbstractItemView.EditTrigger.EditKeyPressed
                      | QAbstractItemView.EditTrigger.AnyKeyPressed | QAbstractItemView.EditTrigger.SelectedClicked)
    t.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAsNeeded)
    return t


def fit_height(table: QTableWidget, rows_shown: int = 12) -> None:
    """Show up to ``rows_shown`` rows without a scroll bar (more scroll)."""
    n = min(table.rowCount(), rows_shown)
    h = table.horizontalHeader().height() + 4 + sum(table.rowHeight(r) for r in range(n))
    table.setFixedHeight(max(h, 40))


class VariableTable:
    """The variables table (a QTableWidget in :attr:`widget`) of one linkage at a time."""

    def __init__(self) -> None:
        self.widget = _table(HEADERS, "studyVariables")
        self.rows: list[Row] = []
        self.element: str | None = None
        self.mode = "tolerance"
        self.shown = units.current()   # the display units the cells were filled in
        self._kept: dict[tuple[str, str], tuple] = {}   # (element, key) -> (use, tol, lo, hi) as typed

    def set_mode(self, mode: str) -> None:
        """"tolerance" shows the ± column, "optimize" the from/to columns."""
        self.mode = mode
        self.widget.setColumnHidden(TOL, mode != "tolerance")
        self.widget.setColumnHidden(LOW, mode == "tolerance")
        self.widget.setColumnHidden(HIGH, mode == "tolerance")

    def _keep(self) -> None:
        """Remember what is typed (in model units where it reads as a number, else as typed)."""
        t = self.widget
        for r, row in enumerate(self.rows):
            if t.item(r, USE) is None:
                continue
            self._kept[(self.element, row.key)] = (t.item(r, USE).checkState() == Qt.CheckState.Checked,
                                                   *(_model(t.item(r, c).text(), row.unit, self.shown)
                                                     for c in (TOL, LOW, HIGH)))

    def redisplay(self) -> None:
        """Show the same rows again (the display units changed): what is typed is kept."""
        lk_rows, element = self.rows, self.element
        self._keep()
        self.rows = []
        self._fill(lk_rows, element)

    def set_linkage(self, linkage: Linkage | None) -> None:
        """Show the rows of ``linkage`` (None: none), with the user's entries for it kept."""
        self._keep()
        self.linkage = linkage
        self._fill(variable_rows(linkage) if linkage is not None else [], linkage.id if linkage is not None else None)

    linkage: Linkage | None = None

    def _fill(self, rows: list[Row], element: str | None) -> None:
        t = self.widget
        t.blockSignals(True)
        self.rows, self.element, self.shown = rows, element, units.current()
        size = size_of(self.linkage) if self.linkage is not None else 1.0
        t.setRowCount(len(self.rows))
        for r, row in enumerate(self.rows):
            lo, hi = default_range(row, size)
            use, tol, low, high = self._kept.get((self.element, row.key), (
                default_use(row, self.linkage), default_tolerance(row, size), lo, hi))
            tol, low, high = (_shown(v, row.unit) for v in (tol, low, high))
            t.setItem(r, USE, _check(use))
            t.setItem(r, LINK, _item(row.link))
            t.setItem(r, NAME, _item(row.label))
            t.item(r, NAME).setData(Qt.ItemDataRole.UserRole, row.key)
            t.item(r, NAME).setToolTip(row.key)
            t.setItem(r, NOMINAL, _item(units.format_value(row.nominal, row.unit, digits=4)))
            t.setItem(r, TOL, _item(tol, True))
            t.setItem(r, LOW, _item(low, True))
            t.setItem(r, HIGH, _item(high, True))
            t.setItem(r, UNIT, _item(units.display_unit(row.unit)))
        t.blockSignals(False)
        self.set_mode(self.mode)
        fit_height(t)

    def row_of(self, key: str) -> int:
        return next(r for r, row in enumerate(self.rows) if row.key == key)

    def set_use(self, key: str, on: bool) -> None:
        self.widget.item(self.row_of(key), USE).setCheckState(Qt.CheckState.Checked if on else Qt.CheckState.Unchecked)

    def used(self) -> list[Row]:
        return [row for r, row in enumerate(self.rows)
                if self.widget.item(r, USE).checkState() == Qt.CheckState.Checked]

    def _number(self, r: int, column: int, row: Row, what: str) -> float:
        text = self.widget.item(r, column).text()
        try:
            return units.parse(text, row.unit)
        except ValueError as exc:
            raise EntryError(f"{row.link} {row.label}: the {what} {exc}; type a number in "
                             f"{units.display_unit(row.unit)}", self.widget, r, column) from None

    def tolerances(self, distribution: str) -> dict[str, dict]:
        """The study spec of the used rows: key -> {"normal": σ} (σ = the ± half-width / 3) or
        {"uniform": half-width}, model units; :class:`EntryError` for a bad entry."""
        out = {}
        for r, row in enumerate(self.rows):
            if self.widget.item(r, USE).checkState() != Qt.CheckState.Checked:
                continue
            w = self._number(r, TOL, row, "tolerance")
            if w < 0:
                raise EntryError(f"{row.link} {row.label}: a tolerance is a ± half-width, not negative "
                                 f"({units.format_value(w, row.unit)} {units.display_unit(row.unit)})",
                                 self.widget, r, TOL)
            out[row.key] = {"normal": w / 3.0} if distribution == "normal" else {"uniform": w}
        return out

    def ranges(self) -> dict[str, dict]:
        """The study variables of the used rows: key -> {"range": [from, to]} (model units);
        :class:`EntryError` for a bad entry (not numbers, from ≥ to, a length not above 0)."""
        out = {}
        for r, row in enumerate(self.rows):
            if self.widget.item(r, USE).checkState() != Qt.CheckState.Checked:
                continue
            lo, hi = self._number(r, LOW, row, "'from' value"), self._number(r, HIGH, row, "'to' value")
            if not lo < hi:
                raise EntryError(f"{row.link} {row.label}: 'from' must be below 'to' (they are "
                                 f"{units.format_value(lo, row.unit)} and {units.format_value(hi, row.unit)} "
                                 f"{units.display_unit(row.unit)})", self.widget, r, LOW)
            if row.key.startswith("length:") and lo <= 0:
                raise EntryError(f"{row.link} {row.label}: a length's range must stay above 0 (from is "
                                 f"{units.format_value(lo, row.unit)} {units.display_unit(row.unit)})",
                                 self.widget, r, LOW)
            out[row.key] = {"range": [lo, hi]}
        return out


PIN_HEADERS = ["use", "pin", "links", "fit", "bore Ø", "radial play"]
P_USE, P_PIN, P_LINKS, P_FIT, P_DIA, P_PLAY = range(6)


class ClearanceTable:
    """The pins of one linkage with an ISO 286 fit each (a QTableWidget in :attr:`widget`)."""

    def __init__(self) -> None:
        self.widget = _table(PIN_HEADERS, "studyClearances")
        self.pins: list[str] = []
        self.element: str | None = None
        self.shown = units.current()
        self._kept: dict[tuple[str, str], tuple] = {}
        self.widget.itemChanged.connect(self._edited)

    def _keep(self) -> None:
        for r, j in enumerate(self.pins):
            if self.widget.item(r, P_USE) is not None:
                self._kept[(self.element, j)] = (self.widget.item(r, P_USE).checkState() == Qt.CheckState.Checked,
                                                 self.fit_box(r).currentText(),
                                                 _model(self.widget.item(r, P_DIA).text(), "mm", self.shown))

    def fit_box(self, r: int) -> QComboBox:
        return self.widget.cellWidget(r, P_FIT)

    linkage: Linkage | None = None

    def redisplay(self) -> None:
        """Show the same pins again (the display units changed): what is typed is kept."""
        self.set_linkage(self.linkage)

    def set_linkage(self, linkage: Linkage | None) -> None:
        """Show the pins of ``linkage`` (None: none), with the user's fits for it kept."""
        self._keep()
        self.linkage, self.shown = linkage, units.current()
        t = self.widget
        t.blockSignals(True)
        self.pins = pins(linkage) if linkage is not None and linkage.has_driver and \
            linkage.driver.kind != "cylinder" else []
        self.element = linkage.id if linkage is not None else None
        dia = bore_diameter(linkage) if self.pins else 0.0
        t.setRowCount(len(self.pins))
        for r, j in enumerate(self.pins):
            use, fit, d = self._kept.get((self.element, j), (True, DEFAULT_FIT, float(f"{dia:.3g}")))
            d = _shown(d, "mm")
            t.setItem(r, P_USE, _check(use))
            t.setItem(r, P_PIN, _item(j))
            t.setItem(r, P_LINKS, _item(", ".join(linkage.links_of(j))))
            box = QComboBox()
            box.setEditable(True)
            box.addItems(FITS)
            box.setCurrentText(fit)
            box.setToolTip("ISO 286 fit of the pin in its bore: hole/shaft, e.g. H7/g6 (type any other)")
            box.currentTextChanged.connect(lambda _t, r=r: self._show_play(r))
            t.setCellWidget(r, P_FIT, box)
            t.setItem(r, P_DIA, _item(d, True))
            t.setItem(r, P_PLAY, _item(""))
            self._show_play(r)
        t.blockSignals(False)
        fit_height(t, 8)

    def _edited(self, item: QTableWidgetItem) -> None:
        if item.column() == P_DIA:
            self._show_play(item.row())

    def _show_play(self, r: int) -> None:
        """The radial play range the fit gives on the bore (µm), or why it cannot be read."""
        from mechsketch.core.studies.iso286 import fit

        item = self.widget.item(r, P_PLAY)
        if item is None or self.widget.item(r, P_DIA) is None:
            return
        try:
            f = fit(self.fit_box(r).currentText().strip(), units.parse(self.widget.item(r, P_DIA).text(), "mm"))
            text = f"{500 * max(f.clearance_min, 0.0):.1f}–{500 * max(f.clearance_max, 0.0):.1f} µm"
        except (ValueError, RequestError) as exc:
            text = f"? {exc}"
        self.widget.blockSignals(True)
        item.setText(text)
        item.setToolTip(text)
        self.widget.blockSignals(False)

    def set_use(self, pin: str, on: bool) -> None:
        self.widget.item(self.pins.index(pin), P_USE).setCheckState(
            Qt.CheckState.Checked if on else Qt.CheckState.Unchecked)

    def spec(self) -> dict[str, dict]:
        """{pin: {"fit": "H7/g6", "diameter": mm}} of the used rows; EntryError for a bad entry."""
        from mechsketch.core.studies.iso286 import fit

        out = {}
        for r, j in enumerate(self.pins):
            if self.widget.item(r, P_USE).checkState() != Qt.CheckState.Checked:
                continue
            name = self.fit_box(r).currentText().strip()
            try:
                dia = units.parse(self.widget.item(r, P_DIA).text(), "mm")
            except ValueError as exc:
                raise EntryError(f"pin {j}: the bore diameter {exc}", self.widget, r, P_DIA) from None
            if not dia > 0:
                raise EntryError(f"pin {j}: the bore diameter must be above 0", self.widget, r, P_DIA)
            try:
                fit(name, dia)
            except (MechsketchError, ValueError) as exc:
                raise EntryError(f"pin {j}: {exc}", self.widget, r, P_FIT) from None
            out[j] = {"fit": name, "diameter": dia}
        return out


def bore_diameter(linkage: Linkage) -> float:
    """The drawn bore of the exported parts (mm), the default pin diameter of a fit."""
    from mechsketch.core.analyses.parts.linkage import BORE_FRACTION, BOSS_FRACTION, scale_of

    return 2.0 * BORE_FRACTION * BOSS_FRACTION * scale_of(linkage)


__all__ = ["ClearanceTable", "EntryError", "Row", "VariableTable", "bore_diameter", "default_range",
           "default_tolerance", "pins", "variable_rows"]
