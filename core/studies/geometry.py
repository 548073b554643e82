"""The drawn geometry of D designs of one linkage: dimension edits applied to the link shapes,
then the linkage re-assembled at its drawn input, for every design at once.

This is :func:`~mechsketch.core.solver.dimensions.set_dimension` and
:func:`~mechsketch.core.solver.assembly.reassemble` over arrays (D,): each link's shape (its
joints in its own frame), the edits of :mod:`.keys` applied in the order given, then the groups
closed in their drawn assembly modes from the driver on. A design whose edit or group cannot close
is marked (``ok`` False) with the reason and by how much, never raised: a study counts and reports
them. Points are (x, y) pairs (:mod:`.vec`); the arithmetic is analytic, so a complex step in the
values gives exact derivatives of the drawn positions (:mod:`.linearised`).
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..model.limits import MAX_ANGLE_DEG, MAX_LENGTH_MM
from ..model.linkage import JointKind, Linkage
from ..solver.assembly import drawn_modes, shapes
from ..solver.kernels import PARALLEL_COND
from ..solver.plan import Plan
from ..solver.structure import GroupKind
from ..solver.tolerances import TOUCH_REL
from . import vec as V
from .keys import GEOMETRIC, check_keys


class Geometry:
    """The drawn geometry of D designs (arrays (D,)).

    ``at`` joint -> (x, y) drawn position (mm); ``axis`` prismatic joint -> (x, y) unit slide axis;
    ``ok`` (D,) bool: the design was re-assembled; for the others ``reason`` (D,) indexes
    :attr:`reasons` and ``amount`` (D,) says by how much it misses (mm or °, NaN if not a size).
    """

    def __init__(self, linkage: Linkage, n: int, at: dict, axis: dict, ok: np.ndarray, reason: np.ndarray,
                 amount: np.ndarray, reasons: list[str]) -> None:
        self.linkage, self.n, self.at, self.axis = linkage, n, at, axis
        self.ok, self.reason, self.amount, self.reasons = ok, reason, amount, reasons

    def message(self, d: int) -> str:
        """Why design ``d`` was not assembled ("" if it was)."""
        if self.ok[d]:
            return ""
        a = float(np.real(self.amount[d]))
        return self.reasons[self.reason[d]] + (f" (by {a:.6g})" if math.isfinite(a) else "")

    def failures(self) -> dict[str, int]:
        """How many designs failed for each reason (reasons without the amount)."""
        out: dict[str, int] = {}
        for code, count in zip(*np.unique(self.reason[~self.ok], return_counts=True)):
            out[self.reasons[int(code)]] = int(count)
        return out

    def point(self, joint: str, d: int) -> complex:
        x, y = self.at[joint]
        return complex(float(np.real(x[d])), float(np.real(y[d])))


class _Fails:
    """The first failure of each design: a reason (index into ``reasons``) and an amount."""

    def __init__(self, n: int) -> None:
        self.ok = np.ones(n, dtype=bool)
        self.reason = np.zeros(n, dtype=np.int32)
        self.amount = np.full(n, np.nan)
        self.reasons: list[str] = ["assembled"]

    def __call__(self, mask, text: str, amount=np.nan) -> None:
        mask = np.broadcast_to(np.asarray(mask, dtype=bool), self.ok.shape)
        new = mask & self.ok
        if not new.any():
            return
        if text not in self.reasons:
            self.reasons.append(text)
        self.reason[new] = self.reasons.index(text)
        self.amount[new] = np.broadcast_to(np.real(amount), self.ok.shape)[new]
        self.ok &= ~mask


def _pair(z: complex, n: int, dtype) -> V.Pair:
    return np.full(n, z.real, dtype=dtype), np.full(n, z.imag, dtype=dtype)


class _Shapes:
    """Link shapes of D designs: per link its points and slide axes in its own frame; the frame
    (ground) kept in world coordinates (``world``, ``waxes``)."""

    def __init__(self, linkage: Linkage, n: int, dtype) -> None:
        self.lk, self.n, self.dtype = linkage, n, dtype
        self.pts: dict[str, dict[str, V.Pair]] = {}
        self.axes: dict[str, dict[str, V.Pair]] = {}
        self.rs: dict[str, tuple[str, ...]] = {}
        for k, s in shapes(linkage).items():
            self.pts[k] = {j: _pair(p, n, dtype) for j, p in s.pts.items()}
            self.axes[k] = {j: _pair(a, n, dtype) for j, a in s.axes.items()}
            self.rs[k] = s.revolute
        g = linkage.ground
        self.world = {j.id: _pair(complex(*j.at), n, dtype) for j in linkage.joints if j.id in linkage.link(g).joints}
        self.waxes = {j: V.polar(1.0, np.full(n, linkage.joint(j).axis_deg or 0.0, dtype=dtype))
                      for j in self.axes[g]}

    def frame(self) -> tuple[V.Pair, V.Pair]:
        """The frame's pose (origin, unit direction) from its world joints (as ``frame_of``)."""
        g = self.lk.ground
        rs = self.rs[g]
        joints = self.lk.link(g).joints
        o = self.world[rs[0] if rs else joints[0]] if joints else _pair(0j, self.n, self.dtype)
        one = _pair(1 + 0j, self.n, self.dtype)
        if len(rs) >= 2:
            d = V.sub(self.world[rs[1]], o)
            same = (V.re(d[0]) == 0) & (V.re(d[1]) == 0)
            with np.errstate(invalid="ignore", divide="ignore"):
                e = V.unit(d)
            alt = self.waxes[next(iter(self.waxes))] if self.waxes else one
            return o, V.where(same, alt, e)
        if self.waxes:
            return o, self.waxes[next(j for j in joints if j in self.waxes)]
        return o, one

    def ground_to_shape(self) -> None:
        o, e = self.frame()
        g = self.lk.ground
        self.pts[g] = {j: V.cmul(e, V.sub(w, o)) for j, w in self.world.items()}
        self.axes[g] = {j: V.cmul(e, a) for j, a in self.waxes.items()}

    def shape_to_ground(self, o: V.Pair, e: V.Pair) -> None:
        g = self.lk.ground
        self.world = {j: V.add(o, V.mul(e, p)) for j, p in self.pts[g].items()}
        self.waxes = {j: V.mul(e, a) for j, a in self.axes[g].items()}


