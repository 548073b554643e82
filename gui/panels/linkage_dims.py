"""The linkage's dimensions and its driver in the properties panel.

- :func:`link_dimension_rows`: the selected link's lengths, angles and slide-axis offsets as
  number fields (``length:A-B``, ``angle:B-C-E``, ``offset:S``, ``axis:S``), the ground's and a
  ternary link's included;
- :func:`dimensions_box`: the table of every dimension of the linkage (link, dimension, value,
  unit), its values editable;
- :func:`driver_box`: what drives the linkage (crank, cylinder, slider), its motion law, speed,
  direction (a crank) or stroke (an actuator); :func:`drive_button`: "Drive this…" on a link
  pivoted on the frame (a crank) or on a prismatic joint (a cylinder or a slider).

Every edit is one core edit through ``controller.push``: a dimension is a
:class:`~mechsketch.core.solver.dimensions.SetDimension` (the core re-assembles the linkage at its
drawn input, or refuses naming the group and by how much — the message goes to the status bar and
the field or cell shows the model again); the driver is a ``ReplaceElement`` whose new linkage the
controller solves first. Widgets hold no model state.
"""
from __future__ import annotations

import math
from dataclasses import replace

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (QAbstractItemView, QComboBox, QFormLayout, QGroupBox, QHeaderView, QLabel,
                               QLineEdit, QTableWidget, QTableWidgetItem, QToolButton)

from mechsketch.core import EditError, MechsketchError, ReplaceElement
from mechsketch.core.model.drivers import DriverKind, LawKind, MotionLaw
from mechsketch.core.model.linkage import Driver, JointKind, Linkage
from mechsketch.core.solver.dimensions import SetDimension, dimensions

from .. import units

#: the laws offered in the driver box (a table law comes from a file or the Python API)
LAWS = (("constant speed", LawKind.CONSTANT), ("cycloidal", LawKind.CYCLOIDAL), ("harmonic", LawKind.HARMONIC),
        ("modified trapezoid", LawKind.MODIFIED_TRAPEZOID))


def field_name(key: str) -> str:
    """The properties field of a dimension key: ``length:crank:A:B`` -> ``length:A-B``."""
    kind, _link, *joints = key.split(":")
    return f"{kind}:{'-'.join(joints)}"


def push_dimension(panel, eid: str, key: str, value: float) -> None:
    """Set one dimension as one undo command; EditError (the core's reason) when it is refused."""
    edit = SetDimension(eid, key, value, f"set {key.split(':', 1)[0]} {':'.join(key.split(':')[2:])}")
    panel.controller.workspace.check(edit)   # raises the core's reason (which group, by how much)
    panel.controller.push(edit, edit.label)


def link_dimension_rows(panel, form: QFormLayout, eid: str, kid: str) -> None:
    """Number fields for every dimension of link ``kid`` (see the module docstring)."""
    lk: Linkage = panel.controller.scene.element(eid)
    for d in dimensions(lk):
        if d.link != kid:
            continue

        def read(key: str = d.key) -> float:
            return next(x.value for x in dimensions(panel.controller.scene.element(eid)) if x.key == key)

        edit = panel.number_field(field_name(d.key), read, lambda v, key=d.key: push_dimension(panel, eid, key, v))
        edit.setToolTip("Sets this dimension; every other one is kept and the linkage is re-assembled at its "
                        "drawn input in its assembly modes (refused, with the reason, where it cannot close).")
        form.addRow(d.label, panel.row(edit, d.unit))


