"""The export dialog (File → Export DXF… / Export SVG…): which element, which parts, the layout,
the curve tolerance, the DXF entity style and the minimum web, as one :class:`ExportRequest`.

The dialog is reached through the injectable dialog service
(:meth:`~mechsketch.gui.dialogs.QtDialogService.export_request`), so tests answer with a fake.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDialogButtonBox, QDoubleSpinBox, QFormLayout,
                               QLineEdit, QWidget)

from mechsketch.core.analyses.parts import DEFAULT_MIN_WEB, Vocabulary
from mechsketch.core.analyses.parts.build import DEFAULT_TOLERANCE, PartOptions

#: how messages of an export started from this dialog name its options (its fields)
DIALOG_VOCABULARY = Vocabulary((("min_web", "the dialog's Minimum web"), ("tolerance", "the dialog's Curve tolerance")),
                               "the export dialog")


@dataclass(frozen=True)
class ExportRequest:
    """What to export: ``element_id``; ``fmt`` "dxf" | "svg"; ``layout`` "apart" | "assembled";
    ``parts`` (None: all); ``split`` one file per part; ``arcs`` "bulge" | "entities" (DXF);
    ``options`` (tolerance, minimum web, plate sizes)."""

    element_id: str
    fmt: str = "dxf"
    layout: str = "apart"
    parts: tuple[str, ...] | None = None
    split: bool = False
    arcs: str = "bulge"
    options: PartOptions = field(default_factory=PartOptions)


class ExportDialog(QDialog):
    """The form behind :class:`ExportRequest`; ``choices`` maps element id -> its part names."""

    def __init__(self, title: str, choices: dict[str, tuple[str, ...]], default_id: str, fmt: str,
                 min_webs: dict[str, float] | None = None, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle(title)
        self.fmt = fmt
        self.choices = choices
        self.min_webs = min_webs or {}
        form = QFormLayout(self)
        self.element = QComboBox()
        self.element.addItems(list(choices))
        self.element.setCurrentText(default_id)
        self.parts = QLineEdit()
        self.layout_box = QComboBox()
        self.layout_box.addItems(["apart", "assembled"])
        self.split = QCheckBox("one file per part")
        self.tolerance = QDoubleSpinBox()
        self.tolerance.setDecimals(6)
        self.tolerance.setRange(1e-6, 10.0)
        self.tolerance.setValue(DEFAULT_TOLERANCE)
        self.tolerance.setSuffix(" mm")
        self.arcs = QComboBox()
        self.arcs.addItems(["bulge", "entities"])
        self.arcs.setEnabled(fmt == "dxf")
        self.min_web = QDoubleSpinBox()
        self.min_web.setDecimals(3)
        self.min_web.setRange(0.0, 1000.0)
        self.min_web.setSuffix(" mm")
        for label, w in (("Element", self.element), ("Parts", self.parts), ("Layout", self.layout_box),
                         ("", self.split), ("Curve tolerance", self.tolerance), ("DXF entities", self.arcs),
                         ("Minimum web", self.min_web)):
            form.addRow(label, w)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self.element.currentTextChanged.connect(self._element_changed)
        self._element_changed(default_id)

    def _element_changed(self, eid: str) -> None:
        names = self.choices.get(eid, ())
        self.parts.setPlaceholderText("all: " + ", ".join(names))
        self.parts.clear()
        self.min_web.setValue(self.min_webs.get(eid, DEFAULT_MIN_WEB))

    def request(self) -> ExportRequest:
        """The request the form describes."""
        names = tuple(n.strip() for n in self.parts.text().split(",") if n.strip()) or None
        return ExportRequest(self.element.currentText(), self.fmt, self.layout_box.currentText(), names,
                             self.split.isChecked(), self.arcs.currentText(),
                             PartOptions(tolerance=self.tolerance.value(), min_web=self.min_web.value(),
                                         vocabulary=DIALOG_VOCABULARY))
