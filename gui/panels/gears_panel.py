"""The properties of a selected gear pair or geared (smooth) Geneva drive: the few sizes a designer
edits here, and what the core derived, read-only.

Editable (one undo step each, through :func:`.element_props.push_changes`; a value the core refuses
leaves the document as it was, the reason in the status bar): a gear pair's centre distance and
input speed; a geared Geneva's slot count, centre distance, roller radius, crank mean speed and the
gears' centre distance. Read-only: the speed-ratio range, the pitch curves' perimeters, curvature
and pressure-angle swing, and for the geared Geneva the acceleration jump and peak jerk against the
constant-speed crank (the summary's words).
"""
from __future__ import annotations

from PySide6.QtWidgets import QFormLayout, QGroupBox, QLabel

from mechsketch.core.workspace import GearedGenevaResult, GearResult
from .element_props import push_changes, whole_number


def _value(el, key: str) -> float:
    node = el.to_dict()
    for part in key.split("."):
        node = node[part]
    return float(node)


def gears_boxes(panel, element_id: str) -> list[QGroupBox]:
    """The group boxes of one ``gear_pair`` or ``geared_geneva`` (fields registered on ``panel``)."""
    ctl = panel.controller

    def el():
        return ctl.scene.element(element_id)

    def push(changes: dict, label: str) -> None:
        push_changes(ctl, element_id, changes, f"{label} of {element_id}")

    geared = el().type == "geared_geneva"
    box = QGroupBox(f"{'Smooth Geneva drive' if geared else 'Gear pair'} {element_id}")
    form = QFormLayout(box)
    specs = ((("geneva.center_distance", "wheel A", "mm"), ("geneva.roller_radius", "roller r_p", "mm"),
              ("geneva.speed_rpm", "crank mean speed", "rpm"), ("gears.center_distance", "gears a", "mm"))
             if geared else (("center_distance", "centre distance a", "mm"), ("speed_rpm", "input speed", "rpm")))
    if geared:
        def write_slots(v: float) -> None:
            push({"geneva.slots": whole_number(v, "the number of slots")}, "set slots")
        slots = panel.number_field("geneva.slots", lambda: float(el().geneva.slots), write_slots)
        form.addRow("slots z", panel.row(slots, "—"))
    for key, label, unit in specs:
        edit = panel.number_field(key, lambda key=key: _value(el(), key),
                                  lambda v, key=key, label=label: push({key: v}, f"set {label}"))
        form.addRow(label, panel.row(edit, unit))
    derived = QGroupBox("Derived (read-only)")
    dform = QFormLayout(derived)
    labels = {k: QLabel() for k in ("ratio", "curves", "smooth")}
    for key, text in (("ratio", "speed ratio"), ("curves", "pitch curves"), ("smooth", "against constant crank")):
        labels[key].setWordWrap(True)
        if key != "smooth" or geared:
            dform.addRow(text, labels[key])

    def show() -> None:
        res = ctl.element_result(element_id)
        gres = res.gears if isinstance(res, GearedGenevaResult) else res if isinstance(res, GearResult) else None
        ch = gres.checks if gres is not None else None
        if ch is None:
            for lb in labels.values():
                lb.setText(res.error if res is not None and res.error else "—")
            return
        labels["ratio"].setText(f"ψ' from {ch.ratio_min:.4g} to {ch.ratio_max:.4g}")
        shape = "convex" if ch.convex else "concave in places"
        labels["curves"].setText(f"perimeters {ch.input_length:.4f} / {ch.output_length:.4f} mm, {shape}, pressure "
                                 f"angle swing ≤ {max(ch.pressure_input_deg, ch.pressure_output_deg):.1f}°")
        if isinstance(res, GearedGenevaResult) and res.smoothness is not None:
            sm = res.smoothness
            labels["smooth"].setText(f"jump {100 * sm.jump_reduction:.1f} % less, peak jerk "
                                     f"{100 * sm.jerk_reduction:.1f} % less, same index time {sm.index_time:.4g} s")
    panel.add_refresher(show)
    return [box, derived]
