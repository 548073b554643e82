"""A Geneva drive whose crank is driven through a non-circular gear pair (the smooth Geneva drive,
issue 25, item 4): the crank's motion, the wheel's kinematics, the comparison with the
constant-speed crank, and the torques passed back through the gears.

The input turns at constant speed ω (its progress angle θ = ω·t − π over one turn); the gears
make the crank's progress angle u = ψ(θ) (u = θ = 0 at mid-indexing), so u̇ = ψ'ω, ü = ψ''ω²,
u⃛ = ψ'''ω³. The wheel's angle is the closed form Θ(φ) of the crank angle φ = s·u (s the crank's
sense), so, with i, ε̃, j̃ of :mod:`.kinematics` (indexing sense),

    ω2 = i·φ̇,   α2 = ε̃·φ̇² + i·φ̈,   jerk = j̃·φ̇³ + 3·ε̃·φ̇·φ̈ + i·φ⃛,

in the world frame with the minus sign of :mod:`.kinematics`. At entry and exit i = 0, so the
acceleration jumps by tan(π/z)·u̇² there instead of tan(π/z)·ω1²: the gears that slow the crank at
entry and exit reduce the jump by (u̇/ω1)². With ψ(±φ0) = ±φ0 the engagement takes the input the
same 2φ0 as the constant crank: the same index time and dwell.

The contact and wear analysis runs on this motion (:func:`~.contact.contact` with the crank's
angles at equal times and :class:`GearCrank` as its crank motion), and the crank torque T_c (the
contact model's, :mod:`.torque`) is passed back through the gears: T_in = −T_c·ψ' (frictionless
gears: T_in·ω_in = T_c·ω_c, the input turning the other way).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..gears.function import FunctionEval
from ...model.gear_function import GearFunction
from .kinematics import (EDGE_TOL, GenevaKinematics, Phase, accel_ratio, jerk_ratio, peak_accel, velocity_ratio,
                         wheel_angle)

#: points over the engagement on which the continuous peaks are searched (then refined)
PEAK_GRID = 2001


class GearCrank:
    """The crank's motion through the gears: u̇, ü (and u⃛) at progress angles u (rad), the input
    at |ω| rad/s. Implements :class:`~.contact.CrankMotion`."""

    def __init__(self, fn: GearFunction, omega: float) -> None:
        self.ev = FunctionEval(fn)
        self.omega = abs(omega)

    def theta(self, u: np.ndarray) -> np.ndarray:
        """The input's progress angle at crank progress angles u (rad)."""
        return self.ev.inverse(np.asarray(u, dtype=float))

    def rates3(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        _, p1, p2, p3 = self.ev.derivatives(self.theta(u))
        w = self.omega
        return p1 * w, p2 * w * w, p3 * w ** 3

    def rates(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ud, udd, _ = self.rates3(u)
        return ud, udd


def wheel_rates(u: np.ndarray, lam: float, ud, udd, uddd) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(ω2, α2, jerk) in the wheel's indexing sense at crank progress angles u with the crank's
    rates (rad/s, rad/s², rad/s³); arrays of the shape of ``u``."""
    i, e, j = velocity_ratio(u, lam), accel_ratio(u, lam), jerk_ratio(u, lam)
    return i * ud, e * ud * ud + i * udd, j * ud ** 3 + 3.0 * e * ud * udd + i * uddd


@dataclass(frozen=True)
class Smoothness:
    """The geared drive against the constant-speed crank at the same mean speed (rad/s², rad/s³,
    s; magnitudes): ``jump`` / ``jump_constant`` the acceleration steps at entry (the larger of
    entry and exit), ``jerk`` / ``jerk_constant`` the peaks of the finite jerk over the engagement
    (continuous: a grid of :data:`PEAK_GRID` points refined by a parabola), ``accel`` /
    ``accel_constant`` the acceleration peaks, ``index_time`` / ``index_time_constant`` the time
    the wheel indexes, ``dwell_fraction`` / ``dwell_fraction_constant``."""

    jump: float
    jump_constant: float
    jerk: float
    jerk_constant: float
    accel: float
    accel_constant: float
    index_time: float
    index_time_constant: float
    dwell_fraction: float
    dwell_fraction_constant: float

    @property
    def jump_reduction(self) -> float:
        return 1.0 - self.jump / self.jump_constant

    @property
    def jerk_reduction(self) -> float:
        return 1.0 - self.jerk / self.jerk_constant

    def lines(self) -> list[str]:
        return [f"smooth drive against the constant-speed crank (same mean speed): acceleration jump at entry/exit "
                f"{self.jump:.6g} rad/s² against {self.jump_constant:.6g} ({100 * self.jump_reduction:.1f} % less); "
                f"peak jerk {self.jerk:.6g} rad/s³ against {self.jerk_constant:.6g} ({100 * self.jerk_reduction:.1f} % "
                f"less); peak acceleration {self.accel:.6g} against {self.accel_constant:.6g} rad/s²",
                f"index time {self.index_time:.6g} s (constant crank {self.index_time_constant:.6g} s), dwell fraction "
                f"{self.dwell_fraction:.6f} ({self.dwell_fraction_constant:.6f})"]


def _peak(f, lo: float, hi: float) -> float:
    """max |f| over [lo, hi]: a grid, then a parabola through the best point and its neighbours."""
    x = np.linspace(lo, hi, PEAK_GRID)
    y = np.abs(f(x))
    k = int(np.argmax(y))
    if 0 < k < len(x) - 1:
        y0, y1, y2 = y[k - 1], y[k], y[k + 1]
        den = y0 - 2 * y1 + y2
        if den < 0:
            return float(y1 - 0.125 * (y2 - y0) ** 2 / den)
    return float(y[k])


def smoothness(fn: GearFunction, z: int, omega1: float) -> Smoothness:
    """:class:`Smoothness` of a drive of ``z`` slots whose crank's mean speed is ``omega1`` rad/s."""
    lam, phi0 = math.sin(math.pi / z), math.pi / 2 - math.pi / z
    w = abs(omega1)
    ev = FunctionEval(fn)
    th_in, th_out = ev.inverse(np.array([-phi0, phi0]))

    def rates_at(theta):
        u, p1, p2, p3 = ev.derivatives(theta)
        return wheel_rates(u, lam, p1 * w, p2 * w * w, p3 * w ** 3)

    ud_ends = ev.derivatives(np.array([th_in, th_out]))[1] * w
    jump = math.tan(math.pi / z) * float(np.max(ud_ends)) ** 2
    jerk = _peak(lambda t: rates_at(t)[2], th_in, th_out)
    accel = _peak(lambda t: rates_at(t)[1], th_in, th_out)
    jerk_c = _peak(lambda u: jerk_ratio(u, lam) * w ** 3, -phi0, phi0)
    index = (th_out - th_in) / w
    period = 2 * math.pi / w
    return Smoothness(jump, math.tan(math.pi / z) * w * w, jerk, jerk_c, accel, peak_accel(lam)[1] * w * w,
                      index, 2 * phi0 / w, 1.0 - index / period, (z + 2) / (2 * z))


def driven_kinematics(z: int, omega1: float, fn: GearFunction, samples: int) -> tuple[GenevaKinematics, np.ndarray]:
    """The wheel's kinematics at ``samples`` equal times over one input turn, and the input's
    progress angles θ (N,) rad. ``omega1``: the crank's mean speed (rad/s, signed: the crank's
    sense). The arrays follow :class:`GenevaKinematics` (φ the crank angle, world-frame wheel)."""
    lam, phi0 = math.sin(math.pi / z), math.pi / 2 - math.pi / z
    s = 1.0 if omega1 > 0 else -1.0
    w = abs(omega1)
    ev = FunctionEval(fn)
    n = int(samples)
    k = np.arange(n, dtype=float)
    theta = -math.pi + 2.0 * math.pi * k / n
    u, p1, p2, p3 = ev.derivatives(theta)
    u = np.remainder(u + math.pi, 2 * math.pi) - math.pi
    phi = s * u
    eng = np.abs(u) <= phi0 + EDGE_TOL
    ue = np.where(eng, u, 0.0)
    om, al, je = wheel_rates(ue, lam, p1 * w, p2 * w * w, p3 * w ** 3)
    angle = np.where(eng, -s * wheel_angle(ue, lam), -np.sign(phi) * math.pi / z) + 0.0
    period = 2.0 * math.pi / w
    th_in, th_out = ev.inverse(np.array([-phi0, phi0]))
    t_in, t_out = (th_in + math.pi) / w, (th_out + math.pi) / w
    phases = (Phase("dwell", s * -math.pi, s * -phi0, 0.0, t_in), Phase("indexing", s * -phi0, s * phi0, t_in, t_out),
              Phase("dwell", s * phi0, s * math.pi, t_out, period))
    sm = smoothness(fn, z, omega1)
    _, q1, q2, q3 = ev.derivatives(ev.inverse(np.zeros(1)))
    j0 = wheel_rates(np.zeros(1), lam, q1 * w, q2 * w * w, q3 * w ** 3)[2]
    kin = GenevaKinematics(
        phi=phi, t=k * period / n, engaged=eng, wheel_angle=angle, omega=np.where(eng, -s * om, 0.0),
        alpha=np.where(eng, -s * al, 0.0), jerk=np.where(eng, -s * je, 0.0), slots=z, lam=lam, phi0=phi0, omega1=omega1,
        period=period, i_max=lam / (1.0 - lam), phi_peak=peak_accel(lam)[0], accel_peak=sm.accel,
        accel_peak_ratio=sm.accel / (w * w), jump=sm.jump, jerk_centre=float(j0[0]),
        motion_fraction=1.0 - sm.dwell_fraction, dwell_fraction=sm.dwell_fraction, phases=phases)
    return kin, theta