def dimensions_box(panel, eid: str) -> QGroupBox:
    """The table of every dimension of linkage ``eid``; a value typed in a cell sets it."""
    box = QGroupBox(f"Dimensions ({eid})")
    form = QFormLayout(box)
    table = QTableWidget(0, 4)
    table.setObjectName("dimensions")
    table.setHorizontalHeaderLabels(["link", "dimension", "value", "unit"])
    table.verticalHeader().setVisible(False)
    head = table.horizontalHeader()
    head.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)   # values are read whole,
    head.setSectionResizeMode(1, QHeaderView.ResizeMode.Stretch)         # a long label is elided
    table.setTextElideMode(Qt.TextElideMode.ElideMiddle)
    table.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)   # every row shown:
    table.setVerticalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)     # the panel scrolls
    table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
    table.setEditTriggers(QAbstractItemView.EditTrigger.DoubleClicked | QAbstractItemView.EditTrigger.EditKeyPressed
                          | QAbstractItemView.EditTrigger.AnyKeyPressed)
    panel.tables["dimensions"] = table
    keys: list[str] = []
    shown: list = [None]   # (element, units) the values show: a refresh of the same is free

    def show(force: bool = False) -> None:
        try:
            el = panel.controller.scene.element(eid)
        except MechsketchError:
            return
        if not force and shown[0] is not None and shown[0][0] is el and shown[0][1] == units.current():
            return   # (a 1,000-joint linkage: 1.5 s of dimensions per refresh)
        try:
            rows = dimensions(el)
        except MechsketchError:
            return
        shown[0] = (el, units.current())
        table.blockSignals(True)
        if [d.key for d in rows] != keys:
            keys[:] = [d.key for d in rows]
            table.setRowCount(len(rows))
            for r, d in enumerate(rows):
                for c, text in ((0, d.link), (1, d.label), (3, units.display_unit(d.unit))):
                    item = QTableWidgetItem(text)
                    item.setToolTip(text)
                    item.setFlags(item.flags() & ~Qt.ItemFlag.ItemIsEditable)
                    table.setItem(r, c, item)
                item = QTableWidgetItem()
                item.setData(Qt.ItemDataRole.UserRole, d.key)
                item.setToolTip(d.key)
                table.setItem(r, 2, item)
        for r, d in enumerate(rows):
            table.item(r, 2).setText(units.format_value(d.value, d.unit))   # in the display unit
        table.blockSignals(False)
        table.setFixedHeight(head.height() + 4 + sum(table.rowHeight(r) for r in range(len(rows))))

    def edited(item: QTableWidgetItem) -> None:
        if item.column() != 2:
            return
        key = item.data(Qt.ItemDataRole.UserRole)
        try:   # typed in the display unit (or with its own); back in the model's
            value = units.parse(item.text(), next(d.unit for d in dimensions(panel.controller.scene.element(eid))
                                                  if d.key == key))
        except ValueError as exc:
            panel.controller.message.emit(f"{key}: {exc}")
            show(force=True)
            return
        try:
            push_dimension(panel, eid, key, value)
        except MechsketchError as exc:
            panel.controller.message.emit(f"cannot set {key}: {exc}")
        show(force=True)   # what the model holds now (the typed text replaced)

    table.itemChanged.connect(edited)
    panel.add_refresher(show)
    form.addRow(table)
    return box


def _push_driver(panel, eid: str, driver: Driver, text: str) -> bool:
    """Replace the driver as one undo command, after the workspace solved the new linkage."""
    lk = panel.controller.scene.element(eid)
    new = lk.with_driver(driver)
    edit = ReplaceElement(new, text)
    panel.controller.workspace.check(edit)   # read as a file would be: the speed's range, the stroke
    problem = panel.controller.check_element(new)
    if problem is not None:
        raise EditError(problem)
    return panel.controller.push(edit, text)


