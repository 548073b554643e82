"""Non-circular gear pitch curves from a required transmission function (issue 25, item 3):
``mechsketch design gears REQ.json --out OUT.json``.

The requirements: ``function`` ψ(φ) as the gear pair element takes it (``{"table": [[φ, ψ], ...],
"ratio": q}``, ``{"fourier": {...}}`` or ``{"elliptic": {"eccentricity": e}}``), ``center_distance``
a (mm) and optionally the pair's placement and sizes (``input_center``, ``direction_deg``,
``speed_rpm``, ``samples``, ``bore_radius``, ``tolerance``, ``min_web``) and limits:
``max_pressure_deg`` (the pitch curves' pressure-angle swing), ``min_concave_radius`` (mm; the
tightest concave stretch a cutter can follow; ``convex: true`` forbids concave stretches).

The result is a ``gear_pair`` element whose pitch curves are the exact centrodes of the relative
motion (:mod:`mechsketch.core.analyses.gears.pitch`); the report gives, each with its value and
margin: the centre distance and mean ratio achieved (from the curves: the pitch radii's sum and
the output's turns), closure, pure rolling (the curves' rolled lengths), the speed-ratio range,
the pressure swing, the curvature, and the blanks' web around their bores after the biarc fit.
A requirement the curves cannot meet is refused naming what to change: the centre distance (the
curvature and the web scale with it), the bore, or the limit itself (the pressure swing depends on
the function alone).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

from ..analyses.gears.pitch import PitchChecks, checks, kinematics
from ..analyses.parts import check_parts
from ..analyses.parts.gears import gear_blanks
from ..errors import MechsketchError
from ..model.gear_pair import SCHEMA, GearPair, parse
from .design_report import (DesignError, DesignReport, Progress, Relaxation, Requirement, infeasible,
                            report_progress, schema_problems)

ELEMENT_KEYS = ("function", "center_distance", "input_center", "direction_deg", "speed_rpm", "samples", "bore_radius",
                "tolerance", "min_web")
LIMIT_KEYS = ("max_pressure_deg", "min_concave_radius", "convex")


@dataclass(frozen=True)
class GearDesign:
    """The result: ``element`` (a ``gear_pair``), ``report``, the pitch ``checks``."""

    element: GearPair
    report: DesignReport
    checks: PitchChecks


def _element(data: Any, element_id: str) -> GearPair:
    if not isinstance(data, dict):
        raise DesignError(f"the requirements must be a JSON object, got {type(data).__name__}")
    problems = [f"unknown key {k!r} (known: {', '.join(ELEMENT_KEYS + LIMIT_KEYS)})"
                for k in data if k not in ELEMENT_KEYS + LIMIT_KEYS]
    for key in ("function", "center_distance"):
        if key not in data:
            problems.append(f"{key} is required")
    doc = {"type": "gear_pair", "id": element_id, "input_center": [0.0, 0.0],
           **{k: v for k, v in data.items() if k in ELEMENT_KEYS}}
    if not problems:
        problems += schema_problems(SCHEMA, doc)
    if not problems:
        el, found = parse(doc, "$")
        problems += [f"{p.path.removeprefix('$.')}: {p.message}" for p in found]
        if el is not None and not problems:
            return el
    raise DesignError("the requirements cannot be read: " + "; ".join(problems))


def design_gears(requirements: Any, element_id: str = "gears", progress: Progress | None = None) -> GearDesign:
    """The gear pair realising ``requirements['function']`` at ``center_distance`` (see the module
    docstring); :class:`~.design_report.DesignError` naming what to change when a limit fails."""
    t0 = time.perf_counter()
    el = _element(requirements, element_id)
    report_progress(progress, 0.0, "pitch curves")
    kin = kinematics(el.function, el.center_distance, el.speed_rpm, max(el.samples, 64))
    sense = kin.sense
    ch = checks(el.function, el.center_distance, sense)
    report_progress(progress, 0.5, "fitting the blanks")
    try:
        parts = gear_blanks(el.function, el.center_distance, sense, el.tolerance, el.bore, el.input_center,
                            math.radians(el.direction_deg))
        pc = check_parts(parts, el.min_web)
        web = min(c.web for c in pc) if all(c.ok or "web" in " ".join(c.problems) for c in pc) else 0.0
    except MechsketchError:
        web, parts = 0.0, ()
    a_measured = float((kin.r1 + kin.r2).max())
    turns = (kin.psi[-1] - kin.psi[0] + (kin.psi[1] - kin.psi[0])) / (2 * math.pi)
    rows = [Requirement("center_distance", "centre distance from the pitch radii r1 + r2", a_measured,
                        el.center_distance, "==", "mm", tolerance=1e-9 * el.center_distance),
            Requirement("ratio", "mean ratio: output turns per input turn", turns, el.function.ratio, "==",
                        tolerance=1e-9 * el.function.ratio),
            Requirement("closure", "largest gap of a pitch curve after its period", ch.closure_gap,
                        1e-9 * el.center_distance, "<=", "mm"),
            Requirement("pure_rolling", "|arc rolled on the input − on the output| over a common period",
                        abs(ch.rolling_mismatch), 1e-9 * ch.rolled_input, "<=", "mm"),
            Requirement("min_web", "thinnest web of the blanks (pitch curve to bore)", web, el.min_web, ">=", "mm")]
    lim = {k: requirements.get(k) for k in LIMIT_KEYS}
    if lim["max_pressure_deg"] is not None:
        rows.append(Requirement("max_pressure_deg", "largest pressure-angle swing of the pitch curves",
                                max(ch.pressure_input_deg, ch.pressure_output_deg), float(lim["max_pressure_deg"]),
                                "<=", "°"))
    concave = -min(ch.curvature_input, ch.curvature_output, 0.0) if not ch.convex else math.inf
    tight = min(ch.curvature_input if ch.curvature_input < 0 else math.inf,
                ch.curvature_output if ch.curvature_output < 0 else math.inf)
    if lim["convex"]:
        rows.append(Requirement("convex", "concave stretches on the pitch curves (count)", 0.0 if ch.convex else 1.0,
                                0.0, "<=", ""))
    if lim["min_concave_radius"] is not None:
        rows.append(Requirement("min_concave_radius", "tightest concave radius of the pitch curves",
                                -tight if math.isfinite(tight) else math.inf, float(lim["min_concave_radius"]), ">=",
                                "mm"))
    failing = [r for r in rows if not r.met]
    if failing:
        raise _refusal(el, ch, failing, web)
    binding = min((r for r in rows if r.sense != "=="), key=lambda r: r.margin)
    rows = [Requirement(**{**r.__dict__, "binding": r is binding}) for r in rows]
    notes = ch.lines() + [f"blanks: bores {el.bore:g} mm, biarcs within {el.tolerance:g} mm (largest deviation "
                          f"{max((p.deviation for p in parts), default=math.nan):.3e} mm); teeth not cut",
                          f"concave stretches: {'none' if ch.convex else f'tightest radius {concave:.5g} mm'}"]
    report_progress(progress, 1.0, "done")
    return GearDesign(el, DesignReport(f"non-circular gears {el.id!r} for the required function", tuple(rows),
                                       tuple(notes), time.perf_counter() - t0), ch)


def _refusal(el: GearPair, ch: PitchChecks, failing: list[Requirement], web: float) -> DesignError:
    """What fails and the single change that would do (the centre distance scales radii, webs and
    curvatures linearly; the pressure swing does not depend on it)."""
    relax: list[Relaxation] = []
    for r in failing:
        if r.name == "min_web":
            r_min = el.center_distance * min(ch.ratio_min / (1 + ch.ratio_min), 1 / (1 + ch.ratio_max))
            need = (el.bore + el.min_web) / (r_min / el.center_distance) * 1.001
            relax.append(Relaxation("center_distance", el.center_distance, need, "mm"))
            relax.append(Relaxation("bore_radius", el.bore, max(r_min - el.min_web, 0.0) * 0.999, "mm"))
        elif r.name == "min_concave_radius" and math.isfinite(r.value) and r.value > 0:
            relax.append(Relaxation("center_distance", el.center_distance, el.center_distance * r.limit / r.value * 1.001,
                                    "mm"))
            relax.append(Relaxation("min_concave_radius", r.limit, r.value * (1 - 1e-9), "mm"))
        elif r.name == "max_pressure_deg":
            relax.append(Relaxation("max_pressure_deg", r.limit, r.value * (1 + 1e-9), "°"))
    what = "; ".join(f"{r.name}: {r.what} {r.value:.6g} against {r.limit:.6g}{(' ' + r.unit) if r.unit else ''}"
                     for r in failing)
    return infeasible(f"the gears cannot meet the requirements: {what}", relax, several=len(failing) > 1)
