"""The floor of the batch kinematics: the four-bar and the six-bar of the examples written by hand
as one fused numba loop over designs × samples (what :mod:`bench_studies` compares the engine to).

Each loop takes per design only what the mechanism needs — pivots, lengths, the assembly mode,
the coupler point's offset — and per sample the crank's cos/sin and speed, and writes the traced
point's position, velocity and acceleration (mm, mm/s, mm/s²) and the validity, NaN where the
design cannot be assembled: the least a fused compiled loop of this mechanism can do.
"""
from __future__ import annotations

import math

import numba
import numpy as np

NAN = math.nan


def fourbar_constants(lk, crank: np.ndarray, coupler: np.ndarray) -> np.ndarray:
    """Per design (D, 12): Ax, Ay, Dx, Dy, the crank arm (x, y) (drawn direction, length
    ``crank``), li = B–C (``coupler``), lj = D–C, mode, the coupler point E in the frame (B, B→C)
    (u, v), and the drawn |B–C|."""
    j = {x.id: complex(*x.at) for x in lk.joints}
    A, B, C, D, E = j["A"], j["B"], j["C"], j["D"], j["E"]
    n = crank.size
    out = np.empty((n, 12))
    u = (B - A) / abs(B - A)
    out[:, 0], out[:, 1], out[:, 2], out[:, 3] = A.real, A.imag, D.real, D.imag
    out[:, 4], out[:, 5] = crank * u.real, crank * u.imag
    # E keeps its distances to B and C when B–C changes (as the dimension table's edit does)
    be, ce = abs(E - B), abs(E - C)
    x = (be * be - ce * ce + coupler * coupler) / (2.0 * coupler)
    y = np.sqrt(be * be - x * x) * (1.0 if ((C - B).conjugate() * (E - B)).imag >= 0 else -1.0)
    e_loc = x + 1j * y
    out[:, 6] = coupler
    out[:, 7] = abs(C - D)
    out[:, 8] = 1.0 if ((D - B).conjugate() * (C - B)).imag >= 0 else -1.0
    out[:, 9], out[:, 10] = e_loc.real, e_loc.imag
    out[:, 11] = abs(C - B)
    return out


@numba.njit(cache=True, nogil=True)
def fourbar(K, cq, sq, w, pos, vel, acc, valid):
    """Four-bar A–B–C–D with the coupler point E, order 2 (constant crank speed w)."""
    for d in range(K.shape[0]):
        ax, ay, dxp, dyp, abx, aby, li, lj, mode, eu, ev, l0 = (K[d, 0], K[d, 1], K[d, 2], K[d, 3], K[d, 4],
                                                                K[d, 5], K[d, 6], K[d, 7], K[d, 8], K[d, 9],
                                                                K[d, 10], K[d, 11])
        for k in range(cq.shape[0]):
            c, s = cq[k], sq[k]
            armx, army = c * abx - s * aby, s * abx + c * aby
            bx, by = ax + armx, ay + army
            vbx, vby = -w * army, w * armx
            gbx, gby = -w * w * armx, -w * w * army
            dx, dy = dxp - bx, dyp - by
            D2 = dx * dx + dy * dy
            D = math.sqrt(D2)
            a = (li * li - lj * lj + D2) / (2.0 * D)
            h2 = li * li - a * a
            if not (h2 >= 0.0):
                valid[d, k] = False
                for o in (pos, vel, acc):
                    o[d, k, 0] = NAN
                    o[d, k, 1] = NAN
                continue
            h = mode * math.sqrt(h2)
            rix, riy = (a * dx - h * dy) / D, (a * dy + h * dx) / D
            rjx, rjy = bx + rix - dxp, by + riy - dyp
            det = riy * rjx - rix * rjy
            wi = (vbx * rjx + vby * rjy) / det
            qx, qy = gbx - wi * wi * rix, gby - wi * wi * riy
            wj = (rix * vbx + riy * vby) / det
            qx, qy = qx + wj * wj * rjx, qy + wj * wj * rjy
            ali = (qx * rjx + qy * rjy) / det
            cx, cy = rix / li, riy / li
            ex, ey = cx * eu - cy * ev, cy * eu + cx * ev
            pos[d, k, 0], pos[d, k, 1] = bx + ex, by + ey
            vel[d, k, 0], vel[d, k, 1] = vbx - wi * ey, vby + wi * ex
            acc[d, k, 0] = gbx - wi * wi * ex - ali * ey
            acc[d, k, 1] = gby - wi * wi * ey + ali * ex
            valid[d, k] = True


