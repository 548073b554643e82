"""Evaluation of a gear pair's transmission function ψ(φ) with its first three derivatives.

:class:`FunctionEval` turns a :class:`~mechsketch.core.model.gear_function.GearFunction` into
arrays: ψ, its first three derivatives (the first the speed ratio ω_out/ω_in) at input angles φ
(rad, arrays of any shape), in closed form for the Fourier and elliptic functions and from a
periodic quintic spline for a table; :meth:`FunctionEval.inverse` gives φ(ψ) (Newton on the
monotone function). :func:`spline_ratio_problem` checks a table's spline keeps the speed ratio in
its range between the table's points.
"""
from __future__ import annotations

import math

import numpy as np

from ...errors import GeometryError
from ...model.gear_function import MAX_RATIO, MIN_RATIO, GearFunction

#: points per input turn on which the speed ratio's range is checked 
RANGE_GRID = 4096


class FunctionEval:
    """ψ(φ) and derivatives of ``fn`` (see the module docstring)."""

    def __init__(self, fn: GearFunction) -> None:
        self.fn = fn
        self.q = fn.ratio
        if fn.kind == "elliptic":
            self.k = (1.0 + fn.eccentricity) / (1.0 - fn.eccentricity)
        elif fn.kind == "fourier":
            n = max(len(fn.sin), len(fn.cos))
            self.ks = np.arange(1, n + 1, dtype=float)
            self.s = np.array(fn.sin + (0.0,) * (n - len(fn.sin)))
            self.c = np.array(fn.cos + (0.0,) * (n - len(fn.cos)))
        else:
            from scipy.interpolate import make_interp_spline   # heavy; only for a table

            x = np.array([p[0] for p in fn.table])
            g = np.array([p[1] for p in fn.table]) - self.q * x
            self.x0 = float(x[0])
            self.g0 = float(g[0])
            xs = np.append(x, x[0] + 2 * math.pi)
            gs = np.append(g, g[0])
            self._sp = make_interp_spline(xs, gs, k=5 if len(x) >= 6 else 3, bc_type="periodic")
            self._d = [self._sp.derivative(k) for k in (1, 2, 3)]

    def derivatives(self, phi) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(ψ, ψ', ψ'', ψ''') at φ (array (N,) rad)."""
        phi = np.asarray(phi, dtype=float)
        if self.fn.kind == "elliptic":
            k = self.k
            h = 0.5 * phi
            a, b = 0.5 * (1 + k * k), 0.5 * (1 - k * k)
            d = a + b * np.cos(phi)           # cos²(φ/2) + k² sin²(φ/2)
            d1, d2 = -b * np.sin(phi), -b * np.cos(phi)
            psi = phi + 2.0 * np.arctan2((k - 1.0) * np.sin(h) * np.cos(h), np.cos(h) ** 2 + k * np.sin(h) ** 2)
            return psi, k / d, -k * d1 / d ** 2, -k * (d2 * d - 2.0 * d1 * d1) / d ** 3
        if self.fn.kind == "fourier":
            flat = phi.ravel()
            kp = np.outer(flat, self.ks)
            sn, cs = np.sin(kp), np.cos(kp)
            k1, k2, k3 = self.ks, self.ks ** 2, self.ks ** 3
            psi = self.q * flat + sn @ self.s + (cs - 1.0) @ self.c
            p1 = self.q + cs @ (k1 * self.s) - sn @ (k1 * self.c)
            p2 = -(sn @ (k2 * self.s)) - cs @ (k2 * self.c)
            p3 = -(cs @ (k3 * self.s)) + sn @ (k3 * self.c)
            return tuple(v.reshape(phi.shape) for v in (psi, p1, p2, p3))
        # table: the periodic part g(φ) = ψ − q·φ, evaluated modulo the period from its first point
        turns = np.floor((phi - self.x0) / (2 * math.pi))
        x = phi - 2 * math.pi * turns
        return (self.q * phi + self._sp(x), self.q + self._d[0](x), self._d[1](x), self._d[2](x))

    def value(self, phi) -> np.ndarray:
        return self.derivatives(phi)[0]

    def ratio_range(self) -> tuple[float, float, float, float]:
        """(smallest ψ', at φ, largest ψ', at φ) over one input turn (grid, then a parabola through
        the best point and its neighbours)."""
        grid = np.linspace(-math.pi, math.pi, RANGE_GRID, endpoint=False)
        p1 = self.derivatives(grid)[1]
        out = []
        for sign in (1.0, -1.0):
            k = int(np.argmin(sign * p1))
            out += [float(p1[k]), float(grid[k])]
        return out[0], out[1], out[2], out[3]

    def inverse(self, psi, guess=None) -> np.ndarray:
        """φ with ψ(φ) = ``psi`` (array (N,)), Newton from ``guess`` (default ψ/q), to rounding."""
        psi = np.asarray(psi, dtype=float)
        phi = psi / self.q if guess is None else np.asarray(guess, dtype=float).copy()
        for _ in range(60):
            v, d1, _, _ = self.derivatives(phi)
            step = (v - psi) / d1
            phi = phi - step
            if np.all(np.abs(step) <= 4e-16 * (1.0 + np.abs(phi))):
                break
        return phi



def spline_ratio_problem(fn: GearFunction) -> None:
    """Raise :class:`GeometryError` when a table's spline takes the speed ratio out of
    [MIN_RATIO, MAX_RATIO] between its points (the model checked the secants only)."""
    if fn.kind != "table":
        return
    lo, at_lo, hi, at_hi = FunctionEval(fn).ratio_range()
    if not (MIN_RATIO <= lo and hi <= MAX_RATIO):
        bad, at = (lo, at_lo) if lo < MIN_RATIO else (hi, at_hi)
        raise GeometryError(f"the table's spline takes the speed ratio to {bad:.4g} at φ = {math.degrees(at):.4g}° "
                            f"(it must stay within {MIN_RATIO:g}..{MAX_RATIO:g}): add points or smooth the table")
