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

from mechsketch.core.model.edits import AddElement, RemoveElement, ReplaceElement
from mechsketch.core.model.linkage import Joint, JointKind, Linkage

from . import ops
from .events import XY, CanvasEvent, Hit
from .items import Overlay, short_error
from .pose import ElementPose, PoseCache, pick, rebase, to_drawn, walk_to

DRAG_START = 0.4   # of the pick tolerance: how far the mouse moves before a press becomes a drag


class ToolContext:
    """What tools read and change: the controller, the poses on screen, the displayed frame."""

    def __init__(self, controller, cache: PoseCache | None = None) -> None:
        self.controller = controller
        self.cache = cache or PoseCache()
        self.hold_frame = False   # while a geometry drag runs, the canvas shows the drawn pose
        self.pushing = False      # a tool is pushing an edit (the view does not re-fit then)

    # -- reading ----------------------------------------------------------------------------
    def display_frame(self) -> int:
        return 0 if self.hold_frame else self.controller.frame

    def poses(self) -> list[ElementPose]:
        return self.cache.poses(self.controller, self.display_frame())

    def pose(self, element_id: str) -> ElementPose | None:
        return next((p for p in self.poses() if p.element == element_id), None)

    def pick(self, pos: XY, tol: float) -> Hit | None:
        return pick(self.poses(), pos, tol)

    def linkage(self, element_id: str) -> Linkage:
        return self.controller.scene.element(element_id)

    def at(self, element_id: str, joint_id: str) -> XY:
        """Where the joint is on screen now."""
        pose = self.pose(element_id)
        return pose.at[joint_id] if pose is not None else self.linkage(element_id).joint(joint_id).at

    def editable(self, element_id: str) -> tuple[Linkage, bool]:
        """The linkage drawn as on screen (rebased when a non-zero frame is shown), and whether
        it was rebased."""
        lk = self.linkage(element_id)
        pose = self.pose(element_id)
        if pose is None or pose.arrays is None or pose.index in (None, 0):
            return lk, False
        new = rebase(lk, pose.arrays, pose.index)
        return new, new is not lk

    def active_element(self) -> str | None:
        """The linkage of the first selected item, if any."""
        ids = {lk.id for lk in self.controller.linkages()}
        return next((el for el, _, _ in self.controller.selection if el in ids), None)

    # -- writing ----------------------------------------------------------------------------
    def say(self, text: str) -> None:
        self.controller.message.emit(text)

    def commit(self, old_id: str | None, new: Linkage | None, text: str, rebased: bool = False) -> bool:
        """Push one undo command replacing (adding, removing) a linkage; refuse an edit that
        breaks a linkage that solved before. Shows frame 0 afterwards if the edit was rebased."""
        old = self.linkage(old_id) if old_id is not None and old_id in self.controller.scene.ids else None
        if new is not None and old is not None and ops.structure_error(old) is None:
            err = ops.structure_error(new)
            if err is not None:
                self.say(f"cannot {text}: {err}")
                return False
        if new is None:
            edit = RemoveElement(old_id, text)
        elif old is None:
            edit = AddElement(new, label=text)
        else:
            edit = ReplaceElement(new, text)
        self.pushing = True
        try:
            ok = self.controller.push(edit, text)
        finally:
            self.pushing = False
        if ok and rebased:
            self.controller.set_frame(0)
        return ok

    def status(self, element_id: str) -> str:
        """One line on how the linkage solves now (after an edit)."""
        res = self.controller.result(element_id)
        if res is None:
            return ""
        if res.error:
            return f"{element_id}: {short_error(res.error)}"
        diag = res.diagnostics
        if diag is None or diag.full_turn:
            return f"{element_id} moves through a full turn of its crank"
        ranges = ", ".join(f"{math.degrees(a):.1f}° to {math.degrees(b):.1f}°" for a, b in diag.reachable)
        return f"{element_id}: the crank reaches only {ranges or 'no input'} ({len(diag.dead_points)} dead points)"


