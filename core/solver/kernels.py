"""Closed-form kinematics of the driver and of the five class-II dyads, on whole sample arrays.

Points and vectors are x + iy (mm) over arrays of shape (N,); J is the 90° rotation. A link's
motion is a :class:`~.link_state.LinkState`: the position of an anchor point (its drawn position
``a0``), the rotation ``rot = exp(i·ρ)`` from the drawn pose, and the derivatives. Any point drawn
at ``p0`` on the link is then ``A + rot·(p0 − a0)``. The driver, RRR and RRP kernels and the
slider states compute in real arithmetic on float x/y arrays (one determinant per group, its
reciprocal shared by the velocity and acceleration systems); RPR, PRP and RPP use the complex
views of the states they read.

Positions are closed form; velocities and accelerations solve the 2×2 linear system obtained by
differentiating the loop equation once and twice. Pasika's eqs. (2)–(3) (RRR) and (6)–(7) (RRP,
with corrections A1–A6 of the notes) are exactly Cramer's rule on these systems; RPR, PRP and RPP
are derived the same way. Infeasible samples (no assembly) come out as NaN, never as exceptions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .link_state import LinkState, ground_state, to_complex
from .skip_ops import _add, _minus, _pair, _sc, _sub

Arr = np.ndarray  # complex (N,) for points/vectors, float (N,) for scalars

__all__ = ["DyadOut", "LinkState", "PARALLEL_COND", "Slide", "crank", "cross", "dot", "ground_state",
           "crank_cs", "prp", "rpp", "rpr", "rrp", "rrr", "solve2", "to_complex"]


def cross(a: Arr, b: Arr) -> Arr:
    """z-component of a × b for complex-encoded vectors."""
    return (a.conjugate() * b).imag


def dot(a: Arr, b: Arr) -> Arr:
    return (a.conjugate() * b).real


def solve2(c1: Arr, c2: Arr, w: Arr) -> tuple[Arr, Arr, Arr]:
    """Solve x1·c1 + x2·c2 = w for real x1, x2 (complex columns); returns x1, x2, det."""
    det = cross(c1, c2)
    return cross(w, c2) / det, cross(c1, w) / det, det


@dataclass
class Slide:
    """Motion along one prismatic pair: the displacement ``s`` (mm, 0 in the drawn pose) of the
    sliding link relative to the link carrying the guide, along the guide's axis as that link
    turns it; ``sd`` (mm/s) and ``sdd`` (mm/s²) its first and second time derivatives (relative
    rates, as seen from the guide). Float (N,); derivatives None below the requested order;
    meaningful only where the group's ``ok`` is True.
    """

    s: Arr
    sd: Arr | None = None
    sdd: Arr | None = None


class DyadOut:
    """What a dyad kernel returns: the two link states, the feasibility mask and conditioning.

    ``cond`` is |det| / (|c1||c2|) of the velocity system, in [0, 1]: the sine of the angle
    between its columns (|sin μ| for RRR); a kernel may give it as a function of no arguments,
    called on first read (most solves never read it). ``gap`` is the signed assembly margin (mm
    or mm², negative where the group cannot be assembled) used to locate limits precisely.
    ``mode`` is the assembly mode read from the drawn pose (+1 or −1; the per-sample mode is it
    times the branch-point flip), None for PRP and RPP, which have a single assembly.
    ``slides`` holds one :class:`Slide` per prismatic joint of the group, in the order outer_i,
    inner, outer_j: RRP (outer_j: slider j on the guide of known_j), RPR (inner: link i on link
    j), PRP (outer_i: link i on known_i; outer_j: link j on known_j), RPP (inner: link i on link
    j; outer_j: link j on known_j); none for RRR.
    ``singular`` (bool (N,), or None: nowhere) marks samples where the group assembles but its pose
    is undetermined (RRR, RPR: the outer joints coincide within rounding); ``ok`` is False there.
    ``probe``: (N,) finite exactly where both link states are (a sum of the kernel's
    coordinates), or None; a finite float: the kernel proved both states finite at every sample.
    ``cond_floor``: a lower bound of ``cond`` at every sample from the assembly margins, exact
    arithmetic (0.0: none known); the rounding of the computed ``cond`` is far below it where it
    is ≥ 1e-6. ``every``: the kernel found every sample assembled (``ok`` all True, a new array).
    """

    __slots__ = ("state_i", "state_j", "ok", "_cond", "gap", "mode", "slides", "singular", "probe",
                 "cond_floor", "every")

    def __init__(self, state_i: LinkState, state_j: LinkState, ok: Arr, cond, gap: Arr,
                 mode: int | None = None, slides: tuple[Slide, ...] = (), singular: Arr | None = None,
                 probe: Arr | float | None = None, cond_floor: float = 0.0, every: bool = False) -> None:
        self.state_i, self.state_j, self.ok, self._cond, self.gap = state_i, state_j, ok, cond, gap
        self.mode, self.slides, self.singular, self.probe = mode, slides, singular, probe
        self.cond_floor, self.every = cond_floor, every

    @property
    def cond(self) -> Arr:
        c = self._cond
        if callable(c):
            c = self._cond = c()
        return c

    @cond.setter
    def cond(self, value: Arr) -> None:
        self._cond = value

    def __repr__(self) -> str:
        return (f"DyadOut(mode={self.mode!r}, every={self.every!r}, cond_floor={self.cond_floor!r}, "
                f"slides={len(self.slides)})")


#: PRP/RPP: below this |sin| between the two slide axes the lines are taken as parallel (not
#: assemblable). The intersection lies ~size/|sin| away and its rounding error is ~eps·size/|sin|,
#: so 1e-6 keeps loop closure within ~1e-10 of the size; a smaller limit lets rounding noise at
#: exactly parallel axes (|sin| ~ 1e-15) through as a "valid" pose 1e16 mm away.
PARALLEL_COND = 1e-6


def _sqrt_ok(x: Arr, gap: Arr, tol: float) -> tuple[Arr, Arr]:
    """sqrt(x) where the assembly margin ``gap`` ≥ −tol (x clamped at 0: an exact toggle that
    rounding pushed below zero still assembles); NaN and ok False elsewhere."""
    root, ok, _ = _root(x, gap, tol)
    return root, ok


def _root(x: Arr, gap: Arr, tol: float) -> tuple[Arr, Arr, float | None]:
    """:func:`_sqrt_ok` and, when every sample has ``gap`` ≥ 0 (then ok is True everywhere), the
    smallest margin (a float ≥ 0; None otherwise).

    ``x`` must be a product of factors that are all ≥ 0 where ``gap`` (their minimum) is: then
    x ≥ +0 there, and sqrt(x) is bit for bit sqrt(max(x, 0)), without the clamping pass and the
    masks (one reduction instead; a NaN margin fails it and takes the general path)."""
    if isinstance(gap, np.ndarray) and gap.ndim and gap.size:
        g = _MIN(gap)   # gap.min() without its Python wrapper (the same reduction)
        if g >= 0.0:
            ok = np.empty(gap.shape, dtype=bool)   # np.ones: 0.4 µs more
            ok.fill(True)
            return np.sqrt(x), ok, float(g)
    ok = gap >= -tol
    root = np.sqrt(np.maximum(x, 0.0))
    if isinstance(root, np.ndarray) and root.ndim:
        if not ok.all():
            root[~ok] = np.nan
        return root, ok, None
    return np.sqrt(np.where(ok, np.maximum(x, 0.0), np.nan)), ok, None


def _floor(num: float, den: float) -> float:
    """num / den as a conditioning's lower bound: 0.0 (none known) unless both are finite and
    den > 0, so that overflow, underflow or a NaN margin never pass for a bound."""
    if math.isfinite(num) and math.isfinite(den) and den > 0.0:
        f = num / den
        if math.isfinite(f):
            return f
    return 0.0


def crank_cs(inputs: Arr, a0_angle: float) -> tuple[Arr, Arr]:
    """(cos, sin) of ``inputs − a0_angle``, float (N,): the driver's rotation from the drawn pose."""
    th = inputs - a0_angle
    return np.cos(th), np.sin(th, out=th)   # sin into th


