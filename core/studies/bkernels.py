"""The solver's kernels over D designs × N samples: the numpy reference of the batch engine.

Each function is the closed form of :mod:`mechsketch.core.solver.kernels` (and of the cylinder's
:mod:`~mechsketch.core.solver.stroke_kernels`) with the drawn constants of a group — positions,
lengths, assembly modes, tolerances — given per design as arrays (D, 1) instead of Python scalars,
so that they broadcast against the samples (1, N) or (D, N). Points are (x, y) pairs
(:mod:`.vec`); a link's motion is a :class:`BState`: its anchor (drawn at ``a0``) at ``A``, its
rotation (cos ρ, sin ρ) from the drawn pose, and their rates (mm/s, mm/s², rad/s, rad/s²). Any
point drawn at p0 on the link is A + rot·(p0 − a0). Infeasible samples are NaN with ``ok`` False,
never exceptions.

The arithmetic is analytic (+, −, ×, ÷, √; masks read real parts), so the same code differentiates
by complex step (:mod:`.linearised`). Why not the solver's kernels themselves: they take the drawn
constants as Python complex scalars, which they also use as cache keys (a link's points, the
groups' constants) and in scalar fast paths; arrays of them are neither hashable nor scalars.
"""
from __future__ import annotations

import numpy as np

from ..solver.kernels import PARALLEL_COND
from . import vec as V

Pair = V.Pair
ZERO: Pair = (0.0, 0.0)


class BState:
    """The motion of one link for D designs × N samples (arrays broadcastable to (D, N)).

    ``a0`` drawn anchor (mm, (D, 1)); ``A`` anchor (mm); ``cs`` rotation (cos ρ, sin ρ) from the
    drawn pose; ``v``, ``acc`` anchor velocity (mm/s) and acceleration (mm/s²); ``w`` ω (rad/s),
    ``al`` α (rad/s²); scalars where they do not vary (the frame). ``pts`` caches per joint its
    [arm, position, velocity, acceleration].
    """

    __slots__ = ("a0", "A", "cs", "v", "w", "acc", "al", "pts")

    def __init__(self, a0: Pair, A: Pair, cs: Pair, v: Pair = ZERO, w=0.0, acc: Pair = ZERO, al=0.0) -> None:
        self.a0, self.A, self.cs, self.v, self.w, self.acc, self.al = a0, A, cs, v, w, acc, al
        self.pts: dict[str, list] = {}

    def _entry(self, joint: str, p0: Pair) -> list:
        e = self.pts.get(joint)
        if e is None:
            dx, dy = p0[0] - self.a0[0], p0[1] - self.a0[1]
            c, s = self.cs
            e = self.pts[joint] = [(c * dx - s * dy, s * dx + c * dy), None, None, None]
        return e

    def arm(self, joint: str, p0: Pair) -> Pair:
        """rot·(p0 − a0): the point ``joint`` drawn at ``p0`` from the anchor, mm."""
        return self._entry(joint, p0)[0]

    def point(self, joint: str, p0: Pair) -> Pair:
        e = self._entry(joint, p0)
        if e[1] is None:
            e[1] = V.add(self.A, e[0])
        return e[1]

    def vel(self, joint: str, p0: Pair) -> Pair:
        e = self._entry(joint, p0)
        if e[2] is None:
            ax, ay = e[0]
            e[2] = (self.v[0] - self.w * ay, self.v[1] + self.w * ax)
        return e[2]

    def accel(self, joint: str, p0: Pair) -> Pair:
        e = self._entry(joint, p0)
        if e[3] is None:
            ax, ay = e[0]
            w2 = self.w * self.w
            e[3] = (self.acc[0] - w2 * ax - self.al * ay, self.acc[1] - w2 * ay + self.al * ax)
        return e[3]

    def set_point(self, joint: str, arm: Pair, at: Pair) -> None:
        self.pts[joint] = [arm, at, None, None]


def ground() -> BState:
    """The frame: identity motion (scalars)."""
    return BState(ZERO, ZERO, (1.0, 0.0))


