"""The properties of a selected rolling lever: circles, pin, rocker pivot, slider, stroke, method.

Fields in the drawn pose (mm, degrees for the slider axis, rad for the stroke as in the scene
file): the lever circle and the slider circle (centre, radius), the contact branch, the slider
axis and side, the pin f, the rocker pivot G, the stroke θ from/to, the synthesis method (exact,
paper, corrected) and the number of intervals N, and the drive's crank pivot and coupler point
when the lever has a drive. Each edit is one undo step through
:func:`.element_props.push_changes`; a refused value (a stroke beyond the working range, a rocker
line missing the lever circle, ...) leaves the document as it was and the core's message in the
status bar. Read-only: the rocker length, the working range and the slider travel. "Methods side
by side" runs the three synthesis methods at the element's N and tabulates their slip measures.
"""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtWidgets import (QFormLayout, QGroupBox, QLabel, QPushButton, QTableWidget, QTableWidgetItem,
                               QVBoxLayout)

from mechsketch.core.errors import MechsketchError

from mechsketch.core.model.rolling_lever import METHODS, RollingLever

from mechsketch.core.workspace import RollingResult
from .element_props import combo_field, push_changes, whole_number

#: the order of the side-by-side columns
METHODS_SHOWN = ("exact", "corrected", "paper")


def _get(el: RollingLever, key: str):
    node = el.to_dict()
    for part in key.split("."):
        node = node[int(part)] if isinstance(node, list) else node[part]
    return node


def rolling_boxes(panel, element_id: str) -> list[QGroupBox]:
    """The group boxes of one rolling lever for the properties panel (fields registered on ``panel``)."""
    ctl = panel.controller

    def el() -> RollingLever:
        return ctl.scene.element(element_id)

    def push(changes: dict, label: str) -> None:
        push_changes(ctl, element_id, changes, f"{label} of {element_id}")

    def number(form: QFormLayout, key: str, label: str, unit: str, what: str, tip: str = "") -> None:
        """A field for a number (``key`` may name a list item: ``pin.0``); ``what`` names the undo step."""
        def write(v: float) -> None:
            head, _, tail = key.rpartition(".")
            if tail.isdigit():   # one coordinate of a point: write the whole point
                point = list(_get(el(), head))
                point[int(tail)] = v
                push({head: point}, f"set {what}")
            else:
                push({key: v}, f"set {what}")
        edit = panel.number_field(key, lambda: float(_get(el(), key)), write)
        edit.setToolTip(tip or what)
        form.addRow(label, panel.row(edit, unit))

    lever = QGroupBox(f"Rolling lever {element_id}: lever circle")
    form = QFormLayout(lever)
    number(form, "lever_circle.center.0", "centre x", "mm", "lever circle centre",
           "centre of the lever's circle rolling on the frame profile (drawn pose)")
    number(form, "lever_circle.center.1", "centre y", "mm", "lever circle centre")
    number(form, "lever_circle.radius", "radius R1", "mm", "lever circle radius")
    form.addRow("contact", combo_field(
        panel, "contact_branch", [("near", "near"), ("far", "far")],
        lambda: el().contact_branch, lambda v: push({"contact_branch": v}, "set contact branch"),
        "which intersection of the rocker line with the lever circle is the contact"))

    rocker = QGroupBox("Rocker")
    rform = QFormLayout(rocker)
    number(rform, "pin.0", "pin f x", "mm", "pin", "the rocker's pin on the lever (drawn pose)")
    number(rform, "pin.1", "pin f y", "mm", "pin")
    number(rform, "rocker_pivot.0", "pivot G x", "mm", "rocker pivot", "the rocker's ground pivot")
    number(rform, "rocker_pivot.1", "pivot G y", "mm", "rocker pivot")

    law = el().slider_law
    slider = QGroupBox("Slider circle and axis" if law is None else "Slider law and axis")
    sform = QFormLayout(slider)
    if law is None:
        number(sform, "slider_circle.center.0", "centre x", "mm", "slider circle centre",
               "centre of the lever's circle rolling on the slider profile (drawn pose)")
        number(sform, "slider_circle.center.1", "centre y", "mm", "slider circle centre")
        number(sform, "slider_circle.radius", "radius R2", "mm", "slider circle radius")
    else:   # a prescribed S5(θ): the lever element and the slider profile are derived from it
        what = (f"table of {len(law.table)} points" if law.kind == "table"
                else f"{law.kind}, travel {law.travel:g} mm")
        label = QLabel(f"S5(θ): {what} (the lever element Π30 and the slider profile are its exact centrodes)")
        label.setWordWrap(True)
        sform.addRow("law", label)
    number(sform, "slider_axis_deg", "axis", "°", "slider axis", "direction of the slider's motion")
    sform.addRow("side", combo_field(
        panel, "slider_side", [("+1", 1), ("−1", -1)],
        lambda: el().slider_side, lambda v: push({"slider_side": v}, "set slider side"),
        "which intersection of the normal to the slider axis with the slider circle is the contact: "
        "+1 on the side of the axis turned by +90°, −1 by −90°"))

    stroke = QGroupBox("Stroke and synthesis")
    tform = QFormLayout(stroke)
    number(tform, "stroke.from", "from θ", "rad", "stroke start", "lever rotation at the start (0 = drawn pose)")
    number(tform, "stroke.to", "to θ", "rad", "stroke end", "lever rotation at the end; it must stay in the working range")
    tform.addRow("method", combo_field(
        panel, "method", [(m, m) for m in METHODS], lambda: el().method,
        lambda v: push({"method": v}, "set method"),
        "exact: the ODE; paper: the paper's compass construction (levels off near 1 mm slip); "
        "corrected: the notes' corrected construction"))

    def write_points(v: float) -> None:
        push({"points": whole_number(v, "points")}, "set points")
    points = panel.number_field("points", lambda: float(el().points), write_points)
    points.setToolTip("N intervals over the stroke (N + 1 points)")
    tform.addRow("points N", panel.row(points, "—"))
    boxes = [lever, rocker, slider, stroke]

    if el().drive is not None:
        drive = QGroupBox("Drive (crank and coupler)")
        dform = QFormLayout(drive)
        number(dform, "drive.crank_pivot.0", "crank A x", "mm", "crank pivot", "the crank's ground pivot")
        number(dform, "drive.crank_pivot.1", "crank A y", "mm", "crank pivot")
        number(dform, "drive.coupler_point.0", "lever C x", "mm", "coupler point",
               "the lever point the coupler drives (drawn pose)")
        number(dform, "drive.coupler_point.1", "lever C y", "mm", "coupler point")
        boxes.append(drive)

    derived = QGroupBox("Derived (read-only)")
    xform = QFormLayout(derived)
    labels = {k: QLabel() for k in ("ell", "stroke", "range", "S5", "drive")}
    for key, text in (("ell", "rocker ℓ"), ("stroke", "stroke"), ("range", "range"),
                      ("S5", "travel S5"), ("drive", "crank / coupler")):
        labels[key].setWordWrap(True)
        xform.addRow(text, labels[key])

    def show_derived() -> None:
        e = el()
        labels["ell"].setText(f"{e.rocker_length:.4f} mm")
        labels["stroke"].setText(f"{math.degrees(e.stroke.span):+.3f}°")
        res = ctl.element_result(element_id)
        syn = res.synthesis if isinstance(res, RollingResult) else None
        if syn is None:
            for k in ("range", "S5", "drive"):
                labels[k].setText("—")
            return
        wr = syn.working_range
        labels["range"].setText(f"θ from {wr.lower:.4f} to {wr.upper:.4f} rad")
        labels["S5"].setText(f"{float(np.nanmax(syn.S5) - np.nanmin(syn.S5)):.4f} mm")
        d = syn.drive
        labels["drive"].setText(f"{d.crank:.4f} / {d.coupler:.4f} mm" if d is not None else "no drive")
    panel.add_refresher(show_derived)
    boxes.append(derived)
    boxes.append(method_comparison_box(panel, element_id))
    return boxes


