"""Rolling levers with a prescribed slider law (issue 25, item 2): ``mechsketch design rolling``.

The requirements hold the rolling-lever element's own fields (``lever_circle``, ``pin``,
``rocker_pivot``, ``contact_branch``, ``stroke``, ``slider_axis_deg``, ``slider_side``, and
optionally ``points``, ``tolerance``, ``pin_diameter``, ``drive``) and, instead of a slider circle,
``slider_law``: ``{"table": [[θ rad, S5 mm], ...]}`` or ``{"law": "cycloidal", "travel": mm}``
(also harmonic, modified_trapezoid, constant). Optional limits: ``max_pressure_angle_deg``,
``rolling_tolerance`` and ``s5_tolerance`` (mm; default 1e-6), ``min_web`` (mm, the parts; 1).

Pair D is synthesised as for any rolling lever (the exact ODE dα/dθ = 1 − g/ℓ); pair E comes from
the law: the lever element Π30 and the slider profile Π50 are the exact centrodes of the relative
motion (:mod:`mechsketch.core.analyses.rolling.law`). The result is an ordinary ``rolling_lever``
element with ``slider_law``; its report gives each check with its value and margin: pure rolling
(the two profiles' arc lengths), S5 reproduced, no cusp, no fold (a profile crossing itself cannot
be cut), the contact on the working side, the pressure angle, the parts' web. A failing check is
refused naming what to change: ``slider_side`` when the contact is on the other side throughout,
the travel (or the table's scale) at which the profiles stop folding, the stroke's reachable range.
"""
from __future__ import annotations

import copy
import math
import time
from dataclasses import dataclass, replace
from typing import Any

from ..analyses.parts import check_parts
from ..analyses.parts.rolling import RollingStyle, rolling_parts
from ..analyses.rolling.law import CUSP_FRACTION, LawChecks, law_checks
from ..analyses.rolling.synthesis import RollingSynthesis, synthesize
from ..errors import MechsketchError
from ..model.drawing import DEFAULT_MIN_WEB
from ..model.rolling_lever import SCHEMA, RollingLever, parse
from .design_report import (DesignError, DesignReport, Progress, Relaxation, Requirement, infeasible,
                            report_progress, schema_problems)

#: the element's keys a REQ may hold
ELEMENT_KEYS = ("lever_circle", "pin", "rocker_pivot", "contact_branch", "stroke", "slider_axis_deg", "slider_side",
                "slider_law", "points", "tolerance", "pin_diameter", "drive")
LIMIT_KEYS = ("max_pressure_angle_deg", "rolling_tolerance", "s5_tolerance", "min_web")
DEFAULT_CHECK_TOLERANCE = 1e-6   # mm
#: bisection steps on the law's scale when the profiles fold
SCALE_STEPS = 12


@dataclass(frozen=True)
class RollingDesign:
    """The result: ``element`` (a ``rolling_lever`` with ``slider_law``), ``report``, ``synthesis``."""

    element: RollingLever
    report: DesignReport
    synthesis: RollingSynthesis


def _element(data: dict, element_id: str) -> RollingLever:
    """The element the REQ describes; :class:`DesignError` with every problem."""
    if not isinstance(data, dict):
        raise DesignError(f"the requirements must be a JSON object, got {type(data).__name__}")
    unknown = [k for k in data if k not in ELEMENT_KEYS + LIMIT_KEYS]
    problems = [f"unknown key {k!r} (known: {', '.join(ELEMENT_KEYS + LIMIT_KEYS)})" for k in unknown]
    if "slider_law" not in data:
        problems.append("slider_law is required: {\"table\": [[θ rad, S5 mm], ...]} or {\"law\": \"cycloidal\", "
                        "\"travel\": mm}")
    if "slider_circle" in data:
        problems.append("a designed lever has no slider_circle: its pair-E element is derived from slider_law")
    doc = {"type": "rolling_lever", "id": element_id, "method": "exact",
           **{k: v for k, v in data.items() if k in ELEMENT_KEYS}}
    if not problems:
        problems += schema_problems(SCHEMA, doc)
    if not problems:
        el, found = parse(doc, "$")
        problems += [f"{p.path.removeprefix('$.')}: {p.message}" for p in found]
        if el is not None and not problems:
            return el
    raise DesignError("the requirements cannot be read: " + "; ".join(problems))


def _limits(data: dict) -> dict[str, float | None]:
    out: dict[str, float | None] = {}
    for key in LIMIT_KEYS:
        v = data.get(key)
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0):
            raise DesignError(f"{key} must be a positive number, got {v!r}")
        out[key] = None if v is None else float(v)
    return out


