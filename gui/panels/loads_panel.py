"""Masses, loads and joint friction in the properties panel (each edit is one undo command).

- a selected moving link: its ``mass`` (kg), centre of mass ``com_x`` / ``com_y`` (mm, drawn;
  the centroid of its joints until set) and ``inertia`` (kg·m² about the centre of mass; the
  slender-bar estimate m·L²/12 until set, marked "estimate");
- a selected revolute joint on two or more links: its friction-circle radius ``friction`` (mm;
  0: frictionless);
- the linkage's "Loads" box: gravity ``gx`` / ``gy`` (m/s²), every load with its fields (a force's
  point ``ID.x`` ``ID.y`` in mm and ``ID.Fx`` ``ID.Fy`` in N; a torque's ``ID.T`` in N·m; a
  spring's ``ID.k`` in N/mm and free length ``ID.L0`` in mm; a damper's ``ID.c`` in N·s/mm) and a
  Remove button, and buttons that add a force, a torque, a spring or a damper to the selected
  link (else the last moving link).

The widgets hold no model state: reads go to ``controller.scene``, writes build the new linkage
with the model's own methods and push one ``ReplaceElement`` (the workspace reads it with the
scene reader, so a refused value is reported with the loader's message and nothing changes).
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Callable

from PySide6.QtWidgets import QFormLayout, QGridLayout, QGroupBox, QHBoxLayout, QLabel, QPushButton, QWidget

from mechsketch.core import EditError, ReplaceElement
from mechsketch.core.model.linkage import JointKind, Linkage
from mechsketch.core.model.loads import (Damper, End, LinkMass, PointForce, Spring, Torque, default_inertia,
                                         next_load_id)


def _centroid(lk: Linkage, link: str) -> tuple[float, float]:
    pts = [lk.joint(j).at for j in lk.link(link).joints]
    return (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))


def _span(lk: Linkage, link: str) -> float:
    pts = [lk.joint(j).at for j in lk.link(link).joints]
    return max((math.hypot(p[0] - q[0], p[1] - q[1]) for p in pts for q in pts), default=0.0)


def _push(panel, eid: str, new: Linkage, text: str) -> None:
    panel.controller.push(ReplaceElement(new, text), text)


def link_mass_rows(panel, form: QFormLayout, eid: str, kid: str) -> None:
    """Mass, centre of mass and moment of inertia of link ``kid`` (see the module docstring)."""
    lk: Callable[[], Linkage] = lambda: panel.controller.scene.element(eid)   # noqa: E731

    def current() -> LinkMass:
        return lk().mass_of(kid) or LinkMass(kid, 0.0)

    def write_mass(v: float) -> None:
        if v < 0:
            raise EditError("a mass must be 0 kg or more")
        _push(panel, eid, lk().with_mass(kid, replace(current(), mass=v)), f"set mass of {kid}")

    def write_com(i: int, v: float) -> None:
        m = current()
        com = list(m.com if m.com is not None else _centroid(lk(), kid))
        com[i] = v
        _push(panel, eid, lk().with_mass(kid, replace(m, com=(com[0], com[1]))), f"set centre of mass of {kid}")

    def write_inertia(v: float) -> None:
        if v < 0:
            raise EditError("a moment of inertia must be 0 kg·m² or more")
        _push(panel, eid, lk().with_mass(kid, replace(current(), inertia=v)), f"set inertia of {kid}")

    def read_inertia() -> float:
        m = current()
        return m.inertia if m.inertia is not None else default_inertia(m.mass, _span(lk(), kid))

    form.addRow("mass", panel.row(panel.number_field("mass", lambda: current().mass, write_mass), "kg"))
    for axis, i in (("x", 0), ("y", 1)):
        edit = panel.number_field(f"com_{axis}", lambda i=i: (current().com or _centroid(lk(), kid))[i],
                                  lambda v, i=i: write_com(i, v))
        edit.setToolTip("drawn position of the centre of mass (default: the centroid of the link's joints)")
        form.addRow(f"centre {axis}", panel.row(edit, "mm"))
    inertia = panel.number_field("inertia", read_inertia, write_inertia)
    inertia.setToolTip("about the centre of mass; until set, the slender-bar estimate m·L²/12 "
                       "(L the longest joint-to-joint span)")
    note = QLabel()
    panel.add_refresher(lambda: note.setText("kg·m²" if current().inertia is not None else "kg·m² (estimate)"))
    row = QWidget()
    h = QHBoxLayout(row)
    h.setContentsMargins(0, 0, 0, 0)
    h.addWidget(inertia, 1)
    h.addWidget(note)
    form.addRow("inertia", row)


def joint_friction_row(panel, form: QFormLayout, eid: str, jid: str) -> None:
    """The friction-circle radius of revolute joint ``jid`` (when it joins two or more links)."""
    lk = panel.controller.scene.element(eid)
    if lk.joint(jid).kind is not JointKind.R or len(lk.links_of(jid)) < 2:
        return

    def write(v: float) -> None:
        if v < 0:
            raise EditError("a friction-circle radius must be 0 mm or more")
        cur = panel.controller.scene.element(eid)
        _push(panel, eid, cur.with_friction(jid, v), f"set friction of {jid}")

    edit = panel.number_field("friction", lambda: panel.controller.scene.element(eid).friction_of(jid), write)
    edit.setToolTip("Coulomb friction: the friction-circle radius (0: frictionless); the forces are "
                    "reported with and without it")
    form.addRow("friction circle", panel.row(edit, "mm"))


def _target_link(panel, lk: Linkage) -> str:
    sel = panel.selected()
    if sel is not None and sel[0] == lk.id and sel[1] == "link" and sel[2] != lk.ground:
        return sel[2]
    return lk.moving_links[-1]


def add_load(panel, eid: str, kind: str) -> bool:
    """Add a load of ``kind`` ("force", "torque", "spring", "damper") to the selected link (else
    the last moving link) with round default values, as one undo command."""
    lk: Linkage = panel.controller.scene.element(eid)
    if not lk.moving_links:
        panel.controller.message.emit("draw a moving link first")
        return False
    link = _target_link(panel, lk)
    lid = next_load_id(kind, lk.load_ids)
    c = _centroid(lk, link)
    if kind == "force":
        load = PointForce(lid, link, c, (0.0, -10.0))
    elif kind == "torque":
        load = Torque(lid, link, 1.0)
    else:
        anchor = (c[0], c[1] + 60.0)
        ends = (End(lk.ground, anchor), End(link, c))
        load = Spring(lid, ends, 1.0, None) if kind == "spring" else Damper(lid, ends, 0.01)
    return panel.controller.push(ReplaceElement(lk.with_load(load), f"add {kind} {lid}"), f"add {kind} {lid}")


def loads_box(panel, eid: str) -> QGroupBox:
    """The linkage's gravity and loads (see the module docstring)."""
    box = QGroupBox(f"Loads ({eid})")
    form = QFormLayout(box)
    lk: Callable[[], Linkage] = lambda: panel.controller.scene.element(eid)   # noqa: E731

    def write_g(i: int, v: float) -> None:
        g = list(lk().gravity or (0.0, 0.0))
        g[i] = v
        new = lk().with_gravity(None if g == [0.0, 0.0] else (g[0], g[1]))
        _push(panel, eid, new, "set gravity")

    for axis, i in (("x", 0), ("y", 1)):
        edit = panel.number_field(f"g{axis}", lambda i=i: (lk().gravity or (0.0, 0.0))[i],
                                  lambda v, i=i: write_g(i, v))
        form.addRow(f"gravity {axis}", panel.row(edit, "m/s²"))
    for ld in lk().loads:
        _load_rows(panel, form, eid, ld.id)
    buttons = QWidget()
    h = QGridLayout(buttons)   # two by two: the dock fits a 1024 px screen
    h.setContentsMargins(0, 0, 0, 0)
    for k, kind in enumerate(("force", "torque", "spring", "damper")):
        b = QPushButton(f"+ {kind}")
        b.setObjectName(f"add_{kind}")
        b.setToolTip(f"add a {kind} to the selected link (else the last moving link); one undo step")
        b.clicked.connect(lambda _=False, k=kind: add_load(panel, eid, k))
        panel.buttons[f"add_{kind}"] = b
        h.addWidget(b, k // 2, k % 2)
    form.addRow(buttons)
    hint = QLabel("Forces in N, torques in N·m (CCW +), points drawn in mm; drag a load's ◇ on the canvas to move it.")
    hint.setWordWrap(True)
    form.addRow(hint)
    return box


def _load_rows(panel, form: QFormLayout, eid: str, lid: str) -> None:
    lk: Callable[[], Linkage] = lambda: panel.controller.scene.element(eid)   # noqa: E731
    load = lk().load(lid)

    def set_(text: str, **changes) -> None:
        _push(panel, eid, lk().with_load(replace(lk().load(lid), **changes)), f"{text} {lid}")

    title = QWidget()
    h = QHBoxLayout(title)
    h.setContentsMargins(0, 6, 0, 0)
    where = ", ".join(load.links)
    h.addWidget(QLabel(f"<b>{lid}</b>: {load.kind} on {where}"), 1)
    remove = QPushButton("Remove")
    remove.setObjectName(f"remove:{lid}")
    remove.clicked.connect(lambda _=False: panel.controller.push(
        ReplaceElement(lk().without_load(lid), f"remove load {lid}"), f"remove load {lid}"))
    panel.buttons[f"remove:{lid}"] = remove
    h.addWidget(remove)
    form.addRow(title)

    def field(name: str, label: str, unit: str, read, write) -> None:
        form.addRow(label, panel.row(panel.number_field(f"{lid}.{name}", read, write), unit))

    if load.kind == "force":
        for axis, i in (("x", 0), ("y", 1)):
            field(axis, f"point {axis}", "mm", lambda i=i: lk().load(lid).at[i],
                  lambda v, i=i: set_("move", at=tuple(v if m == i else c for m, c in enumerate(lk().load(lid).at))))
        for axis, i in (("Fx", 0), ("Fy", 1)):
            field(axis, axis, "N", lambda i=i: lk().load(lid).force[i],
                  lambda v, i=i: set_("set force", force=tuple(v if m == i else c
                                                                for m, c in enumerate(lk().load(lid).force))))
    elif load.kind == "torque":
        field("T", "torque", "N·m", lambda: lk().load(lid).torque, lambda v: set_("set torque", torque=v))
    elif load.kind == "spring":
        field("k", "stiffness", "N/mm", lambda: lk().load(lid).stiffness, lambda v: set_("set stiffness", stiffness=v))
        field("L0", "free length", "mm", lambda: lk().load(lid).rest_length,
              lambda v: set_("set free length", free_length=v))
    else:
        field("c", "damping", "N·s/mm", lambda: lk().load(lid).damping, lambda v: set_("set damping", damping=v))
