"""How the linkage's input enters a plan: a crank, a slider on a fixed guide, or a cylinder.

:func:`make_drive` reads :attr:`Linkage.driver <mechsketch.core.model.linkage.Linkage.driver>`
and returns the object the plan asks (:mod:`mechsketch.core.solver.plan`):

- its input at the drawn pose ``input0`` (a crank's drawn angle, rad; a cylinder's drawn length,
  mm; a slider's drawn displacement, 0 mm) and the input's unit;
- the decomposition into groups (:meth:`decompose`), and the links it makes known before them;
- the states of the driven links for an array of inputs with their rates (:meth:`set_states`);
- for actuators, the branch points along the stroke and the ±1 mode flips they cause.

A **crank** is the class-I mechanism of the structure theory: a link of any number of joints on a
revolute joint of the frame (it turns by input − input0). A **slider** is its prismatic twin: a
link translating along a guide of the frame by the input. A **cylinder** (an RPR with driven
length) is not a link but a bar of variable length between its two pivots, the *virtual link* V:
the decomposition runs on the linkage with barrel and rod replaced by V (named as the barrel), V
falls in one dyad (RRR, or the rod of an RRP), and that dyad is solved by the kernels of
:mod:`.stroke_kernels` with V's length set to the input; barrel and rod then follow V, and the
cylinder's slide is reported as the group's :class:`~.kernels.Slide`.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..errors import StructureError
from ..model.drivers import DriverKind, input_unit
from ..model.linkage import JointKind, Link, Linkage
from . import kernels as K
from .branches import CANDIDATE, GOLDEN_STEPS, REF_SAMPLES, golden_min
from .solution import _axis, _c
from .steps import StepPlan
from .stroke_kernels import Cylinder, Stroke, _bar, rrp_var, rrr_var
from .structure import MODAL_KINDS, Group, GroupKind, _split, decompose, fixed_links, joint_count, mobility
from .tolerances import TOUCH_REL



def _check_mobility(linkage: Linkage) -> None:
    f = mobility(linkage)
    if f != 1:
        state = "under-constrained (it can move freely)" if f > 1 else "over-constrained (it cannot move)"
        raise StructureError(
            f"linkage {linkage.id!r} has mobility {f}, needs 1 for one driver: it is {state}. "
            f"{len(linkage.links)} links, {joint_count(linkage)} lower pairs "
            f"(F = 3·({len(linkage.links)}−1) − 2·{joint_count(linkage)})",
            joints=linkage.joint_ids, links=linkage.link_ids)


def _fixed(linkage: Linkage, groups: list[Group]) -> list[Group]:
    """Mark the groups hung on the frame only (see :func:`.structure.decompose`)."""
    fixed = fixed_links(linkage)

    def frame_side(joint: str, known: str) -> str:
        return linkage.ground if known not in fixed and linkage.ground in linkage.links_of(joint) else known

    return [replace(g, fixed=True, known_i=frame_side(g.outer_i, g.known_i),
                    known_j=frame_side(g.outer_j, g.known_j))
            if g.link_i in fixed and g.link_j in fixed else g for g in groups]


class CrankDrive:
    """A crank: ``link`` turns about the frame's revolute joint ``pivot`` (input: angle, rad)."""

    kind = DriverKind.CRANK
    linear = False

    def __init__(self, linkage: Linkage) -> None:
        drv = linkage.driver
        self.link = drv.link
        self.pivot = _c(linkage.joint(drv.pivot).at)
        tip = next(j for j in linkage.link(drv.link).joints if j != drv.pivot)
        d = _c(linkage.joint(tip).at) - self.pivot
        self.input0 = math.atan2(d.imag, d.real)
        #: links known before the first group (besides the frame); links solved with a group
        self.known: tuple[str, ...] = (drv.link,)
        self.extra: dict[str, str] = {}

    @property
    def unit(self) -> str:
        return input_unit(self.kind)

    def decompose(self, linkage: Linkage) -> list[Group]:
        return decompose(linkage)

    def compile_step(self, linkage: Linkage, group: Group) -> tuple | None:
        """(run, scale, coord) of a group this drive solves itself, else None (a plain dyad)."""
        return None

    def set_states(self, states: dict, inputs: np.ndarray, rate, accel, order: int) -> None:
        states[self.link] = K.crank(self.pivot, self.input0, inputs, rate, accel, order)