class Tool:
    """Base of the canvas tools: event dispatch, overlay, de-duplicated status messages."""

    name = "tool"
    title = "Tool"
    shortcut = ""
    hint = ""

    def __init__(self, ctx: ToolContext) -> None:
        self.ctx = ctx
        self._overlay = Overlay()
        self._said: str | None = None
        self.reset()

    def reset(self) -> None:
        """Forget a half-finished placement."""
        self._overlay = Overlay()

    def activate(self) -> None:
        self.reset()
        self._said = None
        if self.hint:
            self.ctx.say(self.hint)

    def deactivate(self) -> None:
        self.cancel()

    def cancel(self) -> None:
        self.reset()

    @property
    def busy(self) -> bool:
        """A drag is in progress (the view reports it and holds the frame)."""
        return False

    def overlay(self) -> Overlay:
        return self._overlay

    def explain(self, text: str) -> None:
        """Say ``text`` once (repeated moves over the same impossible spot say it once)."""
        if text != self._said:
            self._said = text
            self.ctx.say(text)

    def ok(self) -> None:
        self._said = None

    def handle(self, ev: CanvasEvent) -> None:
        getattr(self, f"on_{ev.kind}")(ev)

    def on_press(self, ev: CanvasEvent) -> None:
        pass

    def on_move(self, ev: CanvasEvent) -> None:
        pass

    def on_release(self, ev: CanvasEvent) -> None:
        pass

    def on_double(self, ev: CanvasEvent) -> None:
        self.on_press(ev)

    # -- helpers ----------------------------------------------------------------------------
    def _joint_hit(self, ev: CanvasEvent, revolute: bool = True) -> Hit | None:
        h = ev.hit
        if h is None or h.kind != "joint":
            return None
        if revolute and self.ctx.linkage(h.element).joint(h.id).kind is not JointKind.R:
            return None
        return h

    def _select(self, element: str, kind: str, id_: str) -> None:
        self.ctx.controller.set_selection([(element, kind, id_)])


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
        elif h.id == self.ctx.linkage(h.element).driver.link and self.ctx.controller.result(h.element) \
                and self.ctx.controller.result(h.element).solution is not None:
            self._mode = "input"
        else:
            self._mode = "link"

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


class GroundPivotTool(Tool):
    """Click to place a ground pivot (an R joint on the frame)."""

    name, title, shortcut = "ground", "Ground pivot", "G"
    hint = "Ground pivot: click to place a pivot on the frame (a new linkage unless one is selected)"

    def on_move(self, ev: CanvasEvent) -> None:
        bad = ev.hit is not None and ev.hit.kind == "joint"
        self._overlay = Overlay(points=[ev.pos], labels=[(ev.pos, "ground pivot")], bad=bad)

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if ev.hit is not None and ev.hit.kind == "joint":
            self.explain(f"joint {ev.hit.id} is already here: place the ground pivot elsewhere")
            return
        el = self.ctx.active_element()
        if el is None:
            el = ops.fresh_element_id(self.ctx.controller.scene.ids)
            lk = ops.new_linkage(el, Joint(ops.fresh_joint_id(None), JointKind.R,
                                           (float(ev.pos[0]), float(ev.pos[1]))))
            jid = lk.joints[0].id
            if not self.ctx.commit(None, lk, f"add ground pivot {jid}"):
                return
        else:
            lk, jid = ops.add_ground_pivot(self.ctx.linkage(el), ev.pos)
            if not self.ctx.commit(el, lk, f"add ground pivot {jid}"):
                return
        self._select(el, "joint", jid)
        nxt = "another pivot (G) or a crank from a pivot (C)" if not ops.has_driver(lk) else "a dyad (R, P, I)"
        self.explain(f"ground pivot {jid} added to {el}; next: {nxt}")