class BOut:
    """What a group kernel returns: both link states, ``ok`` (D, N) bool, ``gap`` the signed
    assembly margin, ``cond`` the velocity system's conditioning in [0, 1], ``singular`` (or
    None), ``slides`` per prismatic joint (s, ṡ, s̈) as in :class:`~mechsketch.core.solver.kernels.Slide`."""

    __slots__ = ("si", "sj", "ok", "gap", "cond", "singular", "slides")

    def __init__(self, si: BState, sj: BState, ok, gap, cond, singular=None, slides=()) -> None:
        self.si, self.sj, self.ok, self.gap, self.cond, self.singular, self.slides = si, sj, ok, gap, cond, singular, slides


def crank(pivot: Pair, theta0: float, inputs, omega, alpha, order: int) -> BState:
    """The driver crank: rotation about ``pivot`` (D, 1) by inputs − θ0 (inputs (1, N) rad, or
    (D, 1) for one input per design)."""
    th = inputs - theta0
    st = BState(pivot, pivot, (np.cos(th), np.sin(th)))
    if order >= 1:
        st.w = omega
    if order >= 2:
        st.al = alpha
    return st


def slider(g: BState, s0: Pair, u0: Pair, joint: str, s, sd, sdd, order: int) -> BState:
    """A link translating along the guide of ``g`` through its point ``joint`` drawn at ``s0``,
    direction ``u0`` (drawn, unit), displaced by ``s`` (mm) with rates ``sd``, ``sdd``."""
    arm = g.arm(joint, s0)
    z = g.point(joint, s0)
    u = V.mul(g.cs, u0)
    st = BState(s0, (z[0] + u[0] * s, z[1] + u[1] * s), g.cs)
    if order >= 1:
        vz = (g.v[0] - g.w * arm[1], g.v[1] + g.w * arm[0])
        ws = g.w * s
        st.v = (vz[0] + u[0] * sd - u[1] * ws, vz[1] + u[1] * sd + u[0] * ws)
        st.w = g.w
    if order >= 2:
        w2 = g.w * g.w
        az = (g.acc[0] - w2 * arm[0] - g.al * arm[1], g.acc[1] - w2 * arm[1] + g.al * arm[0])
        p = sdd - w2 * s
        q = 2.0 * g.w * sd + g.al * s
        st.acc = (az[0] + u[0] * p - u[1] * q, az[1] + u[1] * p + u[0] * q)
        st.al = g.al
    return st


def _turned(a0: Pair, A: Pair, r: Pair, r0: Pair) -> tuple:
    """Rotation (cos, sin) from the drawn vector ``r0`` (D, 1) to the current ``r``: r / r0."""
    return V.div(r, r0)


def _root(x, gap, tol):
    """√x where the margin ``gap`` ≥ −tol (x clamped at 0), NaN elsewhere; and the mask."""
    ok = V.re(gap) >= -tol
    root = np.sqrt(np.where(ok & (V.re(x) > 0), x, 0.0))
    return np.where(ok, root, np.nan), ok


def _solve2(c1: Pair, c2: Pair, w: Pair):
    """x1·c1 + x2·c2 = w for real x1, x2: (x1, x2, det)."""
    det = V.cross(c1, c2)
    return V.cross(w, c2) / det, V.cross(c1, w) / det, det


def _moved(p: Pair, e) -> Pair:
    """``p`` displaced by a pin's play ``e`` (None: not displaced)."""
    return p if e is None else (p[0] + e[0], p[1] + e[1])


