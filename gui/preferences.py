"""Edit › Preferences (Ctrl+,): the units shown, grid and snap, default samples, the autosave
interval, the dead-point policy, and the defaults of new parts — kept in the settings file.

:class:`Preferences` is the record (model units: mm, seconds); :func:`load_preferences` and
:func:`save_preferences` read and write it under ``preferences/`` in the app's QSettings INI file
(a value that cannot be read falls back to its default, with nothing lost elsewhere);
:class:`PreferencesDialog` edits it (lengths shown in the chosen length unit); and
:func:`apply_preferences` hands each value to the part of the app that uses it:

- units -> :mod:`mechsketch.gui.units` (every Properties field, the Dimensions table, the plots,
  the cursor read-out);
- snap on at start and a fixed snap step -> the canvas (:attr:`CanvasView.fixed_snap_step`);
- samples per cycle -> new linkages drawn with the tools;
- autosave interval -> :class:`~mechsketch.gui.autosave.Autosave`;
- dead-point policy -> the animation player;
- materials -> new Geneva drives (roller, wheel); plate sizes -> the export's defaults.

Inch is a display and entry unit only: scene files always hold millimetres.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from PySide6.QtCore import QEvent, QObject, QSettings, Qt
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDialogButtonBox, QDoubleSpinBox, QFormLayout,
                               QLabel, QSpinBox, QTabWidget, QVBoxLayout, QWidget)

from mechsketch.core.model.geneva import Material

from . import units
from .units import Units
from .qtsafe import qt_safe

#: materials a new Geneva drive's roller and wheel may be made of: name -> (E MPa, Poisson's ratio)
MATERIALS: dict[str, tuple[float, float]] = {
    "steel": (210000.0, 0.30), "stainless steel": (193000.0, 0.29), "cast iron": (110000.0, 0.26),
    "bronze": (110000.0, 0.34), "brass": (100000.0, 0.34), "aluminium": (70000.0, 0.33),
    "POM (acetal)": (2900.0, 0.35), "PA6 (nylon)": (2700.0, 0.39),
}
DEAD_POINTS = ("reverse", "stop")
SAMPLES_RANGE = (8, 1_000_000)
AUTOSAVE_RANGE_S = (5, 3600)


@dataclass(frozen=True)
class Preferences:
    """What the user prefers; lengths in mm, 0 for a size meaning "scaled to the part"."""

    length_unit: str = "mm"
    angle_unit: str = "deg"
    speed_unit: str = "rpm"
    snap: bool = True              # snapping on when the app starts
    snap_step: float = 0.0         # mm; 0: the grid's minor step at the zoom
    samples: int = 360             # samples per cycle of a new linkage
    autosave_s: int = 60
    dead_points: str = "reverse"   # the animation at a dead point: "reverse" or "stop"
    roller_material: str = "steel"
    wheel_material: str = "steel"
    boss_radius: float = 0.0       # link plates (mm; 0: scaled to the linkage)
    bore_diameter: float = 0.0
    link_width: float = 0.0
    min_web: float = 0.0           # 0: the element's or 1 mm

    @property
    def units(self) -> Units:
        return Units(self.length_unit, self.angle_unit, self.speed_unit)

    def problems(self) -> list[str]:
        """What is out of range (empty: every value is usable)."""
        out = []
        try:
            self.units
        except ValueError as exc:
            out.append(str(exc))
        if not SAMPLES_RANGE[0] <= self.samples <= SAMPLES_RANGE[1]:
            out.append(f"samples {self.samples} outside {SAMPLES_RANGE[0]}..{SAMPLES_RANGE[1]:,}")
        if not AUTOSAVE_RANGE_S[0] <= self.autosave_s <= AUTOSAVE_RANGE_S[1]:
            out.append(f"autosave every {self.autosave_s} s: outside {AUTOSAVE_RANGE_S[0]}..{AUTOSAVE_RANGE_S[1]} s")
        if self.dead_points not in DEAD_POINTS:
            out.append(f"dead-point policy {self.dead_points!r} is not one of {', '.join(DEAD_POINTS)}")
        for name in ("roller_material", "wheel_material"):
            if getattr(self, name) not in MATERIALS:
                out.append(f"{name.replace('_', ' ')} {getattr(self, name)!r} is not one of {', '.join(MATERIALS)}")
        for name in ("snap_step", "boss_radius", "bore_diameter", "link_width", "min_web"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0.0 <= v <= 1e6):
                out.append(f"{name.replace('_', ' ')} {v} mm: 0 (automatic) to 1e6 mm")
        return out

    def material(self, part: str) -> Material:
        """The :class:`Material` chosen for a new Geneva drive's ``part`` ("roller" or "wheel")."""
        e, nu = MATERIALS[getattr(self, f"{part}_material")]
        return Material(e, nu)


