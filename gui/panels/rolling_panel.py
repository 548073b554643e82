"""The properties of a selected rolling lever: circles, pin, rocker pivot, slider, stroke, method.

Fields in the drawn pose (mm, degrees for the slider axis, rad for the stroke as in the scene
file): the lever circle and the slider circle (centre, radius), the contact branch, the slider
axis and side, the pin f, the rocker pivot G, the stroke θ from/to, the synthesis method (exact,
paper, corrected) and the number of intervals N, and the drive's crank pivot and coupler point
when the lever has a drive. Each edit is one undo step through
:func:`.element_props.push_changes`; a refused value (a stroke beyond the working range, a rocker
line missing the lever circle, ...) leaves the document as it was and the core's message in the
status bar. Read-only: the rocker length, the working range and the slider travel.
"""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtWidgets import QFormLayout, QGroupBox, QLabel

from mechsketch.core.model.rolling_lever import METHODS, RollingLever

from ..element_results import RollingResult
from .element_props import combo_field, push_changes, whole_number


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

    def number(form: QFormLayout, key: str, label: str, unit: str, tip: str = "") -> None:
        """A field for a number (``key`` may name a list item: ``pin.0``)."""
        def write(v: float) -> None:
            head, _, tail = key.rpartition(".")
            if tail.isdigit():   # one coordinate of a point: write the whole point
                point = list(_get(el(), head))
                point[int(tail)] = v
                push({head: point}, f"set {label}")
            else:
                push({key: v}, f"set {label}")
        edit = panel.number_field(key, lambda: float(_get(el(), key)), write)
        edit.setToolTip(tip)
        form.addRow(label, panel.row(edit, unit))

    lever = QGroupBox(f"Rolling lever {element_id}: lever (drawn pose)")
    form = QFormLayout(lever)
    number(form, "lever_circle.center.0", "lever circle x", "mm", "centre of the circle rolling on the frame profile")
    number(form, "lever_circle.center.1", "lever circle y", "mm")
    number(form, "lever_circle.radius", "lever circle R1", "mm")
    form.addRow("contact", combo_field(
        panel, "contact_branch", [("near intersection", "near"), ("far intersection", "far")],
        lambda: el().contact_branch, lambda v: push({"contact_branch": v}, "set contact branch"),
        "which intersection of the rocker line with the lever circle is the contact"))
    number(form, "pin.0", "pin f x", "mm", "the rocker's pin on the lever")
    number(form, "pin.1", "pin f y", "mm")
    number(form, "rocker_pivot.0", "rocker pivot G x", "mm", "the rocker's ground pivot")
    number(form, "rocker_pivot.1", "rocker pivot G y", "mm")

    slider = QGroupBox("Slider")
    sform = QFormLayout(slider)
    number(sform, "slider_circle.center.0", "slider circle x", "mm", "centre of the circle rolling on the slider")
    number(sform, "slider_circle.center.1", "slider circle y", "mm")
    number(sform, "slider_circle.radius", "slider circle R2", "mm")
    number(sform, "slider_axis_deg", "slider axis", "°", "direction of the slider's motion")
    sform.addRow("side", combo_field(
        panel, "slider_side", [("+1 (left of the axis)", 1), ("−1 (right of the axis)", -1)],
        lambda: el().slider_side, lambda v: push({"slider_side": v}, "set slider side"),
        "which intersection of the normal to the slider axis with the slider circle is the contact"))

    stroke = QGroupBox("Stroke and synthesis")
    tform = QFormLayout(stroke)
    number(tform, "stroke.from", "stroke from θ", "rad", "lever rotation at the start (0 = drawn pose)")
    number(tform, "stroke.to", "stroke to θ", "rad", "lever rotation at the end; must stay in the working range")
    tform.addRow("method", combo_field(
        panel, "method", [(m, m) for m in METHODS], lambda: el().method,
        lambda v: push({"method": v}, "set method"),
        "exact: the ODE; paper: the paper's compass construction (levels off near 1 mm slip); "
        "corrected: the notes' corrected construction"))

    def write_points(v: float) -> None:
        push({"points": whole_number(v, "points")}, "set points")
    points = panel.number_field("points", lambda: float(el().points), write_points)
    points.setToolTip("N intervals over the stroke (N + 1 points)")
    tform.addRow("points N", panel.row(points, "intervals"))
    boxes = [lever, slider, stroke]

    if el().drive is not None:
        drive = QGroupBox("Drive (crank and coupler)")
        dform = QFormLayout(drive)
        number(dform, "drive.crank_pivot.0", "crank pivot A x", "mm")
        number(dform, "drive.crank_pivot.1", "crank pivot A y", "mm")
        number(dform, "drive.coupler_point.0", "coupler point C x", "mm", "the lever point the coupler drives")
        number(dform, "drive.coupler_point.1", "coupler point C y", "mm")
        boxes.append(drive)

    derived = QGroupBox("Derived (read-only)")
    xform = QFormLayout(derived)
    labels = {k: QLabel() for k in ("ell", "stroke", "range", "S5", "drive")}
    for key, text in (("ell", "rocker length ℓ"), ("stroke", "stroke"), ("range", "working range"),
                      ("S5", "slider travel"), ("drive", "crank / coupler")):
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
    return boxes
