"""Geneva-drive kinematics in closed form (external, radial entry), vectorised over the revolution.

Notation of seeds/NOTES.md, section B ("Textbook Geneva kinematics"): λ = sin(π/z), the crank angle
φ is measured from the line of centres (crank centre → wheel centre), counter-clockwise positive,
and the roller is in a slot for |φ| ≤ φ0 = π/2 − π/z. In the wheel's own indexing sense (opposite
to the crank):

- θ(φ) = atan2(λ sin φ, 1 − λ cos φ), θ(±φ0) = ±π/z;
- i(φ) = ω2/ω1 = λ(cos φ − λ)/D with D = 1 − 2λ cos φ + λ²;
- ε̃(φ) = ε2/ω1² = −λ(1 − λ²) sin φ / D²;
- j̃(φ) = −λ(1 − λ²)(cos φ·D − 4λ sin² φ)/D³.

The world-frame results (counter-clockwise positive) are wheel.angle = −θ(φ), ω2 = −i·ω1,
α2 = −ε̃·ω1², jerk = −j̃·ω1³, with ω1 signed; they are zero (angle ∓π/z) in the dwell. The
acceleration jumps between 0 and ∓tan(π/z)·ω1² at entry and exit: the sampled table shows it as
a step between neighbouring rows and :meth:`GenevaKinematics.alpha_with_jumps` gives both one-sided
values at ±φ0; nothing is interpolated across it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ...model.geneva import Geneva

#: a sample within this many radians of ±φ0 counts as engaged (it is the engagement end point)
EDGE_TOL = 1e-12


def wheel_angle(phi: np.ndarray | float, lam: float) -> np.ndarray:
    """θ(φ), the wheel rotation in its indexing sense (rad); valid for |φ| ≤ φ0. Shape of ``phi``."""
    phi = np.asarray(phi, dtype=float)
    return np.arctan2(lam * np.sin(phi), 1.0 - lam * np.cos(phi))


def velocity_ratio(phi: np.ndarray | float, lam: float) -> np.ndarray:
    """i(φ) = ω2/ω1 (indexing sense, dimensionless). Shape of ``phi``."""
    phi = np.asarray(phi, dtype=float)
    c = np.cos(phi)
    return lam * (c - lam) / (1.0 - 2.0 * lam * c + lam * lam)


def accel_ratio(phi: np.ndarray | float, lam: float) -> np.ndarray:
    """ε̃(φ) = ε2/ω1² (indexing sense, dimensionless). Shape of ``phi``."""
    phi = np.asarray(phi, dtype=float)
    d = 1.0 - 2.0 * lam * np.cos(phi) + lam * lam
    return -lam * (1.0 - lam * lam) * np.sin(phi) / (d * d)


def jerk_ratio(phi: np.ndarray | float, lam: float) -> np.ndarray:
    """j̃(φ) = (d³θ/dt³)/ω1³ (indexing sense, dimensionless). Shape of ``phi``."""
    phi = np.asarray(phi, dtype=float)
    c, s = np.cos(phi), np.sin(phi)
    d = 1.0 - 2.0 * lam * c + lam * lam
    return -lam * (1.0 - lam * lam) * (c * d - 4.0 * lam * s * s) / d ** 3


def peak_accel(lam: float) -> tuple[float, float]:
    """(φ_m, ε̃_max): the crank angle of the acceleration peak (rad, the accelerating one is −φ_m)
    and its value, from 2λc² + (1 + λ²)c − 4λ = 0 with c = cos φ_m."""
    k = (1.0 + lam * lam) / (4.0 * lam)
    c = -k + math.sqrt(k * k + 2.0)
    phi_m = math.acos(c)
    d = 1.0 - 2.0 * lam * c + lam * lam
    return phi_m, lam * (1.0 - lam * lam) * math.sin(phi_m) / (d * d)


@dataclass(frozen=True)
class Phase:
    """One phase of the revolution in time order: ``name`` is ``"dwell"`` or ``"indexing"``;
    crank angles (rad) and times (s) where it starts and ends."""

    name: str
    phi_start: float
    phi_end: float
    t_start: float
    t_end: float


@dataclass(frozen=True)
class GenevaKinematics:
    """Kinematics over one crank revolution of N samples, in time order.

    Arrays, all shape (N,): ``phi`` crank angle from the line of centres (rad, CCW; φ_k =
    −π + 2πk/N for a CCW crank, π − 2πk/N for a CW one); ``t`` time (s, t_k = k·T/N);
    ``engaged`` roller in a slot (bool, |φ| ≤ φ0 inclusive); ``wheel_angle`` wheel rotation in
    the world frame (rad, CCW positive, 0 at φ = 0, ±π/z in the dwell); ``omega`` (rad/s),
    ``alpha`` (rad/s²), ``jerk`` (rad/s³) of the wheel, world frame; the jerk is the finite
    part (the steps of α at ±φ0 are infinite jerk, not represented).

    Scalars: ``slots`` z; ``lam`` λ; ``phi0`` (rad); ``omega1`` (rad/s, signed); ``period`` T (s);
    ``i_max`` = λ/(1 − λ); ``phi_peak`` φ_m (rad, > 0; |α2| peaks at φ = ±φ_m);
    ``accel_peak`` ε̃_max·ω1² (rad/s², magnitude) and ``accel_peak_ratio`` ε̃_max;
    ``jump`` = tan(π/z)·ω1² (rad/s², magnitude of the step at entry and exit);
    ``jerk_centre`` = j̃(0)·|ω1|³, the jerk at mid-indexing in the wheel's indexing sense (rad/s³,
    negative: j̃(0) = −λ(1 + λ)/(1 − λ)³);
    ``motion_fraction`` (z − 2)/(2z), ``dwell_fraction`` (z + 2)/(2z); ``phases``.
    """

    phi: np.ndarray
    t: np.ndarray
    engaged: np.ndarray
    wheel_angle: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    jerk: np.ndarray
    slots: int
    lam: float
    phi0: float
    omega1: float
    period: float
    i_max: float
    phi_peak: float
    accel_peak: float
    accel_peak_ratio: float
    jump: float
    jerk_centre: float
    motion_fraction: float
    dwell_fraction: float
    phases: tuple[Phase, ...]

    @property
    def sampled_peak(self) -> tuple[float, float]:
        """(φ, α2) of the sample with the largest |α2| (rad, rad/s²)."""
        k = int(np.argmax(np.abs(self.alpha)))
        return float(self.phi[k]), float(self.alpha[k])

    def alpha_with_jumps(self) -> tuple[np.ndarray, np.ndarray]:
        """(φ, α2) in time order with both one-sided values at entry and exit, for plotting.

        The samples at ±φ0 (if any) are replaced by the pair (dwell value 0, engaged value),
        so a plotted line shows a vertical step, never a slope. Shapes (N + 2 or so,), rad, rad/s².
        """
        s = 1.0 if self.omega1 > 0 else -1.0
        entry, exit_ = -s * self.phi0, s * self.phi0
        a_in = -float(accel_ratio(entry, self.lam)) * self.omega1 ** 2
        a_out = -float(accel_ratio(exit_, self.lam)) * self.omega1 ** 2
        u = s * self.phi  # progress angle, increasing in time
        keep = np.abs(np.abs(u) - self.phi0) > EDGE_TOL
        pu = np.concatenate([u[keep], [-self.phi0, -self.phi0, self.phi0, self.phi0]])
        pa = np.concatenate([self.alpha[keep], [0.0, a_in, a_out, 0.0]])
        # stable sort keeps each pair in the order given (dwell then engaged at entry, etc.)
        order = np.argsort(pu, kind="stable")
        return s * pu[order], pa[order]


def kinematics(element: "Geneva", samples: int) -> GenevaKinematics:
    """Closed-form kinematics of ``element`` at ``samples`` points over one crank revolution.

    Vectorised (no loop over samples). See :class:`GenevaKinematics` for the arrays and units.
    """
    n = int(samples)
    z = element.slots
    lam = element.lam
    phi0 = element.phi0
    w1 = element.omega1
    s = 1.0 if w1 > 0 else -1.0
    k = np.arange(n, dtype=float)
    u = -math.pi + 2.0 * math.pi * k / n  # progress angle: entry at u = −φ0 in either direction
    phi = s * u
    period = 2.0 * math.pi / abs(w1)
    t = k * period / n
    eng = np.abs(u) <= phi0 + EDGE_TOL
    pe = np.where(eng, phi, 0.0)
    angle = np.where(eng, -wheel_angle(pe, lam), -np.sign(phi) * math.pi / z) + 0.0  # no −0.0
    omega = np.where(eng, -velocity_ratio(pe, lam) * w1, 0.0)
    alpha = np.where(eng, -accel_ratio(pe, lam) * w1 * w1, 0.0)
    jerk = np.where(eng, -jerk_ratio(pe, lam) * w1 ** 3, 0.0)
    phi_m, eps_max = peak_accel(lam)
    t_entry = (math.pi - phi0) / abs(w1)
    t_exit = (math.pi + phi0) / abs(w1)
    phases = (Phase("dwell", s * -math.pi, s * -phi0, 0.0, t_entry),
              Phase("indexing", s * -phi0, s * phi0, t_entry, t_exit),
              Phase("dwell", s * phi0, s * math.pi, t_exit, period))
    return GenevaKinematics(
        phi=phi, t=t, engaged=eng, wheel_angle=angle, omega=omega, alpha=alpha, jerk=jerk,
        slots=z, lam=lam, phi0=phi0, omega1=w1, period=period, i_max=lam / (1.0 - lam),
        phi_peak=phi_m, accel_peak=eps_max * w1 * w1, accel_peak_ratio=eps_max,
        jump=math.tan(math.pi / z) * w1 * w1,
        jerk_centre=float(jerk_ratio(0.0, lam)) * abs(w1) ** 3,
        motion_fraction=(z - 2) / (2 * z), dwell_fraction=(z + 2) / (2 * z), phases=phases)