def crank(pivot: complex, a0_angle: float, inputs: Arr, omega: float | Arr, alpha: float | Arr,
          order: int, cs: tuple[Arr, Arr] | None = None) -> LinkState:
    """The driver: rotation about a ground pivot by ``inputs − a0_angle`` (rad). ``cs``: its
    :func:`crank_cs`, if the caller keeps it (a plan keeps the read-only (cos, sin) of its sweeps'
    input grids; nothing writes into a state's arrays)."""
    # the anchor (the pivot) as scalars, like the frame's: points of the crank are pivot + arm
    st = LinkState.real(pivot, (pivot.real, pivot.imag), crank_cs(inputs, a0_angle) if cs is None else cs)
    if order >= 1:
        st._vA_xy, st.omega = (0.0, 0.0), omega      # slots: the state is new, no complex view
    if order >= 2:
        st._aA_xy, st.alpha = (0.0, 0.0), alpha
    return st


def _slider(g: LinkState, s0: complex, u0: complex, s: Arr, sd: Arr | None, sdd: Arr | None,
            order: int, guide: tuple | None = None, still: bool | None = None) -> LinkState:
    """State of a link translating along a guide of link ``g`` (axis through drawn s0, dir u0),
    displaced by ``s`` (mm) with rates ``sd``, ``sdd``. ``guide``: (arm, z, u) of the guide point
    and direction as (x, y) pairs, if already computed; ``still``: ``g.still()``, if known."""
    if guide is None:
        guide = (g.arm_xy(s0), g.point_xy(s0), g.rotate(u0))
    arm, (zx, zy), (ux, uy) = guide
    shape = np.shape(s)
    st = LinkState.real(s0, _pair(_add(zx, _sc(ux, s)), _add(zy, _sc(uy, s)), shape), None)
    st.share_rotation(g)
    if still is None:
        still = g.still()
    if order >= 1:
        vzx, vzy = g.vel_xy(arm)
        if still:
            st._vA_xy = _pair(_add(vzx, _sc(ux, sd)), _add(vzy, _sc(uy, sd)), shape)
        else:
            ws = g.omega * s
            st._vA_xy = (_sub(_add(vzx, _sc(ux, sd)), _sc(uy, ws)), _add(_add(vzy, _sc(uy, sd)), _sc(ux, ws)))
        st.omega = g.omega
    if order >= 2:
        azx, azy = g.acc_xy(arm)
        if still:
            st._aA_xy = _pair(_add(azx, _sc(ux, sdd)), _add(azy, _sc(uy, sdd)), shape)
        else:
            w = g.omega
            p = sdd - w * w * s                  # (sdd + 2iω·sd + (iα − ω²)·s)·u = (p + iq)·u
            q = 2.0 * w * sd + g.alpha * s
            st._aA_xy = (_sub(_add(azx, _sc(ux, p)), _sc(uy, q)), _add(_add(azy, _sc(uy, p)), _sc(ux, q)))
        st.alpha = g.alpha
    return st


