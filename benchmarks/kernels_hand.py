"""Hand-written numpy closed forms of the three benchmark mechanisms (the floor of
:mod:`bench_kernels`): real arithmetic on float (N,) arrays, one determinant per group, each joint
computed once, the results written into (N, 2) arrays like ``Solution.position`` returns.

Each ``make_*`` takes the example linkage and returns ``run(N, order) -> {joint: (P, V, A)}``
(V, A None below ``order``) for a constant-speed crank sampled like ``plan.sweep`` (sample k at
θ0 + sign(ω)·2πk/N). Mode signs and drawn offsets are read from the drawn pose, as the solver does.
Units: mm, s, rad.
"""
from __future__ import annotations

import math

import numpy as np

from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver.plan import compile_plan


def _xy(x, y, n: int) -> np.ndarray:
    out = np.empty((n, 2))
    out[:, 0] = x
    out[:, 1] = y
    return out


def _at(lk: Linkage) -> dict[str, complex]:
    return {j.id: complex(*j.at) for j in lk.joints}


def _axis(lk: Linkage, jid: str) -> complex:
    a = math.radians(lk.joint(jid).axis_deg or 0.0)
    return complex(math.cos(a), math.sin(a))


def _crank(w: float, n: int):
    """cos and sin of the offsets from the drawn crank angle, ω (rad/s)."""
    th = (math.copysign(2.0 * math.pi / n, w)) * np.arange(n)
    return np.cos(th), np.sin(th), w


def _rrr_pos(mx, my, hx, hy, li: float, lj: float, mode: float):
    """Inner joint L of an RRR dyad (|L − M| = li, |L − H| = lj), mode +1: L left of M→H."""
    dx, dy = hx - mx, hy - my
    d2 = dx * dx + dy * dy
    inv = 1.0 / np.sqrt(d2)
    a = (li * li - lj * lj + d2) * (0.5 * inv)
    h = mode * np.sqrt(li * li - a * a)
    ex, ey = dx * inv, dy * inv
    return mx + a * ex - h * ey, my + a * ey + h * ex


def make_fourbar(lk: Linkage):
    """A, D frame; crank A–B; coupler B–C–E; rocker D–C."""
    p = _at(lk)
    omega = compile_plan(lk).omega
    A, B0, C0, D, E0 = p["A"], p["B"], p["C"], p["D"], p["E"]
    li, lj = abs(C0 - B0), abs(C0 - D)
    mode = 1.0 if ((D - B0).conjugate() * (C0 - B0)).imag >= 0 else -1.0
    k = (E0 - B0) / (C0 - B0)
    kr, ki = k.real, k.imag
    b0x, b0y = (B0 - A).real, (B0 - A).imag

    def run(n: int, order: int):
        c, s, w = _crank(omega, n)
        rbx, rby = c * b0x - s * b0y, s * b0x + c * b0y
        bx, by = A.real + rbx, A.imag + rby
        cx, cy = _rrr_pos(bx, by, D.real, D.imag, li, lj, mode)
        rix, riy = cx - bx, cy - by
        rex, rey = kr * rix - ki * riy, kr * riy + ki * rix
        out = {"A": [np.full((n, 2), (A.real, A.imag))], "D": [np.full((n, 2), (D.real, D.imag))],
               "B": [_xy(bx, by, n)], "C": [_xy(cx, cy, n)], "E": [_xy(bx + rex, by + rey, n)]}
        if order >= 1:
            rjx, rjy = cx - D.real, cy - D.imag
            inv = 1.0 / (riy * rjx - rix * rjy)
            vbx, vby = -w * rby, w * rbx
            # ωi·J·ri − ωj·J·rj = −vB (columns c1 = J ri, c2 = −J rj)
            wi = (-vbx * -rjx + vby * rjy) * inv
            wj = (riy * vby + rix * vbx) * inv
            out["A"].append(np.zeros((n, 2)))
            out["D"].append(np.zeros((n, 2)))
            out["B"].append(_xy(vbx, vby, n))
            out["C"].append(_xy(vbx - wi * riy, vby + wi * rix, n))
            out["E"].append(_xy(vbx - wi * rey, vby + wi * rex, n))
        if order >= 2:
            w2 = w * w
            abx, aby = -w2 * rbx, -w2 * rby
            wi2, wj2 = wi * wi, wj * wj
            qx = -abx + wi2 * rix - wj2 * rjx
            qy = -aby + wi2 * riy - wj2 * rjy
            ai = (qx * -rjx - qy * rjy) * inv
            for j in ("A", "D"):
                out[j].append(np.zeros((n, 2)))
            out["B"].append(_xy(abx, aby, n))
            out["C"].append(_xy(abx - ai * riy - wi2 * rix, aby + ai * rix - wi2 * riy, n))
            out["E"].append(_xy(abx - ai * rey - wi2 * rex, aby + ai * rex - wi2 * rey, n))
        return {j: tuple(v) + (None,) * (3 - len(v)) for j, v in out.items()}

    return run


