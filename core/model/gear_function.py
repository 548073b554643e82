"""A gear pair's transmission function ψ(φ): the authored record and its parsing (no numpy:
the model loads without it; the evaluation is :mod:`mechsketch.core.analyses.gears.function`).

:class:`FunctionEval` turns a :class:`~.gear_pair.GearFunction` into arrays: ψ, ψ' (the speed
ratio ω_out/ω_in), ψ'' and ψ''' at input angles φ (rad, arrays (N,)), in closed form for the
Fourier and elliptic functions and from a periodic quintic spline for a table; :meth:`inverse`
gives φ(ψ) (Newton on the monotone function). Used by the element's checks (the speed ratio must
stay within its range over a whole turn) and by the analyses (pitch curves, a crank driven
through the gears).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

#: the slowest and fastest speed ratio ψ' a pair may have (the pitch radii a·ψ'/(1 + ψ') and
#: a/(1 + ψ') stay above a/21)
MIN_RATIO, MAX_RATIO = 0.05, 20.0


@dataclass(frozen=True)
class GearFunction:
    """The transmission function ψ(φ) (rad) of a gear pair; see the module docstring."""

    kind: str
    ratio: float = 1.0
    sin: tuple[float, ...] = ()
    cos: tuple[float, ...] = ()
    eccentricity: float = 0.0
    table: tuple[tuple[float, float], ...] = ()

    def to_dict(self) -> dict:
        if self.kind == "fourier":
            return {"fourier": {"ratio": self.ratio, "sin": list(self.sin), "cos": list(self.cos)}}
        if self.kind == "elliptic":
            return {"elliptic": {"eccentricity": self.eccentricity}}
        return {"table": [[a, b] for a, b in self.table], "ratio": self.ratio}

    @property
    def lobes(self) -> int:
        """Input turns per output turn when the ratio is 1/m (m), else 1."""
        return round(1.0 / self.ratio) if self.ratio < 1.0 else 1


def parse_function(data: Any, where: str, bad) -> GearFunction | None:
    """A transmission function dict (schema-checked) as a record, or None (problems to ``bad``)."""
    kinds = [k for k in ("fourier", "elliptic", "table") if k in data]
    if len(kinds) != 1:
        bad(where, "give one of 'fourier', 'elliptic' or 'table' (with 'ratio')")
        return None
    if kinds[0] == "elliptic":
        e = float(data["elliptic"]["eccentricity"])
        if not 0.0 <= e < 0.95:
            bad(f"{where}.elliptic.eccentricity", f"must lie in [0, 0.95) (the speed ratio then stays within "
                                                  f"{MIN_RATIO:g}..{MAX_RATIO:g}); got {e:g}")
            return None
        return GearFunction("elliptic", 1.0, eccentricity=e)
    if kinds[0] == "fourier":
        fd = data["fourier"]
        q = float(fd.get("ratio", 1.0))
        fn = GearFunction("fourier", q, tuple(float(x) for x in fd.get("sin", ())),
                          tuple(float(x) for x in fd.get("cos", ())))
    else:
        pts = tuple((float(a), float(b)) for a, b in data["table"])
        q = float(data.get("ratio", 1.0))
        phis, psis = [a for a, _ in pts], [b for _, b in pts]
        if any(b <= a for a, b in zip(phis, phis[1:])) or phis[-1] - phis[0] >= 2 * math.pi:
            bad(f"{where}.table", "φ must increase strictly over less than one turn (2π rad)")
            return None
        if any(b <= a for a, b in zip(psis, psis[1:])) or psis[-1] - psis[0] >= 2 * math.pi * q:
            bad(f"{where}.table", "ψ must increase strictly, by less than 2π·ratio over the table")
            return None
        fn = GearFunction("table", q, table=pts)
    if not _whole_or_inverse(q):
        bad(f"{where}.ratio" if kinds[0] == "table" else f"{where}.fourier.ratio",
            f"the mean ratio (output turns per input turn) must be a whole number or its inverse so that "
            f"both pitch curves close; got {q:g}")
        return None
    if kinds[0] == "fourier" and q > 1.0:
        m = round(q)
        off = [k + 1 for k, (s, c) in enumerate(zip(fn.sin + (0.0,) * len(fn.cos), fn.cos + (0.0,) * len(fn.sin)))
               if (s or c) and (k + 1) % m]
        if off:
            bad(f"{where}.fourier", f"with ratio {m} the output pitch curve closes only if the speed ratio repeats "
                                    f"{m} times per input turn: harmonics {off} are not multiples of {m}")
            return None
    return fn


def _whole_or_inverse(q: float) -> bool:
    if not (math.isfinite(q) and q > 0):
        return False
    m = q if q >= 1 else 1.0 / q
    return abs(m - round(m)) <= 1e-9 * m and 1 <= round(m) <= 12



#: points per input turn on which the model checks the speed ratio's range
RANGE_GRID = 4096


def _ratio_pure(fn: GearFunction, phi: float) -> float:
    """ψ'(φ) in plain floats (Fourier and elliptic functions)."""
    if fn.kind == "elliptic":
        k = (1.0 + fn.eccentricity) / (1.0 - fn.eccentricity)
        return k / (math.cos(0.5 * phi) ** 2 + k * k * math.sin(0.5 * phi) ** 2)
    out = fn.ratio
    for j, s in enumerate(fn.sin, start=1):
        out += j * s * math.cos(j * phi)
    for j, c in enumerate(fn.cos, start=1):
        out -= j * c * math.sin(j * phi)
    return out


def ratio_problem(fn: GearFunction) -> str | None:
    """The message when the speed ratio ψ' leaves [MIN_RATIO, MAX_RATIO] over a turn, else None:
    on a grid of :data:`RANGE_GRID` points for a Fourier or elliptic function; for a table, on the
    secant slopes between its points (the spline's own range is checked when the pitch curves are
    built: :func:`mechsketch.core.analyses.gears.function.spline_ratio_problem`)."""
    if fn.kind == "table":
        pts = list(fn.table) + [(fn.table[0][0] + 2 * math.pi, fn.table[0][1] + 2 * math.pi * fn.ratio)]
        slopes = [((b[1] - a[1]) / (b[0] - a[0]), a[0]) for a, b in zip(pts, pts[1:])]
    else:
        grid = [-math.pi + 2 * math.pi * i / RANGE_GRID for i in range(RANGE_GRID)]
        slopes = [(_ratio_pure(fn, x), x) for x in grid]
    lo, at_lo = min(slopes)
    hi, at_hi = max(slopes)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return "the speed ratio ψ' is not a finite number everywhere"
    if lo < MIN_RATIO:
        return (f"the speed ratio ψ' falls to {lo:.4g} at φ = {math.degrees(at_lo):.4g}° (it must stay at least "
                f"{MIN_RATIO:g}: the input gear's pitch radius a·ψ'/(1 + ψ') would vanish)")
    if hi > MAX_RATIO:
        return (f"the speed ratio ψ' reaches {hi:.4g} at φ = {math.degrees(at_hi):.4g}° (at most {MAX_RATIO:g}: the "
                "output gear's pitch radius a/(1 + ψ') would vanish)")
    return None