class CrankTool(Tool):
    """Click a ground pivot, then the crank tip: adds the crank link and makes it the driver."""

    name, title, shortcut = "crank", "Crank (driver)", "C"
    hint = "Crank: click a ground pivot, then the crank tip"

    def reset(self) -> None:
        super().reset()
        self._pivot: Hit | None = None

    def on_move(self, ev: CanvasEvent) -> None:
        if self._pivot is None:
            return
        c = self.ctx.at(self._pivot.element, self._pivot.id)
        r = ops.dist(c, ev.pos)
        bad = r <= ops.SAME_POINT or (ev.hit is not None and ev.hit.kind == "joint")
        self._overlay = Overlay(lines=[(c, ev.pos)], points=[ev.pos], circles=[(c, r)],
                                labels=[(ev.pos, f"r = {r:.2f} mm")], bad=bad)

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if self._pivot is None:
            h = self._joint_hit(ev)
            if h is None:
                self.explain("crank: click a ground pivot first (place one with G)")
                return
            lk = self.ctx.linkage(h.element)
            if not ops.on_ground(lk, h.id):
                self.explain(f"crank: {h.id} is not on the frame; a crank turns about a ground pivot")
            elif ops.has_driver(lk):
                self.explain(f"{h.element} already has a driver ({lk.driver.link}); one driver per linkage")
            else:
                self._pivot = h
                self.explain(f"crank from {h.id}: click where its tip goes")
            return
        el, pivot = self._pivot.element, self._pivot.id
        c = self.ctx.at(el, pivot)
        if ev.hit is not None and ev.hit.kind == "joint":
            self.explain(f"the crank tip must be a new point; joint {ev.hit.id} is already there")
            return
        if ops.dist(c, ev.pos) <= ops.SAME_POINT:
            self.explain("the crank would have zero length: click away from its pivot")
            return
        lk, cid, tip = ops.add_crank(self.ctx.linkage(el), pivot, ev.pos)
        if self.ctx.commit(el, lk, f"add crank {cid}"):
            self._select(el, "joint", tip)
            self.explain(f"crank {cid} ({pivot}-{tip}) drives {el}; next: an RRR dyad (R) or a slider (P, I)")
        self.reset()


class _DyadTool(Tool):
    """Shared picking of known joints for the dyad tools."""

    def reset(self) -> None:
        super().reset()
        self._picked: list[Hit] = []

    def _pick_known(self, ev: CanvasEvent, role: str) -> Hit | None:
        h = self._joint_hit(ev)
        if h is None:
            what = "a P joint cannot be" if ev.hit is not None and ev.hit.kind == "joint" else "click a joint for"
            self.explain(f"{self.title}: {what} {role} (pick a revolute joint already in the linkage)")
            return None
        if self._picked and h.element != self._picked[0].element:
            self.explain(f"{h.id} belongs to {h.element}, not {self._picked[0].element}: a dyad joins one linkage")
            return None
        if any(p.id == h.id for p in self._picked):
            self.explain(f"{h.id} is picked already: pick a different joint for {role}")
            return None
        return h


