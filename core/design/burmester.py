"""Burmester theory: the dyads (circle point on the coupler, centre point on the frame) whose
crank guides a body through given poses.

Poses j = 1..n: the reference point P_j (complex, mm) and angle φ_j. A point drawn at m in pose 1
(world coordinates, complex) is at m_j = P_j + e^{i(φ_j − φ_1)}·(m − P_1) in pose j. A dyad
(centre G on the frame, circle point m) guides the body when every m_j lies on one circle about G.

- **3 poses**: every point is a circle point; its centre is the circumcentre of m_1, m_2, m_3
  (:func:`circle_centres`). Exact.
- **4 poses**: the circle points form a cubic (Burmester's circle-point curve). It is traced with
  the standard dyad equation W·(e^{iβ_j} − 1) + Z·(e^{iα_j} − 1) = δ_j (j = 2..4; W the crank
  G→m, Z the coupler m→P_1, α_j the body's turn, δ_j = P_j − P_1, β_j the crank's turn), which
  has a solution (W, Z) only if the 3 × 3 determinant vanishes: Δ₁ + Δ₂e^{iβ₂} + Δ₃e^{iβ₃} +
  Δ₄e^{iβ₄} = 0. For each β₂ this closes a triangle of known sides, giving β₃, β₄ in closed form
  (two solutions) and then W, Z (:func:`four_pose_dyads`). Exact.
- **5 or more poses**: no exact dyad in general; :func:`fit_centres` gives the least-squares
  circle of each point's positions (algebraic, then geometric refinement) and its residual.

Arrays: circle points ``m`` (G,) complex (pose-1 world, mm); centres (G,) complex; positions
(G, n) complex.
"""
from __future__ import annotations

import math

import numpy as np

from .targets import PoseTarget


def pose_maps(target: PoseTarget) -> tuple[np.ndarray, np.ndarray]:
    """(P (n,), turn (n,)): each pose's point and its rotation e^{i(φ_j − φ_1)} from pose 1."""
    return target.complex_points, np.exp(1j * (target.angles_rad - target.angles_rad[0]))


def positions(target: PoseTarget, m: np.ndarray) -> np.ndarray:
    """(G, n) positions in each pose of the points ``m`` (G,) drawn in pose 1."""
    P, turn = pose_maps(target)
    m = np.asarray(m, dtype=complex).reshape(-1, 1)
    return P[None, :] + turn[None, :] * (m - P[0])


def inverse_positions(target: PoseTarget, g: np.ndarray) -> np.ndarray:
    """(G, n) the frame points ``g`` (G,) seen from the body in each pose, drawn in pose 1: a
    circle point is equidistant from these (the inverse motion's circle points are the centre
    points)."""
    P, turn = pose_maps(target)
    g = np.asarray(g, dtype=complex).reshape(-1, 1)
    return P[0] + np.conj(turn)[None, :] * (g - P[None, :])


def circumcentre(z1: np.ndarray, z2: np.ndarray, z3: np.ndarray) -> np.ndarray:
    """Centre of the circle through three points (complex arrays; inf/NaN where collinear)."""
    a, b = z2 - z1, z3 - z1
    den = 2j * (np.conj(a) * b).imag
    with np.errstate(invalid="ignore", divide="ignore"):
        return z1 + (np.abs(a) ** 2 * b - np.abs(b) ** 2 * a) / den


def circle_centres(target: PoseTarget, m: np.ndarray) -> np.ndarray:
    """3 poses: the centre point of each circle point ``m`` (G,) (pose 1, world)."""
    z = positions(target, m)
    return circumcentre(z[:, 0], z[:, 1], z[:, 2])


def circle_points(target: PoseTarget, g: np.ndarray) -> np.ndarray:
    """3 poses: the circle point (pose 1, world) of each centre point ``g`` (G,)."""
    z = inverse_positions(target, g)
    return circumcentre(z[:, 0], z[:, 1], z[:, 2])