def sixbar_constants(lk, crank: np.ndarray, coupler: np.ndarray) -> np.ndarray:
    """Per design (D, 16): the four-bar's (B, C, D; no coupler point) and the slider dyad B–E on
    the rocker's guide through Q: rod length, guide point and direction in the rocker's frame
    (D, D→C), mode."""
    j = {x.id: complex(*x.at) for x in lk.joints}
    A, B, C, D, E, Q = j["A"], j["B"], j["C"], j["D"], j["E"], j["Q"]
    ax = next(x.axis_deg for x in lk.joints if x.id == "Q")
    u0 = complex(math.cos(math.radians(ax)), math.sin(math.radians(ax)))
    n = crank.size
    out = np.empty((n, 16))
    u = (B - A) / abs(B - A)
    out[:, 0], out[:, 1], out[:, 2], out[:, 3] = A.real, A.imag, D.real, D.imag
    out[:, 4], out[:, 5] = crank * u.real, crank * u.imag
    out[:, 6], out[:, 7] = coupler, abs(C - D)
    out[:, 8] = 1.0 if ((D - B).conjugate() * (C - B)).imag >= 0 else -1.0
    rf = (C - D) / abs(C - D)                        # the rocker's frame
    q_loc, u_loc = (Q - D) / rf, u0 / rf
    out[:, 9], out[:, 10], out[:, 11], out[:, 12] = q_loc.real, q_loc.imag, u_loc.real, u_loc.imag
    out[:, 13] = abs(E - B)
    out[:, 14] = 1.0 if (u0.conjugate() * (E - B)).real >= 0 else -1.0
    out[:, 15] = abs(C - D)
    return out


@numba.njit(cache=True, nogil=True)
def sixbar(K, cq, sq, w, pos, vel, acc, valid):
    """The six-bar: the four-bar A–B–C–D, then the rod B–E whose block slides on the rocker's
    guide; E's position, velocity and acceleration, order 2."""
    for d in range(K.shape[0]):
        ax, ay, dxp, dyp, abx, aby, li, lj, mode = K[d, 0], K[d, 1], K[d, 2], K[d, 3], K[d, 4], K[d, 5], K[d, 6], \
            K[d, 7], K[d, 8]
        qu, qv, uu, uv, lr, mode2, l0 = K[d, 9], K[d, 10], K[d, 11], K[d, 12], K[d, 13], K[d, 14], K[d, 15]
        for k in range(cq.shape[0]):
            c, s = cq[k], sq[k]
            armx, army = c * abx - s * aby, s * abx + c * aby
            bx, by = ax + armx, ay + army
            vbx, vby = -w * army, w * armx
            gbx, gby = -w * w * armx, -w * w * army
            dx, dy = dxp - bx, dyp - by
            D2 = dx * dx + dy * dy
            D = math.sqrt(D2)
            a = (li * li - lj * lj + D2) / (2.0 * D)
            h2 = li * li - a * a
            ok = h2 >= 0.0
            h = mode * math.sqrt(max(h2, 0.0))
            rix, riy = (a * dx - h * dy) / D, (a * dy + h * dx) / D
            rjx, rjy = bx + rix - dxp, by + riy - dyp
            det = riy * rjx - rix * rjy
            wi = (vbx * rjx + vby * rjy) / det
            wj = (rix * vbx + riy * vby) / det
            qx = gbx - wi * wi * rix + wj * wj * rjx
            qy = gby - wi * wi * riy + wj * wj * rjy
            alj = (rix * qx + riy * qy) / det
            # the rocker turns at wj, alj; its guide: point Q and direction u
            cr, sr = rjx / l0, rjy / l0
            zx, zy = dxp + cr * qu - sr * qv, dyp + sr * qu + cr * qv
            ux, uy = cr * uu - sr * uv, sr * uu + cr * uv
            ex, ey = zx - bx, zy - by
            du, dn = ux * ex + uy * ey, ux * ey - uy * ex
            r2 = lr * lr - dn * dn
            ok = ok and r2 >= 0.0
            sl = mode2 * math.sqrt(max(r2, 0.0)) - du
            rx, ry = ex + ux * sl, ey + uy * sl              # the rod B→E
            px, py = bx + rx, by + ry
            # guide point under E: velocity and acceleration on the rocker
            gx, gy = px - dxp, py - dyp
            vgx, vgy = -wj * gy, wj * gx
            agx, agy = -wj * wj * gx - alj * gy, -wj * wj * gy + alj * gx
            udr = ux * rx + uy * ry
            wx, wy = vbx - vgx, vby - vgy
            sd = (wx * rx + wy * ry) / udr
            wr = (uy * wx - ux * wy) / udr
            cor = 2.0 * wj * sd
            q2x = gbx - wr * wr * rx - agx + uy * cor
            q2y = gby - wr * wr * ry - agy - ux * cor
            alr = (uy * q2x - ux * q2y) / udr
            if ok:
                pos[d, k, 0], pos[d, k, 1] = px, py
                vel[d, k, 0], vel[d, k, 1] = vbx - wr * ry, vby + wr * rx
                acc[d, k, 0] = gbx - wr * wr * rx - alr * ry
                acc[d, k, 1] = gby - wr * wr * ry + alr * rx
            else:
                for o in (pos, vel, acc):
                    o[d, k, 0] = NAN
                    o[d, k, 1] = NAN
            valid[d, k] = ok
