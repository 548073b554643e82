"""The paper's compass construction of the fixed centrode (pair D) and its corrected form.

Literal construction (Dvornikov & Maksimova, Fig. 2; notes section C, "the paper's construction
as an algorithm"): the arc of the lever circle covered by the stroke is divided into N equal parts
π_0…π_N, drawn with the lever in the start pose; F_k = G + ℓ (π_k − G)/|π_k − G| on the rocker's
circle KK; P_0 = π_0 and P_k = circle(P_{k−1}, |π_{k−1}π_k|) ∩ circle(F_k, |F_0 π_k|), the root
taken by continuity. The pose implied at step k maps f → F_k and π_k → P_k. Flaw C1: the rays G–π_k
go through the lever in its start pose, not where it actually is, so the instant centre is never
enforced and the slip levels off at a finite value instead of vanishing as N grows.

Corrected construction (notes, "Corrected compass construction"): at step k the pose (α_k, θ_k)
is found by Newton's method such that the lever point π_k lies on the *current* rocker line G–F_k
and |P_k − P_{k−1}| = |π_k − π_{k−1}|; it converges to the exact centrode as O(N⁻²).

Pair E for both: P0_k on the normal to the slider axis through P_k with the moved slider circle,
k53_k = −t2, S5 by the trapezoidal rule over θ_k (the paper's graphical integration), Q_k = P0_k − S5_k d_s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import GeometryError
from .geometry import LeverGeometry, lever_map, pair_e, slider_point

_EPS = float(np.finfo(float).eps)


@dataclass
class Construction:
    """Points of a construction, k = 0…N (mm, rad); ``u1`` are the lever-frame angles of π_k."""

    theta: np.ndarray
    alpha: np.ndarray
    F: np.ndarray
    P: np.ndarray
    u1: np.ndarray
    P0: np.ndarray
    u2: np.ndarray
    k53: np.ndarray
    S5: np.ndarray
    Q: np.ndarray


def _circle_meet(p0, r0, p1, r1):
    """Both intersections of circle(p0, r0) and circle(p1, r1) (floats), or None."""
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    d = math.hypot(dx, dy)
    if d == 0.0:
        return None
    a = (r0 * r0 - r1 * r1 + d * d) / (2.0 * d)
    h2 = r0 * r0 - a * a
    if h2 < 0.0:
        return None
    h = math.sqrt(h2)
    mx, my = p0[0] + a * dx / d, p0[1] + a * dy / d
    nx, ny = -dy / d, dx / d
    return (mx + h * nx, my + h * ny), (mx - h * nx, my - h * ny)


def _lever_points(geom: LeverGeometry, u: np.ndarray) -> np.ndarray:
    """π (lever frame) at angles u (N,) on the lever circle, (N, 2) mm."""
    return np.asarray(geom.c1) + geom.R1 * np.stack([np.cos(u), np.sin(u)], axis=-1)


def literal(geom: LeverGeometry, start: tuple[float, float], u_start: float, u_end: float, n: int
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The paper's construction with ``n`` intervals from the start pose ``start`` = (θ_s, α_s).

    ``u_start``, ``u_end``: lever-frame angles (rad) of the contact at the stroke's ends.
    Returns (θ_k, α_k, F_k, P_k, u_k), arrays over k = 0…n (rad, mm).
    """
    th_s, a_s = start
    u = np.linspace(u_start, u_end, n + 1)
    lev = _lever_points(geom, u)
    pi = lever_map(geom, np.full(n + 1, a_s), np.full(n + 1, th_s), lev)  # drawn in the start pose
    G = np.asarray(geom.G)
    F_s = np.array([geom.G[0] + geom.ell * math.cos(a_s), geom.G[1] + geom.ell * math.sin(a_s)])
    ray = pi - G
    F = G + geom.ell * ray / np.hypot(ray[:, 0], ray[:, 1])[:, None]
    P = np.empty_like(pi)
    P[0] = pi[0]
    for k in range(1, n + 1):
        r0 = math.dist(pi[k], pi[k - 1])
        r1 = math.dist(pi[k], F_s)
        roots = _circle_meet(P[k - 1], r0, F[k], r1)
        if roots is None:
            raise GeometryError(f"the paper's construction fails at step {k} of {n}: the circle about P_{k - 1} "
                                f"(radius {r0:.6g} mm) and the circle about F_{k} (radius {r1:.6g} mm) do not meet")
        pred = pi[k] if k == 1 else 2.0 * P[k - 1] - P[k - 2]
        a, b = roots
        P[k] = a if math.dist(a, pred) <= math.dist(b, pred) else b
    th = th_s + (np.arctan2(P[:, 1] - F[:, 1], P[:, 0] - F[:, 0]) - np.arctan2(pi[:, 1] - F_s[1], pi[:, 0] - F_s[0]))
    th = np.unwrap(th)
    th += th_s - th[0]
    alpha = np.unwrap(np.arctan2(F[:, 1] - G[1], F[:, 0] - G[0]))
    alpha += 2.0 * math.pi * round((a_s - alpha[0]) / (2.0 * math.pi))
    return th, alpha, F, P, u