def rrr(mi: BState, m: str, m0: Pair, hj: BState, h: str, h0: Pair, l: str, l0: Pair, k: dict, order: int,
        flip=None, play: tuple = (None, None, None)) -> BOut:
    """RRR dyad: link i = M–L, link j = H–L (see :func:`mechsketch.core.solver.kernels.rrr`).
    ``k``: the group's constants per design (D, 1): ``li``, ``lj``, ``mode``, ``tol``, ``near``.
    ``play``: the displacements (pairs, or None) of link i's M from its known link's, of link j's
    H, and of link j's L from link i's (pin clearances; positions only)."""
    li, lj = k["li"], k["lj"]
    mode = k["mode"] if flip is None else k["mode"] * flip
    mx, my = _moved(mi.point(m, m0), play[0])
    hx, hy = _moved(hj.point(h, h0), play[1])
    sx, sy = _moved((mx, my), play[2])       # link j's L is link i's L + its play
    dx, dy = hx - sx, hy - sy
    D2 = dx * dx + dy * dy
    D = np.sqrt(D2)
    dl, sl = li - lj, li + lj
    f1, f2, f3 = sl - D, D - dl, D + dl
    prod = (D + sl) * f1 * f2 * f3
    gap = np.minimum(V.re(f1), np.where(V.re(dl) >= 0.0, V.re(f2), V.re(f3)))
    root, ok = _root(prod, gap, k["tol"])
    meet = V.re(D) <= k["near"]
    singular = ok & meet
    ok = ok & ~meet
    x = dl * sl + D2
    h_ = mode * root
    t = li / (np.sqrt(x * x + h_ * h_) * D)
    x = x * t
    h_ = h_ * t
    rix, riy = x * dx - h_ * dy, x * dy + h_ * dx
    lx, ly = sx + rix, sy + riy
    rjx, rjy = lx - hx, ly - hy
    si = BState(m0, (mx, my), _turned(m0, (mx, my), (rix, riy), V.sub(l0, m0)))
    sj = BState(h0, (hx, hy), _turned(h0, (hx, hy), (rjx, rjy), V.sub(l0, h0)))
    si.set_point(l, (rix, riy), (lx, ly) if play[2] is None else (mx + rix, my + riy))
    det = riy * rjx - rix * rjy
    cond = np.abs(V.re(det)) / V.re(li * lj)
    if order >= 1:
        inv = 1.0 / det
        vM, vH = mi.vel(m, m0), hj.vel(h, h0)
        wx, wy = vM[0] - vH[0], vM[1] - vH[1]
        wi = (wx * rjx + wy * rjy) * inv
        wj = (rix * wx + riy * wy) * inv
        si.v, si.w, sj.v, sj.w = vM, wi, vH, wj
    if order >= 2:
        aM, aH = mi.accel(m, m0), hj.accel(h, h0)
        wi2, wj2 = wi * wi, wj * wj
        qx = aM[0] - aH[0] - wi2 * rix + wj2 * rjx
        qy = aM[1] - aH[1] - wi2 * riy + wj2 * rjy
        si.acc, si.al = aM, (qx * rjx + qy * rjy) * inv
        sj.acc, sj.al = aH, (rix * qx + riy * qy) * inv
    ok = ok & np.isfinite(V.re(lx + ly + hx + hy))
    return BOut(si, sj, ok, gap, cond, singular)


def rrp(mi: BState, m: str, m0: Pair, g: BState, sjoint: str, s0: Pair, u0: Pair, l: str, l0: Pair, k: dict,
        order: int, flip=None, play: tuple = (None, None)) -> BOut:
    """RRP dyad: rod i = M–L, slider j carrying L on the guide of ``g`` through ``sjoint`` drawn at
    ``s0``, direction ``u0`` (see :func:`mechsketch.core.solver.kernels.rrp`). ``play``: the
    displacements of the rod's M and of the slider's L from the rod's (positions only)."""
    li = k["li"]
    mode = k["mode"] if flip is None else k["mode"] * flip
    ax_, ay_ = _moved(mi.point(m, m0), play[0])
    mx, my = _moved((ax_, ay_), play[1])
    zx, zy = g.point(sjoint, s0)
    ux, uy = V.mul(g.cs, u0)
    bx, by = V.mul(g.cs, V.sub(l0, s0))
    dx, dy = (zx + bx) - mx, (zy + by) - my
    du = ux * dx + uy * dy
    dn = ux * dy - uy * dx
    gap = V.re(li) - np.abs(V.re(dn))
    root, ok = _root((li - dn) * (li + dn), gap, k["tol"])
    s = mode * root - du
    rix, riy = dx + ux * s, dy + uy * s
    lx, ly = mx + rix, my + riy
    si = BState(m0, (ax_, ay_), _turned(m0, (ax_, ay_), (rix, riy), V.sub(l0, m0)))
    si.set_point(l, (rix, riy), (lx, ly) if play[1] is None else (ax_ + rix, ay_ + riy))
    udr = ux * rix + uy * riy
    cond = np.abs(V.re(udr)) / V.re(li)
    sd = sdd = None
    if order >= 1:
        inv = 1.0 / udr
        vM = mi.vel(m, m0)
        vLx, vLy = g.v[0] - g.w * (ly - g.A[1]), g.v[1] + g.w * (lx - g.A[0])   # the guide's point under L
        wx, wy = vM[0] - vLx, vM[1] - vLy
        sd = (wx * rix + wy * riy) * inv
        wi = (uy * wx - ux * wy) * inv
        si.v, si.w = vM, wi
    if order >= 2:
        aM = mi.accel(m, m0)
        wi2 = wi * wi
        armx, army = lx - g.A[0], ly - g.A[1]
        gw2 = g.w * g.w
        aLx = g.acc[0] - gw2 * armx - g.al * army
        aLy = g.acc[1] - gw2 * army + g.al * armx
        cor = 2.0 * g.w * sd
        qx = aM[0] - wi2 * rix - aLx + uy * cor
        qy = aM[1] - wi2 * riy - aLy - ux * cor
        sdd = (qx * rix + qy * riy) * inv
        si.acc, si.al = aM, (uy * qx - ux * qy) * inv
    sj = slider(g, s0, u0, sjoint, s, sd, sdd, order)
    ok = ok & np.isfinite(V.re(lx + ly + sj.A[0] + sj.A[1]))
    return BOut(si, sj, ok, gap, cond, None, ((s, sd, sdd),))


