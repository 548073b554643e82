"""The PRP and RPP tools, so every dyad kind the solver knows can be drawn.

- PRP (Y): two blocks pinned together at L, each sliding on a guide of a known link. Click guide 1's
  start (on a moving link, or on empty space for the frame of the selected linkage), then the pin
  L (guide 1 runs from its start through L), then guide 2's start (guide 2 runs through L). At
  least one guide must be on a moving link, and the two on different links, not parallel.
- RPP (X): a block pivoting on a known joint M slides in a slot of a yoke that slides on a guide
  of a known link (the Scotch yoke). Click M, then the guide's start (a moving link, or empty
  space for the frame), then the yoke's point Y: the guide runs from its start through Y, the slot
  from M through Y.

Each adds its two links as one undo command; see :mod:`.build_tools` for the other dyads.
"""
from __future__ import annotations

import math
from dataclasses import replace

from mechsketch.core.model.linkage import Joint, JointKind, Link, Linkage

from . import ops
from .events import XY, CanvasEvent, Hit
from .items import Overlay
from .tool_base import Tool


def _axis(a: XY, b: XY) -> float:
    return math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))


def _on(lk: Linkage, link_id: str, jid: str) -> Linkage:
    g = lk.link(link_id) if link_id in lk.link_ids else Link(link_id, ())
    return lk.with_link(Link(g.id, g.joints + (jid,)))


def add_prp(linkage: Linkage, guide_i: str, axis_i: float, guide_j: str, axis_j: float, at: XY
            ) -> tuple[Linkage, str, tuple[str, str]]:
    """Blocks on guides of ``guide_i`` and ``guide_j`` (axes in degrees, through ``at``), pinned
    at a new R joint L at ``at``. Returns (linkage, L, (P joint i, P joint j))."""
    jl = ops.fresh_joint_id(linkage)
    s1 = ops.fresh_joint_id(linkage, taken=(jl,))
    s2 = ops.fresh_joint_id(linkage, taken=(jl, s1))
    bi = ops.fresh_link_id(linkage, "block")
    bj = ops.fresh_link_id(linkage, "block", taken=(bi,))
    p = (float(at[0]), float(at[1]))
    lk = (linkage.with_joint(Joint(jl, JointKind.R, p)).with_joint(Joint(s1, JointKind.P, p, float(axis_i)))
          .with_joint(Joint(s2, JointKind.P, p, float(axis_j))))
    lk = lk.with_link(Link(bi, (s1, jl))).with_link(Link(bj, (jl, s2)))
    return _on(_on(lk, guide_i, s1), guide_j, s2), jl, (s1, s2)


def add_rpp(linkage: Linkage, m: str, guide: str, at: XY, guide_axis: float) -> tuple[Linkage, str, str]:
    """RPP: block (M, slot joint q at M, axis M -> ``at``) and yoke (q, guide joint s at ``at``,
    axis ``guide_axis`` degrees) sliding on ``guide``. Returns (linkage, q, s)."""
    pm = linkage.joint(m).at
    q = ops.fresh_joint_id(linkage)
    s = ops.fresh_joint_id(linkage, taken=(q,))
    block = ops.fresh_link_id(linkage, "block")
    yoke = ops.fresh_link_id(linkage, "yoke", taken=(block,))
    lk = (linkage.with_joint(Joint(q, JointKind.P, (float(pm[0]), float(pm[1])), _axis(pm, at)))
          .with_joint(Joint(s, JointKind.P, (float(at[0]), float(at[1])), float(guide_axis))))
    lk = lk.with_link(Link(block, (m, q))).with_link(Link(yoke, (q, s)))
    return _on(lk, guide, s), q, s