def corrected(geom: LeverGeometry, start: tuple[float, float], u_start: float, u_end: float, n: int
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The corrected construction (same interface as :func:`literal`): π_k on the current rocker line.

    Each step solves the 2×2 system by Newton's method, the first from the paper's first step, the
    others from the poses extrapolated from the two before.
    """
    u = np.linspace(u_start, u_end, n + 1)
    th_lit, a_lit, _, _, _ = literal(geom, start, u_start, u[1], 1)  # first guess: the paper's first step
    lev = _lever_points(geom, u)
    gx, gy = geom.G
    fx, fy = geom.f
    ell = geom.ell
    th = np.empty(n + 1)
    al = np.empty(n + 1)
    P = np.empty((n + 1, 2))
    th[0], al[0] = start
    P[0] = lever_map(geom, al[:1], th[:1], lev[:1])[0]
    for k in range(1, n + 1):
        chord = math.dist(lev[k], lev[k - 1])
        px, py = lev[k][0] - fx, lev[k][1] - fy
        if k == 1:
            t, a = th_lit[1], a_lit[1]
        else:
            t, a = 2.0 * th[k - 1] - th[k - 2], 2.0 * al[k - 1] - al[k - 2]
        prev = math.inf
        for _ in range(50):
            ca, sa, ct, st = math.cos(a), math.sin(a), math.cos(t), math.sin(t)
            rx, ry = ct * px - st * py, st * px + ct * py
            xx, xy = gx + ell * ca + rx, gy + ell * sa + ry
            qx, qy = xx - P[k - 1][0], xy - P[k - 1][1]
            dist = math.hypot(qx, qy)
            r1 = ca * (xy - gy) - sa * (xx - gx)  # cross(e(α), X − G)
            r2 = dist - chord
            # dX/dα = ℓ e⊥(α), dX/dθ = J Rot(θ)(π − f)
            xa, ya = -ell * sa, ell * ca
            xt, yt = -ry, rx
            j11 = -sa * (xy - gy) - ca * (xx - gx) + (ca * ya - sa * xa)
            j12 = ca * yt - sa * xt
            j21 = (qx * xa + qy * ya) / dist
            j22 = (qx * xt + qy * yt) / dist
            det = j11 * j22 - j12 * j21
            if det == 0.0:
                break
            da = -(r1 * j22 - r2 * j12) / det
            dt = -(j11 * r2 - j21 * r1) / det
            a += da
            t += dt
            step = abs(da) + abs(dt)
            if step <= 4.0 * _EPS * (1.0 + abs(a) + abs(t)):  # round-off level of (α, θ)
                break
            if step >= 0.5 * prev and max(abs(r1), abs(r2)) <= 1e-12 * geom.scale:
                break  # stalled at round-off (the system is ill-conditioned near the range end)
            prev = step
        else:
            raise GeometryError(f"the corrected construction did not converge at step {k} of {n} (θ ≈ {t:.6f} rad): "
                                "no pose puts π_k on the rocker line there, as happens close to the end of the "
                                "working range where the rocker line is almost tangent to the lever circle")
        th[k], al[k] = t, a
        P[k] = lever_map(geom, al[k:k + 1], th[k:k + 1], lev[k:k + 1])[0]
    F = np.stack([gx + ell * np.cos(al), gy + ell * np.sin(al)], axis=-1)
    return th, al, F, P, u


def construct(geom: LeverGeometry, method: str, start: tuple[float, float], s5_start: float,
              u_start: float, u_end: float, n: int) -> Construction:
    """Run the ``"paper"`` (literal) or ``"corrected"`` construction and add pair E; see module doc."""
    fn = literal if method == "paper" else corrected
    th, al, F, P, u = fn(geom, start, u_start, u_end, n)
    _, D2, t2, P0, u2 = pair_e(geom, F, th, P)
    if np.any(~np.isfinite(t2)):
        k = int(np.argmax(~np.isfinite(t2)))
        raise GeometryError(f"the {method} construction: at point {k} (θ = {th[k]:.6f} rad) the normal to the "
                            "slider axis through the contact cannot reach the slider circle")
    k53 = -t2
    S5 = s5_start + np.concatenate([[0.0], np.cumsum(0.5 * (k53[1:] + k53[:-1]) * np.diff(th))])
    return Construction(th, al, F, P, u, P0, np.unwrap(u2), k53, S5, slider_point(geom, P0, S5))
