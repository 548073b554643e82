"""The export dialog (File → Export DXF… / Export SVG…): which element, which parts, the layout,
the DXF entity style (with which readers need LINE/ARC), annotations, the kerf, the curve
tolerance, the minimum web and a linkage's plate sizes or a rolling lever's plate depth, as one
:class:`ExportRequest`. Fields that do not apply to the chosen element are disabled, and the
request never carries them (the command line refuses such options; here they cannot be set).

The dialog is reached through the injectable dialog service
(:meth:`~mechsketch.gui.dialogs.QtDialogService.export_request`), so tests answer with a fake.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDialogButtonBox, QDoubleSpinBox, QFormLayout,
                               QLabel, QLineEdit, QWidget)

from mechsketch.core.analyses.parts import DEFAULT_MIN_WEB, Vocabulary
from mechsketch.core.analyses.parts.build import DEFAULT_TOLERANCE, PartOptions

#: how messages of an export started from this dialog name its options (its fields)
DIALOG_VOCABULARY = Vocabulary((
    ("min_web", "the dialog's Minimum web"), ("tolerance", "the dialog's Curve tolerance"),
    ("kerf", "the dialog's Kerf"), ("boss_radius", "the dialog's Boss radius"),
    ("bore_diameter", "the dialog's Bore diameter"), ("link_width", "the dialog's Link width"),
    ("depth", "the dialog's Plate depth"), ("frame", "the dialog's Frame"),
    ("arcs_entities", "the dialog's DXF entities: LINE and ARC"), ("annotate", "the dialog's Annotate box"),
    ("fasteners", "the dialog's Fasteners"), ("base_plate", "the dialog's Base plate box"),
    ("bore_key", "the dialog's Bore key")),
    "the export dialog")
#: what the DXF entity styles are for (shown in the dialog)
ARC_CHOICES = (("bulge", "Bulge polylines: AutoCAD, LibreCAD, QCAD, FreeCAD, GDAL"),
               ("entities", "LINE and ARC: older CAM (dxf2gcode, some plasma and laser software)"))
#: element type -> the plate fields that apply
PLATE_FIELDS = {"linkage": ("boss_radius", "bore_diameter", "link_width", "frame", "bore_key", "fasteners", "base_plate"),
                "rolling_lever": ("depth", "fasteners", "base_plate"), "geneva": ("bore_key",),
                "gear_pair": ("bore_key",), "geared_geneva": ("bore_key",)}
#: the bore key choices: (PartOptions.bore_key, shown)
KEY_CHOICES = ((None, "none"), ("keyway", "keyway (DIN 6885-1)"), ("flat", "flat (D-bore)"))
FITTED = ("linkage", "rolling_lever")


@dataclass(frozen=True)
class ExportRequest:
    """What to export: ``element_id``; ``fmt`` "dxf" | "svg"; ``layout`` "apart" | "assembled";
    ``parts`` (None: all); ``split`` one file per part; ``arcs`` "bulge" | "entities" (DXF);
    ``options`` (tolerance, minimum web, plate sizes); ``annotate``: names and traced curves on
    NOTES_ layers; ``kerf`` (mm): write the tool paths."""

    element_id: str
    fmt: str = "dxf"
    layout: str = "apart"
    parts: tuple[str, ...] | None = None
    split: bool = False
    arcs: str = "bulge"
    options: PartOptions = field(default_factory=PartOptions)
    annotate: bool = False
    kerf: float = 0.0


def _size(suffix: str = " mm", top: float = 1000.0, decimals: int = 3, special: str = "default") -> QDoubleSpinBox:
    box = QDoubleSpinBox()
    box.setDecimals(decimals)
    box.setRange(0.0, top)
    box.setSuffix(suffix)
    if special:
        box.setSpecialValueText(special)   # 0: the scene's drawing block, else scaled to the part
    return box


class ExportDialog(QDialog):
    """The form behind :class:`ExportRequest`; ``choices`` maps element id -> its part names,
    ``kinds`` element id -> type (which fields apply), ``sizes`` preferred plate sizes (mm)."""

    def __init__(self, title: str, choices: dict[str, tuple[str, ...]], default_id: str, fmt: str,
                 min_webs: dict[str, float] | None = None, parent: QWidget | None = None,
                 kinds: dict[str, str] | None = None, sizes: dict[str, float] | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle(title)
        self.fmt = fmt
        self.choices = choices
        self.kinds = kinds or {}
        self.min_webs = min_webs or {}
        form = QFormLayout(self)
        self.element = QComboBox()
        self.element.addItems(list(choices))
        self.element.setCurrentText(default_id)
        self.parts = QLineEdit()
        self.layout_box = QComboBox()
        self.layout_box.addItems(["apart", "assembled"])
        self.split = QCheckBox("one file per part")
        self.arcs = QComboBox()
        for key, text in ARC_CHOICES:
            self.arcs.addItem(text, key)
        self.arcs.setEnabled(fmt == "dxf")
        self.arcs.setToolTip("Bulge polylines are read exactly by CAD programs and GDAL; CAM importers that drop or "
                             "misread bulges (2–42 % off in a test) need LINE and ARC entities.")
        self.annotate = QCheckBox("part names and traced curves, on NOTES_ layers (not cut)")
        self.kerf = _size(top=10.0, special="none")
        self.kerf.setToolTip("Width of the cut: outlines are written kerf/2 outside, holes kerf/2 inside")
        self.tolerance = QDoubleSpinBox()
        self.tolerance.setDecimals(6)
        self.tolerance.setRange(1e-6, 10.0)
        self.tolerance.setValue(DEFAULT_TOLERANCE)
        self.tolerance.setSuffix(" mm")
        self.min_web = _size(special="")
        self.boss_radius, self.bore_diameter, self.link_width, self.depth = _size(), _size(), _size(), _size()
        self.frame = QComboBox()
        self.frame.addItems(["plate", "drill"])
        self.frame.setToolTip("plate: the frame as a plate; drill: only the drilling pattern of its pivots")
        self.fasteners = _size(top=100.0, special="none")
        self.fasteners.setToolTip("Diameter of two fastener holes in the frame and slider plates, matched in the "
                                  "frame's drilling pattern or base plate")
        self.base_plate = QCheckBox("a plate carrying every pivot and the frame's fasteners")
        self.bore_key = QComboBox()
        for key, text in KEY_CHOICES:
            self.bore_key.addItem(text, key)
        self.bore_key.setToolTip("Key the shaft bores (Geneva wheel and crank, a linkage's driver)")
        for name, box in (("boss_radius", self.boss_radius), ("bore_diameter", self.bore_diameter),
                          ("link_width", self.link_width)):
            box.setValue((sizes or {}).get(name, 0.0))
        self.readers = QLabel()
        self.readers.setWordWrap(True)
        self.readers.setMinimumHeight(3 * self.readers.fontMetrics().lineSpacing())   # two lines, not clipped
        for label, w in (("Element", self.element), ("Parts", self.parts), ("Layout", self.layout_box),
                         ("", self.split), ("DXF entities", self.arcs), ("", self.readers), ("Annotate", self.annotate),
                         ("Kerf", self.kerf), ("Curve tolerance", self.tolerance), ("Minimum web", self.min_web),
                         ("Boss radius", self.boss_radius), ("Bore diameter", self.bore_diameter),
                         ("Link width", self.link_width), ("Frame", self.frame), ("Plate depth", self.depth),
                         ("Fasteners", self.fasteners), ("Base plate", self.base_plate), ("Bore key", self.bore_key)):
            form.addRow(label, w)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)
        self.element.currentTextChanged.connect(self._element_changed)
        self.arcs.currentIndexChanged.connect(self._arcs_changed)
        self._element_changed(default_id)
        self._arcs_changed()

    def _element_changed(self, eid: str) -> None:
        names = self.choices.get(eid, ())
        self.parts.setPlaceholderText("all: " + ", ".join(names))
        self.parts.clear()
        self.min_web.setValue(self.min_webs.get(eid, DEFAULT_MIN_WEB))
        kind = self.kinds.get(eid)
        fields = PLATE_FIELDS.get(kind, ())
        for name in ("boss_radius", "bore_diameter", "link_width", "frame", "depth", "fasteners", "base_plate",
                     "bore_key"):
            getattr(self, name).setEnabled(name in fields)
        self.tolerance.setEnabled(kind in FITTED or kind is None)

    def _arcs_changed(self) -> None:
        if self.fmt != "dxf":
            self.readers.setText("SVG: arcs as SVG arcs of at most 90°, in millimetres")
        elif self.arcs.currentData() == "bulge":
            self.readers.setText("Read exactly by CAD programs and GDAL; choose LINE and ARC for CAM importers that "
                                 "drop or misread bulges.")
        else:
            self.readers.setText("LINE and ARC entities: for older CAM importers.")

    def request(self) -> ExportRequest:
        """The request the form describes (fields that do not apply are left out)."""
        names = tuple(n.strip() for n in self.parts.text().split(",") if n.strip()) or None

        def value(box):
            return box.value() if box.isEnabled() and box.value() > 0 else None

        opts = PartOptions(tolerance=self.tolerance.value(), min_web=self.min_web.value(),
                           boss_radius=value(self.boss_radius), bore_diameter=value(self.bore_diameter),
                           link_width=value(self.link_width), depth=value(self.depth),
                           frame=self.frame.currentText() if self.frame.isEnabled() else "plate",
                           fasteners=value(self.fasteners),
                           base_plate=self.base_plate.isEnabled() and self.base_plate.isChecked(),
                           bore_key=self.bore_key.currentData() if self.bore_key.isEnabled() else None,
                           vocabulary=DIALOG_VOCABULARY)
        return ExportRequest(self.element.currentText(), self.fmt, self.layout_box.currentText(), names,
                             self.split.isChecked(), self.arcs.currentData() if self.fmt == "dxf" else "bulge", opts,
                             self.annotate.isChecked(), self.kerf.value())
