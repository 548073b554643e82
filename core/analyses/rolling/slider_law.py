"""A slider law S5(θ) evaluated (:class:`LawCurve`): the pair-E input of a rolling lever whose
slider's displacement is prescribed (see :mod:`.law` for the profiles it gives).
"""
from __future__ import annotations

import math

import numpy as np

from ...model.drivers import LawKind
from ...model.rolling_lever import SliderLaw, Stroke
from ...solver.motion_law import profile


class LawCurve:
    """S5(θ) (mm), S5'(θ) (mm/rad) and S5''(θ) (mm/rad²) of a :class:`SliderLaw` over a stroke."""

    def __init__(self, law: SliderLaw, stroke: Stroke) -> None:
        self.law = law
        self.kind = law.kind
        if law.kind == "table":
            from scipy.interpolate import make_interp_spline   # heavy; only for a table law

            pts = sorted(law.table)
            x = np.array([p[0] for p in pts])
            y = np.array([p[1] for p in pts])
            self._spline = make_interp_spline(x, y, k=5 if len(x) >= 6 else 3)
            self._d1 = self._spline.derivative(1)
            self._d2 = self._spline.derivative(2)
        else:
            self._lk = LawKind(law.kind)
            self.th0 = stroke.start
            self.span = stroke.span
            self.travel = law.travel

    def values(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(S5, S5', S5'') at θ (array (N,) rad)."""
        th = np.asarray(theta, dtype=float)
        if self.kind == "table":
            return self._spline(th), self._d1(th), self._d2(th)
        h, h1, h2 = profile(self._lk, (th - self.th0) / self.span)
        return self.travel * h, self.travel * h1 / self.span, self.travel * h2 / self.span ** 2

    def rate(self, theta: float) -> float:
        """S5'(θ) for one θ (rad): the ODE's dS5/dθ, called per step."""
        if self.kind == "table":
            return float(self._d1(theta))
        x = (theta - self.th0) / self.span
        if self._lk is LawKind.CYCLOIDAL:
            h1 = 1.0 - math.cos(2.0 * math.pi * x)
        elif self._lk is LawKind.HARMONIC:
            h1 = 0.5 * math.pi * math.sin(math.pi * x)
        elif self._lk is LawKind.CONSTANT:
            h1 = 1.0
        else:
            h1 = float(profile(self._lk, np.array([x]))[1][0])
        return self.travel * h1 / self.span

    def rates(self, theta: np.ndarray) -> np.ndarray:
        """S5'(θ) at θ (N,) rad."""
        return self.values(theta)[1]