def rpr(mi: BState, m: str, m0: Pair, hj: BState, h: str, h0: Pair, u0: Pair, k: dict, order: int,
        flip=None, play: tuple = (None, None)) -> BOut:
    """RPR dyad: link i (pin M) slides on link j (pin H) along an axis of drawn direction ``u0``
    (see :func:`mechsketch.core.solver.kernels.rpr`)."""
    c, a_d = V.cross(u0, V.sub(m0, h0)), V.dot(u0, V.sub(m0, h0))
    mode = k["mode"] if flip is None else k["mode"] * flip
    M, H = _moved(mi.point(m, m0), play[0]), _moved(hj.point(h, h0), play[1])
    d = V.sub(M, H)
    D = V.norm(d)
    gap = V.re(D) - np.abs(V.re(c))
    root, ok = _root((D - c) * (D + c), gap, k["tol"])
    meet = V.re(D) <= k["near"]
    singular = ok & meet
    ok = ok & ~meet
    sigma = mode * root
    u = V.div(d, (sigma, c + 0.0 * sigma))
    rot = V.cmul(u0, u)
    s = sigma - a_d
    si, sj = BState(m0, M, rot), BState(h0, H, rot)
    cond = np.minimum(np.abs(V.re(sigma)) / np.maximum(V.re(V.norm(V.sub(m0, h0))), np.abs(V.re(c))), 1.0)
    c1, c2 = u, V.perp(d)
    sd = sdd = None
    if order >= 1:
        vM, vH = mi.vel(m, m0), hj.vel(h, h0)
        sd, w, _ = _solve2(c1, c2, V.sub(vM, vH))
        si.v, sj.v, si.w, sj.w = vM, vH, w, w
    if order >= 2:
        aM, aH = mi.accel(m, m0), hj.accel(h, h0)
        rhs = V.add(V.sub(V.sub(aM, aH), V.scale(2.0 * w * sd, V.perp(u))), V.scale(w * w, d))
        sdd, al, _ = _solve2(c1, c2, rhs)
        si.acc, sj.acc, si.al, sj.al = aM, aH, al, al
    return BOut(si, sj, ok, gap, cond, singular, ((s, sd, sdd),))


def _guide_rates(g: BState, joint: str, s0: Pair, L: Pair, z: Pair, order: int):
    """Velocity and acceleration of the point of ``g`` under ``L`` (``z``: g's point at ``s0``)."""
    r = V.sub(L, z)
    v = a = None
    if order >= 1:
        vz = g.vel(joint, s0)
        v = (vz[0] - g.w * r[1], vz[1] + g.w * r[0])
    if order >= 2:
        az = g.accel(joint, s0)
        w2 = g.w * g.w
        a = (az[0] - w2 * r[0] - g.al * r[1], az[1] - w2 * r[1] + g.al * r[0])
    return v, a