class RRRTool(_DyadTool):
    """Pick two known joints M and H, then place the inner joint L: adds links M-L and H-L."""

    name, title, shortcut = "rrr", "RRR dyad", "R"
    hint = "RRR dyad: click the first known joint (M), the second (H), then place the inner joint"

    def _check(self, ev: CanvasEvent) -> str | None:
        m, h = self._picked
        pm, ph = self.ctx.at(m.element, m.id), self.ctx.at(h.element, h.id)
        if ev.hit is not None and ev.hit.kind == "joint":
            return f"the inner joint would coincide with joint {ev.hit.id}: place it on a free spot"
        if ops.dist(ev.pos, pm) <= ops.SAME_POINT or ops.dist(ev.pos, ph) <= ops.SAME_POINT:
            return "the inner joint would coincide with an outer joint"
        if ops.sin_angle(ev.pos, pm, ph) < ops.COLLINEAR_SIN:
            return f"the inner joint is on the line through {m.id} and {h.id}: the dyad would be drawn at a dead point"
        return None

    def on_move(self, ev: CanvasEvent) -> None:
        if len(self._picked) == 1:
            pm = self.ctx.at(self._picked[0].element, self._picked[0].id)
            self._overlay = Overlay(lines=[(pm, ev.pos)])
        elif len(self._picked) == 2:
            m, h = self._picked
            pm, ph = self.ctx.at(m.element, m.id), self.ctx.at(h.element, h.id)
            why = self._check(ev)
            self._overlay = Overlay(lines=[(pm, ev.pos), (ph, ev.pos)], points=[ev.pos],
                                    labels=[(ev.pos, f"{ops.dist(pm, ev.pos):.1f} / {ops.dist(ph, ev.pos):.1f} mm")],
                                    bad=why is not None)
            self.explain(why) if why else self.ok()

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if len(self._picked) < 2:
            h = self._pick_known(ev, "M" if not self._picked else "H")
            if h is not None:
                self._picked.append(h)
                self.explain(f"RRR dyad: {h.id} picked; " + ("now the second joint (H)" if len(self._picked) == 1
                                                              else "now place the inner joint"))
            return
        why = self._check(ev)
        if why:
            self.explain(f"cannot place the dyad: {why}")
            return
        m, h = self._picked
        base, rebased = self.ctx.editable(m.element)
        lk, jl, links = ops.add_rrr(base, m.id, h.id, ev.pos)
        if self.ctx.commit(m.element, lk, f"add RRR dyad {m.id}-{jl}-{h.id}", rebased):
            self._select(m.element, "joint", jl)
            self.explain(f"dyad {links[0]}, {links[1]} added. " + self.ctx.status(m.element))
        self.reset()


class SliderTool(_DyadTool):
    """RRP: pick the known joint M, click the guide (on a moving link, or empty space for the
    frame) where it starts, then place the slider pin: the guide runs from the first guide click
    through the pin."""

    name, title, shortcut = "rrp", "Slider dyad (RRP)", "P"
    hint = "Slider (RRP): click the known joint, then the guide's start (on a link, or empty space for the frame), then the slider pin"

    def reset(self) -> None:
        super().reset()
        self._guide: tuple[str, XY] | None = None

    def _check(self, ev: CanvasEvent) -> str | None:
        pm = self.ctx.at(self._picked[0].element, self._picked[0].id)
        if ev.hit is not None and ev.hit.kind == "joint":
            return f"the slider pin would coincide with joint {ev.hit.id}"
        if ops.dist(ev.pos, pm) <= ops.SAME_POINT:
            return "the slider pin would coincide with the rod's other joint"
        if ops.dist(ev.pos, self._guide[1]) <= ops.SAME_POINT:
            return "the pin is at the guide's first point: move away to give the guide a direction"
        return None

    def on_move(self, ev: CanvasEvent) -> None:
        if not self._picked:
            return
        pm = self.ctx.at(self._picked[0].element, self._picked[0].id)
        if self._guide is None:
            self._overlay = Overlay(lines=[(pm, ev.pos)])
            return
        g = self._guide[1]
        d = complex(ev.pos[0] - g[0], ev.pos[1] - g[1])
        far = complex(*g) + (d / abs(d) * max(abs(d) * 1.5, 1.0) if abs(d) > 0 else 0)
        why = self._check(ev)
        self._overlay = Overlay(lines=[(pm, ev.pos), (g, (far.real, far.imag))], points=[ev.pos],
                                labels=[(ev.pos, f"guide {math.degrees(math.atan2(d.imag, d.real)):.1f}°")],
                                bad=why is not None)
        self.explain(why) if why else self.ok()

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if not self._picked:
            h = self._pick_known(ev, "the rod's joint")
            if h is not None:
                self._picked.append(h)
                self.explain(f"slider: rod from {h.id}; click the guide's start (on a moving link, or empty space for the frame)")
            return
        el = self._picked[0].element
        if self._guide is None:
            lk = self.ctx.linkage(el)
            if ev.hit is not None and ev.hit.kind == "link" and ev.hit.element == el:
                self._guide = (ev.hit.id, ev.pos)
            elif ev.hit is not None and ev.hit.element != el:
                self.explain(f"that belongs to {ev.hit.element}: the guide must be in {el}")
                return
            else:
                self._guide = (lk.ground, ev.pos)
            self.explain(f"slider: guide on {self._guide[0]}; click where the slider pin goes")
            return
        why = self._check(ev)
        if why:
            self.explain(f"cannot place the slider: {why}")
            return
        g = self._guide[1]
        axis = math.degrees(math.atan2(ev.pos[1] - g[1], ev.pos[0] - g[0]))
        base, rebased = self.ctx.editable(el)
        lk, pin, slide = ops.add_rrp(base, self._picked[0].id, self._guide[0], ev.pos, axis)
        if self.ctx.commit(el, lk, f"add slider {pin}/{slide} on {self._guide[0]}", rebased):
            self._select(el, "joint", pin)
            self.explain(f"slider added (pin {pin}, P joint {slide} on {self._guide[0]}). " + self.ctx.status(el))
        self.reset()


