"""The locking disc's relief: V(φ), the farthest distance from the relief centre (A, 0) (crank
frame, mm) of any point of the disc (radius R_L) that the (offset) wheel outline covers at crank
angle φ, and its maximum over the engagement |φ| ≤ φ0 (see geometry.py's docstring).

V(φ) is closed form per angle: the farthest point among (a) outline vertices inside the disc,
(b) the farthest points of arcs inside the disc and (c) the crossings of lines and arcs with the
disc circle. The maximum: a grid of RELIEF_GRID angles, then RELIEF_ZOOM[0] zoom levels of
RELIEF_ZOOM[1] points around each of the 3 best local maxima, one after another in the first
version; here every outline and candidate at once.

Speed (issue 14). Only segments that can come within R_L of the crank centre are evaluated, and
only over the angles where they can: in the wheel frame the crank centre runs along the arc of
radius A about the wheel centre at angles π + θ(φ), θ increasing with φ (|θ| ≤ π/z); a segment,
bounded by a circle, is kept for a window of crank angles if that circle comes within R_L (plus a
margin) of the window's arc. The grid is cut into GRID_CHUNKS windows, the zoom has one window per
candidate (the points of all its levels stay within 1.2 half-widths of its grid point), and each
call evaluates all windows of all outlines at once, each with its own segments (padded with inert
ones far away). A left-out segment yields no candidate, so V is the same, value for value.
"""
from __future__ import annotations

import math

import numpy as np

from ...model.geneva import WheelDimensions
from ..contour import Contour, Segments
from .kinematics import wheel_angle

#: crank-angle grid for the relief search, and zoom levels/points around the best maxima
RELIEF_GRID = 601
RELIEF_ZOOM = (8, 41)
#: a point counts as inside the disc only if it is this far inside (relative to A): touching is allowed
INSIDE_TOL = 1e-12
#: windows the grid is cut into (each with the segments that can reach the disc over it)
GRID_CHUNKS = 8
#: a segment is kept for a window of crank angles if its bounding circle comes within
#: R_L + REACH_MARGIN·A of the crank centre's positions, the window's θ widened by REACH_MARGIN_ANGLE
REACH_MARGIN = 1e-3
REACH_MARGIN_ANGLE = 1e-3


def bounding_circles(sg: Segments) -> tuple[np.ndarray, np.ndarray]:
    """Centres (K, 2) and radii (K,) mm of circles containing each segment: lines and arcs of at
    most a half turn, the circle on their chord (Thales); longer arcs, their own circle."""
    mid = 0.5 * (sg.p0 + sg.p1)
    half_chord = 0.5 * np.hypot(*(sg.p1 - sg.p0).T)
    big = sg.is_arc & (np.abs(sg.theta) > math.pi)
    bc = np.where(big[:, None], np.nan_to_num(sg.centre), mid)
    br = np.where(big, np.where(sg.is_arc, sg.radius, 0.0), half_chord)
    return bc, br


def reaching(bc: np.ndarray, br: np.ndarray, d: WheelDimensions, phi_lo: np.ndarray,
             phi_hi: np.ndarray) -> np.ndarray:
    """Which segments (bounding circles ``bc`` (K, 2), ``br`` (K,), wheel frame, mm) may come within
    R_L of the crank centre for some crank angle in [phi_lo, phi_hi] (rad, each (W,), inside
    [−φ0, φ0]): bool (W, K), conservative (margins REACH_MARGIN, REACH_MARGIN_ANGLE)."""
    a = d.center_distance
    lo = wheel_angle(np.asarray(phi_lo, float), d.lam)[:, None] - REACH_MARGIN_ANGLE
    hi = wheel_angle(np.asarray(phi_hi, float), d.lam)[:, None] + REACH_MARGIN_ANGLE
    # the crank centre is A·(−cos θ, −sin θ): ψ is a point's angle seen that way
    psi = np.arctan2(-bc[:, 1], -bc[:, 0])[None, :]
    radial = np.abs(np.hypot(bc[:, 0], bc[:, 1]) - a)[None, :]
    ends = [np.hypot(bc[None, :, 0] + a * np.cos(e), bc[None, :, 1] + a * np.sin(e)) for e in (lo, hi)]
    dist = np.where((psi >= lo) & (psi <= hi), radial, np.minimum(*ends))
    return dist - br[None, :] <= d.lock_disc_radius + REACH_MARGIN * a


class _Outline:
    """One outline's segments, their bounding circles and per-arc sweep data."""

    def __init__(self, outline: Contour, d: WheelDimensions) -> None:
        sg = outline.segments()
        self.sg = sg
        self.bounds = bounding_circles(sg)
        self.sense = np.where(sg.theta > 0, 1.0, -1.0)
        self.sweep = np.abs(sg.theta) + 1e-12