def driver_box(panel, eid: str) -> QGroupBox:
    """What drives linkage ``eid`` and how (see the module docstring)."""
    ctl = panel.controller

    def drv() -> Driver:
        return ctl.scene.element(eid).driver

    d = drv()
    kinds = {DriverKind.CRANK: "crank", DriverKind.CYLINDER: "cylinder", DriverKind.SLIDER: "slider"}
    box = QGroupBox(f"Driver: {kinds[d.kind]} {d.link} on {d.pivot} ({eid})")
    form = QFormLayout(box)

    def write_speed(v: float) -> None:
        if v <= 0:
            raise EditError("the speed must be positive (choose the direction below)")
        sign = 1.0 if drv().speed_rpm > 0 else -1.0
        _push_driver(panel, eid, replace(drv(), speed_rpm=sign * v), "set driver speed")
    speed = panel.number_field("speed", lambda: abs(drv().speed_rpm), write_speed)
    speed.setToolTip("cycles per minute: crank revolutions, or actuator strokes out and back")
    form.addRow("speed", panel.row(speed, "rpm" if d.kind is DriverKind.CRANK else "cycles/min"))
    period = QLabel()
    period.setWordWrap(True)
    panel.add_refresher(lambda: period.setText(f"{drv().period:.6g} s per cycle, {abs(drv().omega):.6g} rad/s"))
    form.addRow("", period)
    if d.kind is DriverKind.CRANK:
        direction = QComboBox()
        direction.setObjectName("direction")
        direction.addItems(["CCW", "CW"])
        direction.setToolTip("turning sense of the driver: counter-clockwise (CCW) or clockwise (CW)")
        panel.direction = direction

        def show_direction() -> None:
            direction.blockSignals(True)
            direction.setCurrentIndex(0 if drv().speed_rpm > 0 else 1)
            direction.blockSignals(False)

        def write_direction(index: int) -> None:
            want = abs(drv().speed_rpm) * (1.0 if index == 0 else -1.0)
            if want != drv().speed_rpm:
                try:
                    _push_driver(panel, eid, replace(drv(), speed_rpm=want), "reverse driver")
                except MechsketchError as exc:
                    ctl.message.emit(f"cannot reverse the driver: {exc}")
            show_direction()
        direction.activated.connect(write_direction)
        panel.add_refresher(show_direction)
        form.addRow("direction", direction)
    else:
        for i, label in ((0, "stroke from"), (1, "stroke to")):
            def write_stroke(v: float, i: int = i) -> None:
                stroke = list(drv().stroke)
                stroke[i] = v
                if not stroke[0] < stroke[1]:
                    raise EditError(f"the stroke must increase, got {stroke[0]:g} to {stroke[1]:g} mm")
                _push_driver(panel, eid, replace(drv(), stroke=(stroke[0], stroke[1])), "set stroke")
            edit = panel.number_field(f"stroke.{i}", lambda i=i: drv().stroke[i], write_stroke)
            edit.setToolTip("the input over a cycle: " + ("the cylinder's length between its pivots" if
                                                          d.kind is DriverKind.CYLINDER else
                                                          "the slider's travel from its drawn place"))
            form.addRow(label, panel.row(edit, "mm"))
    law = QComboBox()
    law.setObjectName("law")
    for text, kind in LAWS + (("table (spline)", LawKind.TABLE),):
        law.addItem(text, kind)
    law.setToolTip("how the input moves over a cycle; velocities and accelerations follow the law's closed form")
    panel.combos["law"] = law

    def show_law() -> None:
        law.blockSignals(True)
        law.setCurrentIndex(next((k for k in range(law.count()) if law.itemData(k) == drv().law.kind), 0))
        law.blockSignals(False)

    def write_law(index: int) -> None:
        kind = LawKind(law.itemData(index))
        if kind != drv().law.kind:
            new = MotionLaw(kind, default_table(drv()) if kind is LawKind.TABLE else ())
            try:
                _push_driver(panel, eid, replace(drv(), law=new), f"motion law {kind.value}")
            except MechsketchError as exc:
                ctl.message.emit(f"cannot set the motion law: {exc}")
        show_law()
    law.activated.connect(write_law)
    panel.add_refresher(show_law)
    form.addRow("motion law", law)
    if d.law.kind is LawKind.TABLE:
        form.addRow("table", table_field(panel, eid, drv))
    return box


def default_table(d: Driver) -> tuple[tuple[float, float], ...]:
    """A first table law to edit: a crank's turn slowed in its middle (degrees from the drawn
    angle), an actuator's stroke out and back with a pause at its end (mm)."""
    if d.linear and d.stroke is not None:
        lo, hi = d.stroke
        return ((0.0, lo), (0.4, hi), (0.6, hi), (1.0, lo))
    return ((0.0, 0.0), (0.3, 150.0), (0.7, 210.0), (1.0, 360.0))


def points_text(points) -> str:
    """A table law's points as typed in the field: ``τ value; τ value; …``."""
    return "; ".join(f"{t:g} {v:g}" for t, v in points)


def table_field(panel, eid: str, drv) -> QLineEdit:
    """The table law's points, editable as ``τ value; τ value; …`` (τ: the fraction of the cycle;
    value: degrees from the drawn angle for a crank, mm for an actuator)."""
    edit = QLineEdit()
    edit.setObjectName("law.points")
    edit.setToolTip("cycle fraction and value per point, separated by ';' (a crank: degrees from its drawn angle, "
                    "a last point at 1 may add whole turns; an actuator: mm). A periodic cubic spline passes "
                    "through them.")
    panel.fields["law.points"] = edit

    def show() -> None:
        if not (edit.hasFocus() and edit.isModified()):
            edit.setText(points_text(drv().law.points))
            edit.setModified(False)

    def commit() -> None:
        text = edit.text().strip()
        if text != points_text(drv().law.points):
            try:
                points = tuple(tuple(float(x) for x in item.split()) for item in text.split(";") if item.strip())
                if any(len(p) != 2 for p in points):
                    raise ValueError
            except ValueError:
                panel.controller.message.emit(f"table: {text!r} is not 'τ value; τ value; …'")
            else:
                try:
                    _push_driver(panel, eid, replace(drv(), law=MotionLaw(LawKind.TABLE, points)), "set law table")
                except MechsketchError as exc:
                    panel.controller.message.emit(f"table: {exc}")
        edit.setModified(False)
        show()

    edit.editingFinished.connect(commit)
    panel.add_refresher(show)
    return edit