class SliderDrive(CrankDrive):
    """A slider: ``link`` translates along the frame's guide ``pivot`` (input: displacement from
    the drawn position along the guide's direction, mm)."""

    kind = DriverKind.SLIDER
    linear = True

    def __init__(self, linkage: Linkage) -> None:
        drv = linkage.driver
        self.link = drv.link
        self.pivot, self.u0 = _axis(linkage, drv.pivot)
        self.input0 = 0.0
        self.stroke = drv.stroke
        self.known = (drv.link,)
        self.extra = {}

    def decompose(self, linkage: Linkage) -> list[Group]:
        drv = linkage.driver
        if linkage.ground not in linkage.link_ids or drv.link not in linkage.link_ids or drv.link == linkage.ground:
            raise StructureError(f"linkage {linkage.id!r}: the slider {drv.link!r} must be a moving link",
                                 links=(drv.link,))
        if drv.pivot not in linkage.link(linkage.ground).joints or drv.pivot not in linkage.link(drv.link).joints \
                or linkage.joint(drv.pivot).kind is not JointKind.P:
            raise StructureError(f"driver {drv.link!r} must slide on a prismatic joint of the ground link "
                                 f"(its guide {drv.pivot!r})", joints=(drv.pivot,), links=(drv.link,))
        _check_mobility(linkage)
        return _fixed(linkage, _split(linkage, {linkage.ground, drv.link}))

    def set_states(self, states: dict, inputs: np.ndarray, rate, accel, order: int) -> None:
        states[self.link] = K._slider(K.ground_state(), self.pivot, self.u0, inputs, rate, accel, order)