#: the drawn constants of a group (lengths, mode) per drawn geometry: Python floats for the tests
#: and 0-d float arrays for the sample arithmetic (an array operand skips numpy's scalar
#: conversion, ~0.16 µs a pass; the same double either way, so the same bits)
_CONST: dict = {}
_MIN = np.minimum.reduce
_ONE, _TWO = np.array(1.0), np.array(2.0)


def _const(key: tuple, make) -> tuple:
    c = _CONST.get(key)
    if c is None:
        if len(_CONST) > 4096:     # geometry edited many times (a drag): start over
            _CONST.clear()
        c = _CONST[key] = make()
    return c


def _rrr_const(m0: complex, h0: complex, l0: complex) -> tuple:
    li, lj = abs(l0 - m0), abs(l0 - h0)
    mode0 = 1.0 if ((h0 - m0).conjugate() * (l0 - m0)).imag >= 0.0 else -1.0
    dl, sl = li - lj, li + lj
    a = np.array
    return li, lj, mode0, dl, sl, a(li), a(dl), a(sl), a(dl * sl), a(li * lj)


def _rrp_const(m0: complex, u0: complex, l0: complex) -> tuple:
    li = abs(l0 - m0)
    mode0 = 1.0 if (u0.conjugate() * (l0 - m0)).real >= 0.0 else -1.0
    return li, mode0, np.array(li)


