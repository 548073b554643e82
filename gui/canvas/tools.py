"""Canvas tools: plain classes consuming :class:`CanvasEvent`, so they are testable without Qt events.

Each tool turns clicks into one undo command on the controller (``ReplaceElement`` or
``AddElement``), shows what it will create in :meth:`Tool.overlay` while the mouse moves, and
explains an impossible placement through ``controller.message`` - never by raising.

Editing at an animation frame other than 0: tools that attach to moving joints (dyads, joint
drags) first make the pose on screen the drawn pose (:func:`pose.rebase`: same lengths and
assembly modes, only the drawn input angle moves) and then show frame 0, so what you click is
what you get. A coupler point is mapped back onto its link instead.

Usage without Qt events::

    ctx = ToolContext(controller)
    tool = GroundPivotTool(ctx)
    tool.handle(CanvasEvent("press", (0.0, 0.0), hit=ctx.pick((0.0, 0.0), 2.0)))
"""
from __future__ import annotations

import math

from mechsketch.core.model.edits import RemoveElement, ReplaceElement
from mechsketch.core.model.linkage import Linkage

from . import ops
from .build_tools import CouplerPointTool, CrankTool, GroundPivotTool, RPRTool, RRRTool, SliderTool
from .geneva_tool import GenevaTool
from .insert_tool import InsertTool
from .rolling_tool import RollingTool
from .slider_tools import PRPTool, RPPTool
from .events import XY, CanvasEvent
from .items import Overlay
from ..frames import walk_to
from .tool_base import DRAG_START, Tool, ToolContext

__all__ = ["TOOLS", "CouplerPointTool", "CrankTool", "DeleteTool", "GroundPivotTool", "MeasureTool",
           "RPRTool", "RRRTool", "SelectTool", "SliderTool", "Tool", "ToolContext", "delete_selection"]


