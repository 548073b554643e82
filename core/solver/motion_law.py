"""Motion laws of a linkage's input over one cycle, in closed form with their time derivatives.

A law (:class:`~mechsketch.core.model.drivers.MotionLaw`) gives the input q(t) over a cycle of
period T = 60/|speed_rpm| s, and its rate q'(t) and acceleration q''(t) from the same closed form
(never from differences), so that the solver's velocities and accelerations are exact:

- the normalised rise laws :func:`profile` h(x), x ∈ [0, 1], h(0) = 0, h(1) = 1: constant speed
  (h = x), cycloidal (x − sin 2πx / 2π), harmonic ((1 − cos πx)/2) and the modified trapezoid
  (sine ramps over eighths, constant acceleration between; peak h'' = 4.888);
- a table of points through which a periodic cubic spline passes (:class:`PeriodicSpline`:
  continuous with its first and second derivatives, also across the end of the cycle).

A crank makes one turn per cycle: q = θ0 + s·2π·h(t/T) (s the sign of ``speed_rpm``), or θ0 plus
the table's degrees. An actuator rises from the stroke's start a to its end b in the first half
cycle and returns in the second: q = a + (b − a)·h(2t/T), then b − (b − a)·h(2t/T − 1); or the
table's millimetres. Arrays are (N,): samples on the leading axis.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, RequestError
from ..model.drivers import LawKind, MotionLaw
from ..model.linkage import Driver

TWO_PI = 2.0 * math.pi

# modified trapezoid: a = A sin 4πx on [0, 1/8], A on [1/8, 3/8], A cos 4π(x − 3/8) on [3/8, 1/2],
# odd about x = 1/2; A makes h(1/2) = 1/2
_V1 = 1.0 / (4.0 * math.pi)                          # h'/A at 1/8
_H1 = _V1 * (0.125 - 1.0 / (4.0 * math.pi))          # h/A at 1/8
_V2 = _V1 + 0.25                                     # h'/A at 3/8
_H2 = _H1 + _V1 * 0.25 + 0.25 * 0.25 / 2.0           # h/A at 3/8
MODTRAP_PEAK = 1.0 / (2.0 * (_H2 + _V2 * 0.125 + 1.0 / (16.0 * math.pi ** 2)))


def _modtrap_half(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """h, h', h'' of the modified trapezoid on x ∈ [0, 1/2]."""
    A = MODTRAP_PEAK
    k = 4.0 * math.pi
    s1, s2 = x, x - 0.125
    s3 = x - 0.375
    seg1, seg2 = x <= 0.125, (x > 0.125) & (x <= 0.375)
    h = np.where(seg1, A * _V1 * (s1 - np.sin(k * s1) / k),
                 np.where(seg2, A * (_H1 + _V1 * s2 + s2 * s2 / 2.0),
                          A * (_H2 + _V2 * s3 + (1.0 - np.cos(k * s3)) / (k * k))))
    v = np.where(seg1, A * _V1 * (1.0 - np.cos(k * s1)),
                 np.where(seg2, A * (_V1 + s2), A * (_V2 + np.sin(k * s3) / k)))
    a = np.where(seg1, A * np.sin(k * s1), np.where(seg2, A, A * np.cos(k * s3)))
    return h, v, a