class _Packed:
    """Groups of (outline, segment indices) as padded arrays (G, K, ...): vertices, lines, arcs.
    Padding: a vertex, a line and a tiny arc 3·A beyond the wheel centre on the far side from the
    crank (never within the disc)."""

    def __init__(self, groups: list[tuple[_Outline, np.ndarray]], d: WheelDimensions) -> None:
        far = 3.0 * d.center_distance
        self.n = len(groups)
        ln_sets = [idx[~o.sg.is_arc[idx]] for o, idx in groups]
        arc_sets = [idx[o.sg.is_arc[idx]] for o, idx in groups]
        kv = max((len(idx) for _, idx in groups), default=0)
        kl = max((len(s) for s in ln_sets), default=0)
        ka = max((len(s) for s in arc_sets), default=0)
        self.p0 = np.full((self.n, kv, 2), [far, 0.0])
        self.l0 = np.full((self.n, kl, 2), [far, 0.0])
        self.l1 = np.full((self.n, kl, 2), [far, d.center_distance])
        self.centre = np.full((self.n, ka, 2), [far, 0.0])
        self.rad = np.full((self.n, 1, ka), 0.1 * d.center_distance)
        self.a0 = np.zeros((self.n, 1, ka))
        self.sense = np.ones((self.n, 1, ka))
        self.sweep = np.full((self.n, 1, ka), 1e-12)
        for g, ((o, idx), li, ai) in enumerate(zip(groups, ln_sets, arc_sets)):
            self.p0[g, :len(idx)] = o.sg.p0[idx]
            self.l0[g, :len(li)] = o.sg.p0[li]
            self.l1[g, :len(li)] = o.sg.p1[li]
            self.centre[g, :len(ai)] = o.sg.centre[ai]
            self.rad[g, 0, :len(ai)] = o.sg.radius[ai]
            self.a0[g, 0, :len(ai)] = o.sg.a0[ai]
            self.sense[g, 0, :len(ai)] = o.sense[ai]
            self.sweep[g, 0, :len(ai)] = o.sweep[ai]


