"""Re-assemble a linkage from the shapes of its links, at its drawn input, group by group.

Each link's *shape* is where its joints sit in its own frame (origin its first revolute joint, x
axis towards its second; see :func:`shapes`), and for each prismatic joint on it the slide axis's
direction in that frame. Given shapes — the drawn ones, or ones a dimension edit changed — the
linkage is put together again in the solving order of its plan: the frame keeps its first joint
and its direction; the driver keeps its input (a crank its drawn angle, a cylinder its drawn
length, a slider its drawn place); each Assur group is closed in closed form from the links it
hangs on, in its drawn assembly mode (or the other one, for a flip):

- RRR: circle meets circle; RRP: circle meets line; RPR: both links along one axis through the
  two pins; PRP: line meets line; RPP: the pin's line meets the guide's.

Where a group cannot be closed the re-assembly raises :class:`~mechsketch.core.errors.EditError`
naming the group, its joints and by how much it misses (mm or degrees). Positions are complex
numbers (x + iy, mm); a pose (Z, r) maps a local point p to Z + r·p (|r| = 1).
"""
from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field, replace

from ..errors import EditError
from ..model.linkage import JointKind, Linkage
from .kernels import PARALLEL_COND
from .plan import Plan, compile_plan
from .structure import Group, GroupKind
from .tolerances import TOUCH_REL

Pose = tuple[complex, complex]


def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


def _cross(a: complex, b: complex) -> float:
    return (a.conjugate() * b).imag


def _dot(a: complex, b: complex) -> float:
    return (a.conjugate() * b).real


def _unit(a: complex) -> complex:
    return a / abs(a)


def axis_dir(deg: float | None) -> complex:
    a = math.radians(deg or 0.0)
    return complex(math.cos(a), math.sin(a))


@dataclass
class Shape:
    """One link in its own frame: ``pts`` joint -> local position (mm), ``axes`` P joint -> local
    unit direction of its slide axis; ``revolute`` its R joints in link order (the first is the
    origin, the second on the +x axis)."""

    link: str
    pts: dict[str, complex] = field(default_factory=dict)
    axes: dict[str, complex] = field(default_factory=dict)
    revolute: tuple[str, ...] = ()
    frame: Pose = (0j, 1 + 0j)   # the drawn pose of the frame (origin, direction)

    def copy(self) -> "Shape":
        return Shape(self.link, dict(self.pts), dict(self.axes), self.revolute, self.frame)


def frame_of(linkage: Linkage, link: str) -> Pose:
    """The drawn pose of ``link``'s frame: its first revolute joint (else its first joint) and the
    direction to its second revolute joint (else its first slide axis, else +x)."""
    lk = linkage.link(link)
    rs = [j for j in lk.joints if linkage.joint(j).kind is JointKind.R]
    ps = [j for j in lk.joints if linkage.joint(j).kind is JointKind.P]
    o = _c(linkage.joint(rs[0] if rs else lk.joints[0]).at) if lk.joints else 0j
    e = 1 + 0j
    if len(rs) >= 2 and _c(linkage.joint(rs[1]).at) != o:
        e = _unit(_c(linkage.joint(rs[1]).at) - o)
    elif ps:
        e = axis_dir(linkage.joint(ps[0]).axis_deg)
    return o, e


def shapes(linkage: Linkage) -> dict[str, Shape]:
    """The drawn shape of every link (see :class:`Shape`)."""
    out = {}
    for lk in linkage.links:
        o, e = frame_of(linkage, lk.id)
        s = Shape(lk.id, revolute=tuple(j for j in lk.joints if linkage.joint(j).kind is JointKind.R), frame=(o, e))
        for j in lk.joints:
            jt = linkage.joint(j)
            s.pts[j] = (_c(jt.at) - o) / e
            if jt.kind is JointKind.P:
                s.axes[j] = axis_dir(jt.axis_deg) / e
        out[lk.id] = s
    return out