def rrr(m_state: LinkState, m0: complex, h_state: LinkState, h0: complex, l0: complex,
        order: int, flip: Arr | None = None, tol: float = 0.0, near: float = 0.0,
        const: tuple | None = None) -> DyadOut:
    """RRR dyad: link i = M–L, link j = H–L; M, H outer joints on known links, L the inner joint.

    Lengths and the assembly mode (sign of cross(H−M, L−M), +1: L left of M→H) come from the
    drawn positions m0, h0, l0. ``flip`` (±1 per sample) switches the mode past branch points
    so that the smooth branch is followed (see :mod:`mechsketch.core.solver.branches`).
    ``tol`` (mm): a margin ≥ −tol assembles; ``near`` (mm): M and H closer than this leave the
    direction M→H undetermined (a rhombus or kite where B meets D): singular, not solved.
    ``const``: ``_rrr_const(m0, h0, l0)``, if the caller keeps it (a compiled plan does).
    """
    li, lj, mode0, dl, sl, LI, DL, SL, DLSL, LILJ = (const if const is not None else
                                                     _const((m0, h0, l0), lambda: _rrr_const(m0, h0, l0)))
    mode = mode0 if flip is None else mode0 * flip
    armM, armH = m_state.arm_xy(m0), h_state.arm_xy(h0)
    mx, my = m_state.point_xy(m0)
    hx, hy = h_state.point_xy(h0)
    dx, dy = hx - mx, hy - my
    # (augmented assignments below work in place on this kernel's own temporaries — the same
    # operations in the same order, one allocation less each — and rebind scalars)
    D2 = dx * dx
    D2 += dy * dy
    D = np.sqrt(D2)
    # Heron in factored form: accurate near toggles (paper eq. 1 via atan2/Heron, notes §A)
    f1, f2, f3 = SL - D, D - DL, D + DL
    prod = D + SL
    prod *= f1
    prod *= f2
    prod *= f3
    # min(f2, f3) is D − |li − lj|: f2 for li ≥ lj (rounding is monotonic: D − DL ≤ D ≤ D + DL)
    gap = np.minimum(f1, f2 if dl >= 0.0 else f3)
    root, ok, gmin = _root(prod, gap, tol)
    every = gmin is not None
    singular = None                  # nowhere, unless the outer joints meet at some sample
    # every f2, f3 ≥ 0: D ≥ |li − lj| at every sample, so |li − lj| > near rules out a meeting
    if not (every and abs(dl) > near):
        meet = D <= near
        if not isinstance(meet, np.ndarray) or meet.ndim == 0 or meet.any():
            singular = ok & meet
            ok = ok & ~singular
    # L − M = q·(li/|q|)·(d/D) with q = x + i·h, x = (li² − lj² + D²)/(2D), h = mode·√prod/(2D):
    # L in polar form, |L − M| = li exactly. (x, h) lose accuracy like eps·li²/D where M and H
    # nearly coincide (li ≈ lj), and the Cartesian form then left the loop open by up to li.
    # The common factor 1/(2D) of x and h cancels in q/|q|.
    x = D2                                               # D² + (li² − lj²), D2's own array
    x += DLSL
    h = root if (flip is None and mode0 == 1.0) else mode * root
    q = x * x
    q += h * h
    t = LI / (np.sqrt(q) * D)
    x *= t
    h *= t
    rix = x * dx                                         # L − M
    rix -= h * dy
    riy = x * dy
    riy += h * dx
    lx, ly = mx + rix, my + riy
    rjx, rjy = lx - hx, ly - hy                          # L − H
    si = LinkState.turned(m0, (mx, my), (rix, riy), l0 - m0)
    sj = LinkState.turned(h0, (hx, hy), (rjx, rjy), l0 - h0)
    si.set_point(l0, (rix, riy), (lx, ly))
    # velocity system (eq. 2): i·ω_i·r_i − i·ω_j·r_j = v_H − v_M, det = cross(J·ri, −J·rj)
    det = riy * rjx
    det -= rix * rjy
    cond = lambda: np.abs(det) / LILJ                    # noqa: E731 (made if read)
    if order >= 1:
        inv = _ONE / det
        vM, vH = m_state.vel_at(m0, armM), h_state.vel_at(h0, armH)
        wx, wy = _minus(vM, vH)                          # −(right-hand side)
        wi = wx * rjx
        wi += wy * rjy
        wi *= inv
        wj = rix * wx
        wj += riy * wy
        wj *= inv
        si._vA_xy, si.omega, sj._vA_xy, sj.omega = vM, wi, vH, wj   # new states: set the slots
    if order >= 2:
        aM, aH = m_state.acc_at(m0, armM), h_state.acc_at(h0, armH)
        wi2, wj2 = wi * wi, wj * wj
        si.set_omega2(wi2)
        sj.set_omega2(wj2)
        qx, qy = _minus(aM, aH)                          # −(eq. 3's right-hand side)
        qx = qx - wi2 * rix                              # (aM's own arrays are not written)
        qx += wj2 * rjx
        qy = qy - wi2 * riy
        qy += wj2 * rjy
        ai = qx * rjx
        ai += qy * rjy
        ai *= inv
        aj = rix * qx
        aj += riy * qy
        aj *= inv
        si._aA_xy, si.alpha = aM, ai
        sj._aA_xy, sj.alpha = aH, aj
    # L finite: M and L − M are; with H finite both links' states are
    if (every and isinstance(hx, float) and abs(hx) + abs(hy) < 1e200 and 1e-60 < sl < 1e60
            and abs(dl) > max(near, 1e-8 * sl)):
        # every pose finite, provably: D finite (every margin is), so M is; |li − lj| ≤ D ≤ li + lj
        # keeps x, h, |q|² = (2·D·li)² and t ~ 1/(2D²) far from overflow and underflow
        probe = 0.0
    else:
        probe = lx + ly if isinstance(hx, float) and math.isfinite(hx + hy) else lx + ly + (hx + hy)
    # |det| = li·lj·|sin μ| = √prod / 2; with every margin ≥ gmin: f1 ≥ gmin, the smaller of
    # f2, f3 (D − |li − lj|) ≥ gmin, the larger ≥ gmin + 2·|li − lj|, D + li + lj ≥ li + lj
    floor = _floor(gmin * math.sqrt(sl * (gmin + 2.0 * abs(dl))), 2.0 * li * lj) if every else 0.0
    return DyadOut(si, sj, ok, cond, gap, int(mode0), singular=singular, probe=probe,
                   cond_floor=floor, every=every and singular is None)