def profile(kind: LawKind, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The normalised rise h(x) and its derivatives h'(x), h''(x) for x ∈ [0, 1] (arrays (N,)).

    h(0) = 0 and h(1) = 1 for every kind; cycloidal and modified trapezoid also start and end with
    h' = h'' = 0, harmonic with h' = 0. ``kind`` is one of the shaped laws or constant (h = x).
    """
    x = np.asarray(x, dtype=float)
    if kind is LawKind.CONSTANT:
        return x.copy(), np.ones_like(x), np.zeros_like(x)
    if kind is LawKind.CYCLOIDAL:
        w = TWO_PI * x
        return x - np.sin(w) / TWO_PI, 1.0 - np.cos(w), TWO_PI * np.sin(w)
    if kind is LawKind.HARMONIC:
        w = math.pi * x
        return (1.0 - np.cos(w)) / 2.0, (math.pi / 2.0) * np.sin(w), (math.pi ** 2 / 2.0) * np.cos(w)
    if kind is LawKind.MODIFIED_TRAPEZOID:
        lo = x <= 0.5
        h1, v1, a1 = _modtrap_half(np.where(lo, x, 0.0))
        h2, v2, a2 = _modtrap_half(np.where(lo, 0.0, 1.0 - x))
        return np.where(lo, h1, 1.0 - h2), np.where(lo, v1, v2), np.where(lo, a1, -a2)
    raise GeometryError(f"{kind} is not a rise law")


class PeriodicSpline:
    """The periodic cubic spline (period 1) through (τ_k, y_k), τ_0 = 0 < τ_1 < … < 1, continuous
    with its first and second derivatives everywhere, plus a linear trend ``slope``·τ (a crank's
    whole turns). Evaluates value, first and second derivative in τ for any real τ."""

    def __init__(self, tau, y, slope: float = 0.0) -> None:
        self.tau = np.asarray(tau, dtype=float)
        self.slope = float(slope)
        p = np.asarray(y, dtype=float) - self.slope * self.tau
        m = self.tau.size
        h = np.diff(np.append(self.tau, 1.0 + self.tau[0]))
        if m < 3 or np.any(h <= 0.0):
            raise GeometryError("a table law needs at least 3 points at increasing cycle fractions in [0, 1)")
        A = np.zeros((m, m))
        rhs = np.empty(m)
        for k in range(m):
            hp, hk = h[k - 1], h[k]
            A[k, (k - 1) % m] += hp
            A[k, k] += 2.0 * (hp + hk)
            A[k, (k + 1) % m] += hk
            rhs[k] = 6.0 * ((p[(k + 1) % m] - p[k]) / hk - (p[k] - p[k - 1]) / hp)
        self.p, self.h = p, h
        self.M = np.linalg.solve(A, rhs)

    def __call__(self, tau) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(S, S', S'') at ``tau`` (array (N,)), derivatives with respect to τ."""
        tau = np.asarray(tau, dtype=float)
        turns = np.floor(tau)
        f = tau - turns
        m = self.tau.size
        k = np.clip(np.searchsorted(self.tau, f, side="right") - 1, 0, m - 1)
        k1 = (k + 1) % m
        h, Mk, Mk1, pk, pk1 = self.h[k], self.M[k], self.M[k1], self.p[k], self.p[k1]
        s = f - self.tau[k]
        a = h - s
        ck, ck1 = pk / h - Mk * h / 6.0, pk1 / h - Mk1 * h / 6.0
        val = (Mk * a ** 3 + Mk1 * s ** 3) / (6.0 * h) + ck * a + ck1 * s
        d1 = (-Mk * a * a + Mk1 * s * s) / (2.0 * h) - ck + ck1
        d2 = (Mk * a + Mk1 * s) / h
        return val + self.slope * tau, d1 + self.slope, d2


def table_spline(law: MotionLaw, crank: bool) -> PeriodicSpline:
    """The spline of a table law: the points before τ = 1; a point at τ = 1 sets a crank's whole
    turns (its value minus the first, 360° per turn; an actuator's must repeat the first)."""
    pts = list(law.points)
    slope = 0.0
    if pts and pts[-1][0] >= 1.0:
        last = pts.pop()
        if crank:
            slope = last[1] - pts[0][1]
    return PeriodicSpline([t for t, _ in pts], [v for _, v in pts], slope)


@dataclass
class InputMotion:
    """The input over the samples of a cycle: time ``t`` (s), input ``q`` (rad or mm), its rate
    ``qd`` (rad/s or mm/s) and acceleration ``qdd`` (rad/s² or mm/s²); float (N,) (``qd``/``qdd``
    may be scalars for a crank at constant speed)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray | float
    qdd: np.ndarray | float


def at_times(driver: Driver, input0: float, t) -> InputMotion:
    """The input of ``driver`` at times ``t`` (s, array (N,)); ``input0`` is the drawn input (a
    crank's drawn angle, rad; unused by an actuator, whose stroke is absolute)."""
    t = np.asarray(t, dtype=float)
    T = driver.period
    if not (math.isfinite(T) and T > 0.0):
        raise RequestError(f"driver {driver.link!r}: a cycle of {T:g} s (speed {driver.speed_rpm:g} rpm) has no "
                           "motion law; give a speed from 0.001 to 100,000 cycles per minute")
    tau = t / T
    law = driver.law
    if not driver.linear:
        sgn = 1.0 if driver.speed_rpm >= 0 else -1.0
        if law.kind is LawKind.TABLE:
            v, d1, d2 = table_spline(law, crank=True)(tau)
            return InputMotion(t, input0 + np.radians(v), np.radians(d1) / T, np.radians(d2) / (T * T))
        turns = np.floor(tau)
        h, d1, d2 = profile(law.kind, tau - turns)
        return InputMotion(t, input0 + sgn * TWO_PI * (turns + h), sgn * TWO_PI * d1 / T,
                           sgn * TWO_PI * d2 / (T * T))
    lo, hi = driver.stroke
    if law.kind is LawKind.TABLE:
        v, d1, d2 = table_spline(law, crank=False)(tau)
        return InputMotion(t, v, d1 / T, d2 / (T * T))
    f = tau - np.floor(tau)
    rise = f < 0.5
    x = np.where(rise, 2.0 * f, 2.0 * f - 1.0)
    h, d1, d2 = profile(law.kind, x)
    span = hi - lo
    q = np.where(rise, lo + span * h, hi - span * h)
    qd = np.where(rise, 1.0, -1.0) * span * d1 * (2.0 / T)
    qdd = np.where(rise, 1.0, -1.0) * span * d2 * (4.0 / (T * T))
    return InputMotion(t, q, qd, qdd)


def cycle(driver: Driver, input0: float, samples: int) -> InputMotion:
    """The input at the N = ``samples`` times t_k = k·T/N of one cycle (k = 0 … N−1).

    A crank at constant speed gives q_k = θ0 + s·(2π/N)·k and the scalar rate ω, exactly as the
    solver always sampled it (so that results stay bit for bit the same).
    """
    n = int(samples)
    k = np.arange(n)
    if not driver.linear and driver.law.is_constant:
        sgn = 1.0 if driver.omega >= 0 else -1.0
        inputs = input0 + sgn * (2.0 * math.pi / n) * k
        t = k * (2.0 * math.pi / abs(driver.omega) / n)
        return InputMotion(t, inputs, driver.omega, 0.0)
    return at_times(driver, input0, k * (driver.period / n))


__all__ = ["InputMotion", "MODTRAP_PEAK", "PeriodicSpline", "at_times", "cycle", "profile", "table_spline"]