class SelectTool(Tool):
    """Click to select (Shift adds), drag a joint to change the geometry live (one undo command
    on release), drag the crank's bar to turn the input, drag on empty space for a rubber band."""

    name, title, shortcut = "select", "Select / drag", "S"
    hint = "Select: drag a joint to reshape (live), drag the crank bar to turn the input, drag on empty space to select"

    def reset(self) -> None:
        super().reset()
        self._press: CanvasEvent | None = None
        self._mode: str | None = None           # joint | link | input | rubber (pending until moved)
        self._dragging = False
        self._base: Linkage | None = None
        self._rebased = False
        self._moving: list[str] = []
        self._anchor: XY = (0.0, 0.0)
        self._good: Linkage | None = None

    @property
    def busy(self) -> bool:
        return self._dragging and self._mode in ("joint", "link", "input")

    def refers_to(self) -> set[str]:
        h = self._press.hit if self._press is not None else None
        return {h.element} if h is not None else set()

    def stale(self) -> str | None:
        if self._dragging and self._mode in ("joint", "link") and not self.ctx.controller.workspace.previewing:
            return "the drag was interrupted (an edit, undo or another document)"
        return super().stale()

    def cancel(self) -> None:
        if self._dragging and self._mode in ("joint", "link"):
            self.ctx.controller.end_preview(None)
            self.ctx.hold_frame = False
        self.reset()

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        self.reset()
        self._press = ev
        h = ev.hit
        if h is None:
            self._mode = "rubber"
        elif h.kind == "joint":
            self._mode = "joint"
        elif self._turns_input(h) and self.ctx.controller.result(h.element) \
                and self.ctx.controller.result(h.element).solution is not None:
            self._mode = "input"
        else:
            self._mode = "link"

    def _turns_input(self, h) -> bool:
        """Dragging link ``h`` turns the input: the driver is a crank at constant speed (its samples
        are equally spaced angles); an actuator's or a law-driven crank's link drags like any link."""
        drv = self.ctx.linkage(h.element).driver
        return h.id == drv.link and drv.kind == "crank" and drv.law.is_constant

    def on_move(self, ev: CanvasEvent) -> None:
        p = self._press
        if p is None:
            return
        if not self._dragging:
            if ops.dist(ev.raw, p.raw) < DRAG_START * ev.tolerance:
                return
            self._dragging = True
            if self._mode in ("joint", "link"):
                self._start_geometry_drag()
        if self._mode in ("joint", "link"):
            self._drag_geometry(ev)
        elif self._mode == "input":
            self._drag_input(ev)
        elif self._mode == "rubber":
            self._overlay = Overlay(rect=(p.raw, ev.raw))

    def on_release(self, ev: CanvasEvent) -> None:
        p = self._press
        if p is None:
            return
        if not self._dragging:
            self._click(p)
        elif self._mode in ("joint", "link"):
            self._finish_geometry_drag()
        elif self._mode == "rubber":
            self._rubber(p.raw, ev.raw, p.shift)
        self.reset()

    # -- click and rubber band ----------------------------------------------------------------
    def _click(self, p: CanvasEvent) -> None:
        ctl = self.ctx.controller
        if p.hit is None:
            if not p.shift:
                ctl.set_selection([])
            return
        item = tuple(p.hit)
        if p.shift:
            sel = list(ctl.selection)
            sel.remove(item) if item in sel else sel.append(item)
            ctl.set_selection(sel)
        else:
            ctl.set_selection([item])

    def _rubber(self, a: XY, b: XY, add: bool) -> None:
        x0, x1 = sorted((a[0], b[0]))
        y0, y1 = sorted((a[1], b[1]))
        inside = lambda q: x0 <= q[0] <= x1 and y0 <= q[1] <= y1  # noqa: E731
        found = []
        for pose in self.ctx.poses():
            for j in pose.linkage.joints:
                if inside(pose.at[j.id]):
                    found.append((pose.element, "joint", j.id))
            for lk in pose.linkage.links:
                if lk.id != pose.linkage.ground and lk.joints and all(inside(pose.at[j]) for j in lk.joints):
                    found.append((pose.element, "link", lk.id))
        ctl = self.ctx.controller
        sel = list(ctl.selection) if add else []
        ctl.set_selection(sel + [f for f in found if f not in sel])

    # -- geometry drag ------------------------------------------------------------------------
    def _start_geometry_drag(self) -> None:
        h = self._press.hit
        base, self._rebased = self.ctx.editable(h.element)
        self._base = base
        if h.kind == "joint":
            moving = {h.id}
            sel = self.ctx.controller.selection
            if (h.element, "joint", h.id) in sel:
                moving |= {i for el, kind, i in sel if el == h.element and kind == "joint"}
            self._anchor = base.joint(h.id).at
        else:
            moving = set(base.link(h.id).joints)
            self._anchor = self._press.pos
        for jid in list(moving):
            moving.update(ops.coincident_partners(base, jid))
        self._moving = [j.id for j in base.joints if j.id in moving]
        self.ctx.controller.begin_preview()

    def _drag_geometry(self, ev: CanvasEvent) -> None:
        base, el = self._base, self._press.hit.element
        dx, dy = ev.pos[0] - self._anchor[0], ev.pos[1] - self._anchor[1]
        new = base.with_joints_moved({j: (base.joint(j).at[0] + dx, base.joint(j).at[1] + dy)
                                      for j in self._moving})
        why = ops.coincidence(new, self._moving)
        if why:
            self._overlay = Overlay(points=[ev.pos], labels=[(ev.pos, "impossible")], bad=True)
            self.explain(f"cannot move {', '.join(self._moving)} there: {why}")
            return
        self._overlay = Overlay()
        if self.ctx.controller.preview(ReplaceElement(new, "move joint")):
            self._good = new
            self.ctx.hold_frame = True
            if self.ctx.controller.frame != 0:
                self.ctx.controller.set_frame(0)
            self.explain(self.ctx.status(el))

    def _finish_geometry_drag(self) -> None:
        self.ctx.hold_frame = False
        what = self._press.hit
        text = f"move joint {what.id}" if what.kind == "joint" else f"move link {what.id}"
        good = self._good
        self.ctx.controller.end_preview(ReplaceElement(good, text) if good is not None else None, text)
        if good is not None and self._rebased:
            self.ctx.controller.set_frame(0)

    # -- turning the input ----------------------------------------------------------------------
    def _drag_input(self, ev: CanvasEvent) -> None:
        el = self._press.hit.element
        pose = self.ctx.pose(el)
        arrays = pose.arrays if pose is not None else None
        if arrays is None:
            return
        lk = pose.linkage
        c = pose.at[lk.driver.pivot]
        ang = math.atan2(ev.raw[1] - c[1], ev.raw[0] - c[0])
        inp = arrays.solution.input
        step = float(inp[1] - inp[0])
        target = int(round(math.remainder(ang - float(inp[0]), 2 * math.pi) / step)) % arrays.n
        start = pose.index if pose.index is not None else 0
        reached, blocked = walk_to(arrays.valid, start, target)
        ctl = self.ctx.controller
        total = ctl.sample_count()
        ctl.set_frame(reached if arrays.n == total else int(round(reached * total / arrays.n)))
        deg = math.degrees(ang)
        if blocked:
            limit = math.degrees(float(inp[reached]))
            self._overlay = Overlay(lines=[(c, ev.raw)], labels=[(ev.raw, f"{deg:.1f}° unreachable")], bad=True)
            self.explain(f"{el} cannot be assembled at input {deg:.1f}°: it stops at its limit "
                         f"{math.remainder(limit, 360.0):.1f}° and does not jump to the other branch")
        else:
            self._overlay = Overlay()
            self.ok()


