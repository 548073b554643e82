"""The Geneva tool: click the crank centre, then the wheel centre; keys 3-9 choose the slot count.

The second click sets the centre distance A and the direction of the line of centres. The drive
is made with :func:`scaled_drive`: every default size (roller, clearances, roller length, bores,
journal, wheel inertia) scaled to A and to the slot count so that it validates for any z from 3
to 9 and any A. Keys 3-9 change the slot count of the preview and of the drive this tool just
placed (one undo step each). Handles to reshape a placed drive are in :mod:`.handles`.
"""
from __future__ import annotations

import math

from mechsketch.core.model.edits import ReplaceElement
from mechsketch.core.errors import GeometryError
from mechsketch.core.model.drawing import DEFAULT_MIN_WEB
from mechsketch.core.model.geneva import Clearances, Drawing, Geneva, Load, Material, parse, wheel_dimensions

from ..selection import ELEMENT
from . import ops
from .events import XY, CanvasEvent
from .items import Overlay
from .tool_base import Tool

DEFAULT_SLOTS = 6
#: reference drive the defaults are scaled from: A = 100 mm (seeds/NOTES.md, example 4)
REF_A = 100.0
#: (roller, wheel) materials of a drive the tool places (Edit › Preferences sets them)
NEW_MATERIALS: tuple[Material, Material] = (Material(), Material())


def scaled_drive(element_id: str, slots: int, crank_center: XY, wheel_center: XY,
                 speed_rpm: float = 300.0 / math.pi) -> Geneva:
    """A Geneva drive between two clicked centres (mm) with sizes scaled to A = |wheel − crank|.

    Roller r_p = 0.08·A (at most 0.45·(r − A + R_o), so a 3-slot wheel keeps its land), roller
    length 0.1·A, clearances slot / bottom / lock 0.0005·A, 0.005·A, 0.001·A, journal (hub bore)
    radius min(0.15·A, half the largest hub), wheel inertia 0.05 kg·m²·(A/100 mm)⁵ (a plate of
    the same proportions); below A = 100 mm the minimum web of the parts scales too (1 mm at
    A = 100 mm). Raises GeometryError if the centres coincide.
    """
    dx, dy = wheel_center[0] - crank_center[0], wheel_center[1] - crank_center[1]
    a = math.hypot(dx, dy)
    if a <= ops.SAME_POINT:
        raise GeometryError("the wheel centre is on the crank centre: click it away from it (that sets A)")
    s = a / REF_A
    cl = Clearances(slot=0.05 * s, bottom=0.5 * s, lock=0.1 * s)
    rp = 8.0 * s
    dims = wheel_dimensions(slots, a, rp, cl)
    lo, hi = dims.lock_arc_range
    rp = min(rp, 0.45 * (dims.crank_radius - lo))      # narrow wheels (z = 3) need a thinner roller
    dims = wheel_dimensions(slots, a, rp, cl)
    journal = min(15.0 * s, 0.5 * dims.hub_max)
    load = Load(wheel_inertia=0.05 * s ** 5, external_moment=0.0, journal_friction=0.05, journal_radius=journal)
    # a drive smaller than the reference keeps a web in proportion (the default web is 1 mm)
    drawing = Drawing(min_web=DEFAULT_MIN_WEB * s) if s < 1.0 else None
    return Geneva(element_id, int(slots), a, rp, 10.0 * s, cl, (float(crank_center[0]), float(crank_center[1])),
                  math.degrees(math.atan2(dy, dx)), speed_rpm, load, drawing=drawing,
                  roller_material=NEW_MATERIALS[0], wheel_material=NEW_MATERIALS[1])


def problems_of(element: Geneva) -> str | None:
    """What makes the drive impossible (the model's messages), or None."""
    _, problems = parse(element.to_dict(), "$")
    return "; ".join(p.message for p in problems) if problems else None