def _cofactors(alpha: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """Δ₁..Δ₄ of the 4-pose compatibility equation (alpha, delta: turns and displacements of
    poses 2..4)."""
    a = np.exp(1j * alpha) - 1.0
    c2 = a[1] * delta[2] - a[2] * delta[1]
    c3 = -(a[0] * delta[2] - a[2] * delta[0])
    c4 = a[0] * delta[1] - a[1] * delta[0]
    return np.array([-(c2 + c3 + c4), c2, c3, c4])


def four_pose_dyads(target: PoseTarget, samples: int = 360, beta2: np.ndarray | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """4 poses: (circle points m, centre points G, crank turns β (·, 3) rad) along Burmester's
    curves, ``samples`` values of β₂ over a turn (or the given ``beta2``, rad), two solutions
    each (where they exist). The trivial solution (crank and coupler one rigid link, β = α) is
    left out."""
    if len(target.points) != 4:
        raise ValueError("four_pose_dyads needs exactly 4 poses")
    P = target.complex_points
    alpha = target.angles_rad[1:] - target.angles_rad[0]
    delta = P[1:] - P[0]
    d1, d2, d3, d4 = _cofactors(alpha, delta)
    b2 = (np.linspace(0.0, 2 * math.pi, samples, endpoint=False) + math.pi / samples if beta2 is None
          else np.asarray(beta2, dtype=float).reshape(-1))
    S = d1 + d2 * np.exp(1j * b2)
    r3, r4, rs = abs(d3), abs(d4), np.abs(S)
    with np.errstate(invalid="ignore", divide="ignore"):
        cphi = (r3 * r3 + rs * rs - r4 * r4) / (2.0 * r3 * rs)
    ok = np.abs(cphi) <= 1.0
    b2, S, cphi = b2[ok], S[ok], cphi[ok]
    sphi = np.sqrt(1.0 - cphi * cphi)
    ms, gs, betas = [], [], []
    for sgn in (1.0, -1.0):
        X = -S / np.abs(S) * r3 * (cphi + 1j * sgn * sphi)   # Δ₃·e^{iβ₃}
        Y = -S - X                                           # Δ₄·e^{iβ₄}
        e2, e3, e4 = np.exp(1j * b2), X / d3, Y / d4
        # W, Z from poses 2 and 3 (Cramer on the 2 × 2 complex system)
        a2, a3 = np.exp(1j * alpha[0]) - 1.0, np.exp(1j * alpha[1]) - 1.0
        m11, m21 = e2 - 1.0, e3 - 1.0
        det = m11 * a3 - a2 * m21
        with np.errstate(invalid="ignore", divide="ignore"):
            W = (delta[0] * a3 - a2 * delta[1]) / det
            Z = (m11 * delta[1] - m21 * delta[0]) / det
        beta = np.stack([b2, np.angle(e3), np.angle(e4)], axis=1)
        trivial = np.all(np.abs(np.remainder(beta - alpha + math.pi, 2 * math.pi) - math.pi) < 1e-6, axis=1)
        keep = np.isfinite(W) & np.isfinite(Z) & ~trivial
        m = P[0] - Z[keep]
        ms.append(m)
        gs.append(m - W[keep])
        betas.append(beta[keep])
    return np.concatenate(ms), np.concatenate(gs), np.concatenate(betas)


def fit_centres(target: PoseTarget, m: np.ndarray, iterations: int = 8) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares circle of each point's positions: (centres (G,), radii (G,), RMS residual
    (G,) mm of |m_j − G| − R). With 3 poses it is the circumcircle (residual 0)."""
    return fit_circles(positions(target, m), iterations)


def fit_circles(z: np.ndarray, iterations: int = 8) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The least-squares circle through each row of points ``z`` (G, n) complex: (centres (G,),
    radii (G,), RMS residual (G,)). Algebraic fit (Kåsa), then Gauss–Newton on the geometric
    distance."""
    x, y = z.real, z.imag
    # algebraic: x² + y² = 2·cx·x + 2·cy·y + k
    A = np.stack([2 * x, 2 * y, np.ones_like(x)], axis=-1)
    rhs = x * x + y * y
    AtA = np.einsum("gni,gnj->gij", A, A)
    Atb = np.einsum("gni,gn->gi", A, rhs)
    ridge = 1e-14 * np.trace(AtA, axis1=1, axis2=2)[:, None, None] * np.eye(3)
    p = np.linalg.solve(AtA + ridge, Atb[..., None])[..., 0]
    c = p[:, 0] + 1j * p[:, 1]
    R = np.sqrt(np.maximum(p[:, 2] + np.abs(c) ** 2, 0.0))
    for _ in range(iterations):
        v = z - c[:, None]
        dist = np.abs(v)
        r = dist - R[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            u = v / dist
        J = np.stack([-u.real, -u.imag, -np.ones_like(dist)], axis=-1)
        JtJ = np.einsum("gni,gnj->gij", J, J)
        Jtr = np.einsum("gni,gn->gi", J, r)
        ridge = 1e-12 * (np.trace(JtJ, axis1=1, axis2=2)[:, None, None] + 1e-300) * np.eye(3)
        step = np.linalg.solve(JtJ + ridge, -Jtr[..., None])[..., 0]
        c = c + step[:, 0] + 1j * step[:, 1]
        R = R + step[:, 2]
    res = np.sqrt(np.mean((np.abs(z - c[:, None]) - R[:, None]) ** 2, axis=1))
    return c, np.abs(R), res


def concyclic_residual(target: PoseTarget, m: np.ndarray, g: np.ndarray) -> np.ndarray:
    """(G,) the largest difference of |m_j − G| over the poses, mm: 0 for an exact dyad."""
    d = np.abs(positions(target, m) - np.asarray(g).reshape(-1, 1))
    return d.max(axis=1) - d.min(axis=1)


__all__ = ["circle_centres", "circle_points", "fit_circles", "inverse_positions", "circumcentre", "concyclic_residual", "fit_centres", "four_pose_dyads", "pose_maps",
           "positions"]