class RPRTool(_DyadTool):
    """RPR (inverted slider): pick the joint M the block pivots on, then the pivot H of the slotted
    bar; the bar's axis runs through H and M."""

    name, title, shortcut = "rpr", "RPR dyad", "I"
    hint = "RPR: click the joint the block pivots on (M), then the pivot of the slotted bar (H)"

    def on_move(self, ev: CanvasEvent) -> None:
        if self._picked:
            pm = self.ctx.at(self._picked[0].element, self._picked[0].id)
            self._overlay = Overlay(lines=[(ev.pos, pm)], points=[pm], labels=[(ev.pos, "bar pivot")])

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        h = self._pick_known(ev, "M" if not self._picked else "H")
        if h is None:
            return
        if not self._picked:
            self._picked.append(h)
            self.explain(f"RPR: block on {h.id}; now click the pivot of the slotted bar (H)")
            return
        m = self._picked[0]
        base, rebased = self.ctx.editable(m.element)
        lk, q = ops.add_rpr(base, m.id, h.id)
        if self.ctx.commit(m.element, lk, f"add RPR dyad {m.id}-{q}-{h.id}", rebased):
            self._select(m.element, "joint", q)
            self.explain(f"RPR dyad added (P joint {q}). " + self.ctx.status(m.element))
        self.reset()


class CouplerPointTool(Tool):
    """Click on a moving link to add a point to it (traced as a coupler curve)."""

    name, title, shortcut = "coupler", "Coupler point", "K"
    hint = "Coupler point: click on a moving link to add a point to it"

    def on_move(self, ev: CanvasEvent) -> None:
        h = ev.hit
        if h is not None and h.kind == "link":
            pose = self.ctx.pose(h.element)
            pts = [pose.at[j] for j in pose.linkage.link(h.id).joints]
            self._overlay = Overlay(lines=[(p, ev.pos) for p in pts], points=[ev.pos])
        else:
            self._overlay = Overlay(points=[ev.pos], bad=True)

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        h = ev.hit
        if h is None or h.kind != "link":
            self.explain("coupler point: click on a moving link (a bar or plate), not on "
                         + (f"joint {h.id}" if h is not None else "empty space"))
            return
        pose = self.ctx.pose(h.element)
        lk = pose.linkage
        at = to_drawn(pose.arrays, lk, h.id, pose.index, ev.pos)
        new, jid = ops.add_coupler_point(lk, h.id, at)
        why = ops.coincidence(new, [jid])
        if why:
            self.explain(f"cannot add the point: {why}")
            return
        if self.ctx.commit(h.element, new, f"add coupler point {jid} on {h.id}"):
            self._select(h.element, "joint", jid)
            self.explain(f"coupler point {jid} added on {h.id} (its path is traced)")


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
                                 CouplerPointTool, DeleteTool, MeasureTool)
