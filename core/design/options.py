"""Options and results shared by the linkage syntheses (path, motion, function).

:class:`LinkageOptions` holds what the designer may ask of every candidate (how many, the least
transmission angle, a fully turning crank, where the fixed pivots may go, how large the linkage
may be); :class:`DesignResult` is what a synthesis returns: the candidates best first, the time
and notes on what was tried. Both are plain records, safe to pass between threads.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .candidates import Candidate
from .targets import DesignError


@dataclass(frozen=True)
class LinkageOptions:
    """What every candidate must satisfy.

    ``candidates``: how many to return (K ≥ 1); ``min_transmission_deg``: the least transmission
    angle over the target span (°, 0 to 90); ``full_turn``: the crank must turn fully (a Grashof
    crank, or a slider-crank whose crank turns); ``grashof``: the four-bar type asked for, one of
    None (any), "crank-rocker", "double crank"; ``pivot_region``: (xmin, ymin, xmax, ymax) mm that
    the fixed pivots must lie in, or None; ``max_size``: the fixed pivots lie within this many
    target sizes of the target's centre, and no link is longer (a guard against pivots at
    infinity); ``max_deviation``: a candidate's largest deviation from the target (mm for a path
    or poses, the output's unit for a function) must not exceed it (None: the best that can be
    had; with it, a target no linkage asked for reaches that closely is refused); ``speed_rpm``,
    ``samples``: the candidates' driver speed and samples per cycle;
    ``prefix``: the candidates' element ids are ``prefix_1``, ``prefix_2``, ..."""

    candidates: int = 5
    min_transmission_deg: float = 30.0
    full_turn: bool = False
    grashof: str | None = None
    pivot_region: tuple[float, float, float, float] | None = None
    max_size: float = 5.0
    max_deviation: float | None = None
    speed_rpm: float = 60.0
    samples: int = 360
    prefix: str = "candidate"

    def check(self) -> "LinkageOptions":
        """Itself, or DesignError naming the option out of range."""
        if not 1 <= self.candidates <= 1000:
            raise DesignError(f"candidates must be from 1 to 1000, got {self.candidates}")
        if not 0.0 <= self.min_transmission_deg < 90.0:
            raise DesignError(f"the minimum transmission angle must be from 0 to 90°, got {self.min_transmission_deg}")
        if self.grashof not in (None, "crank-rocker", "double crank"):
            raise DesignError(f"grashof type must be 'crank-rocker' or 'double crank', got {self.grashof!r}")
        if self.pivot_region is not None:
            r = self.pivot_region
            if len(r) != 4 or not all(math.isfinite(v) for v in r) or not (r[0] < r[2] and r[1] < r[3]):
                raise DesignError(f"pivot region must be xmin, ymin, xmax, ymax with xmin < xmax and ymin < ymax, got {r}")
        if not self.max_size > 0.0:
            raise DesignError(f"max_size must be positive, got {self.max_size}")
        if self.max_deviation is not None and not (math.isfinite(self.max_deviation) and self.max_deviation > 0):
            raise DesignError(f"the maximum deviation must be a positive number, got {self.max_deviation}")
        return self

    def pivot_ok(self, z: np.ndarray, centre: complex, size: float) -> np.ndarray:
        """(…,) bool: fixed pivots ``z`` (complex mm) allowed by the region and the size guard."""
        ok = np.abs(z - centre) <= self.max_size * size
        if self.pivot_region is not None:
            x0, y0, x1, y1 = self.pivot_region
            ok &= (z.real >= x0) & (z.real <= x1) & (z.imag >= y0) & (z.imag <= y1)
        return ok


@dataclass
class DesignResult:
    """The candidates, best first, the total time (s), notes on the search (what was tried,
    why there are fewer than asked) and the seconds of each stage (``timings``: e.g. "atlas",
    "retrieve", "refine", "drive" — the solver's checks —, "cut" — validate's part check)."""

    candidates: list[Candidate]
    seconds: float
    notes: list[str] = field(default_factory=list)
    timings: dict = field(default_factory=dict)

    def lines(self) -> list[str]:
        """One line per candidate (rank, deviation, transmission angle, type, time)."""
        return [c.line(k + 1) for k, c in enumerate(self.candidates)]


__all__ = ["DesignResult", "LinkageOptions"]
