"""The locking disc's relief search as it was before the speed-up (commit 6935a9e), kept verbatim
as the reference the faster search must reproduce: every wheel segment evaluated at every crank
angle, a 601-point grid, then 8 zoom levels of 41 points around each of the 3 best maxima, one
candidate after another. Used by tests/core/test_geneva_relief.py and benchmarks/bench_geneva.py."""
from __future__ import annotations

import math

import numpy as np

from mechsketch.core.analyses.contour import Contour
from mechsketch.core.analyses.geneva.geometry import INSIDE_TOL, RELIEF_GRID, RELIEF_ROUND, RELIEF_ZOOM
from mechsketch.core.analyses.geneva.geometry import Relief, wheel_outline
from mechsketch.core.analyses.geneva.kinematics import wheel_angle
from mechsketch.core.model.geneva import WheelDimensions


def _in_sweep(ang: np.ndarray, a0: np.ndarray, theta: np.ndarray) -> np.ndarray:
    rel = np.where(theta > 0, np.mod(ang - a0, 2 * math.pi), np.mod(a0 - ang, 2 * math.pi))
    return rel <= np.abs(theta) + 1e-12


def relief_values_old(phi: np.ndarray, offset: Contour, d: WheelDimensions) -> np.ndarray:
    """V(φ) over every segment of ``offset`` (mm, shape of ``phi``; −inf where nothing reaches)."""
    a = d.center_distance
    tol = INSIDE_TOL * a
    rl = d.lock_disc_radius - tol
    phi = np.asarray(phi, float)
    rot = -phi - wheel_angle(phi, d.lam)
    cr, sr = np.cos(rot)[:, None], np.sin(rot)[:, None]
    tx, ty = (a * np.cos(phi))[:, None], (-a * np.sin(phi))[:, None]
    sg = offset.segments()

    def move(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return cr * p[:, 0] - sr * p[:, 1] + tx, sr * p[:, 0] + cr * p[:, 1] + ty

    best = np.full(phi.shape, -np.inf)
    x0, y0 = move(sg.p0)
    r0 = np.hypot(x0, y0)
    val = np.where(r0 <= rl, np.hypot(x0 - a, y0), -np.inf)
    best = np.maximum(best, val.max(axis=1))
    ln = ~sg.is_arc
    if ln.any():
        x1, y1 = move(sg.p1[ln])
        dx, dy = x1 - x0[:, ln], y1 - y0[:, ln]
        qa = dx * dx + dy * dy
        qb = 2 * (x0[:, ln] * dx + y0[:, ln] * dy)
        qc = r0[:, ln] ** 2 - rl * rl
        disc = qb * qb - 4 * qa * qc
        gap = rl - np.abs(x0[:, ln] * dy - y0[:, ln] * dx) / np.sqrt(qa)
        root = np.sqrt(np.where((disc >= 0) & (gap > tol), disc, np.nan))
        for sgn in (-1.0, 1.0):
            t = (-qb + sgn * root) / (2 * qa)
            ok = (t >= 0) & (t <= 1)
            xs, ys = x0[:, ln] + t * dx, y0[:, ln] + t * dy
            best = np.maximum(best, np.where(ok, np.hypot(xs - a, ys), -np.inf).max(axis=1))
    arc = sg.is_arc
    if arc.any():
        cx, cy = move(sg.centre[arc])
        rad = sg.radius[arc][None, :]
        a0 = sg.a0[arc][None, :] + rot[:, None]
        th = np.broadcast_to(sg.theta[arc][None, :], cx.shape)
        dq = np.hypot(cx - a, cy)
        ang = np.arctan2(cy, cx - a)
        fx, fy = cx + rad * np.cos(ang), cy + rad * np.sin(ang)
        ok = _in_sweep(ang, a0, th) & (np.hypot(fx, fy) <= rl)
        best = np.maximum(best, np.where(ok, dq + rad, -np.inf).max(axis=1))
        dc = np.hypot(cx, cy)
        good = (dc - np.abs(rad - rl) > tol) & (rad + rl - dc > tol)
        safe = np.where(good, dc, 1.0)
        along = (rl * rl - rad * rad + dc * dc) / (2 * safe)
        h2 = rl * rl - along * along
        h = np.sqrt(np.where(good & (h2 >= 0), h2, np.nan))
        ux, uy = cx / safe, cy / safe
        for sgn in (-1.0, 1.0):
            xs, ys = along * ux - sgn * h * uy, along * uy + sgn * h * ux
            ok = _in_sweep(np.arctan2(ys - cy, xs - cx), a0, th)
            best = np.maximum(best, np.where(ok, np.hypot(xs - a, ys), -np.inf).max(axis=1))
    return best


def maximise_old(fun, lo: float, hi: float) -> tuple[float, float]:
    """(max, argmax): grid, then zoom around the 3 best local maxima one after another."""
    x = np.linspace(lo, hi, RELIEF_GRID)
    v = fun(x)
    if not np.isfinite(v).any():
        return -math.inf, math.nan
    vv = np.where(np.isfinite(v), v, -np.inf)
    peak = np.r_[True, vv[1:] >= vv[:-1]] & np.r_[vv[:-1] >= vv[1:], True]
    cands = np.nonzero(peak & np.isfinite(vv))[0]
    cands = cands[np.argsort(vv[cands])[::-1][:3]]
    best_v, best_x = -math.inf, math.nan
    step = (hi - lo) / (RELIEF_GRID - 1)
    for k in cands:
        xc, half = x[k], 2 * step
        for _ in range(RELIEF_ZOOM[0]):
            xs = np.clip(np.linspace(xc - half, xc + half, RELIEF_ZOOM[1]), lo, hi)
            vs = fun(xs)
            j = int(np.argmax(vs))
            xc, half = xs[j], half * 4.0 / (RELIEF_ZOOM[1] - 1)
        if vs[j] > best_v:
            best_v, best_x = float(vs[j]), float(xc)
    return best_v, best_x


def relief_old(d: WheelDimensions, clearance_lock: float) -> Relief:
    """The relief radii as the old search found them."""
    outline = wheel_outline(d)
    a, rl = d.center_distance, d.lock_disc_radius
    lim = math.sqrt(rl * rl + a * a - 2 * a * rl * math.cos(d.phi0))
    off = outline.offset(clearance_lock) if clearance_lock > 0 else outline
    v_c, x_c = maximise_old(lambda p: relief_values_old(p, off, d), -d.phi0, d.phi0)
    v_t, _ = maximise_old(lambda p: relief_values_old(p, outline, d), -d.phi0, d.phi0)
    exact = max(v_c, lim)
    return Relief(exact=exact, phi_exact=x_c if v_c >= lim else d.phi0, touch=v_t,
                  classical=d.outer_radius, limit_end=lim,
                  drawn=math.ceil(exact / RELIEF_ROUND - 1e-9) * RELIEF_ROUND)