class CylinderDrive(CrankDrive):
    """A cylinder: barrel ``link`` and rod joined by the prismatic joint ``pivot``, pinned at M
    and H (input: |H − M|, mm). See the module docstring for how it is solved."""

    kind = DriverKind.CYLINDER
    linear = True

    def __init__(self, linkage: Linkage) -> None:
        drv = linkage.driver
        self.link, self.slide = drv.link, drv.pivot
        carriers = linkage.links_of(drv.pivot)
        rods = [k for k in carriers if k != drv.link]
        if drv.link not in carriers or len(rods) != 1 or linkage.joint(drv.pivot).kind is not JointKind.P:
            raise StructureError(f"cylinder {drv.link!r} must be joined to its rod by the prismatic joint "
                                 f"{drv.pivot!r}", joints=(drv.pivot,), links=(drv.link,))
        self.rod = rods[0]
        ends = []
        for lk in (drv.link, self.rod):
            others = [j for j in linkage.link(lk).joints if j != drv.pivot]
            if len(others) != 1 or linkage.joint(others[0]).kind is not JointKind.R:
                raise StructureError(f"the cylinder's {'barrel' if lk == drv.link else 'rod'} {lk!r} must carry "
                                     f"its slide {drv.pivot!r} and one revolute end pivot",
                                     links=(lk,), joints=linkage.link(lk).joints)
            ends.append(others[0])
        self.m, self.h = ends
        _, u0 = _axis(linkage, drv.pivot)
        self.geometry = Cylinder(_c(linkage.joint(self.m).at), _c(linkage.joint(self.h).at), u0)
        self.pivot = self.geometry.m0
        self.input0 = abs(self.geometry.h0 - self.geometry.m0)
        self.stroke = drv.stroke
        self.known = ()
        self.extra = {self.rod: self.link}
        self.current = Stroke(np.array([self.input0]))

    def virtual(self, linkage: Linkage) -> Linkage:
        """The linkage with barrel and rod replaced by the bar V = (M, H), named as the barrel and
        listed last (so that later groups hang on real links where they can)."""
        links = tuple(k for k in linkage.links if k.id not in (self.link, self.rod))
        joints = tuple(j for j in linkage.joints if j.id != self.slide)
        return replace(linkage, joints=joints, links=links + (Link(self.link, (self.m, self.h)),))

    def decompose(self, linkage: Linkage) -> list[Group]:
        _check_mobility(linkage)
        v = self.virtual(linkage)
        groups = _fixed(v, _split(v, {linkage.ground}))
        mine = [g for g in groups if self.link in (g.link_i, g.link_j)]
        if len(mine) != 1 or mine[0].kind not in (GroupKind.RRR, GroupKind.RRP) or (
                mine[0].kind is GroupKind.RRP and mine[0].link_i != self.link):
            raise StructureError(f"cylinder {self.link!r}–{self.rod!r} must move a link pinned to it (an RRR "
                                 f"group) or a slider (an RRP group)", links=(self.link, self.rod))
        out = []
        for g in groups:   # a group hung on V at the rod's pivot hangs on the rod
            if g.known_i == self.link and g.outer_i == self.h:
                g = replace(g, known_i=self.rod)
            if g.known_j == self.link and g.outer_j == self.h:
                g = replace(g, known_j=self.rod)
            out.append(g)
        return out

    def set_states(self, states: dict, inputs: np.ndarray, rate, accel, order: int) -> None:
        self.current = Stroke(inputs, rate, accel)

    def compile_step(self, linkage: Linkage, g: Group) -> tuple | None:
        """(run, scale, coord) of the group V is in (see :class:`~.steps.Step`), else None."""
        if self.link not in (g.link_i, g.link_j):
            return None
        at = {j.id: _c(j.at) for j in linkage.joints}
        ki, kj = g.known_i, g.known_j
        near = set(g.joints) | set(linkage.link(ki).joints) | set(linkage.link(kj).joints)
        coord = max((abs(at[j]) for j in near if j in at), default=0.0)
        cyl, drive = self.geometry, self

        if g.kind is GroupKind.RRR:
            m0, h0, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
            scale = abs(l0 - m0) + abs(l0 - h0)
            tol = TOUCH_REL * (scale + coord)
            v_is_i = g.link_i == self.link

            def run(s: dict, order: int, flip) -> K.DyadOut:
                st = drive.current
                zero = 0.0
                li, dli, ddli = (st.L, st.Ld, st.Ldd) if v_is_i else (abs(l0 - m0), zero, zero)
                lj, dlj, ddlj = (st.L, st.Ld, st.Ldd) if not v_is_i else (abs(l0 - h0), zero, zero)
                o = rrr_var(s[ki], m0, s[kj], h0, l0, li, lj, dli, dlj, ddli, ddlj, order, flip, tol)
                vL = aL = None
                if order >= 1:
                    vL = o["vM"] + 1j * o["wi"] * o["ri"] + (dli / li) * o["ri"]
                if order >= 2:
                    aL = (o["aM"] + (1j * o["ai"] - o["wi"] * o["wi"] + ddli / li) * o["ri"]
                          + 2.0 * (dli / li) * o["wi"] * 1j * o["ri"])
                pos = {g.outer_i: (o["M"], o["vM"], o["aM"]), g.outer_j: (o["H"], o["vH"], o["aH"]),
                       g.inner: (o["L"], vL, aL)}
                if v_is_i:
                    partner = _bar(h0, o["H"], o["rj"], l0 - h0, o["vH"], o["wj"], o["aH"], o["aj"])
                    w, al = o["wi"], o["ai"]
                else:
                    partner = _bar(m0, o["M"], o["ri"], l0 - m0, o["vM"], o["wi"], o["aM"], o["ai"])
                    w, al = o["wj"], o["aj"]
                return drive._finish(s, g, pos, partner, w, al, order, o, tol, v_is_i)
        else:   # RRP with V as the rod (link i)
            m0, l0 = at[g.outer_i], at[g.inner]
            s0, u0 = _axis(linkage, g.outer_j)
            scale = abs(l0 - m0)
            tol = TOUCH_REL * (scale + coord)

            def run(s: dict, order: int, flip) -> K.DyadOut:
                st = drive.current
                o = rrp_var(s[ki], m0, s[kj], s0, u0, l0, st.L, st.Ld, st.Ldd, order, flip, tol)
                vL = aL = None
                if order >= 1:
                    vL = o["vM"] + (1j * o["wi"] + st.Ld / st.L) * o["ri"]
                if order >= 2:
                    aL = (o["aM"] + (1j * o["ai"] - o["wi"] * o["wi"] + st.Ldd / st.L) * o["ri"]
                          + 2.0 * (st.Ld / st.L) * o["wi"] * 1j * o["ri"])
                pos = {g.outer_i: (o["M"], o["vM"], o["aM"]), g.inner: (o["L"], vL, aL)}
                return drive._finish(s, g, pos, o["slider"], o["wi"], o["ai"], order, o, tol, True,
                                     o["slide"])
        return run, max(scale, 1e-300), coord

    def _finish(self, s: dict, g: Group, pos: dict, partner: K.LinkState, w, al, order: int, o: dict,
                tol: float, v_is_i: bool, partner_slide: K.Slide | None = None) -> K.DyadOut:
        """Barrel and rod from V's end pivots; the group's output (V's state is the barrel's)."""
        M, vM, aM = pos[self.m]
        H, vH, aH = pos[self.h]
        barrel, rod, slide, ok_c = self.geometry.states(M, H, self.current, vM, vH, w, aM, aH, al, order, tol)
        s[self.rod] = rod
        ok = o["ok"] & ok_c
        gap = np.minimum(o["gap"], self.current.L - abs(self.geometry.c))
        slides = (slide,) if partner_slide is None else (partner_slide, slide)
        si, sj = (barrel, partner) if v_is_i else (partner, barrel)
        return K.DyadOut(si, sj, ok, o["cond"], gap, o["mode"], slides)



