"""Closed-form kernels of the group a linear actuator drives: a dyad one of whose links has a
length that changes with time (the cylinder, seen as a bar from pivot to pivot), and the states
of the cylinder's barrel and rod.

A cylinder between pivots M (on its barrel) and H (on its rod) acts, once its length L(t) is
given, like a bar M–H of that length: the *virtual link* V. V meets the rest of the linkage in an
RRR dyad (V with a bar) or as the rod of an RRP dyad (V pushing a slider). Positions are the usual
closed forms with the current length; velocities and accelerations add the length's rates: with
r = L·e^{iφ}, ṙ = (L̇/L)·r + iω·r and r̈ = (L̈/L − ω²)·r + (2L̇ω/L)·i·r + iα·r, which enter the
right-hand sides of the dyad's 2×2 systems (Cramer's rule, as in :mod:`.kernels`).

The barrel and the rod turn together along the slide axis u: H − M = u·(σ + ic), with c the
drawn offset of H across the axis (constant) and σ = ±√(L² − c²) the slide coordinate; they turn
with ω_u = φ̇ − β̇ where β = atan2(c, σ) (β̇ = 0 when the axis passes through both pivots).
Arrays are complex or float (N,); lengths mm, rates per second.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import kernels as K

Arr = np.ndarray


@dataclass
class Stroke:
    """The length of the virtual link over the samples: L (mm), L̇ (mm/s), L̈ (mm/s²), (N,) or scalars."""

    L: Arr
    Ld: Arr | float = 0.0
    Ldd: Arr | float = 0.0


def _bar(outer0: complex, outer: Arr, r: Arr, r0: complex, vO: Arr | None, w: Arr | None,
         aO: Arr | None, al: Arr | None) -> K.LinkState:
    """State of a rigid bar anchored at its outer joint (drawn ``outer0``) with r = inner − outer."""
    st = K.LinkState(outer0, outer, r / r0)
    st.vA, st.omega, st.aA, st.alpha = vO, w, aO, al
    return st


def rrr_var(m_state: K.LinkState, m0: complex, h_state: K.LinkState, h0: complex, l0: complex,
            li: Arr | float, lj: Arr | float, dli: Arr | float, dlj: Arr | float, ddli: Arr | float,
            ddlj: Arr | float, order: int, flip: Arr | None, tol: float) -> dict:
    """RRR dyad M–L–H whose link lengths ``li`` (M–L) and ``lj`` (H–L) may change with time.

    The assembly mode is read from the drawn positions m0, h0, l0 (sign of cross(H − M, L − M)),
    times ``flip`` past branch points. Returns a dict: ``M``, ``H``, ``L`` positions, ``ri``, ``rj``
    (L − M, L − H), ``vM``, ``vH``, ``wi``, ``wj``, ``aM``, ``aH``, ``ai``, ``aj`` (None below
    ``order``), ``ok``, ``cond`` (|sin μ|), ``gap`` (mm) and ``mode`` (drawn, ±1).
    """
    mode0 = 1.0 if K.cross(np.asarray(h0 - m0), np.asarray(l0 - m0)) >= 0.0 else -1.0
    mode = mode0 if flip is None else mode0 * flip
    M, H = m_state.point(m0), h_state.point(h0)
    d = H - M
    D = np.abs(d)
    f1, f2, f3 = li + lj - D, D - li + lj, D + li - lj
    gap = np.minimum(np.minimum(f1, f2), f3)
    root, ok = K._sqrt_ok((D + li + lj) * f1 * f2 * f3, gap, tol)
    x = ((li - lj) * (li + lj) + D * D) / (2.0 * D)
    q = x + 1j * (mode * root / (2.0 * D))
    L = M + q * (li / np.abs(q)) * (d / D)
    ri, rj = L - M, L - H
    c1, c2 = 1j * ri, -1j * rj
    out = dict(M=M, H=H, L=L, ri=ri, rj=rj, ok=ok, cond=np.abs(K.cross(c1, c2)) / (li * lj), gap=gap,
               mode=int(mode0), vM=None, vH=None, wi=None, wj=None, aM=None, aH=None, ai=None, aj=None)
    if order >= 1:
        vM, vH = m_state.velocity(m0, M), h_state.velocity(h0, H)
        ei, ej = dli / li, dlj / lj
        wi, wj, _ = K.solve2(c1, c2, vH - vM + ej * rj - ei * ri)
        out.update(vM=vM, vH=vH, wi=wi, wj=wj)
    if order >= 2:
        aM, aH = m_state.acceleration(m0, M), h_state.acceleration(h0, H)
        rhs = (aH - aM + (ddlj / lj - wj * wj) * rj + 2.0 * ej * wj * 1j * rj
               - (ddli / li - wi * wi) * ri - 2.0 * ei * wi * 1j * ri)
        ai, aj, _ = K.solve2(c1, c2, rhs)
        out.update(aM=aM, aH=aH, ai=ai, aj=aj)
    return out


def rrp_var(m_state: K.LinkState, m0: complex, g: K.LinkState, s0: complex, u0: complex, l0: complex,
            li: Arr | float, dli: Arr | float, ddli: Arr | float, order: int, flip: Arr | None,
            tol: float) -> dict:
    """RRP dyad whose rod M–L has a length ``li`` that may change with time; the slider carrying
    L slides on the guide of ``g`` (axis through drawn s0, direction u0). Mode: sign of the rod's
    projection on the guide, drawn. Returns a dict: ``M``, ``L``, ``ri``, ``vM``, ``wi``, ``aM``,
    ``ai``, the slider's :class:`~.kernels.LinkState` ``slider`` and :class:`~.kernels.Slide`
    ``slide``, ``ok``, ``cond``, ``gap``, ``mode``."""
    mode0 = 1.0 if K.dot(np.asarray(u0), np.asarray(l0 - m0)) >= 0.0 else -1.0
    mode = mode0 if flip is None else mode0 * flip
    M = m_state.point(m0)
    z = g.point(s0)
    u = g.rot * u0
    b = g.rot * (l0 - s0)
    dvec = z + b - M
    du, dn = K.dot(u, dvec), K.cross(u, dvec)
    gap = li - np.abs(dn)
    root, ok = K._sqrt_ok((li - dn) * (li + dn), gap, tol)
    s = -du + mode * root
    ri = dvec + s * u
    L = M + ri
    c1, c2 = u, -1j * ri
    out = dict(M=M, L=L, ri=ri, ok=ok, cond=np.abs(K.cross(c1, c2)) / li, gap=gap, mode=int(mode0),
               vM=None, wi=None, aM=None, ai=None)
    sd = sdd = None
    if order >= 1:
        vM = m_state.velocity(m0, M)
        vLg = g.velocity(s0, z) + 1j * g.omega * (L - z)
        ei = dli / li
        sd, wi, _ = K.solve2(c1, c2, vM + ei * ri - vLg)
        out.update(vM=vM, wi=wi)
    if order >= 2:
        aM = m_state.acceleration(m0, M)
        aLg = g.acceleration(s0, z) + (1j * g.alpha - g.omega * g.omega) * (L - z)
        rhs = aM + (ddli / li - wi * wi) * ri + 2.0 * ei * wi * 1j * ri - aLg - 2j * g.omega * sd * u
        sdd, ai, _ = K.solve2(c1, c2, rhs)
        out.update(aM=aM, ai=ai)
    out["slider"] = K._slider(g, s0, u0, s, sd, sdd, order)
    out["slide"] = K.Slide(s, sd, sdd)
    return out


@dataclass(frozen=True)
class Cylinder:
    """The drawn geometry of a cylinder: end pivots ``m0`` (barrel) and ``h0`` (rod), slide axis
    direction ``u0``; ``c`` = cross(u0, h0 − m0) the pivots' constant offset across the axis,
    ``a0`` = dot(u0, h0 − m0) the drawn slide coordinate, ``mode`` its sign (±1)."""

    m0: complex
    h0: complex
    u0: complex

    @property
    def c(self) -> float:
        return float(K.cross(np.asarray(self.u0), np.asarray(self.h0 - self.m0)))

    @property
    def a0(self) -> float:
        return float(K.dot(np.asarray(self.u0), np.asarray(self.h0 - self.m0)))

    @property
    def mode(self) -> float:
        return 1.0 if self.a0 >= 0.0 else -1.0

    def states(self, M: Arr, H: Arr, stroke: Stroke, vM, vH, w, aM, aH, al, order: int, tol: float
               ) -> tuple[K.LinkState, K.LinkState, K.Slide, Arr]:
        """Barrel and rod states, the slide (of the rod on the barrel, 0 drawn) and the assembly
        test (L ≥ |c|), from the pivots' positions M, H (N,), the length and V's rates ``w``, ``al``
        (the direction of H − M turns at w, accelerates at al)."""
        c, L = self.c, stroke.L
        gap = L - abs(c)
        sig_abs, ok = K._sqrt_ok((L - c) * (L + c), gap, tol)
        sigma = self.mode * sig_abs
        u = (H - M) / (sigma + 1j * c)
        rot = u / self.u0
        barrel, rod = K.LinkState(self.m0, M, rot), K.LinkState(self.h0, H, rot)
        sd = sdd = None
        if order >= 1:
            sd = L * stroke.Ld / sigma
            wu = w + c * sd / (L * L)
            barrel.vA, barrel.omega, rod.vA, rod.omega = vM, wu, vH, wu
        if order >= 2:
            sdd = (stroke.Ld * stroke.Ld + L * stroke.Ldd - sd * sd) / sigma
            au = al + c * sdd / (L * L) - 2.0 * c * sd * stroke.Ld / (L * L * L)
            barrel.aA, barrel.alpha, rod.aA, rod.alpha = aM, au, aH, au
        return barrel, rod, K.Slide(sigma - self.a0, sd, sdd), ok


__all__ = ["Cylinder", "Stroke", "rrp_var", "rrr_var"]