#: strokes tried for a new actuator, as fractions of its length (a cylinder) or of the linkage's size
#: (a slider) about the drawn input: the first over which the linkage assembles everywhere is taken
STROKES = ((0.0, 0.2), (-0.2, 0.0), (-0.1, 0.1), (0.0, 0.05), (-0.05, 0.0), (-0.02, 0.02))


def drivable(lk: Linkage, kind: str, ident: str) -> tuple[DriverKind, list[Driver]] | None:
    """The drivers that would make the selected joint or link the input, or None: a link pivoted
    on the frame by a revolute joint becomes a crank; a prismatic joint between two binary links
    pinned at their ends becomes a cylinder; a prismatic joint of the frame makes its slider the
    input. An actuator gets one candidate per stroke of :data:`STROKES`."""
    ground = set(lk.link(lk.ground).joints)
    rpm = abs(lk.driver.speed_rpm) or 60.0
    if kind == "link":
        if ident == lk.ground or (ident == lk.driver.link and lk.driver.kind is DriverKind.CRANK):
            return None
        pivot = next((j for j in lk.link(ident).joints if j in ground and lk.joint(j).kind is JointKind.R), None)
        if pivot is None or len(lk.link(ident).joints) < 2:
            return None
        return DriverKind.CRANK, [Driver(ident, pivot, rpm)]
    joint = lk.joint(ident)
    if joint.kind is not JointKind.P or ident == lk.driver.pivot:
        return None
    carriers = lk.links_of(ident)
    if len(carriers) != 2:
        return None
    if lk.ground in carriers:
        slider = next(k for k in carriers if k != lk.ground)
        size = max((math.dist(lk.joint(a).at, lk.joint(b).at) for a in lk.joint_ids for b in lk.joint_ids),
                   default=100.0)
        return DriverKind.SLIDER, [Driver(slider, ident, rpm, DriverKind.SLIDER, (a * size, b * size))
                                   for a, b in STROKES]
    ends = []
    for k in carriers:
        others = [j for j in lk.link(k).joints if j != ident]
        if len(others) != 1 or lk.joint(others[0]).kind is not JointKind.R:
            return None
        ends.append(others[0])
    length = math.dist(lk.joint(ends[0]).at, lk.joint(ends[1]).at)
    return DriverKind.CYLINDER, [Driver(carriers[0], ident, rpm, DriverKind.CYLINDER,
                                        ((1 + a) * length, (1 + b) * length)) for a, b in STROKES]


def drive_button(panel, form: QFormLayout, eid: str, kind: str, ident: str) -> None:
    """A "Drive this …" button for the selected joint or link when it can be the input."""
    lk = panel.controller.scene.element(eid)
    found = drivable(lk, kind, ident)
    if found is None:
        return
    what, candidates = found
    button = QToolButton()
    button.setObjectName("drive")
    button.setText({DriverKind.CRANK: "Drive this link (crank)", DriverKind.CYLINDER: "Drive this cylinder",
                    DriverKind.SLIDER: "Drive this slider"}[what])
    button.setToolTip("Make it the linkage's input (one undo step); the old driver becomes an ordinary link")
    panel.buttons["drive"] = button

    def go() -> None:
        lk = panel.controller.scene.element(eid)
        driver = candidates[0]
        for d in candidates:   # the first stroke over which the linkage assembles everywhere
            res = panel.controller.workspace.result_of(lk.with_driver(d))
            if res is not None and res.solution is not None and bool(res.solution.valid.all()):
                driver = d
                break
        try:
            _push_driver(panel, eid, driver, f"drive {ident}")
        except MechsketchError as exc:
            panel.controller.message.emit(f"cannot drive {ident}: {exc}")
    button.clicked.connect(go)
    form.addRow("input", button)


__all__ = ["dimensions_box", "drivable", "drive_button", "driver_box", "field_name", "link_dimension_rows",
           "push_dimension"]