class DeleteTool(Tool):
    """Click a joint or link to delete it (and what is left dangling)."""

    name, title, shortcut = "delete", "Delete", "D"
    hint = "Delete: click a joint or a link"

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if ev.hit is None:
            self.explain("delete: click a joint or a link")
            return
        delete_selection(self.ctx, [tuple(ev.hit)])


def delete_selection(ctx: ToolContext, items: list[tuple[str, str, str]]) -> bool:
    """Delete ``items`` (selection format) as one undo command (a macro across linkages)."""
    by_el: dict[str, tuple[list[str], list[str]]] = {}
    ids = set(ctx.controller.scene.ids)
    for el, kind, id_ in items:
        if el in ids:
            by_el.setdefault(el, ([], []))[0 if kind == "joint" else 1].append(id_)
    if not by_el:
        ctx.say("nothing selected to delete")
        return False
    stack = ctx.controller.undo_stack
    names = ", ".join(i for js, ls in by_el.values() for i in js + ls)
    if len(by_el) > 1:
        stack.beginMacro(f"delete {names}")
    done = False
    try:
        for el, (joints, links) in by_el.items():
            new = ops.delete_items(ctx.linkage(el), joints, links)
            done |= ctx.controller.push(RemoveElement(el, f"delete {el}") if new is None
                                        else ReplaceElement(new, f"delete {names}"), f"delete {names}")
    finally:
        if len(by_el) > 1:
            stack.endMacro()
    if done:
        ctx.controller.set_selection([])
        ctx.say(f"deleted {names}")
    return done


class MeasureTool(Tool):
    """Click two points (joints snap) to measure distance and angle."""

    name, title, shortcut = "measure", "Measure", "M"
    hint = "Measure: click two points (joints snap)"

    def reset(self) -> None:
        super().reset()
        self._a: XY | None = None
        self._b: XY | None = None

    def anchor(self) -> XY | None:
        return self._a if self._a is not None and self._b is None else None

    def _point(self, ev: CanvasEvent) -> XY:
        h = ev.hit
        return self.ctx.at(h.element, h.id) if h is not None and h.kind == "joint" else ev.pos

    def _show(self, a: XY, b: XY) -> str:
        d = ops.dist(a, b)
        ang = math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))
        mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
        self._overlay = Overlay(lines=[(a, b)], points=[a, b], labels=[(mid, f"{d:.3f} mm  {ang:.2f}°")])
        return (f"distance {d:.4f} mm, angle {ang:.3f}°, dx {b[0] - a[0]:.4f} mm, dy {b[1] - a[1]:.4f} mm")

    def on_move(self, ev: CanvasEvent) -> None:
        if self._a is not None and self._b is None:
            self._show(self._a, self._point(ev))

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        p = self._point(ev)
        if self._a is None or self._b is not None:
            self.reset()
            self._a = p
            self._overlay = Overlay(points=[p])
            self.explain("measure: click the second point")
        else:
            self._b = p
            self.explain(self._show(self._a, p))


TOOLS: tuple[type[Tool], ...] = (SelectTool, GroundPivotTool, CrankTool, RRRTool, SliderTool, RPRTool,
                                 CouplerPointTool, DeleteTool, MeasureTool, GenevaTool, RollingTool, PRPTool,
                                 RPPTool, InsertTool)
