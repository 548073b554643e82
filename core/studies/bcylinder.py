"""The group a cylinder drives, over D designs × N samples: the batch twin of
:mod:`mechsketch.core.solver.stroke_kernels` and of ``CylinderDrive.compile_step``.

The cylinder between pivots M (barrel) and H (rod) is the bar V of length L (the input, (1, N) mm,
with its rates); V sits in an RRR group (with a bar) or is the rod of an RRP group. Barrel and rod
then turn together along the slide axis through both pivots (offset ``c`` across it). Drawn
constants are arrays (D, 1); see :mod:`.bkernels` for the conventions.
"""
from __future__ import annotations

import numpy as np

from . import vec as V
from .bkernels import BOut, BState, _root, _solve2, slider


def _states(M, H, vM, vH, aM, aH, w, al, L, Ld, Ldd, cyl: dict, order: int):
    """Barrel and rod from V's pivots and V's rates ``w``, ``al`` (``Cylinder.states``)."""
    c, a0 = cyl["c"], cyl["a0"]
    gap = V.re(L) - np.abs(V.re(c))
    sig_abs, ok = _root((L - c) * (L + c), gap, cyl["tol"])
    sigma = cyl["mode"] * sig_abs
    u = V.div(V.sub(H, M), (sigma, c + 0.0 * sigma))
    rot = V.cmul(cyl["u0"], u)
    barrel, rod = BState(cyl["m0"], M, rot), BState(cyl["h0"], H, rot)
    sd = sdd = None
    if order >= 1:
        sd = L * Ld / sigma
        wu = w + c * sd / (L * L)
        barrel.v, barrel.w, rod.v, rod.w = vM, wu, vH, wu
    if order >= 2:
        sdd = (Ld * Ld + L * Ldd - sd * sd) / sigma
        au = al + c * sdd / (L * L) - 2.0 * c * sd * Ld / (L * L * L)
        barrel.acc, barrel.al, rod.acc, rod.al = aM, au, aH, au
    return barrel, rod, (sigma - a0, sd, sdd), ok, gap


def _bar(a0: Pair, A, r, r0, v, w, acc, al) -> BState:
    return BState(a0, A, V.div(r, r0), v, w, acc, al)


Pair = V.Pair


def cyl_rrr(mi: BState, m: str, m0, hj: BState, h: str, h0, l: str, l0, k: dict, cyl: dict, stroke: tuple,
            v_is_i: bool, order: int, flip=None) -> tuple[BOut, BState]:
    """RRR dyad M–L–H one of whose links is V (length L(t)); returns the group's output and the
    rod's state. ``k``: ``mode``, ``tol``, ``li`` or ``lj`` (the bar's length, (D, 1))."""
    L, Ld, Ldd = stroke
    zero = 0.0
    li, dli, ddli = (L, Ld, Ldd) if v_is_i else (k["li"], zero, zero)
    lj, dlj, ddlj = (L, Ld, Ldd) if not v_is_i else (k["lj"], zero, zero)
    mode = k["mode"] if flip is None else k["mode"] * flip
    M, H = mi.point(m, m0), hj.point(h, h0)
    d = V.sub(H, M)
    D = V.norm(d)
    f1, f2, f3 = li + lj - D, D - li + lj, D + li - lj
    gap = np.minimum(np.minimum(V.re(f1), V.re(f2)), V.re(f3))
    root, ok = _root((D + li + lj) * f1 * f2 * f3, gap, k["tol"])
    x = ((li - lj) * (li + lj) + D * D) / (2.0 * D)
    q = (x, mode * root / (2.0 * D))
    Lp = V.add(M, V.mul(V.scale(li / V.norm(q), q), V.scale(1.0 / D, d)))
    ri, rj = V.sub(Lp, M), V.sub(Lp, H)
    c1, c2 = V.perp(ri), V.scale(-1.0, V.perp(rj))
    cond = np.abs(V.re(V.cross(c1, c2))) / np.abs(V.re(li * lj))
    vM = vH = aM = aH = wi = wj = ai = aj = vL = aL = None
    if order >= 1:
        vM, vH = mi.vel(m, m0), hj.vel(h, h0)
        ei, ej = dli / li, dlj / lj
        wi, wj, _ = _solve2(c1, c2, V.sub(V.add(V.sub(vH, vM), V.scale(ej, rj)), V.scale(ei, ri)))
        vL = V.add(V.add(vM, V.scale(wi, V.perp(ri))), V.scale(ei, ri))
    if order >= 2:
        aM, aH = mi.accel(m, m0), hj.accel(h, h0)
        rhs = V.sub(V.sub(V.add(V.add(V.sub(aH, aM), V.scale(ddlj / lj - wj * wj, rj)), V.scale(2.0 * ej * wj, V.perp(rj))),
                          V.scale(ddli / li - wi * wi, ri)), V.scale(2.0 * ei * wi, V.perp(ri)))
        ai, aj, _ = _solve2(c1, c2, rhs)
        aL = V.add(V.add(aM, V.add(V.scale(ddli / li - wi * wi, ri), V.scale(ai, V.perp(ri)))),
                   V.scale(2.0 * ei * wi, V.perp(ri)))
    pos = {m: (M, vM, aM), h: (H, vH, aH), l: (Lp, vL, aL)}
    if v_is_i:
        partner = _bar(h0, H, rj, V.sub(l0, h0), vH, wj, aH, aj)
        w, al = wi, ai
    else:
        partner = _bar(m0, M, ri, V.sub(l0, m0), vM, wi, aM, ai)
        w, al = wj, aj
    return _finish(pos, partner, w, al, ok, gap, cond, cyl, stroke, v_is_i, order)