def drawn_modes(linkage: Linkage, plan: Plan) -> dict[str, int]:
    """Each modal group's assembly mode in the drawn pose (the kernels' conventions)."""
    at = {j.id: _c(j.at) for j in linkage.joints}
    out = {}
    for g in plan.groups:
        if g.kind is GroupKind.RRR:
            v = _cross(at[g.outer_j] - at[g.outer_i], at[g.inner] - at[g.outer_i])
        elif g.kind is GroupKind.RRP:
            v = _dot(axis_dir(linkage.joint(g.outer_j).axis_deg), at[g.inner] - at[g.outer_i])
        elif g.kind is GroupKind.RPR:
            v = _dot(axis_dir(linkage.joint(g.inner).axis_deg), at[g.outer_i] - at[g.outer_j])
        else:
            continue
        out[g.name] = 1 if v >= 0.0 else -1
    return out


class _Builder:
    """The poses of the links as the groups close (see :func:`reassemble`)."""

    def __init__(self, linkage: Linkage, plan: Plan, shp: dict[str, Shape], modes: dict[str, int]) -> None:
        self.lk, self.plan, self.shp, self.modes = linkage, plan, shp, modes
        self.pose: dict[str, Pose] = {}
        self.size = max((abs(p) for s in shp.values() for p in s.pts.values()), default=1.0) + 1.0
        drive = plan.drive
        self.virtual = drive.link if drive is not None and drive.kind == "cylinder" else None

    def world(self, link: str, joint: str) -> complex:
        Z, r = self.pose[link]
        return Z + r * self.shp[link].pts[joint]

    def axis(self, link: str, joint: str) -> complex:
        return self.pose[link][1] * self.shp[link].axes[joint]

    def tol(self, scale: float) -> float:
        return TOUCH_REL * 16 * (scale + self.size)

    def place(self, link: str, a: str, pa: complex, b: str, pb: complex) -> None:
        """The pose of ``link`` putting its joints a, b at pa, pb (their distance is the shape's)."""
        la, lb = self.shp[link].pts[a], self.shp[link].pts[b]
        r = _unit(pb - pa) / _unit(lb - la) if pb != pa and lb != la else 1 + 0j
        self.pose[link] = (pa - r * la, r)

    def length(self, link: str, a: str, b: str) -> float:
        if link == self.virtual:
            return self.plan.drive.input0
        return abs(self.shp[link].pts[b] - self.shp[link].pts[a])

    def set_or_cylinder(self, link: str, a: str, pa: complex, b: str, pb: complex) -> None:
        if link == self.virtual:
            self.cylinder({a: pa, b: pb})
        else:
            self.place(link, a, pa, b, pb)

    # -- the driver ------------------------------------------------------------------------
    def drive(self) -> None:
        lk, shp = self.lk, self.shp
        g = lk.ground
        self.pose[g] = frame_of(lk, g)
        drv = lk.driver
        if drv.kind == "crank":
            pivot = self.world(g, drv.pivot)
            tip = next(j for j in lk.link(drv.link).joints if j != drv.pivot)
            d_old = _unit(_c(lk.joint(tip).at) - _c(lk.joint(drv.pivot).at))
            v = shp[drv.link].pts[tip] - shp[drv.link].pts[drv.pivot]
            r = d_old / _unit(v)
            self.pose[drv.link] = (pivot - r * shp[drv.link].pts[drv.pivot], r)
        elif drv.kind == "slider":
            u = self.axis(g, drv.pivot)
            r = u / shp[drv.link].axes[drv.pivot]
            self.pose[drv.link] = (self.world(g, drv.pivot) - r * shp[drv.link].pts[drv.pivot], r)

    def cylinder(self, ends: dict[str, complex]) -> None:
        """Barrel and rod along their common axis through the cylinder's pivots."""
        d = self.plan.drive
        M, H = ends[d.m], ends[d.h]
        mode = 1 if _dot(axis_dir(self.lk.joint(d.slide).axis_deg),
                         _c(self.lk.joint(d.m).at) - _c(self.lk.joint(d.h).at)) >= 0 else -1
        self.rpr(f"cylinder {d.link}–{d.rod}", d.link, d.m, M, d.rod, d.h, H, d.slide, mode)

    # -- the groups ------------------------------------------------------------------------
    def rpr(self, name: str, li: str, mi: str, M: complex, lj: str, hj: str, H: complex, pj: str, mode: int) -> None:
        si, sj = self.shp[li], self.shp[lj]
        wi, wj = si.axes[pj], sj.axes[pj]
        a, b = si.pts[pj] - si.pts[mi], sj.pts[pj] - sj.pts[hj]
        c = (b / wj).imag - (a / wi).imag
        d = M - H
        D = abs(d)
        if D < abs(c) - self.tol(D):
            raise EditError(f"group {name} cannot be assembled: its pins {mi} and {hj} are {D:.6g} mm apart, "
                            f"{abs(c) - D:.6g} mm less than the slide axis's offset {abs(c):.6g} mm")
        sigma = mode * math.sqrt(max(D * D - c * c, 0.0))
        if D <= self.tol(D) and abs(c) <= self.tol(D):
            raise EditError(f"group {name} cannot be assembled: its pins {mi} and {hj} coincide at the drawn "
                            f"input ({D:.3g} mm apart) on a slide axis through both, which leaves the axis "
                            f"{pj} no direction: move {mi} or {hj} so that they are apart at the drawn input")
        u = _unit(d / complex(sigma, c))
        ri, rj = u / wi, u / wj
        self.pose[li] = (M - ri * si.pts[mi], ri)
        self.pose[lj] = (H - rj * sj.pts[hj], rj)

    def group(self, g: Group) -> None:
        mode = self.modes.get(g.name, 1)
        if g.kind is GroupKind.RRR:
            M, H = self.world(g.known_i, g.outer_i), self.world(g.known_j, g.outer_j)
            li, lj = self.length(g.link_i, g.outer_i, g.inner), self.length(g.link_j, g.outer_j, g.inner)
            d = H - M
            D = abs(d)
            reach, short = li + lj - D, D - abs(li - lj)
            tol = self.tol(li + lj)
            if reach < -tol:
                raise EditError(f"group {g.name} cannot be assembled at the drawn input: its outer joints "
                                f"{g.outer_i} and {g.outer_j} are {D:.6g} mm apart, {-reach:.6g} mm more than "
                                f"its links reach ({li:.6g} + {lj:.6g} mm)")
            if short < -tol:
                raise EditError(f"group {g.name} cannot be assembled at the drawn input: its outer joints "
                                f"{g.outer_i} and {g.outer_j} are {D:.6g} mm apart, {-short:.6g} mm closer than "
                                f"its links allow (|{li:.6g} − {lj:.6g}| mm)")
            if D == 0.0:
                raise EditError(f"group {g.name}: its outer joints {g.outer_i} and {g.outer_j} coincide; "
                                "its pose is undetermined")
            x = (li * li - lj * lj + D * D) / (2 * D)
            h = mode * math.sqrt(max(li * li - x * x, 0.0))
            L = M + complex(x, h) * d / D
            self.set_or_cylinder(g.link_i, g.outer_i, M, g.inner, L)
            self.set_or_cylinder(g.link_j, g.outer_j, H, g.inner, L)
        elif g.kind is GroupKind.RRP:
            M = self.world(g.known_i, g.outer_i)
            G, u = self.world(g.known_j, g.outer_j), self.axis(g.known_j, g.outer_j)
            sj = self.shp[g.link_j]
            rj = u / sj.axes[g.outer_j]
            B = G + rj * (sj.pts[g.inner] - sj.pts[g.outer_j])
            li = self.length(g.link_i, g.outer_i, g.inner)
            dn, du = _cross(u, B - M), _dot(u, B - M)
            if li < abs(dn) - self.tol(li):
                raise EditError(f"group {g.name} cannot be assembled at the drawn input: the rod {g.outer_i}–"
                                f"{g.inner} ({li:.6g} mm) is {abs(dn) - li:.6g} mm too short to reach the line "
                                f"its pin slides on ({abs(dn):.6g} mm away)")
            s = -du + mode * math.sqrt(max(li * li - dn * dn, 0.0))
            L = B + s * u
            self.pose[g.link_j] = (L - rj * sj.pts[g.inner], rj)
            self.set_or_cylinder(g.link_i, g.outer_i, M, g.inner, L)
        elif g.kind is GroupKind.RPR:
            M, H = self.world(g.known_i, g.outer_i), self.world(g.known_j, g.outer_j)
            self.rpr(g.name, g.link_i, g.outer_i, M, g.link_j, g.outer_j, H, g.inner, mode)
        elif g.kind is GroupKind.PRP:
            Bs, us, rs = [], [], []
            for link, known, pj in ((g.link_i, g.known_i, g.outer_i), (g.link_j, g.known_j, g.outer_j)):
                s = self.shp[link]
                u = self.axis(known, pj)
                r = u / s.axes[pj]
                Bs.append(self.world(known, pj) + r * (s.pts[g.inner] - s.pts[pj]))
                us.append(u)
                rs.append(r)
            det = _cross(us[0], -us[1])
            self._parallel(g, det, g.outer_i, g.outer_j)
            p1 = _cross(Bs[1] - Bs[0], -us[1]) / det
            L = Bs[0] + p1 * us[0]
            for link, r in ((g.link_i, rs[0]), (g.link_j, rs[1])):
                self.pose[link] = (L - r * self.shp[link].pts[g.inner], r)
        else:   # RPP
            si, sj = self.shp[g.link_i], self.shp[g.link_j]
            u2, G2 = self.axis(g.known_j, g.outer_j), self.world(g.known_j, g.outer_j)
            rj = u2 / sj.axes[g.outer_j]
            ui = rj * sj.axes[g.inner]
            ri = ui / si.axes[g.inner]
            M = self.world(g.known_i, g.outer_i)
            Pi = M + ri * (si.pts[g.inner] - si.pts[g.outer_i])
            w = Pi - G2 - rj * (sj.pts[g.inner] - sj.pts[g.outer_j])
            det = _cross(u2, -ui)
            self._parallel(g, det, g.inner, g.outer_j)
            p2 = _cross(w, -ui) / det
            self.pose[g.link_i] = (M - ri * si.pts[g.outer_i], ri)
            self.pose[g.link_j] = (G2 + p2 * u2 - rj * sj.pts[g.outer_j], rj)

    @staticmethod
    def _parallel(g: Group, det: float, a: str, b: str) -> None:
        if abs(det) <= PARALLEL_COND:
            raise EditError(f"group {g.name} cannot be assembled: the slide axes of {a} and {b} are parallel "
                            f"(they meet at {math.degrees(math.asin(min(abs(det), 1.0))):.3g}°)")


