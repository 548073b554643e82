"""The properties of a selected Geneva drive: its authored values, editable, and a few derived sizes.

Fields (units beside them): slots z, centre distance A, roller radius r_p and length l, the three
clearances, crank speed (rpm, with ω in rad/s) and turning sense, wheel direction, crank centre and
samples. Each edit is one undo step through :func:`.element_props.push_changes`: a value the core
refuses (z = 2, a roller too large for the crank, ...) leaves the document as it was and the
core's message in the status bar. Read-only: crank radius r = A·sin(π/z), the wheel's outer radius
R_o, slot width and depth, the relief radius drawn, the period, and whether the contact model is
within its validity range (the summary's words).
"""
from __future__ import annotations

import math

from PySide6.QtWidgets import QFormLayout, QGroupBox, QLabel

from mechsketch.core.analyses.geneva.contact import GenevaContact
from mechsketch.core.errors import EditError
from mechsketch.core.model.geneva import Geneva

from mechsketch.core.workspace import GenevaResult
from .element_props import combo_field, push_changes, whole_number

#: (field name = JSON key, label, unit, tooltip) of the plain number fields, by group
SIZES = (
    ("center_distance", "distance A", "mm", "centre distance: crank centre to wheel centre"),
    ("roller_radius", "roller r_p", "mm", "roller radius"),
    ("roller_length", "roller l", "mm", "contact length of the roller"),
)
CLEARANCES = (
    ("clearance.slot", "slot", "mm", "per side of the roller"),
    ("clearance.bottom", "bottom", "mm", "below the deepest roller position"),
    ("clearance.lock", "lock", "mm", "locking disc to the wheel's locking arcs"),
)


def contact_text(con: GenevaContact) -> str:
    """The contact model's validity in one line: within its range (and the margin), or how many
    engaged rows lie outside it and what is then not computed (the summary's words)."""
    v = con.validity
    if v.ok:
        return (f"valid: peak Rn {v.rn_peak:.4g} N ≤ {v.rn_limit:.4g} N (Δ ≤ {v.deformation_limit:g}·r_p, "
                f"b ≤ {v.half_width_limit:g}·r_p and ·l); L_s {con.slip_path_total * 1e3:.4g} µm")
    return (f"outside its validity range at {v.invalid_rows} of {v.engaged_rows} engaged rows (Rn up to "
            f"{v.rn_peak:.4g} N, limit {v.rn_limit:.4g} N): slip, wear and life not computed; use stiffer "
            "materials, a longer or larger roller, or a lighter load")


def _value(el: Geneva, key: str) -> float:
    node = el.to_dict()
    for part in key.split("."):
        node = node[part]
    return float(node)


def geneva_boxes(panel, element_id: str) -> list[QGroupBox]:
    """The group boxes of one Geneva drive for the properties panel (fields registered on ``panel``)."""
    ctl = panel.controller

    def el() -> Geneva:
        return ctl.scene.element(element_id)

    def push(changes: dict, label: str) -> None:
        push_changes(ctl, element_id, changes, f"{label} of {element_id}")

    def numbers(form: QFormLayout, specs: tuple) -> None:
        for key, label, unit, tip in specs:
            edit = panel.number_field(key, lambda key=key: _value(el(), key),
                                      lambda v, key=key, label=label: push({key: v}, f"set {label}"))
            edit.setToolTip(tip)
            form.addRow(label, panel.row(edit, unit))

    box = QGroupBox(f"Geneva drive {element_id}")
    form = QFormLayout(box)

    def write_slots(v: float) -> None:
        push({"slots": whole_number(v, "the number of slots")}, "set slots")
    slots = panel.number_field("slots", lambda: float(el().slots), write_slots)
    slots.setToolTip("number of slots z (at least 3); the crank radius follows: r = A·sin(π/z)")
    form.addRow("slots z", panel.row(slots, "—"))
    numbers(form, SIZES)

    def write_speed(v: float) -> None:
        if not v > 0:
            raise EditError("the speed must be positive (choose the turning sense below)")
        push({"speed_rpm": math.copysign(v, el().speed_rpm)}, "set speed")
    speed = panel.number_field("speed_rpm", lambda: abs(el().speed_rpm), write_speed)
    speed.setToolTip("crank speed")
    form.addRow("speed", panel.row(speed, "rpm"))
    omega = QLabel()
    panel.add_refresher(lambda: omega.setText(f"ω1 = {abs(el().omega1):.6g} rad/s"))
    form.addRow("", omega)
    sense = combo_field(panel, "geneva.sense", [("CCW", 1), ("CW", -1)],
                        lambda: 1 if el().speed_rpm > 0 else -1,
                        lambda s: push({"speed_rpm": s * abs(el().speed_rpm)}, "reverse crank"),
                        "turning sense of the crank: counter-clockwise (CCW) or clockwise (CW); "
                        "the wheel turns the other way")
    form.addRow("direction", sense)

    def write_samples(v: float) -> None:
        push({"samples": whole_number(v, "samples")}, "set samples")
    samples = panel.number_field("samples", lambda: float(el().samples), write_samples)
    samples.setToolTip("samples over one crank revolution (the animation's frames)")
    form.addRow("samples", panel.row(samples, "/ turn"))

    clearances = QGroupBox("Clearances")
    numbers(QFormLayout(clearances), CLEARANCES)

    placement = QGroupBox("Placement")
    pform = QFormLayout(placement)
    for axis, i in (("x", 0), ("y", 1)):
        def write_centre(v: float, i: int = i) -> None:
            c = list(el().crank_center)
            c[i] = v
            push({"crank_center": c}, "move crank centre")
        edit = panel.number_field(f"crank_center.{axis}", lambda i=i: el().crank_center[i], write_centre)
        edit.setToolTip(f"{axis} of the crank centre")
        pform.addRow(f"crank {axis}", panel.row(edit, "mm"))
    numbers(pform, (("wheel_direction_deg", "wheel at", "°", "direction from the crank centre to the wheel centre"),))

    derived = QGroupBox("Derived (read-only)")
    dform = QFormLayout(derived)
    labels = {k: QLabel() for k in ("r", "Ro", "slot", "relief", "period", "contact")}
    for key, text in (("r", "crank r"), ("Ro", "outer R_o"), ("slot", "slot w × d"),
                      ("relief", "relief"), ("period", "period"), ("contact", "contact model")):
        labels[key].setWordWrap(True)
        dform.addRow(text, labels[key])

    def show_derived() -> None:
        e = el()
        d = e.dimensions()
        labels["r"].setText(f"{e.crank_radius:.4f} mm (λ = {e.lam:.4f})")
        labels["Ro"].setText(f"{d.outer_radius:.4f} mm")
        labels["slot"].setText(f"{2 * d.w:.4f} × {d.slot_depth:.4f} mm")
        res = ctl.element_result(element_id)
        geo = res.geometry if isinstance(res, GenevaResult) else None
        labels["relief"].setText(f"{geo.relief.drawn:.3f} mm (the classical R_o interferes)" if geo is not None
                                 else "—")
        labels["period"].setText(f"{60.0 / abs(e.speed_rpm):.4g} s / crank turn")
        con = res.contact if isinstance(res, GenevaResult) else None
        labels["contact"].setText(contact_text(con) if con is not None else "—")
    panel.add_refresher(show_derived)
    return [box, clearances, placement, derived]
