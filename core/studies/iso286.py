"""ISO 286-1 limits and fits for pin clearances: ``fit("H7/g6", 12.0)``.

A fit names a hole (upper-case letter(s) and a tolerance grade) and a shaft (lower case) on one
nominal diameter. The hole's and the shaft's limits are the standard tolerance IT of their grade
(Table 1 of ISO 286-1, nominal sizes up to 500 mm) placed by the fundamental deviation of their
letter (Tables 2-3): shafts d, e, f, g, h (es below zero), js (±IT/2), k, m, n, p (ei above zero);
holes D, E, F, G, H (EI = −es of the same shaft letter, the general rule) and JS. The clearance
of a fitted pin is hole − shaft: from ``clearance_min`` to ``clearance_max`` (mm; negative is
interference). A pin's *radial play* is half its clearance, not below zero.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from ..errors import RequestError

#: upper bounds (mm) of the nominal size ranges ("over a, up to and including b")
RANGES = (3, 6, 10, 18, 30, 50, 80, 120, 180, 250, 315, 400, 500)
#: standard tolerance grades, µm, per range
IT = {
    1: (0.8, 1, 1, 1.2, 1.5, 1.5, 2, 2.5, 3.5, 4.5, 6, 7, 8),
    2: (1.2, 1.5, 1.5, 2, 2.5, 2.5, 3, 4, 5, 7, 8, 9, 10),
    3: (2, 2.5, 2.5, 3, 4, 4, 5, 6, 8, 10, 12, 13, 15),
    4: (3, 4, 4, 5, 6, 7, 8, 10, 12, 14, 16, 18, 20),
    5: (4, 5, 6, 8, 9, 11, 13, 15, 18, 20, 23, 25, 27),
    6: (6, 8, 9, 11, 13, 16, 19, 22, 25, 29, 32, 36, 40),
    7: (10, 12, 15, 18, 21, 25, 30, 35, 40, 46, 52, 57, 63),
    8: (14, 18, 22, 27, 33, 39, 46, 54, 63, 72, 81, 89, 97),
    9: (25, 30, 36, 43, 52, 62, 74, 87, 100, 115, 130, 140, 155),
    10: (40, 48, 58, 70, 84, 100, 120, 140, 160, 185, 210, 230, 250),
    11: (60, 75, 90, 110, 130, 160, 190, 220, 250, 290, 320, 360, 400),
    12: (100, 120, 150, 180, 210, 250, 300, 350, 400, 460, 520, 570, 630),
}
#: upper deviations es (µm) of the clearance shafts
SHAFT_ES = {
    "d": (-20, -30, -40, -50, -65, -80, -100, -120, -145, -170, -190, -210, -230),
    "e": (-14, -20, -25, -32, -40, -50, -60, -72, -85, -100, -110, -125, -135),
    "f": (-6, -10, -13, -16, -20, -25, -30, -36, -43, -50, -56, -62, -68),
    "g": (-2, -4, -5, -6, -7, -9, -10, -12, -14, -15, -17, -18, -20),
    "h": (0,) * 13,
}
#: lower deviations ei (µm) of the transition and interference shafts (k: grades 4 to 7)
SHAFT_EI = {
    "k": (0, 1, 1, 1, 2, 2, 2, 3, 3, 4, 4, 4, 5),
    "m": (2, 4, 6, 7, 8, 9, 11, 13, 15, 17, 20, 21, 23),
    "n": (4, 8, 10, 12, 15, 17, 20, 23, 27, 31, 34, 37, 40),
    "p": (6, 12, 15, 18, 22, 26, 32, 37, 43, 50, 56, 62, 68),
}
HOLES = ("D", "E", "F", "G", "H", "JS")
SHAFTS = ("d", "e", "f", "g", "h", "js", "k", "m", "n", "p")
_ZONE = re.compile(r"^\s*([A-Za-z]{1,2})(\d{1,2})\s*$")


@dataclass(frozen=True)
class Fit:
    """A fit on one nominal ``diameter`` (mm): the hole's and the shaft's limits as deviations
    from it (mm): ``hole`` (EI, ES) and ``shaft`` (ei, es)."""

    name: str
    diameter: float
    hole: tuple[float, float]
    shaft: tuple[float, float]

    @property
    def clearance_min(self) -> float:
        """The smallest clearance, mm (hole at its least, shaft at its greatest)."""
        return self.hole[0] - self.shaft[1]

    @property
    def clearance_max(self) -> float:
        return self.hole[1] - self.shaft[0]

    def radial_play(self, rng: np.random.Generator, n: int, distribution: str = "uniform") -> np.ndarray:
        """(n,) radial play (mm) of n pins: hole and shaft diameters drawn independently within
        their limits (``uniform``; ``normal``: the limits at ±3σ about the middle), half the
        clearance, not below zero."""
        if distribution == "normal":
            h = rng.normal(0.5 * (self.hole[0] + self.hole[1]), (self.hole[1] - self.hole[0]) / 6.0, n)
            s = rng.normal(0.5 * (self.shaft[0] + self.shaft[1]), (self.shaft[1] - self.shaft[0]) / 6.0, n)
        else:
            h = rng.uniform(self.hole[0], self.hole[1], n)
            s = rng.uniform(self.shaft[0], self.shaft[1], n)
        return np.maximum(h - s, 0.0) * 0.5

    @property
    def mean_square_play(self) -> float:
        """E[r²] (mm²) of the radial play with uniform limits, ignoring interference (for the
        first-order variance of a clearance)."""
        a = 0.5 * (self.hole[0] - self.shaft[1])
        w1, w2 = 0.5 * (self.hole[1] - self.hole[0]), 0.5 * (self.shaft[1] - self.shaft[0])
        mean = a + 0.5 * (w1 + w2)
        return max(mean, 0.0) ** 2 + (w1 * w1 + w2 * w2) / 12.0


def _range(d: float) -> int:
    if not 0.0 < d <= RANGES[-1]:
        raise RequestError(f"ISO 286 fits are tabled here for nominal diameters above 0 and up to {RANGES[-1]} mm; "
                           f"got {d:g} mm")
    return next(i for i, hi in enumerate(RANGES) if d <= hi)


def _zone(text: str, hole: bool) -> tuple[str, int]:
    m = _ZONE.match(text)
    known = HOLES if hole else SHAFTS
    if not m or m.group(1) not in known or int(m.group(2)) not in IT:
        what = "hole" if hole else "shaft"
        raise RequestError(f"unknown ISO 286 {what} tolerance zone {text.strip()!r}: give a letter of "
                           f"{', '.join(known)} and a grade IT1 to IT12, e.g. {'H7' if hole else 'g6'}")
    return m.group(1), int(m.group(2))


def _shaft(letter: str, grade: int, r: int) -> tuple[float, float]:
    it = IT[grade][r]
    if letter in SHAFT_ES:
        es = SHAFT_ES[letter][r]
        return (es - it) * 1e-3, es * 1e-3
    if letter == "js":
        return -0.5 * it * 1e-3, 0.5 * it * 1e-3
    ei = SHAFT_EI[letter][r] if (letter != "k" or 4 <= grade <= 7) else 0
    return ei * 1e-3, (ei + it) * 1e-3


def _hole(letter: str, grade: int, r: int) -> tuple[float, float]:
    it = IT[grade][r]
    if letter == "JS":
        return -0.5 * it * 1e-3, 0.5 * it * 1e-3
    ei = -SHAFT_ES[letter.lower()][r]
    return ei * 1e-3, (ei + it) * 1e-3


def fit(name: str, diameter: float) -> Fit:
    """The fit ``name`` (``"H7/g6"``) on ``diameter`` mm; RequestError naming an unknown zone or
    a diameter outside the tables."""
    if not isinstance(name, str) or name.count("/") != 1:
        raise RequestError(f"a fit is written hole/shaft, e.g. 'H7/g6'; got {name!r}")
    h, s = name.split("/")
    (hl, hg), (sl, sg) = _zone(h, True), _zone(s, False)
    r = _range(float(diameter))
    return Fit(name.strip(), float(diameter), _hole(hl, hg, r), _shaft(sl, sg, r))


__all__ = ["Fit", "HOLES", "SHAFTS", "fit"]