def make_drive(linkage: Linkage) -> CrankDrive:
    """The drive of ``linkage`` (raises StructureError for a driver that cannot drive)."""
    drv = linkage.driver
    if drv.kind is DriverKind.SLIDER:
        return SliderDrive(linkage)
    if drv.kind is DriverKind.CYLINDER:
        return CylinderDrive(linkage)
    return CrankDrive(linkage)


# -- branch points of a linear input ----------------------------------------------------------
def linear_range(drive: CrankDrive) -> tuple[float, float]:
    """The inputs searched for branch points: the stroke and the drawn input, mm."""
    lo, hi = drive.stroke if getattr(drive, "stroke", None) is not None else (drive.input0, drive.input0)
    return min(lo, drive.input0), max(hi, drive.input0)


def find_linear_branch_points(plan: StepPlan, steps, known: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Add to ``known`` the inputs (mm, sorted) where the groups of ``steps`` of a plan driven by an
    actuator touch their toggle inside the searched range (:func:`linear_range`): local minima of
    the assembly margin refined by golden-section search, within rounding of zero."""
    lo, hi = linear_range(plan.drive)
    span = hi - lo
    if span <= 0.0:
        for k in steps:
            known.setdefault(plan.steps[k].group.name, np.empty(0))
        return known
    x = np.linspace(lo, hi, REF_SAMPLES)
    h = span / (REF_SAMPLES - 1)
    for k in sorted(steps):
        step = plan.steps[k]
        name = step.group.name
        if name in known:
            continue
        if step.group.kind not in MODAL_KINDS or step.group.fixed:
            known[name] = np.empty(0)
            continue
        idx = plan.closure(k)
        out = plan.run_steps(x, 0, idx, known)[name]
        ok = out.ok
        gap = np.where(ok, out.gap, -np.inf)
        inner = np.zeros(x.shape, dtype=bool)
        inner[1:-1] = ok[1:-1] & ok[:-2] & ok[2:] & (gap[1:-1] <= gap[:-2]) & (gap[1:-1] <= gap[2:])
        cand = np.flatnonzero(inner & (gap < CANDIDATE * step.scale))
        thr = TOUCH_REL * (step.scale + step.coord)

        def margin(v: float) -> float:
            o = plan.run_steps(np.array([v]), 0, idx, known)[name]
            return abs(float(o.gap[0])) if np.isfinite(o.gap[0]) else math.inf

        found: list[float] = []
        for c in cand:
            v, f = golden_min(margin, x[c] - h, x[c] + h, GOLDEN_STEPS)
            if f <= thr and abs(v - plan.drive.input0) > 1e-12 * max(span, 1.0) \
                    and all(abs(v - e) > 1e-9 * span for e in found):
                found.append(v)
        known[name] = np.array(sorted(found))
    return known


def linear_flip(offsets: np.ndarray | None, inputs: np.ndarray, input0: float) -> np.ndarray | None:
    """±1 per input: −1 where an odd number of branch points (inputs, mm) lies between the drawn
    input and it."""
    if offsets is None or offsets.size == 0:
        return None
    n = np.abs(np.searchsorted(offsets, inputs) - np.searchsorted(offsets, input0))
    return 1.0 - 2.0 * (n % 2)


__all__ = ["CrankDrive", "CylinderDrive", "SliderDrive", "find_linear_branch_points", "linear_flip",
           "linear_range", "make_drive"]