def rrp(m_state: LinkState, m0: complex, g: LinkState, s0: complex, u0: complex, l0: complex,
        order: int, flip: Arr | None = None, tol: float = 0.0, const: tuple | None = None) -> DyadOut:
    """RRP dyad: link i = M–L (rod), link j = slider carrying L, sliding on a guide of known link g.

    The guide is the axis through drawn ``s0`` with unit direction ``u0`` (moves with g). Mode:
    sign of the rod's projection on the guide in the drawn pose (the paper's choice of x_q).
    ``const``: ``_rrp_const(m0, u0, l0)``, if the caller keeps it (a compiled plan does).
    """
    li, mode0, LI = const if const is not None else _const((m0, u0, l0, 0), lambda: _rrp_const(m0, u0, l0))
    mode = mode0 if flip is None else mode0 * flip
    armM = m_state.arm_xy(m0)
    mx, my = m_state.point_xy(m0)
    armz = g.arm_xy(s0)
    zx, zy = g.point_xy(s0)
    ux, uy = g.rotate(u0)
    # slider pin relative to the slide point (l_j, φ_jq of the paper)
    bx, by = g.rotate(l0 - s0) if l0 != s0 else (0.0, 0.0)
    dx, dy = np.subtract(_add(zx, bx), mx), np.subtract(_add(zy, by), my)   # numpy even for scalars
    arr = ux.__class__ is np.ndarray and uy.__class__ is np.ndarray   # a turning guide: no scalar terms
    # (augmented assignments work in place on this kernel's own temporaries — the same operations
    # in the same order, one allocation less each — and rebind scalars)
    if arr:
        du = ux * dx
        du += uy * dy
        dn = ux * dy                                     # signed eccentricity e_s + l_j sin φ_jq − M·n
        dn -= uy * dx                                    # (A1–A3 corrected)
    else:
        du = _add(_sc(ux, dx), _sc(uy, dy))
        dn = _sub(_sc(ux, dy), _sc(uy, dx))
    gap = LI - np.abs(dn)
    pr = LI - dn
    pr *= LI + dn
    root, ok, gmin = _root(pr, gap, tol)
    s = root if (flip is None and mode0 == 1.0) else mode * root   # root: _root's own array
    s -= du
    if arr:
        rix = ux * s                                     # d + s·u (the same sum, either order)
        rix += dx
        riy = uy * s
        riy += dy
    else:
        rix, riy = _add(dx, _sc(ux, s)), _add(dy, _sc(uy, s))
    si = LinkState.turned(m0, (mx, my), (rix, riy), l0 - m0)
    lx, ly = mx + rix, my + riy
    si.set_point(l0, (rix, riy), (lx, ly))
    # columns c1 = u, c2 = −J·ri: det = −(u·ri)
    if arr:
        udr = ux * rix
        udr += uy * riy
    else:
        udr = _add(_sc(ux, rix), _sc(uy, riy))
    cond = lambda: np.abs(udr) / LI                      # noqa: E731 (made if read)
    still = g.still()
    # every margin finite: dn = u × d is, which on a turning guide (u arrays, every product
    # taken) needs u and d finite (an infinite component gives ±inf or inf − inf or 0·inf), so
    # M and the guide point z + b are (d = z + b − M), and with |dn| ≤ li so are s = ±√ − du, the
    # rod r_i = d + s·u, L = M + r_i and the slider z + s·u (short of overflow beyond 1e308, as
    # the RRR's and the plan's probes assume)
    proved = gmin is not None and arr and 1e-60 < li < 1e60
    on_guide = not still and l0 == s0   # the pin is the slider's anchor: its motion is L's
    sd = sdd = None
    if not still:
        gx, gy = g.xy
        armL = (lx - gx, ly - gy)                        # the guide's point under L
    if order >= 1:
        inv = _ONE / udr
        vM = m_state.vel_at(m0, armM)
        if still:
            wx, wy = vM
        else:
            vLx, vLy = g.vel_xy(armL)
            wx, wy = vM[0] - vLx, vM[1] - vLy
        sd = wx * rix                                    # eq. 6 with correction A4
        sd += wy * riy
        sd *= inv
        if arr:
            wi = uy * wx
            wi -= ux * wy
            wi *= inv
        else:
            wi = _sub(_sc(uy, wx), _sc(ux, wy)) * inv
        si._vA_xy, si.omega = vM, wi
    if order >= 2:
        aM = m_state.acc_at(m0, armM)
        wi2 = wi * wi
        si.set_omega2(wi2)
        qx, qy = aM[0] - wi2 * rix, aM[1] - wi2 * riy
        aLm = (qx, qy)                                   # a_M − ω_i²·r_i, reused for a_L
        if not still:
            aLx, aLy = g.acc_xy(armL)
            cor = _TWO * g.omega * sd
            if arr:                                      # eq. 7 (new arrays: aLm is kept)
                qx = qx - aLx
                qx += uy * cor
                qy = qy - aLy
                qy -= ux * cor
            else:
                qx, qy = _add(qx - aLx, _sc(uy, cor)), _sub(qy - aLy, _sc(ux, cor))
        sdd = qx * rix
        sdd += qy * riy
        sdd *= inv
        if arr:
            al = uy * qx
            al -= ux * qy
            al *= inv
        else:
            al = _sub(_sc(uy, qx), _sc(ux, qy)) * inv
        si._aA_xy, si.alpha = aM, al
    if on_guide:
        sj = LinkState.real(s0, (lx, ly), None)
        sj.share_rotation(g)
        if order >= 1:   # v_L = v_M + ω_i·J·r_i
            sj._vA_xy, sj.omega = (vM[0] - wi * riy, vM[1] + wi * rix), g.omega
        if order >= 2:   # a_L = (a_M − ω_i²·r_i) + α_i·J·r_i
            ai = si.alpha
            sj._aA_xy = (aLm[0] - ai * riy, aLm[1] + ai * rix)
            sj.alpha = g.alpha
        # L's rates on link i are the slider's anchor rates, the same expressions term by term
        # (a_L: (a_M − ω_i²·r_i) + α_i·J·r_i as acc_xy orders them): extracted as copies
        si.set_rates(l0, sj._vA_xy if order >= 1 else None, sj._aA_xy if order >= 2 else None)
        probe = 0.0 if proved else lx + ly
    else:
        sj = _slider(g, s0, u0, s, sd, sdd, order, (armz, (zx, zy), (ux, uy)), still)
        if still and order >= 1:   # a fixed guide: the slider translates, L moves as its anchor
            si.set_rates(l0, sj._vA_xy, sj._aA_xy if order >= 2 else None)    # ṡ·u, s̈·u: copies
        if still and isinstance(zx, float) and isinstance(zy, float) and isinstance(ux, float):
            # a fixed guide: the slider (z + s·u) is finite where L is; with every margin finite
            # (dn, so √ and s) and M known finite, so are d = z + b − M, du, s, r_i and L (short
            # of overflow beyond 1e308, as above)
            probe = 0.0 if gmin is not None and m_state.finite and math.isfinite(zx + zy + ux + uy) else lx + ly
        elif proved:
            probe = 0.0
        else:
            sx, sy = sj.xy
            probe = lx + ly + (sx + sy)
    # |u·ri| = √((li − dn)(li + dn)), the smaller factor ≥ gmin and the larger ≥ li
    floor = _floor(math.sqrt(gmin), math.sqrt(li)) if gmin is not None else 0.0
    return DyadOut(si, sj, ok, cond, gap, int(mode0), (Slide(s, sd, sdd),), probe=probe,
                   cond_floor=floor, every=gmin is not None)