def _values(phi: np.ndarray, pk: _Packed, d: WheelDimensions) -> np.ndarray:
    """V at crank angles ``phi`` (rad, (G, N), row g for group g of ``pk``): (G, N) mm, −inf where
    the group's segments do not reach the disc."""
    a = d.center_distance
    tol = INSIDE_TOL * a
    # the disc shrunk by ``tol``: an outline that only touches the disc (c_l reached exactly, as in
    # the dwell) yields no candidate, one that enters it by more than ``tol`` does
    rl = d.lock_disc_radius - tol
    rot = -phi - wheel_angle(phi, d.lam)  # wheel frame -> crank frame
    cr, sr = np.cos(rot)[..., None], np.sin(rot)[..., None]
    tx, ty = (a * np.cos(phi))[..., None], (-a * np.sin(phi))[..., None]

    def move(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # (G, K, 2) -> 2 × (G, N, K)
        px, py = p[:, None, :, 0], p[:, None, :, 1]
        return cr * px - sr * py + tx, sr * px + cr * py + ty

    best = np.full(phi.shape, -np.inf)
    if pk.p0.shape[1]:  # (a) vertices inside the disc
        x0, y0 = move(pk.p0)
        best = np.where(np.hypot(x0, y0) <= rl, np.hypot(x0 - a, y0), -np.inf).max(axis=-1)
    if pk.l0.shape[1]:  # lines: crossings with the disc circle
        x0, y0 = move(pk.l0)
        x1, y1 = move(pk.l1)
        dx, dy = x1 - x0, y1 - y0
        qa = dx * dx + dy * dy
        qb = 2 * (x0 * dx + y0 * dy)
        qc = np.hypot(x0, y0) ** 2 - rl * rl
        disc = qb * qb - 4 * qa * qc
        # transversal crossings only: the line passes at least ``tol`` inside the disc circle
        gap = rl - np.abs(x0 * dy - y0 * dx) / np.sqrt(qa)
        root = np.sqrt(np.where((disc >= 0) & (gap > tol), disc, np.nan))
        for sgn in (-1.0, 1.0):
            t = (-qb + sgn * root) / (2 * qa)
            xs, ys = x0 + t * dx, y0 + t * dy
            best = np.maximum(best, np.where((t >= 0) & (t <= 1), np.hypot(xs - a, ys), -np.inf).max(axis=-1))
    if pk.centre.shape[1]:
        cx, cy = move(pk.centre)
        rad = pk.rad
        a0 = pk.a0 + rot[..., None]

        def on_arc(ang: np.ndarray) -> np.ndarray:  # the angle lies on the arc's sweep
            return np.mod(pk.sense * (ang - a0), 2 * math.pi) <= pk.sweep

        # (b) the farthest point of each arc's circle from (A, 0), if on the arc and inside the disc
        dq = np.hypot(cx - a, cy)
        ang = np.arctan2(cy, cx - a)
        fx, fy = cx + rad * np.cos(ang), cy + rad * np.sin(ang)
        ok = on_arc(ang) & (np.hypot(fx, fy) <= rl)
        best = np.maximum(best, np.where(ok, dq + rad, -np.inf).max(axis=-1))
        # (c) crossings of each arc with the disc circle
        dc = np.hypot(cx, cy)
        # transversal crossings only: the circles overlap by more than ``tol`` both ways
        good = (dc - np.abs(rad - rl) > tol) & (rad + rl - dc > tol)
        safe = np.where(good, dc, 1.0)
        along = (rl * rl - rad * rad + dc * dc) / (2 * safe)
        h2 = rl * rl - along * along
        h = np.sqrt(np.where(good & (h2 >= 0), h2, np.nan))
        ux, uy = cx / safe, cy / safe
        for sgn in (-1.0, 1.0):
            xs, ys = along * ux - sgn * h * uy, along * uy + sgn * h * ux
            ok = on_arc(np.arctan2(ys - cy, xs - cx))
            best = np.maximum(best, np.where(ok, np.hypot(xs - a, ys), -np.inf).max(axis=-1))
    return best


def _windows(outlines: list[_Outline], d: WheelDimensions, lo: np.ndarray, hi: np.ndarray) -> _Packed:
    """One group per (outline, window [lo_w, hi_w]), outline-major, with the segments that reach."""
    groups = []
    for o in outlines:
        keep = reaching(*o.bounds, d, lo, hi)
        groups.extend((o, np.nonzero(row)[0]) for row in keep)
    return _Packed(groups, d)


def relief_values(phi: np.ndarray, offset: Contour, d: WheelDimensions) -> np.ndarray:
    """V(φ): farthest distance (mm) from the relief centre (A, 0) of any point of the disc
    (radius R_L) covered by the outline ``offset`` at crank angles ``phi`` (rad, shape (N,), within
    [−φ0, φ0]); −inf where the outline does not reach the disc."""
    phi = np.asarray(phi, float)
    pk = _windows([_Outline(offset, d)], d, np.array([-d.phi0]), np.array([d.phi0]))
    return _values(phi[None, :], pk, d)[0]


def maximise(outlines: list[Contour], d: WheelDimensions) -> list[tuple[float, float]]:
    """(max V, argmax φ) over [−φ0, φ0] for each outline ((−inf, nan) if it never reaches the
    disc): the grid, then the zoom around the 3 best local maxima of each (the first best wins)."""
    lo, hi = -d.phi0, d.phi0
    outs = [_Outline(c, d) for c in outlines]
    x = np.linspace(lo, hi, RELIEF_GRID)
    # the grid in GRID_CHUNKS windows (rows padded with their last angle)
    bounds = np.linspace(0, RELIEF_GRID, GRID_CHUNKS + 1).astype(int)
    width = int(np.diff(bounds).max())
    take = np.minimum(bounds[:-1, None] + np.arange(width)[None, :], bounds[1:, None] - 1)  # (chunks, width)
    pk = _windows(outs, d, x[bounds[:-1]], x[bounds[1:] - 1])
    rows = _values(np.tile(x[take], (len(outs), 1)), pk, d)
    step = (hi - lo) / (RELIEF_GRID - 1)
    cands = []
    for o in range(len(outs)):
        v = np.empty(RELIEF_GRID)
        v[take] = rows[o * GRID_CHUNKS:(o + 1) * GRID_CHUNKS]
        if not np.isfinite(v).any():
            cands.append(np.zeros(0, int))
            continue
        vv = np.where(np.isfinite(v), v, -np.inf)
        peak = np.r_[True, vv[1:] >= vv[:-1]] & np.r_[vv[:-1] >= vv[1:], True]
        k = np.nonzero(peak & np.isfinite(vv))[0]
        cands.append(k[np.argsort(vv[k])[::-1][:3]])
    owner = np.concatenate([np.full(len(k), o) for o, k in enumerate(cands)])
    if owner.size == 0:
        return [(-math.inf, math.nan)] * len(outs)
    xc, half = x[np.concatenate(cands)], 2 * step
    # every zoom point stays within half·(1 + 0.1 + 0.01 + …) of its grid point
    groups = []
    for o, out in enumerate(outs):
        mine = xc[owner == o]
        keep = reaching(*out.bounds, d, np.maximum(mine - 1.2 * half, lo), np.minimum(mine + 1.2 * half, hi))
        groups.extend((out, np.nonzero(row)[0]) for row in keep)
    pk = _Packed(groups, d)
    g = np.arange(owner.size)
    for _ in range(RELIEF_ZOOM[0]):
        xs = np.clip(np.linspace(xc - half, xc + half, RELIEF_ZOOM[1], axis=1), lo, hi)  # (groups, points)
        vs = _values(xs, pk, d)
        j = np.argmax(vs, axis=1)
        xc, half = xs[g, j], half * 4.0 / (RELIEF_ZOOM[1] - 1)
    top = vs[g, j]
    result = []
    for o in range(len(outs)):
        mine = np.nonzero(owner == o)[0]
        if mine.size == 0:
            result.append((-math.inf, math.nan))
            continue
        k = mine[int(np.argmax(top[mine]))]
        result.append((float(top[k]), float(xc[k])) if top[k] > -math.inf else (-math.inf, math.nan))
    return result