def _triangle(fail: _Fails, link: str, base, a, b, y_old, names: str) -> V.Pair:
    x = (a * a - b * b + base * base) / (2.0 * base)
    h2 = a * a - x * x
    big = np.maximum(np.maximum(V.re(a), V.re(b)), V.re(base))
    bad = V.re(h2) < -1e-9 * big * big
    fail(bad, f"link {link}: the sides {names} do not close a triangle (the longest exceeds the sum of the others)",
         2 * big - (V.re(a) + V.re(b) + V.re(base)))
    h = np.sqrt(np.where(V.re(h2) > 0, h2, 0.0))
    return x, np.where(V.re(y_old) < 0, -h, h)


def _dimension(sh: _Shapes, fail: _Fails, key: str, value) -> None:
    """One dimension edit on the shapes (as :func:`~mechsketch.core.solver.dimensions.reshaped`)."""
    parts = key.split(":")
    kind, link = parts[0], parts[1]
    p, rs = sh.pts[link], sh.rs[link]
    if kind == "length":
        fail(V.re(value) <= 0.0, f"dimension {key}: a length must be positive", value)
        a, b = parts[2], parts[3]
        base = V.norm(p[rs[1]])
        if (a, b) == (rs[0], rs[1]):
            for rm in rs[2:]:
                p[rm] = _triangle(fail, link, value, V.norm(p[rm]), V.norm(V.sub(p[rm], p[rs[1]])), p[rm][1],
                                  f"{rs[0]}–{rs[1]}, {rs[0]}–{rm}, {rs[1]}–{rm}")
            p[rs[1]] = (value, np.zeros_like(value))
        elif a == rs[0]:
            p[b] = _triangle(fail, link, base, value, V.norm(V.sub(p[b], p[rs[1]])), p[b][1],
                             f"{rs[0]}–{rs[1]}, {a}–{b}, {rs[1]}–{b}")
        else:
            p[b] = _triangle(fail, link, base, V.norm(p[b]), value, p[b][1], f"{rs[0]}–{rs[1]}, {rs[0]}–{b}, {a}–{b}")
    elif kind == "angle":
        rm = parts[4]
        p[rm] = V.polar(V.norm(p[rm]), value)
    elif kind == "offset":
        pj = parts[2]
        w = sh.axes[link][pj]
        old = V.cross(w, V.sub(p[rs[0]], p[pj]))
        p[pj] = V.sub(p[pj], V.scale(value - old, V.perp(w)))
    else:   # axis: turned about the foot of the perpendicular from r0, keeping the offset
        pj = parts[2]
        w = sh.axes[link][pj]
        new = V.polar(1.0, value)
        if len(rs) < 2 and link == sh.lk.ground:
            new = V.cmul(sh.frame()[1], new)
        if rs:
            origin = p[rs[0]]
            offset = V.cross(w, V.sub(origin, p[pj]))
            along = V.dot(w, V.sub(p[pj], origin))
            p[pj] = V.add(V.sub(origin, V.scale(offset, V.perp(new))), V.scale(along, new))
        sh.axes[link][pj] = new