def load_preferences(settings: QSettings) -> Preferences:
    """The preferences stored in ``settings``; each value that is missing or unreadable (or out of
    range) is its default."""
    base = Preferences()
    values: dict[str, Any] = {}
    for f in fields(Preferences):
        raw = settings.value(f"preferences/{f.name}")
        if raw is None:
            continue
        try:
            value = _read(raw, type(getattr(base, f.name)))
        except (TypeError, ValueError):
            continue
        if not replace(base, **{f.name: value}).problems():
            values[f.name] = value
    return replace(base, **values)


def _read(raw: Any, kind: type) -> Any:
    if kind is bool:
        if isinstance(raw, bool):
            return raw
        text = str(raw).strip().lower()
        if text not in ("true", "false", "1", "0"):
            raise ValueError(raw)
        return text in ("true", "1")
    if kind is int:
        return int(str(raw))
    if kind is float:
        return float(str(raw))
    return str(raw)


def save_preferences(settings: QSettings, prefs: Preferences) -> None:
    """Write ``prefs`` under ``preferences/`` (and sync the file)."""
    for name, value in asdict(prefs).items():
        settings.setValue(f"preferences/{name}", value)
    settings.sync()


def apply_preferences(prefs: Preferences, window: Any, autosave: bool = True) -> None:
    """Hand each preference to the part of the app that uses it (see the module docstring);
    ``autosave`` False keeps the autosave interval the app was started with (tests)."""
    from .canvas import geneva_tool, ops

    if prefs.units != units.current():
        units.set_current(prefs.units)
        for panel in (getattr(window, "properties", None),):   # the panels that show model values
            if hasattr(panel, "units_changed"):
                panel.units_changed()
        plots = getattr(window, "docks", {}).get("plots")
        if plots is not None and not getattr(plots, "pending", False) and hasattr(plots.widget(), "refresh"):
            plots.widget().refresh()
    canvas = getattr(window, "canvas", None)
    if hasattr(canvas, "snap_enabled"):
        canvas.snap_enabled = prefs.snap
        canvas.fixed_snap_step = prefs.snap_step
    ops.NEW_LINKAGE_SAMPLES = prefs.samples
    geneva_tool.NEW_MATERIALS = (prefs.material("roller"), prefs.material("wheel"))
    player = getattr(window, "player", None)
    if hasattr(player, "set_dead_point_behaviour"):
        player.set_dead_point_behaviour(prefs.dead_points)
    if autosave and getattr(window, "autosave", None) is not None:
        window.autosave.set_interval(prefs.autosave_s * 1000)


def part_options(prefs: Preferences, options):
    """``options`` (a :class:`PartOptions`) with the preferred plate sizes where it has none."""
    sizes = {"boss_radius": prefs.boss_radius, "bore_diameter": prefs.bore_diameter,
             "link_width": prefs.link_width}
    return replace(options, **{k: v for k, v in sizes.items() if v > 0 and getattr(options, k) is None})


def open_preferences_dialog(window: Any) -> None:
    """Show the dialog over ``window`` (window-modal, not blocking); OK stores and applies."""
    dlg = getattr(window, "preferences_dialog", None)
    if dlg is not None and dlg.isVisible():
        dlg.raise_()
        return
    dlg = PreferencesDialog(window.preferences, window)
    dlg.accepted.connect(lambda: window.set_preferences(dlg.value()))
    window.preferences_dialog = dlg
    dlg.open()


