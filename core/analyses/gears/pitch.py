"""Pitch curves of a non-circular gear pair: the exact centrodes of the relative motion, their
checks, and the pair's kinematics (issue 25, items 3 and 4).

Two gears turn about pivots a apart; the output's rotation is ψ(φ) of the input's (opposite
sense). Their relative instant centre lies on the line of centres where the two pitch speeds are
equal: at r1 = a·ψ'/(1 + ψ') from the input pivot and r2 = a/(1 + ψ') from the output one
(r1·ω_in = r2·ω_out, r1 + r2 = a). In the input's body frame (line of centres along +x when the
rotation is 0) that point is C1(φ) = r1·e(−σφ), σ the input's turning sense; in the output's it is
C2(φ) = r2·e(π + σψ(φ)) (the output turns the other way). These pitch curves roll on each other
without slip: |dC1/dφ| = √(r1² + r1'²) equals |dC2/dφ| = √(r2²ψ'² + r2'²) since r1' = −r2' and
r1 = r2ψ'. They close when ψ advances by 2π·q per input turn with q a whole number or its inverse.

Checks (each with its value): closure (the gap after one period of each curve), pure rolling (the
two curves' lengths over a common period, by Gauss–Legendre on each curve's own speed), the speed
ratio's range, the radius of curvature of each curve (convex or where concave, how tightly),
and the pressure angle variation |π/2 − μ| (μ the angle between the pitch curve's tangent and its
radius vector: the tooth's pressure angle varies by that much along the curve).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .function import FunctionEval, spline_ratio_problem
from ...model.gear_function import GearFunction

#: Gauss–Legendre nodes per interval of the arc-length quadrature, intervals per input turn
_NODES, _INTERVALS = 16, 256


@dataclass(frozen=True)
class PitchChecks:
    """Figures of a pair's pitch curves (mm, degrees where named); see the module docstring.

    ``input_length`` / ``output_length``: each curve's perimeter; ``rolled_input`` /
    ``rolled_output``: the arc each rolls over one common period (equal for pure rolling: their
    difference ``rolling_mismatch``); ``closure_gap``: the larger end-to-start gap; ``ratio_min`` /
    ``ratio_max``: ψ' range; ``curvature_input`` / ``curvature_output``: the smallest signed radius
    of curvature (negative: concave there); ``pressure_input_deg`` / ``pressure_output_deg``: the
    largest |π/2 − μ|."""

    input_length: float
    output_length: float
    rolled_input: float
    rolled_output: float
    closure_gap: float
    ratio_min: float
    ratio_max: float
    curvature_input: float
    curvature_output: float
    pressure_input_deg: float
    pressure_output_deg: float

    @property
    def rolling_mismatch(self) -> float:
        return self.rolled_input - self.rolled_output

    @property
    def convex(self) -> bool:
        return self.curvature_input > 0 and self.curvature_output > 0

    def lines(self) -> list[str]:
        def conc(r: float) -> str:
            return f"convex (smallest radius of curvature {r:.5g} mm)" if r > 0 else \
                f"concave in places (tightest concave radius {-r:.5g} mm)"
        return [f"pitch curves: input perimeter {self.input_length:.9g} mm, output {self.output_length:.9g} mm; "
                f"over a common period they roll {self.rolled_input:.9g} and {self.rolled_output:.9g} mm (pure rolling "
                f"mismatch {self.rolling_mismatch:.2e} mm); closed to {self.closure_gap:.2e} mm",
                f"speed ratio ψ' from {self.ratio_min:.6g} to {self.ratio_max:.6g}",
                f"input curve {conc(self.curvature_input)}; output curve {conc(self.curvature_output)}",
                f"pressure angle varies by up to {self.pressure_input_deg:.3f}° (input) and "
                f"{self.pressure_output_deg:.3f}° (output) from the tooth's nominal angle"]


@dataclass(frozen=True)
class GearKinematics:
    """A gear pair over one period of N samples at equal times.

    Arrays (N,): ``theta`` input progress angle (rad, from −π); ``t`` (s); ``psi`` ψ(θ) and its
    derivatives ``ratio`` ψ', ``d2`` ψ'', ``d3`` ψ'''; ``input_rotation`` / ``output_rotation``
    (rad, CCW, from the built frames); ``omega_out`` (rad/s), ``alpha_out`` (rad/s²), ``jerk_out``
    (rad/s³) of the output, CCW; ``r1`` / ``r2`` the pitch radii (mm). ``period`` (s), ``sense``
    the input's turning sense (±1), ``omega`` |ω_in| (rad/s)."""

    theta: np.ndarray
    t: np.ndarray
    psi: np.ndarray
    ratio: np.ndarray
    d2: np.ndarray
    d3: np.ndarray
    input_rotation: np.ndarray
    output_rotation: np.ndarray
    omega_out: np.ndarray
    alpha_out: np.ndarray
    jerk_out: np.ndarray
    r1: np.ndarray
    r2: np.ndarray
    period: float
    sense: float
    omega: float


