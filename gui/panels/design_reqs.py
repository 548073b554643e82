"""The Design dock's requirement forms (issue 25): a Geneva drive, a rolling lever with a slider
law, a non-circular gear pair — each a form whose fields are the REQ keys of
``mechsketch design geneva|rolling|gears`` (lengths in the display unit, the rest in the unit
named beside them; an empty optional field is not asked for), and the report of a design:
each requirement with its value, limit and margin, the binding one marked; a refusal shows
what to relax as buttons that put the needed value in the form.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (QCheckBox, QComboBox, QFormLayout, QHBoxLayout, QHeaderView, QLabel, QLineEdit,
                               QPushButton, QTableWidget, QTableWidgetItem, QVBoxLayout, QWidget)

from .. import units
from .design_runs import report_rows
from .study_inputs import EntryError


@dataclass(frozen=True)
class Field:
    """One REQ field: ``key`` (dotted for a nested one, e.g. ``load.wheel_inertia``), ``label``,
    model ``unit`` ("mm" is shown in the display unit), ``default`` (None: optional, empty),
    ``whole``: a whole number."""

    key: str
    label: str
    unit: str = ""
    default: float | None = None
    whole: bool = False
    tip: str = ""


GENEVA = (
    Field("slots", "slots z", "", 6, True, "the number of slots (3 to 12)"),
    Field("speed_rpm", "crank speed", "rpm", 300),
    Field("roller_length", "roller length", "mm", 12),
    Field("load.wheel_inertia", "wheel inertia", "kg·m²", 0.5),
    Field("load.external_moment", "moment on the wheel", "N·m", 2),
    Field("load.journal_friction", "journal friction μ", "", 0.05),
    Field("load.journal_radius", "journal radius", "mm", 12),
    Field("allowable_contact_stress", "allowable contact stress", "MPa", 900, tip="peak Hertz pressure (optional)"),
    Field("life_cycles", "wear life", "crank turns", 1e7, tip="Archard life until the allowed wear (optional)"),
    Field("max_center_distance", "largest centre distance", "mm", 400, tip="(optional)"),
    Field("min_web", "thinnest web of the parts", "mm", 1),
)
ROLLING = (
    Field("slider_law.travel", "slider travel", "mm", 50, tip="S5 over the stroke"),
    Field("max_pressure_angle_deg", "largest pressure angle", "°", None, tip="(optional)"),
    Field("min_web", "thinnest web of the parts", "mm", 1),
)
GEARS = (
    Field("center_distance", "centre distance a", "mm", 100),
    Field("function.elliptic.eccentricity", "eccentricity (elliptic)", "", 0.3),
    Field("function.fourier.ratio", "mean ratio (Fourier)", "", 1),
    Field("max_pressure_deg", "largest pressure-angle swing", "°", None, tip="(optional)"),
    Field("min_concave_radius", "tightest concave radius", "mm", None, tip="(optional: what a cutter can follow)"),
)
LAWS = ("constant", "cycloidal", "harmonic", "modified_trapezoid")
PRESS = "the press example (rolling_lever_press)"


def _put(d: dict, dotted: str, value) -> None:
    *path, last = dotted.split(".")
    for p in path:
        d = d.setdefault(p, {})
    d[last] = value


class RequirementForm(QWidget):
    """A form of :class:`Field` rows (see the module docstring); subclasses add their choices."""

    kind = ""
    fields: tuple[Field, ...] = ()
    element_id = ""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.form = QFormLayout(self)
        self.form.setContentsMargins(0, 0, 0, 0)
        self.form.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)   # a narrow dock: labels above
        self.edits: dict[str, QLineEdit] = {}
        self._units: dict[str, QLabel] = {}
        self.shown = units.current()
        self.id_edit = QLineEdit(self.element_id)
        self.id_edit.setObjectName(f"{self.kind}Id")

    def _rows(self, fields: tuple[Field, ...]) -> None:
        for f in fields:
            edit = QLineEdit("" if f.default is None else _text(f.default, f.unit))
            edit.setObjectName(f"req:{f.key}")
            edit.setMinimumWidth(60)
            edit.setPlaceholderText("none" if f.default is None else "")
            if f.tip:
                edit.setToolTip(f.tip)
            label = QLabel(units.display_unit(f.unit) if f.unit else "")
            row = QHBoxLayout()
            row.addWidget(edit, 1)
            row.addWidget(label)
            self.form.addRow(f.label, row)
            self.edits[f.key], self._units[f.key] = edit, label

    def redisplay(self) -> None:
        """The display units changed: the fields in mm show the new unit (values kept)."""
        for f in self.fields:
            edit = self.edits[f.key]
            try:
                v = units.parse(edit.text(), f.unit or None, self.shown) if edit.text().strip() else None
            except ValueError:
                continue
            if v is not None:
                edit.setText(_text(v, f.unit))
            self._units[f.key].setText(units.display_unit(f.unit) if f.unit else "")
        self.shown = units.current()

    def values(self, only: tuple[str, ...] | None = None) -> dict:
        """The REQ of the filled fields (model units); EntryError naming a bad one."""
        out: dict = {}
        for f in self.fields:
            if only is not None and f.key not in only:
                continue
            text = self.edits[f.key].text().strip()
            if not text:
                if f.default is not None:
                    raise EntryError(f"{f.label}: give a value" + (f" in {units.display_unit(f.unit)}" if f.unit else ""))
                continue
            try:
                v = units.parse(text, f.unit or None)
            except ValueError as exc:
                raise EntryError(f"{f.label}: {exc}") from None
            if f.whole:
                if v != int(v):
                    raise EntryError(f"{f.label}: a whole number, got {text}")
                v = int(v)
            _put(out, f.key, v)
        return out

    def requirements(self) -> dict:
        return self.values()

    def set_value(self, key: str, value: float) -> bool:
        """Put ``value`` (model units) in the field of REQ key ``key`` (a relaxation); False if the
        form has no such field."""
        f = next((f for f in self.fields if f.key == key), None)
        if f is None:
            return False
        self.edits[key].setText(_text(int(value) if f.whole else value, f.unit))
        return True

    @property
    def design_id(self) -> str:
        return self.id_edit.text().strip() or self.element_id


def _text(v: float, unit: str) -> str:
    if isinstance(v, int) or (isinstance(v, float) and v.is_integer() and abs(v) < 1e15 and unit != "mm"):
        return f"{int(v)}" if abs(v) < 1e6 else f"{v:g}"
    return units.format_value(float(v), unit or None, digits=6)


class GenevaForm(RequirementForm):
    """``mechsketch design geneva``: slots (or a dwell fraction), speed, loads, limits; optionally
    the smooth drive through non-circular gears."""

    kind, fields, element_id = "geneva", GENEVA, "geneva"

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.form.addRow("element id", self.id_edit)
        self._rows(self.fields)
        self.smooth = QCheckBox("smooth: drive the crank through synthesised non-circular gears")
        self.smooth.setObjectName("genevaSmooth")
        self.form.addRow(self.smooth)

    def requirements(self) -> dict:
        req = self.values()
        if self.smooth.isChecked():
            req["smooth"] = {}
        return req


class RollingForm(RequirementForm):
    """``mechsketch design rolling``: a rolling lever (an existing one's circles, pin, pivot and
    stroke, or the press example's) and the slider law S5(θ) it must follow."""

    kind, fields, element_id = "rolling", ROLLING, "lever"

    def __init__(self, levers: Callable[[], list], parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.levers = levers
        self.base = QComboBox()
        self.base.setObjectName("rollingBase")
        self.base.setToolTip("The lever circle, pin, rocker pivot and stroke the design keeps")
        self.law = QComboBox()
        self.law.setObjectName("rollingLaw")
        self.law.addItems(LAWS)
        self.form.addRow("element id", self.id_edit)
        self.form.addRow("pair D from", self.base)
        self.form.addRow("slider law", self.law)
        self._rows(self.fields)
        self.refresh()

    def refresh(self) -> None:
        """The rolling levers of the scene, then the press example."""
        current = self.base.currentText()
        names = [el.id for el in self.levers()] + [PRESS]
        if [self.base.itemText(k) for k in range(self.base.count())] != names:
            self.base.clear()
            self.base.addItems(names)
            if current in names:
                self.base.setCurrentText(current)

    def requirements(self) -> dict:
        from mechsketch.core import load_scene
        from mechsketch.core.design.rolling import requirements_of
        from mechsketch.resources import example_path

        name = self.base.currentText()
        lever = next((el for el in self.levers() if el.id == name), None)
        if lever is None:
            lever = load_scene(example_path("rolling_lever_press")).elements[0]
        req = requirements_of(lever)
        vals = self.values()
        req["slider_law"] = {"law": self.law.currentText(), **vals.pop("slider_law")}
        req.update(vals)
        return req


class GearsForm(RequirementForm):
    """``mechsketch design gears``: an elliptic or Fourier transmission function at a centre distance,
    and the limits on the pitch curves."""

    kind, fields, element_id = "gears", GEARS, "gears"

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.function = QComboBox()
        self.function.setObjectName("gearsFunction")
        self.function.addItems(["elliptic", "fourier"])
        self.sines = QLineEdit("0.2")
        self.sines.setObjectName("gearsSines")
        self.sines.setToolTip("Fourier: ψ(φ) = ratio·φ + Σ c_k sin kφ; the c_k separated by commas")
        self.convex = QCheckBox("convex pitch curves only")
        self.form.addRow("element id", self.id_edit)
        self.form.addRow("function ψ(φ)", self.function)
        self._rows(self.fields)
        self.form.addRow("sine terms c_k (Fourier)", self.sines)
        self.form.addRow(self.convex)

    def requirements(self) -> dict:
        kind = self.function.currentText()
        skip = "function.fourier.ratio" if kind == "elliptic" else "function.elliptic.eccentricity"
        req = self.values(tuple(f.key for f in self.fields if f.key != skip))
        if kind == "fourier":
            try:
                sines = [float(x) for x in self.sines.text().replace(";", ",").split(",") if x.strip()]
            except ValueError:
                raise EntryError(f"sine terms: numbers separated by commas, got {self.sines.text()!r}") from None
            if not all(math.isfinite(x) for x in sines):
                raise EntryError("sine terms: finite numbers")
            req["function"]["fourier"]["sin"] = sines
        if self.convex.isChecked():
            req["convex"] = True
        return req


class ReportView(QWidget):
    """The report of a design: a table of its requirements (the binding one in bold), the notes,
    and for a refusal the relaxations as buttons (``relax(name, value)`` when one is pressed)."""

    relax = Signal(str, float)

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        col = QVBoxLayout(self)
        col.setContentsMargins(0, 0, 0, 0)
        self.title = QLabel()
        self.title.setWordWrap(True)
        self.table = QTableWidget(0, 5)
        self.table.setObjectName("designReport")
        self.table.setHorizontalHeaderLabels(["requirement", "value", "limit", "margin", "what"])
        self.table.verticalHeader().setVisible(False)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        self.table.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
        self.notes = QLabel()
        self.notes.setWordWrap(True)
        self.notes.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.buttons = QVBoxLayout()
        for w in (self.title, self.table, self.notes):
            col.addWidget(w)
        col.addLayout(self.buttons)
        self.relax_buttons: list[QPushButton] = []

    def show_report(self, report) -> None:
        self._clear_buttons()
        rows = report_rows(report)
        self.title.setText(report.title)
        self.table.setVisible(True)
        self.table.setRowCount(len(rows))
        for r, (name, what, value, limit, margin, binding) in enumerate(rows):
            for c, text in enumerate((name + ("  ← binding" if binding else ""), value, limit, margin, what)):
                item = QTableWidgetItem(text)
                item.setToolTip(what)
                if binding:
                    font = item.font()
                    font.setBold(True)
                    item.setFont(font)
                self.table.setItem(r, c, item)
        self.table.setFixedHeight(self.table.horizontalHeader().height() + 4
                                  + sum(self.table.rowHeight(r) for r in range(len(rows))))
        self.notes.setText("\n".join(report.notes) + f"\ndesigned in {report.seconds:.3g} s")

    def show_refusal(self, message: str, relax=()) -> None:
        """A refused design: the message and one button per relaxation (the least change first)."""
        self._clear_buttons()
        self.title.setText("Refused: " + message)
        self.table.setRowCount(0)
        self.table.setVisible(False)
        self.notes.setText("")
        for r in relax:
            b = QPushButton(f"Relax: {r.text()}")
            b.setObjectName(f"relax:{r.name}")
            b.clicked.connect(lambda _c=False, r=r: self.relax.emit(r.name, float(r.needed)))
            self.buttons.addWidget(b)
            self.relax_buttons.append(b)

    def _clear_buttons(self) -> None:
        for b in self.relax_buttons:
            self.buttons.removeWidget(b)
            b.deleteLater()
        self.relax_buttons = []


__all__ = ["GearsForm", "GenevaForm", "ReportView", "RequirementForm", "RollingForm"]