def rpr(m_state: LinkState, m0: complex, h_state: LinkState, h0: complex, u0: complex,
        order: int, flip: Arr | None = None, tol: float = 0.0, near: float = 0.0) -> DyadOut:
    """RPR dyad: link i (pin M) slides on link j (pin H) along an axis of drawn direction u0.

    Both links turn together. Only the axis direction matters: M's offset across the axis
    relative to H's is constant wherever the axis lies. Mode: sign of the along-axis distance
    from H to M, drawn pose.
    """
    c = cross(np.asarray(u0), np.asarray(m0 - h0)).item()  # constant offset of M from H ⟂ axis
    a_d = dot(np.asarray(u0), np.asarray(m0 - h0)).item()
    mode0 = 1.0 if a_d >= 0.0 else -1.0
    mode = mode0 if flip is None else mode0 * flip
    M, H = m_state.point(m0), h_state.point(h0)
    d = M - H
    D = np.abs(d)
    gap = D - abs(c)
    root, ok = _sqrt_ok((D - c) * (D + c), gap, tol)
    singular = ok & (D <= near)   # the pins coincide (on a slot through the pivot): no direction
    ok = ok & ~singular
    sigma = mode * root
    u = d / (sigma + 1j * c)
    rot = u / u0
    s = sigma - a_d  # slide of link i relative to link j, 0 in the drawn pose
    si, sj = LinkState(m0, M, rot), LinkState(h0, H, rot)
    c1, c2 = u, 1j * d
    cond = np.minimum(np.abs(sigma) / max(abs(m0 - h0), abs(c)), 1.0)  # 0 as the pin meets the axis foot
    if order >= 1:
        vM, vH = m_state.velocity(m0, M), h_state.velocity(h0, H)
        sd, w, _ = solve2(c1, c2, vM - vH)
        si.vA, sj.vA, si.omega, sj.omega = vM, vH, w, w
    else:
        sd = None
    if order >= 2:
        aM, aH = m_state.acceleration(m0, M), h_state.acceleration(h0, H)
        sdd, al, _ = solve2(c1, c2, aM - aH - 2j * w * sd * u + w * w * d)
        si.aA, sj.aA, si.alpha, sj.alpha = aM, aH, al, al
    else:
        sdd = None
    return DyadOut(si, sj, ok, cond, gap, int(mode0), (Slide(s, sd, sdd),), singular)