def pitch_radii(a: float, ratio: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(r1, r2) mm at speed ratios ψ' (arrays)."""
    return a * ratio / (1.0 + ratio), a / (1.0 + ratio)


def curves(fn: GearFunction, a: float, sense: float, points: int) -> tuple[np.ndarray, np.ndarray]:
    """The input and output pitch curves in their body frames, closed polylines (M, 2) mm with M =
    ``points`` per period of each curve (the input's period is its lobe count of input turns)."""
    ev = FunctionEval(fn)
    turns_in = fn.lobes        # the output closes after this many input turns (q = 1/m)
    phi = np.linspace(0.0, 2 * math.pi, points + 1)
    psi, d1, _, _ = ev.derivatives(phi)
    r1, _ = pitch_radii(a, d1)
    c1 = r1[:, None] * np.stack([np.cos(-sense * phi), np.sin(-sense * phi)], axis=-1)
    phi2 = np.linspace(0.0, 2 * math.pi * turns_in, points * turns_in + 1)
    psi2, d12, _, _ = ev.derivatives(phi2)
    _, r2 = pitch_radii(a, d12)
    ang = math.pi + sense * psi2
    c2 = r2[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
    if fn.ratio > 1.0:   # the output closes after 1/q of an input turn: keep one output turn
        c2 = c2[: points // round(fn.ratio) + 1]
    return c1, c2


def _polar_checks(r: np.ndarray, dr: np.ndarray, d2r: np.ndarray) -> tuple[float, float]:
    """(smallest signed radius of curvature, largest |π/2 − μ| in degrees) of a polar curve r(t)
    with dr = dr/dt, d2r = d²r/dt² along its own polar angle t."""
    num = (r * r + dr * dr) ** 1.5
    den = r * r + 2.0 * dr * dr - r * d2r
    rho = num / den
    mu = np.arctan2(r, dr)          # angle between the radius vector and the tangent
    return float(rho.min()) if np.all(den > 0) else float(rho[den <= 0].max()), \
        float(np.degrees(np.max(np.abs(0.5 * math.pi - np.abs(mu)))))


def checks(fn: GearFunction, a: float, sense: float = 1.0) -> PitchChecks:
    """:class:`PitchChecks` of the pair (closed-form derivatives, Gauss–Legendre arc lengths)."""
    spline_ratio_problem(fn)
    ev = FunctionEval(fn)
    m = fn.lobes
    span = 2 * math.pi * m                      # a common period: m input turns, one output turn (q ≤ 1)
    x, w = np.polynomial.legendre.leggauss(_NODES)
    edges = np.linspace(0.0, span, _INTERVALS * m + 1)
    half = 0.5 * np.diff(edges)
    q = ((0.5 * (edges[1:] + edges[:-1]))[:, None] + half[:, None] * x[None, :]).ravel()
    wq = (half[:, None] * w[None, :]).ravel()
    _, p1, p2, p3 = ev.derivatives(q)
    r1, r2 = pitch_radii(a, p1)
    dr2 = -a * p2 / (1 + p1) ** 2                # dr2/dφ; dr1/dφ = −dr2/dφ
    d2r2 = -a * (p3 * (1 + p1) - 2 * p2 * p2) / (1 + p1) ** 3
    s1 = np.sqrt(r1 * r1 + dr2 * dr2)
    s2 = np.sqrt((r2 * p1) ** 2 + dr2 * dr2)
    rolled_in, rolled_out = float(wq @ s1), float(wq @ s2)
    per_turn = float(wq[: len(wq) // m] @ s1[: len(wq) // m])
    turns_out = fn.ratio * m                    # output turns over the common period
    # the input curve's polar angle is −σφ, the output's π + σψ: derivatives along each curve's own angle
    rc1, pr1 = _polar_checks(r1, -dr2, -d2r2)
    dr2_dpsi = dr2 / p1
    d2r2_dpsi = (d2r2 - dr2_dpsi * p2) / (p1 * p1)
    rc2, pr2 = _polar_checks(r2, dr2_dpsi, d2r2_dpsi)
    c1, c2 = curves(fn, a, sense, 2048)
    gap = max(float(np.hypot(*(c1[-1] - c1[0]))), float(np.hypot(*(c2[-1] - c2[0]))))
    lo, _, hi, _ = ev.ratio_range()
    return PitchChecks(per_turn, rolled_out / turns_out, rolled_in, rolled_out, gap, lo, hi, rc1, rc2, pr1, pr2)


def kinematics(fn: GearFunction, a: float, speed_rpm: float, samples: int,
               direction: float = 0.0) -> GearKinematics:
    """The pair over one input turn of ``samples`` equal time steps (see :class:`GearKinematics`);
    ``direction`` (rad) of the line of centres, input to output."""
    ev = FunctionEval(fn)
    n = int(samples)
    sense = 1.0 if speed_rpm > 0 else -1.0
    w = abs(speed_rpm) * math.pi / 30.0
    k = np.arange(n, dtype=float)
    theta = -math.pi + 2 * math.pi * k / n
    psi, p1, p2, p3 = ev.derivatives(theta)
    r1, r2 = pitch_radii(a, p1)
    period = 2 * math.pi / w
    return GearKinematics(theta, k * period / n, psi, p1, p2, p3, sense * theta, -sense * psi,
                          -sense * p1 * w, -sense * p2 * w * w, -sense * p3 * w ** 3, r1, r2, period, sense, w)