class GenevaTool(Tool):
    """Click the crank centre, then the wheel centre; 3-9 set the slot count (default 6)."""

    name, title, shortcut = "geneva", "Geneva drive", "W"
    hint = "Geneva drive: click the crank centre, then the wheel centre (sets A); keys 3-9 choose the slots"

    def __init__(self, ctx) -> None:
        self.slots = DEFAULT_SLOTS
        self.placed: str | None = None      # the drive this tool made last (keys 3-9 re-slot it)
        super().__init__(ctx)

    def reset(self) -> None:
        super().reset()
        self._centre: XY | None = None
        self._last: XY | None = None

    def anchor(self) -> XY | None:
        return self._centre

    def forget(self, gone=None) -> bool:
        """Also forget the drive just placed (keys 3-9 re-slot it) once it is gone."""
        if gone is None or self.placed in gone:
            self.placed = None
        return super().forget(gone)

    def _candidate(self, pos: XY) -> tuple[Geneva | None, str | None]:
        eid = ops.fresh_element_id(self.ctx.controller.scene.ids, "geneva")
        try:
            el = scaled_drive(eid, self.slots, self._centre, pos)
        except ValueError as exc:
            return None, str(exc)
        return el, problems_of(el)

    def _preview(self, pos: XY) -> None:
        c = self._centre
        el, why = self._candidate(pos)
        a = ops.dist(c, pos)
        if el is None:
            self._overlay = Overlay(points=[pos], labels=[(pos, why or "")], bad=True)
            return
        d = wheel_dimensions(el.slots, el.center_distance, el.roller_radius, el.clearance)
        circles = [(c, d.crank_radius), (pos, d.outer_radius), (pos, max(d.hub_max, 0.0))]
        label = f"A = {a:.2f} mm, z = {self.slots} (keys 3-9), roller {el.roller_radius:.2f} mm"
        self._overlay = Overlay(lines=[(c, pos)], points=[pos], circles=circles,
                                labels=[(pos, label if why is None else f"impossible: {why}")], bad=why is not None)

    def on_move(self, ev: CanvasEvent) -> None:
        self._last = ev.pos
        if self._centre is None:
            self._overlay = Overlay(points=[ev.pos], labels=[(ev.pos, "crank centre")])
        else:
            self._preview(ev.pos)

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if self._centre is None:
            self._centre = ev.pos
            self._overlay = Overlay(points=[ev.pos])
            self.explain(f"Geneva drive: crank centre at ({ev.pos[0]:.1f}, {ev.pos[1]:.1f}); click the wheel centre")
            return
        el, why = self._candidate(ev.pos)
        if el is None or why is not None:
            self.explain(f"cannot place the Geneva drive: {why}")
            return
        if self.ctx.commit(None, el, f"add Geneva drive {el.id} (z = {el.slots})"):
            self.placed = el.id
            self.ctx.controller.set_selection([(el.id, ELEMENT, el.id)])
            self.explain(f"Geneva drive {el.id}: z = {el.slots}, A = {el.center_distance:.2f} mm, roller "
                         f"{el.roller_radius:.2f} mm; keys 3-9 change the slots, drag the handles to reshape")
        self.reset()

    def key(self, text: str) -> bool:
        """Digits 3-9 choose the slot count (and re-slot the drive just placed)."""
        if len(text) != 1 or text not in "3456789":
            return False
        self.slots = int(text)
        if self._centre is not None and self._last is not None:
            self._preview(self._last)
            self.explain(f"Geneva drive: {self.slots} slots")
            return True
        eid = self.placed
        ctl = self.ctx.controller
        if eid is not None and eid in ctl.scene.ids and (eid, ELEMENT, eid) in ctl.selection:
            old = ctl.scene.element(eid)
            if old.slots == self.slots:
                return True
            new = scaled_drive(eid, self.slots, old.crank_center, old.wheel_center, old.speed_rpm)
            why = problems_of(new)
            if why:
                self.explain(f"cannot use {self.slots} slots: {why}")
                return True
            if ctl.push(ReplaceElement(new, f"set slots of {eid}"), f"set {eid} to {self.slots} slots"):
                self.explain(f"{eid}: {self.slots} slots")
            return True
        self.explain(f"Geneva drive: the next drive gets {self.slots} slots")
        return True

