"""Crank synthesis for the rolling lever ("choose the coupler, find the crank", notes section C).

Given the crank pivot A and the lever point C (drawn pose), the distance d(θ) = |A − C(θ)| over the
stroke gives the crank r_c = (d_max − d_min)/2 and the coupler l_c = (d_max + d_min)/2; the
stroke's ends are then the crank's dead centres (folded at d_min, extended at d_max). d must be
monotone over the stroke, otherwise a crank cannot drive the whole stroke and the request is
refused. The crank turns counter-clockwise; the forward stroke (folded → extended) and the return
take the crank angles given by where the coupler pin B lies on either side of the line A–C.

The whole mechanism then runs from the crank angle φ: θ(φ) from the table of both branches
(monotone in φ over one revolution), refined by Newton's method on |B(φ) − C(θ)| = l_c, then the
lever pose, both contacts and the slider travel follow from the exact motion.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import GeometryError
from .exact import ExactPath
from .geometry import LeverGeometry, lever_map, pose_state

_TWO_PI = 2.0 * math.pi


@dataclass
class MechanismFrames:
    """The driven mechanism at crank angles φ (M,) rad: positions (M, 2) mm, θ/α (M,) rad, S5 (M,) mm."""

    phi: np.ndarray
    theta: np.ndarray
    alpha: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    F: np.ndarray
    G: np.ndarray
    P: np.ndarray
    P0: np.ndarray
    S5: np.ndarray
    coupler_residual: float  # max | |B − C| − l_c | (mm)


@dataclass
class DriveSynthesis:
    """Crank and coupler synthesised from the stroke (mm, rad); see the module docstring.

    ``theta_folded``/``theta_extended``: lever rotations at the dead centres (d_min / d_max);
    ``phi_folded``/``phi_extended``: crank angles there; ``forward_angle``: the crank's turn from the
    folded to the extended dead centre (CCW), the return takes 2π minus it.
    """

    crank_pivot: np.ndarray
    coupler_point: np.ndarray
    crank: float
    coupler: float
    d_min: float
    d_max: float
    theta_folded: float
    theta_extended: float
    phi_folded: float
    phi_extended: float
    forward_angle: float
    _path: ExactPath
    _cycle_phi: np.ndarray
    _cycle_theta: np.ndarray

    @property
    def time_ratio(self) -> float:
        """Forward over return crank angle."""
        return self.forward_angle / (_TWO_PI - self.forward_angle)

    def coupler_path(self, theta: np.ndarray) -> np.ndarray:
        """C(θ) in the ground, (M, 2) mm, from the exact motion."""
        alpha, _ = self._path.at(theta)
        return lever_map(self._path.geom, alpha, theta, self.coupler_point)

    def theta_at(self, phi: np.ndarray) -> tuple[np.ndarray, float]:
        """Lever rotation θ (M,) rad at crank angles φ (M,) rad; and the max coupler residual (mm)."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        p = self.phi_folded + np.mod(phi - self.phi_folded, _TWO_PI)
        theta = np.interp(p, self._cycle_phi, self._cycle_theta)
        A = self.crank_pivot
        B = A + self.crank * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
        lo, hi = sorted((self.theta_folded, self.theta_extended))

        def resid(t):
            return np.linalg.norm(B - self.coupler_path(t), axis=1) - self.coupler

        r = resid(theta)
        eps = 1e-7
        for _ in range(6):
            dr = (resid(np.clip(theta + eps, lo, hi)) - resid(np.clip(theta - eps, lo, hi))) / (2.0 * eps)
            safe = np.abs(dr) > 1e-6 * self.coupler
            trial = np.clip(theta - np.where(safe, r / np.where(safe, dr, 1.0), 0.0), lo, hi)
            rt = resid(trial)
            better = np.abs(rt) < np.abs(r)
            theta = np.where(better, trial, theta)
            r = np.where(better, rt, r)
        return theta, float(np.max(np.abs(r))) if len(r) else 0.0

    def frames(self, phi: np.ndarray) -> MechanismFrames:
        """The whole mechanism (crank → coupler → lever → slider) at crank angles φ (M,) rad."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        theta, res = self.theta_at(phi)
        alpha, s5 = self._path.at(theta)
        st = pose_state(self._path.geom, alpha, theta)
        A = np.broadcast_to(self.crank_pivot, (len(phi), 2)).copy()
        B = A + self.crank * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
        C = lever_map(self._path.geom, alpha, theta, self.coupler_point)
        G = np.broadcast_to(np.asarray(self._path.geom.G), (len(phi), 2)).copy()
        return MechanismFrames(phi, theta, alpha, A, B, C, st.F, G, st.P, st.P0, s5, res)


def _angle(v: np.ndarray) -> np.ndarray:
    return np.arctan2(v[..., 1], v[..., 0])


def synthesize_drive(path: ExactPath, geom: LeverGeometry, start: float, end: float,
                     crank_pivot: tuple[float, float], coupler_point: tuple[float, float],
                     samples: int = 2000) -> DriveSynthesis:
    """Crank and coupler lengths from the coupler point's path over the stroke start → end (rad).

    Raises :class:`GeometryError` when d(θ) = |A − C(θ)| is not monotone over the stroke.
    """
    A = np.asarray(crank_pivot, dtype=float)
    c = np.asarray(coupler_point, dtype=float)
    theta = np.linspace(start, end, samples + 1)
    alpha, _ = path.at(theta)
    C = lever_map(geom, alpha, theta, c)
    d = np.linalg.norm(C - A, axis=1)
    dd = np.diff(d)
    if not (np.all(dd > 0.0) or np.all(dd < 0.0)):
        turn = int(np.argmax(np.sign(dd[1:]) != np.sign(dd[0]))) + 1
        raise GeometryError(
            f"the coupler point's distance from the crank pivot is not monotone over the stroke (it turns "
            f"at θ ≈ {theta[turn]:.6f} rad, d ≈ {d[turn]:.6g} mm), so a crank cannot drive the whole stroke; "
            "move drive.crank_pivot or drive.coupler_point")
    if dd[0] < 0.0:  # order from folded (d_min) to extended (d_max)
        theta, C, d = theta[::-1], C[::-1], d[::-1]
    d_min, d_max = float(d[0]), float(d[-1])
    rc, lc = 0.5 * (d_max - d_min), 0.5 * (d_max + d_min)
    u = (C - A) / d[:, None]
    phi_f = float(_angle(-u[0]))
    phi_e = float(_angle(u[-1]))
    forward = (phi_e - phi_f) % _TWO_PI
    # B = A + a u ± h J u on circle(A, rc) ∩ circle(C, lc)
    a = (rc * rc - lc * lc + d * d) / (2.0 * d)
    h = np.sqrt(np.clip(rc * rc - a * a, 0.0, None))
    ju = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    mid = len(theta) // 2
    branches = []
    for sgn in (1.0, -1.0):
        B = A + a[:, None] * u + sgn * h[:, None] * ju
        branches.append(_angle(B - A))
    inside = [((b[mid] - phi_f) % _TWO_PI) < forward for b in branches]
    fwd, ret = (branches[0], branches[1]) if inside[0] else (branches[1], branches[0])
    phi_fwd = phi_f + np.mod(fwd - phi_f, _TWO_PI)
    phi_fwd[0], phi_fwd[-1] = phi_f, phi_f + forward
    phi_ret = phi_f + forward + np.mod(ret[::-1] - (phi_f + forward), _TWO_PI)
    phi_ret[0], phi_ret[-1] = phi_f + forward, phi_f + _TWO_PI
    cyc_phi = np.concatenate([phi_fwd, phi_ret[1:]])
    cyc_theta = np.concatenate([theta, theta[::-1][1:]])
    if np.any(np.diff(cyc_phi) < -1e-12):
        raise GeometryError("the crank angle is not monotone over the cycle: the coupler cannot follow "
                            "the coupler point's path; move drive.crank_pivot")
    return DriveSynthesis(A, c, rc, lc, d_min, d_max, float(theta[0]), float(theta[-1]), phi_f,
                          float(phi_f + forward), float(forward), path, cyc_phi, cyc_theta)