class _GuideTool(Tool):
    """Shared: picking a guide (a moving link, or empty space for the frame) of one linkage."""

    def reset(self) -> None:
        super().reset()
        self._el: str | None = None
        self._guides: list[tuple[str, XY]] = []

    def refers_to(self) -> set[str]:
        return super().refers_to() | ({self._el} if self._el is not None else set())

    def picks(self) -> list[Hit]:
        if self._el is None or not self.ctx.has_linkage(self._el):
            return []
        lk = self.ctx.linkage(self._el)
        return [Hit(self._el, "link", g) for g, _ in self._guides if g != lk.ground]

    def _guide(self, ev: CanvasEvent) -> tuple[str, str] | str:
        """(element, guide link) under ``ev``, or why not."""
        h = ev.hit
        linkages = {lk.id for lk in self.ctx.controller.linkages()}
        if h is not None and h.kind == "link" and h.element in linkages:
            if self._el is not None and h.element != self._el:
                return f"{h.id} belongs to {h.element}, not {self._el}: a dyad joins one linkage"
            return h.element, h.id
        if h is not None and h.kind == "joint":
            return f"joint {h.id} is not a guide: click a link (or empty space for the frame)"
        el = self._el or self.ctx.active_element()
        if el is None:
            return "click a moving link for the guide, or select the linkage first to guide on its frame"
        return el, self.ctx.linkage(el).ground

    def _check_pin(self, ev: CanvasEvent, others: list[XY]) -> str | None:
        if ev.hit is not None and ev.hit.kind == "joint":
            return f"the point would coincide with joint {ev.hit.id}: place it on a free spot"
        if any(ops.dist(ev.pos, p) <= ops.SAME_POINT for p in others):
            return "the point is on a point already picked: the axis would have no direction"
        return None


class PRPTool(_GuideTool):
    """PRP dyad: guide 1's start, the pin, guide 2's start (see the module docstring)."""

    name, title, shortcut = "prp", "PRP dyad", "Y"
    hint = "PRP: click guide 1's start (a moving link, or empty space for the frame), the pin, then guide 2's start"

    def reset(self) -> None:
        super().reset()
        self._pin: XY | None = None

    def anchor(self) -> XY | None:
        """The pin is placed along guide 1 from its start; guide 2's start from the pin."""
        if self._pin is not None:
            return self._pin
        return self._guides[0][1] if self._guides else None

    def _why(self, g2: tuple[str, XY]) -> str | None:
        (g1, a), (g2id, b) = self._guides[0], g2
        lk = self.ctx.linkage(self._el)
        if g1 == lk.ground and g2id == lk.ground:
            return "both guides are on the frame: the pin could not move; put one on a moving link"
        if g1 == g2id:
            return f"both guides are on {g1}: the pin would be fixed to it; put guide 2 on another link"
        if ops.sin_angle(self._pin, a, b) < ops.COLLINEAR_SIN:
            return "the two guides are parallel: the blocks could slide without end; turn one"
        return None

    def on_move(self, ev: CanvasEvent) -> None:
        if not self._guides:
            return
        a = self._guides[0][1]
        if self._pin is None:
            self._overlay = Overlay(lines=[(a, ev.pos)], points=[ev.pos],
                                    labels=[(ev.pos, f"pin; guide 1 at {_axis(a, ev.pos):.1f}°")])
            return
        g = self._guide(ev)
        why = g if isinstance(g, str) else self._why((g[1], ev.pos))
        self._overlay = Overlay(lines=[(a, self._pin), (ev.pos, self._pin)], points=[self._pin],
                                labels=[(ev.pos, why or f"guide 2 at {_axis(ev.pos, self._pin):.1f}°")],
                                bad=why is not None)

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if not self._guides:
            g = self._guide(ev)
            if isinstance(g, str):
                self.explain(f"PRP: {g}")
                return
            self._el = g[0]
            self._guides.append((g[1], ev.pos))
            self.explain(f"PRP: guide 1 on {g[1]}; click where the pin goes")
            return
        if self._pin is None:
            why = self._check_pin(ev, [self._guides[0][1]])
            if why:
                self.explain(f"PRP: {why}")
                return
            self._pin = ev.pos
            self.explain("PRP: now click guide 2's start (a moving link, or empty space for the frame)")
            return
        g = self._guide(ev)
        why = g if isinstance(g, str) else (self._check_pin(ev, [self._pin]) or self._why((g[1], ev.pos)))
        if why:
            self.explain(f"cannot place the PRP dyad: {why}")
            return
        (g1, a), g2, b = self._guides[0], g[1], ev.pos
        base, rebased = self.ctx.editable(self._el)
        lk, pin, (s1, s2) = add_prp(base, g1, _axis(a, self._pin), g2, _axis(b, self._pin), self._pin)
        el = self._el
        if self.ctx.commit(el, lk, f"add PRP dyad {s1}-{pin}-{s2}", rebased):
            self._select(el, "joint", pin)
            self.explain(f"PRP dyad added (pin {pin} sliding on {g1} and {g2}). " + self.ctx.status(el))
        self.reset()