def store_preferences(window: Any, prefs: Preferences) -> bool:
    """Save ``prefs`` in ``window``'s settings file and apply them; False (the reason shown) if a
    value is out of range."""
    problems = prefs.problems()
    if problems:
        window.dialogs.error("Preferences", "Not saved: " + "; ".join(problems))
        return False
    save_preferences(window.file_ops.settings, prefs)
    apply_preferences(prefs, window)
    window.preferences = prefs
    window.show_message(f"preferences saved: lengths in {prefs.length_unit}, angles in "
                        f"{'°' if prefs.angle_unit == 'deg' else 'rad'}, speeds in {prefs.speed_unit}")
    return True


@qt_safe
class _NoWheelUnlessFocused(QObject):
    """Spin boxes and combo boxes of the dialog change on the wheel only when they have focus."""

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt override
        if event.type() == QEvent.Type.Wheel and isinstance(obj, QWidget) and not obj.hasFocus():
            event.ignore()
            return True
        return False


class PreferencesDialog(QDialog):
    """The preferences form: tabs Units, Canvas, Analysis and files, New parts. :meth:`value`
    is what the form holds now; *Restore Defaults* fills in the defaults."""

    def __init__(self, prefs: Preferences, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setObjectName("preferencesDialog")
        self.setWindowTitle("Preferences")
        self._wheel = _NoWheelUnlessFocused(self)
        self.widgets: dict[str, QWidget] = {}
        tabs = QTabWidget()
        tabs.addTab(self._units_tab(), "Units")
        tabs.addTab(self._canvas_tab(), "Canvas")
        tabs.addTab(self._analysis_tab(), "Analysis and files")
        tabs.addTab(self._parts_tab(), "New parts")
        self.tabs = tabs
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel
                                   | QDialogButtonBox.StandardButton.RestoreDefaults)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        buttons.button(QDialogButtonBox.StandardButton.RestoreDefaults).clicked.connect(
            lambda: self.set_value(Preferences()))
        self.buttons = buttons
        layout = QVBoxLayout(self)
        layout.addWidget(tabs)
        layout.addWidget(QLabel("Inch is for display and typing only: files always hold millimetres."))
        layout.addWidget(buttons)
        self.widgets["length_unit"].currentIndexChanged.connect(self._length_unit_changed)
        self._shown_length = prefs.length_unit
        self.set_value(prefs)

    # -- widgets -------------------------------------------------------------------------------
    def _combo(self, name: str, items: list[tuple[str, str]]) -> QComboBox:
        box = QComboBox()
        box.setObjectName(name)
        for text, data in items:
            box.addItem(text, data)
        self._guard(box, name)
        return box

    def _spin(self, name: str, lo: float, hi: float, decimals: int = 3, special: str = "") -> QDoubleSpinBox:
        box = QDoubleSpinBox()
        box.setObjectName(name)
        box.setDecimals(decimals)
        box.setRange(lo, hi)
        if special:
            box.setSpecialValueText(special)    # shown at the minimum (0): automatic
        self._guard(box, name)
        return box

    def _guard(self, box: QWidget, name: str) -> None:
        box.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        box.installEventFilter(self._wheel)
        self.widgets[name] = box

    def _form(self, rows: list[tuple[str, QWidget]]) -> QWidget:
        page = QWidget()
        form = QFormLayout(page)
        for label, w in rows:
            form.addRow(label, w)
        return page

    def _units_tab(self) -> QWidget:
        return self._form([
            ("Lengths", self._combo("length_unit", [("millimetres (mm)", "mm"), ("inches (in)", "in")])),
            ("Angles", self._combo("angle_unit", [("degrees (°)", "deg"), ("radians (rad)", "rad")])),
            ("Speeds", self._combo("speed_unit", [("revolutions per minute (rpm)", "rpm"),
                                                  ("radians per second (rad/s)", "rad/s")]))])

    def _canvas_tab(self) -> QWidget:
        snap = QCheckBox("snap to the grid and to joints when the app starts (F9 switches it)")
        snap.setObjectName("snap")
        self.widgets["snap"] = snap
        return self._form([("Snap", snap),
                           ("Snap step", self._spin("snap_step", 0.0, 1e6, 4, "follows the grid"))])

    def _analysis_tab(self) -> QWidget:
        samples = QSpinBox()
        samples.setObjectName("samples")
        samples.setRange(*SAMPLES_RANGE)
        samples.setSingleStep(360)
        samples.setSuffix(" per cycle")
        self._guard(samples, "samples")
        autosave = QSpinBox()
        autosave.setObjectName("autosave_s")
        autosave.setRange(*AUTOSAVE_RANGE_S)
        autosave.setSuffix(" s")
        self._guard(autosave, "autosave_s")
        return self._form([
            ("Samples of a new linkage", samples),
            ("At a dead point the animation", self._combo("dead_points", [("reverses", "reverse"),
                                                                         ("stops", "stop")])),
            ("Autosave unsaved work every", autosave)])

    def _parts_tab(self) -> QWidget:
        mats = [(f"{name} (E {e / 1000:g} GPa, ν {nu:g})", name) for name, (e, nu) in MATERIALS.items()]
        rows: list[tuple[str, QWidget]] = [("Geneva roller", self._combo("roller_material", mats)),
                                           ("Geneva wheel", self._combo("wheel_material", mats))]
        for name, label in (("boss_radius", "Link plates: boss radius"), ("bore_diameter", "bore diameter"),
                            ("link_width", "link width"), ("min_web", "Minimum web")):
            rows.append((label, self._spin(name, 0.0, 1e6, 4, "scaled to the part")))
        return self._form(rows)

    # -- values --------------------------------------------------------------------------------
    LENGTHS = ("snap_step", "boss_radius", "bore_diameter", "link_width", "min_web")

    def _length_unit_changed(self) -> None:
        """The sizes follow the length unit chosen (the same lengths, in the new unit)."""
        new = self.widgets["length_unit"].currentData()
        old_units, new_units = Units(length=self._shown_length), Units(length=new)
        for name in self.LENGTHS:
            box = self.widgets[name]
            mm = units.to_model(box.value(), "mm", old_units)
            box.setSuffix(f" {new}")
            box.setValue(units.to_display(mm, "mm", new_units))
        self._shown_length = new

    def set_value(self, prefs: Preferences) -> None:
        """Fill the form with ``prefs``."""
        for name in ("length_unit", "angle_unit", "speed_unit", "dead_points", "roller_material",
                     "wheel_material"):
            box: QComboBox = self.widgets[name]
            box.setCurrentIndex(max(0, box.findData(getattr(prefs, name))))
        shown = Units(length=prefs.length_unit)
        self._shown_length = prefs.length_unit
        for name in self.LENGTHS:
            box = self.widgets[name]
            box.setSuffix(f" {prefs.length_unit}")
            box.setValue(units.to_display(getattr(prefs, name), "mm", shown))
        self.widgets["snap"].setChecked(prefs.snap)
        self.widgets["samples"].setValue(prefs.samples)
        self.widgets["autosave_s"].setValue(prefs.autosave_s)

    def value(self) -> Preferences:
        """The preferences the form holds (lengths back in mm)."""
        w = self.widgets
        shown = Units(length=w["length_unit"].currentData())
        sizes = {n: units.to_model(w[n].value(), "mm", shown) for n in self.LENGTHS}
        return Preferences(w["length_unit"].currentData(), w["angle_unit"].currentData(),
                           w["speed_unit"].currentData(), w["snap"].isChecked(), sizes["snap_step"],
                           w["samples"].value(), w["autosave_s"].value(), w["dead_points"].currentData(),
                           w["roller_material"].currentData(), w["wheel_material"].currentData(),
                           sizes["boss_radius"], sizes["bore_diameter"], sizes["link_width"], sizes["min_web"])
