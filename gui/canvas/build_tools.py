"""The tools that draw a linkage: ground pivot, crank, RRR, RRP (slider), RPR, coupler point.

Each turns clicks into one undo command, previews what it will create while the mouse moves,
and explains an impossible placement through ``controller.message``. See :mod:`.tools`.
"""
from __future__ import annotations

import math
from dataclasses import replace

from mechsketch.core.model.linkage import Joint, JointKind
from mechsketch.core.solver.structure import fixed_links

from . import ops
from .events import XY, CanvasEvent, Hit
from .items import Overlay
from .pose import to_drawn
from .tool_base import Tool

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

    def picks(self) -> list[Hit]:
        return [self._pivot] if self._pivot is not None else []

    def anchor(self) -> XY | None:
        p = self._pivot
        return self.ctx.at(p.element, p.id) if p is not None and self.ctx.exists(p) else None

    def overlay(self) -> Overlay:
        p = self._pivot
        if p is None or not self.ctx.exists(p):
            return self._overlay
        return replace(self._overlay, picked=[self.ctx.at(p.element, p.id)])

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

    def picks(self) -> list[Hit]:
        return list(self._picked)

    def overlay(self) -> Overlay:
        """The preview, with the joints picked so far ringed."""
        picked = [self.ctx.at(h.element, h.id) for h in self._picked if self.ctx.exists(h)]
        return replace(self._overlay, picked=picked) if picked else self._overlay

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
        if self._picked:  # the other outer joint: a pair fixed to the frame makes a structure
            why = ops.fixed_dyad(self.ctx.linkage(h.element), self._picked[0].id, h.id)
            if why:
                self.explain(f"{self.title}: {why}")
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

    def anchor(self) -> XY | None:
        return self._guide[1] if self._guide is not None else None

    def picks(self) -> list[Hit]:
        out = list(self._picked)
        if self._guide is not None and self._picked:
            el = self._picked[0].element
            if self.ctx.has_linkage(el) and self._guide[0] != self.ctx.linkage(el).ground:
                out.append(Hit(el, "link", self._guide[0]))
        return out

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
            rod = self._picked[0].id
            if self._guide[0] in fixed_links(lk) and ops.fixed_point(lk, rod):
                what = "the frame" if self._guide[0] == lk.ground else f"{self._guide[0]} (fixed to the frame)"
                self._guide = None
                self.explain(f"slider: the rod's joint {rod} is fixed to the frame and the guide would be on "
                             f"{what}: the slider would not move (zero mobility); click a moving link for "
                             f"the guide, or start the rod from a moving joint")
                return
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