class RPPTool(_GuideTool):
    """RPP dyad (Scotch yoke): the joint M, the guide's start, the yoke point Y."""

    name, title, shortcut = "rpp", "RPP dyad (yoke)", "X"
    hint = "RPP: click the joint the block pivots on (M), the guide's start (a moving link, or empty space for the frame), then the yoke point"

    def reset(self) -> None:
        super().reset()
        self._m: Hit | None = None

    def picks(self) -> list[Hit]:
        return ([self._m] if self._m is not None else []) + super().picks()

    def overlay(self) -> Overlay:
        m = self._m
        if m is None or not self.ctx.exists(m):
            return self._overlay
        return replace(self._overlay, picked=[self.ctx.at(m.element, m.id)])

    def _why(self, ev: CanvasEvent) -> str | None:
        pm = self.ctx.at(self._m.element, self._m.id)
        guide, g = self._guides[0]
        lk = self.ctx.linkage(self._el)
        why = self._check_pin(ev, [pm, g])
        if why:
            return why
        if guide in lk.links_of(self._m.id):
            return f"the guide is on {guide}, which carries {self._m.id}: the yoke could not move; use another link"
        if ops.sin_angle(ev.pos, pm, g) < ops.COLLINEAR_SIN:
            return "the slot and the guide are parallel: the yoke would be undetermined; move the yoke point"
        return None

    def on_move(self, ev: CanvasEvent) -> None:
        if self._m is None:
            return
        pm = self.ctx.at(self._m.element, self._m.id)
        if not self._guides:
            self._overlay = Overlay(lines=[(pm, ev.pos)], labels=[(ev.pos, "guide start")])
            return
        g = self._guides[0][1]
        why = self._why(ev)
        self._overlay = Overlay(lines=[(pm, ev.pos), (g, ev.pos)], points=[ev.pos],
                                labels=[(ev.pos, why or f"slot {_axis(pm, ev.pos):.1f}°, guide {_axis(g, ev.pos):.1f}°")],
                                bad=why is not None)

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if self._m is None:
            h = self._joint_hit(ev)
            if h is None:
                self.explain("RPP: click the revolute joint the block pivots on (M)")
                return
            self._m, self._el = h, h.element
            self.explain(f"RPP: block on {h.id}; click the guide's start (a moving link, or empty space for the frame)")
            return
        if not self._guides:
            g = self._guide(ev)
            if isinstance(g, str):
                self.explain(f"RPP: {g}")
                return
            self._guides.append((g[1], ev.pos))
            self.explain(f"RPP: guide on {g[1]}; click the yoke point (the slot runs from {self._m.id} through it)")
            return
        why = self._why(ev)
        if why:
            self.explain(f"cannot place the RPP dyad: {why}")
            return
        guide, g = self._guides[0]
        el = self._el
        base, rebased = self.ctx.editable(el)
        lk, q, s = add_rpp(base, self._m.id, guide, ev.pos, _axis(g, ev.pos))
        if self.ctx.commit(el, lk, f"add RPP dyad {self._m.id}-{q}-{s}", rebased):
            self._select(el, "joint", s)
            self.explain(f"RPP dyad added (slot {q}, guide {s} on {guide}). " + self.ctx.status(el))
        self.reset()