def _apply(sh: _Shapes, fail: _Fails, key: str, value) -> None:
    parts = key.split(":")
    kind = parts[0]
    limit = MAX_ANGLE_DEG if kind in ("angle", "axis") else MAX_LENGTH_MM
    fail(np.abs(V.re(value)) > limit, f"dimension {key}: beyond ±{limit:g} {'°' if limit == MAX_ANGLE_DEG else 'mm'}",
         value)
    g = sh.lk.ground
    if kind in ("x", "y"):
        j = parts[1]
        w = sh.world[j]
        sh.world[j] = (value, w[1]) if kind == "x" else (w[0], value)
    elif kind == "point":
        link, j, comp = parts[1], parts[2], parts[3]
        q = sh.pts[link][j]
        sh.pts[link][j] = (value, q[1]) if comp == "x" else (q[0], value)
    elif parts[1] == g:   # a dimension of the frame: in its frame at its current pose
        o, e = sh.frame()
        sh.ground_to_shape()
        _dimension(sh, fail, key, value)
        sh.shape_to_ground(o, e)
    else:
        _dimension(sh, fail, key, value)


class _Builder:
    """Poses (origin Z, rotation r) of the links as the groups close (``reassemble`` over D)."""

    def __init__(self, sh: _Shapes, plan: Plan, fail: _Fails) -> None:
        self.sh, self.plan, self.fail = sh, plan, fail
        self.lk = sh.lk
        self.modes = drawn_modes(self.lk, plan)
        self.pose: dict[str, tuple[V.Pair, V.Pair]] = {}
        size = np.zeros(sh.n)
        for k, pts in sh.pts.items():
            for q in pts.values():
                size = np.maximum(size, V.re(V.norm(q)))
        self.size = size + 1.0
        d = plan.drive
        self.virtual = d.link if d is not None and d.kind == "cylinder" else None

    def world(self, link: str, joint: str) -> V.Pair:
        Z, r = self.pose[link]
        return V.add(Z, V.mul(r, self.sh.pts[link][joint]))

    def axis(self, link: str, joint: str) -> V.Pair:
        return V.mul(self.pose[link][1], self.sh.axes[link][joint])

    def tol(self, scale):
        return TOUCH_REL * 16 * (V.re(scale) + self.size)

    def place(self, link: str, a: str, pa: V.Pair, b: str, pb: V.Pair) -> None:
        la, lb = self.sh.pts[link][a], self.sh.pts[link][b]
        d, dl = V.sub(pb, pa), V.sub(lb, la)
        degenerate = ((V.re(d[0]) == 0) & (V.re(d[1]) == 0)) | ((V.re(dl[0]) == 0) & (V.re(dl[1]) == 0))
        r = V.cmul(V.unit(dl), V.unit(d))
        one = (np.ones_like(r[0]), np.zeros_like(r[0]))
        r = V.where(degenerate, one, r)
        self.pose[link] = (V.sub(pa, V.mul(r, la)), r)

    def length(self, link: str, a: str, b: str):
        if link == self.virtual:
            return np.full(self.sh.n, self.plan.drive.input0)
        return V.norm(V.sub(self.sh.pts[link][b], self.sh.pts[link][a]))

    def set_or_cylinder(self, link: str, a: str, pa: V.Pair, b: str, pb: V.Pair) -> None:
        if link == self.virtual:
            self.cylinder({a: pa, b: pb})
        else:
            self.place(link, a, pa, b, pb)

    def drive(self) -> None:
        lk, sh = self.lk, self.sh
        g = lk.ground
        sh.ground_to_shape()
        self.pose[g] = sh.frame()
        drv = lk.driver
        if drv.kind == "crank":
            pivot = self.world(g, drv.pivot)
            tip = next(j for j in lk.link(drv.link).joints if j != drv.pivot)
            d_old = complex(*lk.joint(tip).at) - complex(*lk.joint(drv.pivot).at)
            d_old = V.of(d_old / abs(d_old))
            v = V.sub(sh.pts[drv.link][tip], sh.pts[drv.link][drv.pivot])
            r = V.cmul(V.unit(v), d_old)
            self.pose[drv.link] = (V.sub(pivot, V.mul(r, sh.pts[drv.link][drv.pivot])), r)
        elif drv.kind == "slider":
            u = self.axis(g, drv.pivot)
            r = V.cmul(sh.axes[drv.link][drv.pivot], u)
            self.pose[drv.link] = (V.sub(self.world(g, drv.pivot), V.mul(r, sh.pts[drv.link][drv.pivot])), r)

    def cylinder(self, ends: dict) -> None:
        d = self.plan.drive
        u0 = complex(math.cos(math.radians(self.lk.joint(d.slide).axis_deg or 0.0)),
                     math.sin(math.radians(self.lk.joint(d.slide).axis_deg or 0.0)))
        m0, h0 = complex(*self.lk.joint(d.m).at), complex(*self.lk.joint(d.h).at)
        mode = 1 if (u0.conjugate() * (m0 - h0)).real >= 0 else -1
        self.rpr(f"cylinder {d.link}–{d.rod}", d.link, d.m, ends[d.m], d.rod, d.h, ends[d.h], d.slide, mode)

    def rpr(self, name: str, li: str, mi: str, M: V.Pair, lj: str, hj: str, H: V.Pair, pj: str, mode: int) -> None:
        sh = self.sh
        wi, wj = sh.axes[li][pj], sh.axes[lj][pj]
        a, b = V.sub(sh.pts[li][pj], sh.pts[li][mi]), V.sub(sh.pts[lj][pj], sh.pts[lj][hj])
        c = V.cmul(wj, b)[1] - V.cmul(wi, a)[1]
        d = V.sub(M, H)
        D = V.norm(d)
        short = np.abs(V.re(c)) - V.re(D)
        self.fail(short > self.tol(D), f"group {name} cannot be assembled: its pins {mi} and {hj} are closer "
                  "than the slide axis's offset", short)
        tol = self.tol(D)
        self.fail((V.re(D) <= tol) & (np.abs(V.re(c)) <= tol), f"group {name} cannot be assembled: its pins {mi} "
                  f"and {hj} coincide at the drawn input on a slide axis through both")
        s2 = D * D - c * c
        sigma = mode * np.sqrt(np.where(V.re(s2) > 0, s2, 0.0))
        u = V.unit(V.div(d, (sigma, c)))
        ri, rj = V.cmul(wi, u), V.cmul(wj, u)
        self.pose[li] = (V.sub(M, V.mul(ri, sh.pts[li][mi])), ri)
        self.pose[lj] = (V.sub(H, V.mul(rj, sh.pts[lj][hj])), rj)

    def group(self, g) -> None:
        mode = self.modes.get(g.name, 1)
        sh = self.sh
        if g.kind is GroupKind.RRR:
            M, H = self.world(g.known_i, g.outer_i), self.world(g.known_j, g.outer_j)
            li, lj = self.length(g.link_i, g.outer_i, g.inner), self.length(g.link_j, g.outer_j, g.inner)
            d = V.sub(H, M)
            D = V.norm(d)
            reach, short = li + lj - D, D - np.abs(li - lj)
            tol = self.tol(li + lj)
            self.fail(V.re(reach) < -tol, f"group {g.name} cannot be assembled at the drawn input: its outer joints "
                      f"{g.outer_i} and {g.outer_j} are farther apart than its links reach", -V.re(reach))
            self.fail(V.re(short) < -tol, f"group {g.name} cannot be assembled at the drawn input: its outer joints "
                      f"{g.outer_i} and {g.outer_j} are closer than its links allow", -V.re(short))
            self.fail(V.re(D) == 0, f"group {g.name}: its outer joints {g.outer_i} and {g.outer_j} coincide")
            x = (li * li - lj * lj + D * D) / (2 * D)
            h2 = li * li - x * x
            h = mode * np.sqrt(np.where(V.re(h2) > 0, h2, 0.0))
            L = V.add(M, V.mul((x, h), V.scale(1.0 / D, d)))
            self.set_or_cylinder(g.link_i, g.outer_i, M, g.inner, L)
            self.set_or_cylinder(g.link_j, g.outer_j, H, g.inner, L)
        elif g.kind is GroupKind.RRP:
            M = self.world(g.known_i, g.outer_i)
            G, u = self.world(g.known_j, g.outer_j), self.axis(g.known_j, g.outer_j)
            pts, axes = sh.pts[g.link_j], sh.axes[g.link_j]
            rj = V.cmul(axes[g.outer_j], u)
            B = V.add(G, V.mul(rj, V.sub(pts[g.inner], pts[g.outer_j])))
            li = self.length(g.link_i, g.outer_i, g.inner)
            dn, du = V.cross(u, V.sub(B, M)), V.dot(u, V.sub(B, M))
            short = np.abs(V.re(dn)) - V.re(li)
            self.fail(short > self.tol(li), f"group {g.name} cannot be assembled at the drawn input: the rod "
                      f"{g.outer_i}–{g.inner} is too short to reach the line its pin slides on", short)
            r2 = li * li - dn * dn
            s = -du + mode * np.sqrt(np.where(V.re(r2) > 0, r2, 0.0))
            L = V.add(B, V.scale(s, u))
            self.pose[g.link_j] = (V.sub(L, V.mul(rj, pts[g.inner])), rj)
            self.set_or_cylinder(g.link_i, g.outer_i, M, g.inner, L)
        elif g.kind is GroupKind.RPR:
            M, H = self.world(g.known_i, g.outer_i), self.world(g.known_j, g.outer_j)
            self.rpr(g.name, g.link_i, g.outer_i, M, g.link_j, g.outer_j, H, g.inner, mode)
        elif g.kind is GroupKind.PRP:
            self._prp(g)
        else:   # RPP
            self._rpp(g)

    def _prp(self, g) -> None:
        sh = self.sh
        Bs, us, rs = [], [], []
        for link, known, pj in ((g.link_i, g.known_i, g.outer_i), (g.link_j, g.known_j, g.outer_j)):
            u = self.axis(known, pj)
            r = V.cmul(sh.axes[link][pj], u)
            Bs.append(V.add(self.world(known, pj), V.mul(r, V.sub(sh.pts[link][g.inner], sh.pts[link][pj]))))
            us.append(u)
            rs.append(r)
        det = V.cross(us[0], V.scale(-1.0, us[1]))
        self._parallel(g, det)
        p1 = V.cross(V.sub(Bs[1], Bs[0]), V.scale(-1.0, us[1])) / det
        L = V.add(Bs[0], V.scale(p1, us[0]))
        for link, r in ((g.link_i, rs[0]), (g.link_j, rs[1])):
            self.pose[link] = (V.sub(L, V.mul(r, sh.pts[link][g.inner])), r)

    def _rpp(self, g) -> None:
        sh = self.sh
        pi_, pj_ = sh.pts[g.link_i], sh.pts[g.link_j]
        u2, G2 = self.axis(g.known_j, g.outer_j), self.world(g.known_j, g.outer_j)
        rj = V.cmul(sh.axes[g.link_j][g.outer_j], u2)
        ui = V.mul(rj, sh.axes[g.link_j][g.inner])
        ri = V.cmul(sh.axes[g.link_i][g.inner], ui)
        M = self.world(g.known_i, g.outer_i)
        Pi = V.add(M, V.mul(ri, V.sub(pi_[g.inner], pi_[g.outer_i])))
        w = V.sub(V.sub(Pi, G2), V.mul(rj, V.sub(pj_[g.inner], pj_[g.outer_j])))
        det = V.cross(u2, V.scale(-1.0, ui))
        self._parallel(g, det)
        p2 = V.cross(w, V.scale(-1.0, ui)) / det
        self.pose[g.link_i] = (V.sub(M, V.mul(ri, pi_[g.outer_i])), ri)
        self.pose[g.link_j] = (V.sub(V.add(G2, V.scale(p2, u2)), V.mul(rj, pj_[g.outer_j])), rj)

    def _parallel(self, g, det) -> None:
        self.fail(np.abs(V.re(det)) <= PARALLEL_COND, f"group {g.name} cannot be assembled: its slide axes are parallel")