def prp(g1: BState, j1: str, s1: Pair, u1_0: Pair, g2: BState, j2: str, s2: Pair, u2_0: Pair, l0: Pair,
        order: int, play=None) -> BOut:
    """PRP dyad: link i slides on a guide of g1, link j on a guide of g2, pinned together at L
    (see :func:`mechsketch.core.solver.kernels.prp`)."""
    z1, z2 = g1.point(j1, s1), g2.point(j2, s2)
    u1, u2 = V.mul(g1.cs, u1_0), V.mul(g2.cs, u2_0)
    b1, b2 = V.mul(g1.cs, V.sub(l0, s1)), V.mul(g2.cs, V.sub(l0, s2))
    c1, c2 = u1, V.scale(-1.0, u2)
    rhs = V.sub(V.add(z2, b2), V.add(z1, b1))
    p1, p2, det = _solve2(c1, c2, rhs if play is None else V.sub(rhs, play))
    cond = np.abs(V.re(det))
    # the guides cross as drawn (the side of cross(u1, −u2) in the drawn pose), not beyond parallel
    side = np.where(V.re(V.cross(u1_0, V.scale(-1.0, u2_0))) >= 0.0, 1.0, -1.0)
    gap = V.re(det) * side
    ok = np.isfinite(V.re(p1)) & (gap > PARALLEL_COND)
    L = V.add(V.add(z1, b1), V.scale(p1, u1))
    q1 = q2 = r1 = r2 = None
    if order >= 1:
        v1, a1 = _guide_rates(g1, j1, s1, L, z1, order)
        v2, a2 = _guide_rates(g2, j2, s2, L, z2, order)
        q1, q2, _ = _solve2(c1, c2, V.sub(v2, v1))
    if order >= 2:
        rhs = V.sub(V.add(a2, V.scale(2.0 * g2.w * q2, V.perp(u2))), V.add(a1, V.scale(2.0 * g1.w * q1, V.perp(u1))))
        r1, r2, _ = _solve2(c1, c2, rhs)
    si = slider(g1, s1, u1_0, j1, p1, q1, r1, order)
    sj = slider(g2, s2, u2_0, j2, p2, q2, r2, order)
    return BOut(si, sj, ok, gap, cond, None, ((p1, q1, r1), (p2, q2, r2)))


def rpp(mi: BState, m: str, m0: Pair, ui0: Pair, g: BState, j2: str, s2: Pair, u2_0: Pair, order: int,
        play=None) -> BOut:
    """RPP dyad: link i pinned at M slides along its axis ``ui0`` on link j, which slides on a
    guide of g (see :func:`mechsketch.core.solver.kernels.rpp`)."""
    M = _moved(mi.point(m, m0), play)
    z2 = g.point(j2, s2)
    u1, u2 = V.mul(g.cs, ui0), V.mul(g.cs, u2_0)
    d = V.add(V.sub(M, z2), V.mul(g.cs, V.sub(s2, m0)))
    p1, p2, det = _solve2(u1, u2, d)
    cond = np.abs(V.re(det))
    ok = np.isfinite(V.re(p2)) & (cond > PARALLEL_COND)
    st_i = BState(m0, M, g.cs)
    q1 = q2 = r1 = r2 = None
    if order >= 1:
        vM = mi.vel(m, m0)
        vg, ag = _guide_rates(g, j2, s2, M, z2, order)
        q1, q2, _ = _solve2(u1, u2, V.sub(vM, vg))
        st_i.v, st_i.w = vM, g.w
    if order >= 2:
        aM = mi.accel(m, m0)
        cor = V.scale(2.0 * g.w, V.perp(V.add(V.scale(q1, u1), V.scale(q2, u2))))
        r1, r2, _ = _solve2(u1, u2, V.sub(V.sub(aM, ag), cor))
        st_i.acc, st_i.al = aM, g.al
    st_j = slider(g, s2, u2_0, j2, p2, q2, r2, order)
    return BOut(st_i, st_j, ok, cond, cond, None, ((p1, q1, r1), (p2, q2, r2)))


def held(out: BOut, a0_i: Pair, a0_j: Pair, shape: tuple, order: int) -> BOut:
    """A fixed group (hung on the frame only): its links stay in the drawn pose, its assembly
    test (that of the drawn pose, per design) broadcast over the samples."""
    def still(a0: Pair) -> BState:
        return BState(a0, a0, (1.0, 0.0))

    ok = np.broadcast_to(out.ok, shape)
    gap = np.broadcast_to(out.gap, shape)
    cond = np.broadcast_to(out.cond, shape)
    sing = None if out.singular is None else np.broadcast_to(out.singular, shape)
    zero = np.zeros(shape)
    slides = tuple((zero, zero if order >= 1 else None, zero if order >= 2 else None) for _ in out.slides)
    return BOut(still(a0_i), still(a0_j), ok, gap, cond, sing, slides)


__all__ = ["BOut", "BState", "crank", "ground", "held", "prp", "rpp", "rpr", "rrp", "rrr", "slider"]