def make_slider_crank(lk: Linkage):
    """A frame pivot; crank A–B; rod B–C; slider C on the fixed guide through S (axis u)."""
    p = _at(lk)
    omega = compile_plan(lk).omega
    A, B0, C0, S0 = p["A"], p["B"], p["C"], p["S"]
    u = _axis(lk, "S")
    ux, uy = u.real, u.imag
    li = abs(C0 - B0)
    off = C0 - S0           # slider pin from the guide point (0 here), constant: the guide is fixed
    mode = 1.0 if (u.conjugate() * (C0 - B0)).real >= 0 else -1.0
    b0x, b0y = (B0 - A).real, (B0 - A).imag
    zx, zy = S0.real + off.real, S0.imag + off.imag

    def run(n: int, order: int):
        c, s, w = _crank(omega, n)
        rbx, rby = c * b0x - s * b0y, s * b0x + c * b0y
        bx, by = A.real + rbx, A.imag + rby
        dx, dy = zx - bx, zy - by
        du, dn = ux * dx + uy * dy, ux * dy - uy * dx
        sl = -du + mode * np.sqrt((li - dn) * (li + dn))
        cx, cy = zx + sl * ux, zy + sl * uy
        P = _xy(cx, cy, n)
        out = {"A": [np.full((n, 2), (A.real, A.imag))], "B": [_xy(bx, by, n)], "C": [P], "S": [P.copy()]}
        if order >= 1:
            rix, riy = cx - bx, cy - by
            inv = 1.0 / (ux * rix + uy * riy)      # det of the columns u, −J·ri
            vbx, vby = -w * rby, w * rbx
            sd = (vbx * rix + vby * riy) * inv
            V = _xy(sd * ux, sd * uy, n)
            out["A"].append(np.zeros((n, 2)))
            out["B"].append(_xy(vbx, vby, n))
            out["C"].append(V)
            out["S"].append(V.copy())
        if order >= 2:
            wi = (uy * vbx - ux * vby) * inv
            w2 = w * w
            abx, aby = -w2 * rbx, -w2 * rby
            qx, qy = abx - wi * wi * rix, aby - wi * wi * riy
            sdd = (qx * rix + qy * riy) * inv
            Acc = _xy(sdd * ux, sdd * uy, n)
            out["A"].append(np.zeros((n, 2)))
            out["B"].append(_xy(abx, aby, n))
            out["C"].append(Acc)
            out["S"].append(Acc.copy())
        return {j: tuple(v) + (None,) * (3 - len(v)) for j, v in out.items()}

    return run