def _check_lengths(lk: Linkage, at: dict, fail: _Fails) -> None:
    """Two revolute joints of one link at one point (as ``compile_plan`` refuses)."""
    for link in lk.links:
        rs = [j for j in link.joints if lk.joint(j).kind is JointKind.R]
        if len(rs) < 2:
            continue
        span = np.zeros(fail.ok.shape)
        for a in rs:
            for b in rs:
                span = np.maximum(span, V.re(V.norm(V.sub(at[a], at[b]))))
        for ia in range(len(rs)):
            for ib in range(ia + 1, len(rs)):
                dist = V.re(V.norm(V.sub(at[rs[ia]], at[rs[ib]])))
                fail(dist <= 1e-9 * np.maximum(span, 1.0), f"link {link.id}: joints {rs[ia]} and {rs[ib]} are at the "
                     "same point")


def build_geometry(linkage: Linkage, plan: Plan, values: dict, n: int, dtype=float) -> Geometry:
    """The re-assembled drawn geometry of ``n`` designs: ``values`` key -> array (n,) (geometric
    keys of :mod:`.keys`, applied in order; other keys are ignored here). ``dtype`` complex for a
    complex-step derivative. Designs that do not close are marked in the result, not raised."""
    check_keys(linkage, list(values))
    sh = _Shapes(linkage, n, dtype)
    fail = _Fails(n)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for key, value in values.items():
            if key.split(":", 1)[0] in ("length", "angle", "offset", "axis", "x", "y", "point"):
                _apply(sh, fail, key, np.asarray(value, dtype=dtype))
        b = _Builder(sh, plan, fail)
        b.drive()
        for g in plan.groups:
            b.group(g)
        at, axis = {}, {}
        for j in linkage.joints:
            carrier = plan.reporter[j.id]
            if carrier not in b.pose:
                carrier = next(k for k in linkage.links_of(j.id) if k in b.pose)
            p = b.world(carrier, j.id)
            fail(~(np.isfinite(p[0]) & np.isfinite(p[1])), f"joint {j.id} gets no position")
            at[j.id] = p
            if j.kind is JointKind.P:
                axis[j.id] = b.axis(carrier, j.id)
        _check_lengths(linkage, at, fail)
    return Geometry(linkage, n, at, axis, fail.ok, fail.reason, fail.amount, fail.reasons)


def design_linkage(geo: Geometry, d: int) -> Linkage:
    """Design ``d`` of ``geo`` as a linkage record (drawn positions and slide axes of the design;
    every other field of the base). Raises nothing: check ``geo.ok[d]`` first."""
    lk = geo.linkage
    joints = []
    for j in lk.joints:
        x, y = geo.at[j.id]
        new = j.moved((float(np.real(x[d])), float(np.real(y[d]))))
        if j.kind is JointKind.P:
            ux, uy = geo.axis[j.id]
            deg = math.degrees(math.atan2(float(np.real(uy[d])), float(np.real(ux[d]))))
            old = j.axis_deg or 0.0
            new = replace(new, axis_deg=old + math.remainder(deg - old, 360.0))
        joints.append(new)
    return replace(lk, joints=tuple(joints))


__all__ = ["GEOMETRIC", "Geometry", "build_geometry", "design_linkage"]