def _rows(checks: LawChecks, lim: dict, web: float | None) -> list[Requirement]:
    roll = lim["rolling_tolerance"] or DEFAULT_CHECK_TOLERANCE
    s5 = lim["s5_tolerance"] or DEFAULT_CHECK_TOLERANCE
    speed = min(checks.min_speed_lever / checks.mean_speed_lever, checks.min_speed_slider / checks.mean_speed_slider)
    rows = [
        Requirement("rolling_tolerance", "pure rolling: |arc length Π30 − arc length Π50|",
                    abs(checks.rolling_mismatch), roll, "<=", "mm"),
        Requirement("s5_tolerance", "S5 reproduced: largest |S5 − law|", checks.s5_error, s5, "<=", "mm"),
        Requirement("no_cusp", "smallest profile speed / its mean (a cusp at 0)", speed, CUSP_FRACTION, ">=", ""),
        Requirement("no_fold", "profiles crossing themselves or turning back (count)",
                    float(checks.folds_lever + checks.folds_slider + checks.reversal), 0.0, "<=", ""),
        Requirement("working_side", "contact on the working side: smallest side·(P0 − P)·n",
                    checks.side_margin, 0.0, ">=", "mm"),
    ]
    if lim["max_pressure_angle_deg"] is not None:
        rows.append(Requirement("max_pressure_angle_deg", "largest pressure angle (contact normal to the slider axis)",
                                checks.pressure_angle_deg, lim["max_pressure_angle_deg"], "<=", "°"))
    if web is not None:
        rows.append(Requirement("min_web", "thinnest web of the plates", web, lim["min_web"] or DEFAULT_MIN_WEB,
                                ">=", "mm"))
    return rows


def _evaluate(el: RollingLever, lim: dict, parts: bool) -> tuple[RollingSynthesis, list[Requirement]]:
    syn = synthesize(el)
    web = None
    if parts and syn.law is not None and syn.law.ok:
        need = lim["min_web"] or DEFAULT_MIN_WEB
        try:
            checks = check_parts(rolling_parts(syn, RollingStyle()).parts, need)
        except MechsketchError:   # a profile that cannot be fitted or joined: no plate
            checks = None
        if checks is None:
            web = 0.0
        else:
            web = min((c.web for c in checks if math.isfinite(c.web)), default=0.0)
            if any(not c.ok for c in checks) and web >= need:   # not cut-ready for another reason
                web = 0.0
    return syn, _rows(syn.law, lim, web)


def design_rolling(requirements: Any, element_id: str = "lever", progress: Progress | None = None) -> RollingDesign:
    """The rolling lever whose slider follows ``requirements['slider_law']`` (see the module
    docstring); :class:`~.design_report.DesignError` when the law cannot be realised (naming what to
    change) or :class:`~.design_report.DesignCancelled`."""
    t0 = time.perf_counter()
    el = _element(requirements, element_id)
    lim = _limits(requirements)
    report_progress(progress, 0.0, "synthesising pair D and the law's centrodes")
    try:
        syn, rows = _evaluate(el, lim, parts=True)
    except MechsketchError as exc:
        raise DesignError(f"the lever cannot follow the law: {exc}") from None
    report_progress(progress, 0.6, "checking the profiles")
    failing = [r for r in rows if not r.met]
    if failing:
        raise _refusal(el, lim, syn, failing, progress)
    binding = min((r for r in rows if r.limit != 0.0 or r.sense == ">="), key=lambda r: r.margin)
    rows = [replace(r, binding=r is binding) for r in rows]
    c = syn.slip.continuous if syn.slip is not None else None
    notes = [f"slider law: {_law_text(el)}; stroke θ from {el.stroke.start:g} to {el.stroke.end:g} rad, "
             f"{el.points} intervals; S5 from {float(syn.S5.min()):.6g} to {float(syn.S5.max()):.6g} mm, "
             f"k53 from {float(syn.k53.min()):.6g} to {float(syn.k53.max()):.6g} mm/rad",
             *syn.law.lines()]
    if c is not None:
        notes.append(f"slip of the computed motion: pair D {c.slip_d:.2e} mm, pair E {c.slip_e:.2e} mm; integration "
                     f"error bound {syn.error_mm:.2e} mm")
    report_progress(progress, 1.0, "done")
    return RollingDesign(el, DesignReport(f"rolling lever {el.id!r} following the prescribed slider law", tuple(rows),
                                          tuple(notes), time.perf_counter() - t0), syn)