def make_sixbar(lk: Linkage):
    """The four-bar A–B–C–D, plus rod2 B–E and a block E on the rocker's guide through Q."""
    p = _at(lk)
    omega = compile_plan(lk).omega
    A, B0, C0, D, E0, Q0 = p["A"], p["B"], p["C"], p["D"], p["E"], p["Q"]
    li, lj = abs(C0 - B0), abs(C0 - D)
    mode = 1.0 if ((D - B0).conjugate() * (C0 - B0)).imag >= 0 else -1.0
    u0 = _axis(lk, "Q")
    l2 = abs(E0 - B0)
    mode2 = 1.0 if (u0.conjugate() * (E0 - B0)).real >= 0 else -1.0
    b0x, b0y = (B0 - A).real, (B0 - A).imag
    c0 = C0 - D                # rocker's drawn vector D→C
    g0 = (Q0 - D) / c0         # guide point and direction in the rocker's frame (D→C)
    gu = u0 / c0
    e0 = (E0 - Q0) / c0        # slider pin from the guide point (0 here)

    def run(n: int, order: int):
        c, s, w = _crank(omega, n)
        rbx, rby = c * b0x - s * b0y, s * b0x + c * b0y
        bx, by = A.real + rbx, A.imag + rby
        cx, cy = _rrr_pos(bx, by, D.real, D.imag, li, lj, mode)
        rjx, rjy = cx - D.real, cy - D.imag                     # rocker D→C (turns the guide)
        ux, uy = gu.real * rjx - gu.imag * rjy, gu.real * rjy + gu.imag * rjx
        zrx = (g0.real + e0.real) * rjx - (g0.imag + e0.imag) * rjy
        zry = (g0.real + e0.real) * rjy + (g0.imag + e0.imag) * rjx
        dx, dy = D.real + zrx - bx, D.imag + zry - by
        du, dn = ux * dx + uy * dy, ux * dy - uy * dx
        sl = -du + mode2 * np.sqrt((l2 - dn) * (l2 + dn))
        ex, ey = D.real + zrx + sl * ux, D.imag + zry + sl * uy
        PE = _xy(ex, ey, n)
        out = {"A": [np.full((n, 2), (A.real, A.imag))], "D": [np.full((n, 2), (D.real, D.imag))],
               "B": [_xy(bx, by, n)], "C": [_xy(cx, cy, n)], "E": [PE], "Q": [PE.copy()]}
        if order >= 1:
            rix, riy = cx - bx, cy - by
            inv = 1.0 / (riy * rjx - rix * rjy)
            vbx, vby = -w * rby, w * rbx
            wi = (vbx * rjx + vby * rjy) * inv
            wj = (riy * vby + rix * vbx) * inv
            # block: E = B + r2 slides along u turning at wj: ṡ·u − w2·J·r2 = vB − vE_on_rocker
            r2x, r2y = ex - bx, ey - by
            pex, pey = ex - D.real, ey - D.imag
            inv2 = 1.0 / (ux * r2x + uy * r2y)
            qx, qy = vbx + wj * pey, vby - wj * pex
            sd = (qx * r2x + qy * r2y) * inv2
            w2 = (uy * qx - ux * qy) * inv2
            VE = _xy(vbx - w2 * r2y, vby + w2 * r2x, n)
            out["A"].append(np.zeros((n, 2)))
            out["D"].append(np.zeros((n, 2)))
            out["B"].append(_xy(vbx, vby, n))
            out["C"].append(_xy(-wj * rjy, wj * rjx, n))
            out["E"].append(VE)
            out["Q"].append(VE.copy())
        if order >= 2:
            ww = w * w
            abx, aby = -ww * rbx, -ww * rby
            wi2, wj2 = wi * wi, wj * wj
            hx = -abx + wi2 * rix - wj2 * rjx
            hy = -aby + wi2 * riy - wj2 * rjy
            aj = (-riy * hy - rix * hx) * inv
            # rocker point under E: a = aj·J·pe − wj²·pe; Coriolis 2·wj·ṡ·J·u
            agx = -aj * pey - wj2 * pex - 2.0 * wj * sd * uy
            agy = aj * pex - wj2 * pey + 2.0 * wj * sd * ux
            qx2 = abx - w2 * w2 * r2x - agx
            qy2 = aby - w2 * w2 * r2y - agy
            a2 = (uy * qx2 - ux * qy2) * inv2
            AE = _xy(abx - a2 * r2y - w2 * w2 * r2x, aby + a2 * r2x - w2 * w2 * r2y, n)
            out["A"].append(np.zeros((n, 2)))
            out["D"].append(np.zeros((n, 2)))
            out["B"].append(_xy(abx, aby, n))
            out["C"].append(_xy(-aj * rjy - wj2 * rjx, aj * rjx - wj2 * rjy, n))
            out["E"].append(AE)
            out["Q"].append(AE.copy())
        return {j: tuple(v) + (None,) * (3 - len(v)) for j, v in out.items()}

    return run