def prp(g1: LinkState, s1: complex, u1_0: complex, g2: LinkState, s2: complex, u2_0: complex,
        l0: complex, order: int) -> DyadOut:
    """PRP dyad: link i slides on a guide of g1, link j on a guide of g2, pinned together at L.

    No assembly mode (two lines meet once), but a side: the guides cross one way in the drawn
    pose (the sign of det = cross(u1, −u2)); where they turn parallel the pin runs off to
    infinity and comes back from the other side, which the mechanism cannot reach. So the group
    assembles only where its guides cross as drawn and are more than PARALLEL_COND from parallel;
    its margin ``gap`` is det signed that way (negative beyond a parallel pose).
    """
    z1, z2 = g1.point(s1), g2.point(s2)
    u1, u2 = g1.rot * u1_0, g2.rot * u2_0
    b1, b2 = g1.rot * (l0 - s1), g2.rot * (l0 - s2)
    c1, c2 = u1, -u2
    p1, p2, det = solve2(c1, c2, z2 + b2 - z1 - b1)
    cond = np.abs(det)
    side = 1.0 if cross(np.asarray(u1_0), np.asarray(-u2_0)).item() >= 0.0 else -1.0   # drawn
    gap = det if side > 0.0 else -det
    ok = np.isfinite(p1) & (gap > PARALLEL_COND)
    L = z1 + b1 + p1 * u1
    if order >= 1:
        v1 = g1.velocity(s1, z1) + 1j * g1.omega * (L - z1)
        v2 = g2.velocity(s2, z2) + 1j * g2.omega * (L - z2)
        q1, q2, _ = solve2(c1, c2, v2 - v1)
    else:
        q1 = q2 = None
    if order >= 2:
        a1 = g1.acceleration(s1, z1) + (1j * g1.alpha - g1.omega * g1.omega) * (L - z1)
        a2 = g2.acceleration(s2, z2) + (1j * g2.alpha - g2.omega * g2.omega) * (L - z2)
        r1, r2, _ = solve2(c1, c2, a2 + 2j * g2.omega * q2 * u2 - a1 - 2j * g1.omega * q1 * u1)
    else:
        r1 = r2 = None
    si = _slider(g1, s1, u1_0, p1, q1, r1, order)
    sj = _slider(g2, s2, u2_0, p2, q2, r2, order)
    return DyadOut(si, sj, ok, cond, gap, None, (Slide(p1, q1, r1), Slide(p2, q2, r2)))