def reassemble(linkage: Linkage, shp: dict[str, Shape] | None = None, flip: str | None = None,
               plan: Plan | None = None) -> Linkage:
    """``linkage`` redrawn from the link shapes ``shp`` (default: its own) at its drawn input,
    each group in its drawn assembly mode — the other one for group ``flip``. Raises
    :class:`EditError` naming the group that cannot close and by how much, StructureError when the
    linkage does not decompose."""
    plan = plan if plan is not None else compile_plan(linkage)
    shp = shapes(linkage) if shp is None else shp
    modes = drawn_modes(linkage, plan)
    if flip is not None:
        if flip not in modes:
            raise EditError(f"group {flip!r} has no assembly mode to flip")
        modes[flip] = -modes[flip]
    b = _Builder(linkage, plan, shp, modes)
    b.drive()
    for g in plan.groups:
        b.group(g)
    joints = []
    for j in linkage.joints:
        carrier = plan.reporter[j.id]
        if carrier not in b.pose:
            carrier = next(k for k in linkage.links_of(j.id) if k in b.pose)
        p = b.world(carrier, j.id)
        if not (math.isfinite(p.real) and math.isfinite(p.imag)):
            raise EditError(f"joint {j.id} gets no position; the drawing is unchanged")
        new = j.moved((p.real, p.imag))
        if j.kind is JointKind.P:
            deg = math.degrees(cmath.phase(b.axis(carrier, j.id)))
            old = j.axis_deg or 0.0
            new = replace(new, axis_deg=old + math.remainder(deg - old, 360.0))
        joints.append(new)
    return replace(linkage, joints=tuple(joints))


__all__ = ["Shape", "axis_dir", "drawn_modes", "frame_of", "reassemble", "shapes"]