def _law_text(el: RollingLever) -> str:
    law = el.slider_law
    return (f"table of {len(law.table)} points" if law.kind == "table"
            else f"{law.kind}, travel {law.travel:g} mm")


def _scaled(el: RollingLever, factor: float) -> RollingLever:
    law = el.slider_law
    if law.kind == "table":
        return replace(el, slider_law=replace(law, table=tuple((t, s * factor) for t, s in law.table)))
    return replace(el, slider_law=replace(law, travel=law.travel * factor))


def _refusal(el: RollingLever, lim: dict, syn: RollingSynthesis, failing: list[Requirement],
             progress: Progress | None) -> DesignError:
    """The refusal: what fails, and the change that would do (checked)."""
    names = {r.name for r in failing}
    what = "; ".join(f"{r.name}: {r.what} {r.value:.6g}{(' ' + r.unit) if r.unit else ''} against "
                     f"{r.limit:.6g}{(' ' + r.unit) if r.unit else ''}" for r in failing)
    relax: list[Relaxation] = []
    if names == {"working_side"}:
        flipped = replace(el, slider_side=-el.slider_side)
        if _ok(flipped, lim):
            relax.append(Relaxation("slider_side", el.slider_side, -el.slider_side, "", relative=False))
    if names & {"no_fold", "no_cusp", "max_pressure_angle_deg", "min_web"}:
        factor = _largest_scale(el, lim, progress)
        if factor is not None:
            law = el.slider_law
            if law.kind == "table":
                relax.append(Relaxation("slider_law.table (S5 scaled by)", 1.0, factor, ""))
            else:
                relax.append(Relaxation("slider_law.travel", law.travel, law.travel * factor, "mm"))
    if "max_pressure_angle_deg" in names and len(names) == 1:
        r = next(r for r in failing if r.name == "max_pressure_angle_deg")
        relax.append(Relaxation("max_pressure_angle_deg", r.limit, r.value * (1 + 1e-9), "°"))
    hint = ""
    k53 = syn.k53
    scale = float(max(abs(k53.max()), abs(k53.min()), 1e-300))
    if min(abs(k53[0]), abs(k53[-1])) <= 1e-9 * scale:
        hint = (". The law is at rest at a stroke end (k53 = dS5/dθ = 0): there the pair-E contact is the pair-D "
                "contact P itself, so the lever's two working edges meet; a law still moving at the ends (e.g. "
                "constant, or a table) avoids it")
    return infeasible(f"the rolling lever cannot follow the slider law ({_law_text(el)}): {what}{hint}", relax)


def _ok(el: RollingLever, lim: dict) -> bool:
    try:
        _, rows = _evaluate(el, lim, parts=True)
    except MechsketchError:
        return False
    return all(r.met for r in rows)


def _profiles_ok(el: RollingLever, lim: dict) -> bool:
    """The profile checks alone (no cusp, fold or reversal, working side, pressure angle), without
    the slip report: what the scale search bisects on (~0.1 s a step)."""
    try:
        ch = law_checks(synthesize(el, measures=False))
    except MechsketchError:
        return False
    angle = lim["max_pressure_angle_deg"]
    return (not ch.cusp and not ch.folds and not ch.reversal and ch.side_margin >= 0.0
            and (angle is None or ch.pressure_angle_deg <= angle))


def _largest_scale(el: RollingLever, lim: dict, progress: Progress | None) -> float | None:
    """The largest factor (3 digits, < 1) of the law's S5 with which every check passes (the
    profiles bisected, then everything verified at the factor, stepping down), or None."""
    lo, hi = 0.0, 1.0
    for i in range(SCALE_STEPS):
        report_progress(progress, 0.6 + 0.35 * i / SCALE_STEPS, f"scaling the law: {lo:.4g} .. {hi:.4g}")
        mid = 0.5 * (lo + hi)
        if _profiles_ok(_scaled(el, mid), lim):
            lo = mid
        else:
            hi = mid
    factor = math.floor(lo * 1000) / 1000
    for _ in range(3):   # the plates may need a little less
        if factor <= 0:
            return None
        if _ok(_scaled(el, factor), lim):
            return factor
        factor = math.floor(factor * 900) / 1000
    return None


def requirements_of(el: RollingLever) -> dict:
    """A REQ that designs ``el`` again (its element fields), e.g. to start from an existing lever."""
    d = copy.deepcopy(el.to_dict())
    return {k: v for k, v in d.items() if k in ELEMENT_KEYS}