def cyl_rrp(mi: BState, m: str, m0, g: BState, sjoint: str, s0, u0, l: str, l0, k: dict, cyl: dict,
            stroke: tuple, order: int, flip=None) -> tuple[BOut, BState]:
    """RRP dyad whose rod M–L is V; the slider carrying L slides on the guide of ``g``."""
    li, dli, ddli = stroke
    mode = k["mode"] if flip is None else k["mode"] * flip
    M = mi.point(m, m0)
    z = g.point(sjoint, s0)
    u = V.mul(g.cs, u0)
    b = V.mul(g.cs, V.sub(l0, s0))
    dvec = V.sub(V.add(z, b), M)
    du, dn = V.dot(u, dvec), V.cross(u, dvec)
    gap = V.re(li) - np.abs(V.re(dn))
    root, ok = _root((li - dn) * (li + dn), gap, k["tol"])
    s = -du + mode * root
    ri = V.add(dvec, V.scale(s, u))
    Lp = V.add(M, ri)
    c1, c2 = u, V.scale(-1.0, V.perp(ri))
    cond = np.abs(V.re(V.cross(c1, c2))) / np.abs(V.re(li))
    vM = aM = wi = ai = vL = aL = sd = sdd = None
    r = V.sub(Lp, z)
    if order >= 1:
        vM = mi.vel(m, m0)
        vz = g.vel(sjoint, s0)
        vLg = (vz[0] - g.w * r[1], vz[1] + g.w * r[0])
        ei = dli / li
        sd, wi, _ = _solve2(c1, c2, V.sub(V.add(vM, V.scale(ei, ri)), vLg))
        vL = V.add(vM, V.add(V.scale(wi, V.perp(ri)), V.scale(ei, ri)))
    if order >= 2:
        aM = mi.accel(m, m0)
        az = g.accel(sjoint, s0)
        w2 = g.w * g.w
        aLg = (az[0] - w2 * r[0] - g.al * r[1], az[1] - w2 * r[1] + g.al * r[0])
        rhs = V.sub(V.sub(V.add(V.add(aM, V.scale(ddli / li - wi * wi, ri)), V.scale(2.0 * ei * wi, V.perp(ri))), aLg),
                    V.scale(2.0 * g.w * sd, V.perp(u)))
        sdd, ai, _ = _solve2(c1, c2, rhs)
        aL = V.add(V.add(aM, V.add(V.scale(ddli / li - wi * wi, ri), V.scale(ai, V.perp(ri)))),
                   V.scale(2.0 * ei * wi, V.perp(ri)))
    pos = {m: (M, vM, aM), l: (Lp, vL, aL)}
    partner = slider(g, s0, u0, sjoint, s, sd, sdd, order)
    out, rod = _finish(pos, partner, wi, ai, ok, gap, cond, cyl, stroke, True, order)
    out.slides = ((s, sd, sdd),) + out.slides
    return out, rod


def _finish(pos: dict, partner: BState, w, al, ok, gap, cond, cyl: dict, stroke: tuple, v_is_i: bool,
            order: int) -> tuple[BOut, BState]:
    M, vM, aM = pos[cyl["m"]]
    H, vH, aH = pos[cyl["h"]]
    L, Ld, Ldd = stroke
    barrel, rod, slide, ok_c, gap_c = _states(M, H, vM, vH, aM, aH, w, al, L, Ld, Ldd, cyl, order)
    si, sj = (barrel, partner) if v_is_i else (partner, barrel)
    out = BOut(si, sj, ok & ok_c, np.minimum(gap, gap_c), cond, None, (slide,))
    return out, rod


__all__ = ["cyl_rrp", "cyl_rrr"]