def rpp(m_state: LinkState, m0: complex, ui0: complex, g: LinkState, s2: complex, u2_0: complex,
        order: int) -> DyadOut:
    """RPP dyad: link i pinned at M slides (axis of drawn direction ui0) on link j, which slides
    on a guide of g (axis through drawn s2, direction u2_0).

    Both links keep the guide's rotation. No assembly mode; singular when the two axes are parallel.
    """
    M = m_state.point(m0)
    z2 = g.point(s2)
    u1, u2 = g.rot * ui0, g.rot * u2_0
    d = M - z2 + g.rot * (s2 - m0)
    p1, p2, det = solve2(u1, u2, d)
    cond = np.abs(det)
    ok = np.isfinite(p2) & (cond > PARALLEL_COND)
    st_i = LinkState(m0, M, g.rot)
    q1 = q2 = r1 = r2 = None
    if order >= 1:
        vM = m_state.velocity(m0, M)
        q1, q2, _ = solve2(u1, u2, vM - g.velocity(s2, z2) - 1j * g.omega * (M - z2))
        st_i.vA, st_i.omega = vM, g.omega
    if order >= 2:
        aM = m_state.acceleration(m0, M)
        ag = g.acceleration(s2, z2) + (1j * g.alpha - g.omega * g.omega) * (M - z2)
        r1, r2, _ = solve2(u1, u2, aM - ag - 2j * g.omega * (q1 * u1 + q2 * u2))
        st_i.aA, st_i.alpha = aM, g.alpha
    st_j = _slider(g, s2, u2_0, p2, q2, r2, order)
    return DyadOut(st_i, st_j, ok, cond, cond, None, (Slide(p1, q1, r1), Slide(p2, q2, r2)))