#: rows of the side-by-side table: (label, ErrorRow attribute, format)
COMPARE_ROWS = (("time (ms)", "time_s", "ms"), ("kinematic slip, points (mm)", "kinematic_slip", "e"),
                ("slip of the motion (mm)", "continuous_slip", "e"), ("IC offset (mm)", "ic_offset", "e"),
                ("deviation from exact (mm)", "deviation", "e"), ("physical slip (mm)", "physical_slip", "e"),
                ("arc-length mismatch (mm)", "arc_mismatch", "e"))


def method_comparison_box(panel, element_id: str) -> QGroupBox:
    """The three synthesis methods side by side at the element's N: the core's error table
    (:func:`~mechsketch.core.analyses.rolling.synthesis.error_table`), computed when asked."""
    ctl = panel.controller
    box = QGroupBox("Methods side by side")
    lay = QVBoxLayout(box)
    button = QPushButton("Compare exact / corrected / paper")
    button.setObjectName(f"compare:{element_id}")
    table = QTableWidget(len(COMPARE_ROWS), len(METHODS_SHOWN))
    table.setObjectName(f"comparison:{element_id}")
    table.setHorizontalHeaderLabels(list(METHODS_SHOWN))
    table.setVerticalHeaderLabels([r[0] for r in COMPARE_ROWS])
    table.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
    table.setMinimumHeight(230)
    note = QLabel("the slip measures of each method at the same N")
    note.setWordWrap(True)
    lay.addWidget(button)
    lay.addWidget(table)
    lay.addWidget(note)

    def compare() -> None:
        from mechsketch.core.analyses.rolling.synthesis import error_table   # 30 ms to import: not at start-up

        el = ctl.scene.element(element_id)
        try:
            rows = error_table(el, ns=(el.points,), methods=METHODS_SHOWN, repeat=1)
        except MechsketchError as exc:
            note.setText(f"cannot compare: {exc}")
            return
        for j, row in enumerate(rows):
            for i, (_, attr, fmt) in enumerate(COMPARE_ROWS):
                v = getattr(row, attr)
                text = "—" if not math.isfinite(v) else f"{v * 1e3:.2f}" if fmt == "ms" else f"{v:.3e}"
                table.setItem(i, j, QTableWidgetItem(text))
        note.setText(f"N = {el.points} intervals; the element uses '{el.method}' (change it above)")
        ctl.message.emit(f"{element_id}: methods compared at N = {el.points}")
    button.clicked.connect(compare)
    return box
