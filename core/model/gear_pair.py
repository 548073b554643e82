"""The authored non-circular gear pair: two pivots and the transmission function ψ(φ) (issue 25, 3-4).

Type ``gear_pair``. The input gear turns about ``input_center`` (its rotation φ, rad), the output
gear about the point ``center_distance`` a (mm) away at ``direction_deg``; they are external gears,
so the output turns the other way: its rotation is −ψ(φ). The function is given as

- ``{"fourier": {"ratio": q, "sin": [s1, s2, ...], "cos": [c1, ...]}}``:
  ψ(φ) = q·φ + Σ_k s_k·sin(kφ) + c_k·(cos(kφ) − 1) (closed form to any derivative);
- ``{"elliptic": {"eccentricity": e}}``: the classical pair of equal ellipses turning about their
  foci, tan(ψ/2) = (1 + e)/(1 − e)·tan(φ/2) (mean ratio 1);
- ``{"table": [[φ, ψ], ...], "ratio": q}``: ψ over one input turn (φ strictly increasing over less
  than 2π, ψ increasing), continued by ψ(φ + 2π) = ψ(φ) + 2π·q; a periodic quintic spline.

The mean ratio q (output turns per input turn) is a whole number or the inverse of one, so both
pitch curves close: q = 1/m gives an output of m lobes over m input turns, q = m needs a function
whose speed ratio repeats m times per input turn. The pitch curves themselves (the exact centrodes
of the relative motion) are derived, never stored (:mod:`mechsketch.core.analyses.gears`).
Everything else: ``speed_rpm`` (input, signed), ``samples`` per input turn, ``bore_radius`` of both
blanks (mm), ``tolerance`` of the biarc fit of the exported pitch curves (mm), ``min_web`` (mm).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ..errors import Problem
from .drawing import DEFAULT_MIN_WEB
from .gear_function import GearFunction, parse_function, ratio_problem
from .limits import speed_problem

SCHEMA = "gear_pair.schema.json"
XY = tuple[float, float]

DEFAULT_SAMPLES = 720
DEFAULT_TOLERANCE = 0.01   # mm, biarc fit of the exported pitch curves
@dataclass(frozen=True)
class GearPair:
    """A non-circular gear pair element (type ``gear_pair``); lengths mm, angles rad/degrees as named."""

    id: str
    input_center: XY
    center_distance: float
    function: GearFunction
    direction_deg: float = 0.0
    speed_rpm: float = 60.0
    samples: int = DEFAULT_SAMPLES
    bore_radius: float | None = None
    tolerance: float = DEFAULT_TOLERANCE
    min_web: float = DEFAULT_MIN_WEB
    type: str = field(default="gear_pair", init=False)

    @property
    def output_center(self) -> XY:
        d = math.radians(self.direction_deg)
        return (self.input_center[0] + self.center_distance * math.cos(d),
                self.input_center[1] + self.center_distance * math.sin(d))

    @property
    def omega(self) -> float:
        """Input speed ω (rad/s, signed, CCW positive)."""
        return self.speed_rpm * math.pi / 30.0

    @property
    def bore(self) -> float:
        """The blanks' bore radius in force (mm): ``bore_radius`` or a/40."""
        return self.bore_radius if self.bore_radius is not None else self.center_distance / 40.0

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"type": "gear_pair", "id": self.id, "input_center": list(self.input_center),
                             "center_distance": self.center_distance, "direction_deg": self.direction_deg,
                             "function": self.function.to_dict(), "speed_rpm": self.speed_rpm,
                             "samples": self.samples, "tolerance": self.tolerance, "min_web": self.min_web}
        if self.bore_radius is not None:
            d["bore_radius"] = self.bore_radius
        return d


def parse_fields(data: dict, path: str, eid: str, bad) -> dict | None:
    """The gear fields common to a gear pair and a geared Geneva's gears (a dict for the record)."""
    a = float(data["center_distance"])
    if not a > 0:
        bad("center_distance", f"must be > 0 mm; got {a:g}")
    fn = parse_function(data["function"], "function", bad)
    speed = float(data.get("speed_rpm", 60.0))
    if speed_problem(speed) is not None:
        bad("speed_rpm", speed_problem(speed))
    bore = data.get("bore_radius")
    if bore is not None and not 0 < float(bore) < a / 2:
        bad("bore_radius", f"must lie between 0 and a/2 = {a / 2:g} mm; got {float(bore):g}")
    tol = float(data.get("tolerance", DEFAULT_TOLERANCE))
    if not 1e-6 <= tol <= 1.0:
        bad("tolerance", f"must lie from 1e-6 to 1 mm; got {tol:g}")
    web = float(data.get("min_web", DEFAULT_MIN_WEB))
    if not web > 0:
        bad("min_web", f"must be > 0 mm; got {web:g}")
    if fn is not None and ratio_problem(fn) is not None:
        bad("function", ratio_problem(fn))
        return None
    if fn is None:
        return None
    return {"center_distance": a, "function": fn, "speed_rpm": speed,
            "bore_radius": None if bore is None else float(bore), "tolerance": tol, "min_web": web}


def parse(data: dict[str, Any], path: str) -> tuple[GearPair | None, list[Problem]]:
    """Check a schema-valid gear_pair dict for meaning (the speed ratio's range is checked by the
    pitch-curve analysis, which evaluates the function); return the element or None, and problems."""
    eid = data["id"]
    problems: list[Problem] = []

    def bad(where: str, msg: str) -> None:
        problems.append(Problem(f"{path}.{where}", msg, eid))

    fields = parse_fields(data, path, eid, bad)
    samples = int(data.get("samples", DEFAULT_SAMPLES))
    if samples < 8:
        bad("samples", f"must be at least 8; got {samples}")
    if problems or fields is None:
        return None, problems
    c = data["input_center"]
    return GearPair(eid, (float(c[0]), float(c[1])), fields["center_distance"], fields["function"],
                    float(data.get("direction_deg", 0.0)), fields["speed_rpm"], samples, fields["bore_radius"],
                    fields["tolerance"], fields["min_web"]), []
