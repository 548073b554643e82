"""Geneva drives sized from requirements (issue 25, item 1): the smallest drive meeting them.

The requirements (a JSON object reusing the Geneva element's field names; stress MPa, lengths mm):
``slots`` z, or ``dwell_fraction`` (the z whose dwell fraction (z + 2)/(2z) is nearest, within
``dwell_tolerance``, default 0.01); ``speed_rpm`` (required); ``roller_length``, ``load``,
``material``, ``wear``, ``clearance``, ``contact_model``, ``crank_center``,
``wheel_direction_deg``, ``samples`` as in the element; and the limits
``allowable_contact_stress`` (the Hertz peak pressure over the engagement, MPa),
``life_cycles`` (the Archard life in crank revolutions), ``max_center_distance`` (mm) and
``min_web`` (mm, every part's thinnest web; default 1). Optional ``roller_radius`` fixes the roller;
``resolution`` {``center_distance``, ``roller_radius``} the rounding steps (mm; default about
1/1000 of the smallest possible drive, the roller half of it).

The method. For a centre distance A the roller is made as large as the wheel allows: r_p(A) is
the largest roller radius on the resolution grid with which the element's own checks pass (slots
apart by the web, lands, horns, hub around the bore, a pin in the roller, room for a crank bore;
:func:`~..model.geneva.parse`), found by bisection. A larger roller only lowers the contact
pressure (p_max = √(R_n·E*/(π·l·r_p))) and the wear (depth ∝ R_n^1.5/r_p^1.5), and a larger A
lowers the normal force (R_n ≈ |M|/(A√D)) and widens every geometric limit, so feasibility is
monotone in A: the smallest feasible A on the resolution grid is found by doubling from a
closed-form lower bound (the hub: A(1 − sin(π/z)) > bore + 2·web + c_s + c_b), then bisection.
The pressure, the normal force's validity range and the Archard life are those of the contact
analysis (:func:`~..analyses.geneva.contact.engagement_totals`: continuous peak, Gauss–Legendre
per smooth piece). The drive found is then drawn (exact relief) and its parts checked with the
web; should the exact relief need more room than the closed-form bound, A steps up until they pass.

The binding requirement is the one that fails one resolution step below the design. An infeasible
set (nothing fits within ``max_center_distance``, or no z gives the dwell) raises
:class:`~.design_report.DesignError` naming each requirement whose relaxation alone would do and
the value it needs, the least relative change first.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import Any

from ..analyses.geneva.contact import CrankMotion, EngagementTotals, engagement_totals
from ..analyses.geneva.geometry import geometry
from ..analyses.parts import check_parts
from ..analyses.parts.geneva import geneva_parts
from ..errors import GeometryError
from ..model.geneva import (DEFAULT_CLEARANCE, DEFAULT_LOAD, DEFAULT_ROLLER_LENGTH, DEFAULT_SAMPLES, STEEL,
                            DEFAULT_WEAR, SCHEMA, Geneva, parse)
from ..model.drawing import DEFAULT_MIN_WEB
from .design_report import (DesignError, DesignReport, Progress, Relaxation, Requirement, infeasible,
                            report_progress, schema_problems)

#: REQ keys this design reads
KEYS = ("slots", "dwell_fraction", "dwell_tolerance", "speed_rpm", "roller_length", "roller_radius", "load",
        "material", "wear", "clearance", "contact_model", "crank_center", "wheel_direction_deg", "samples",
        "allowable_contact_stress", "life_cycles", "max_center_distance", "min_web", "resolution", "smooth")
#: the largest centre distance searched when the requirements set none (mm)
SEARCH_LIMIT = 1e6
DEFAULT_DWELL_TOLERANCE = 0.01
#: points of the geometric scan for a roller the wheel takes (from the web to A)
SCAN = 64
#: the drawn drive's parts are re-checked this many resolution steps up at most
DRAW_STEPS = 200


@dataclass(frozen=True)
class GenevaRequirements:
    """Parsed requirements (see the module docstring). ``base`` is the element dict every candidate
    starts from (id, z, speed, load, materials, wear, clearances, placement; sizes set per
    candidate)."""

    slots: int
    dwell_fraction: float | None
    dwell_tolerance: float
    base: dict
    allowable_contact_stress: float | None
    life_cycles: float | None
    max_center_distance: float | None
    min_web: float
    roller_radius: float | None
    step_a: float | None
    step_r: float | None
    smooth: dict | None


@dataclass(frozen=True)
class Candidate:
    """One evaluated (A, r_p): ``element`` (None: no roller fits), the contact totals, the
    requirement rows and whether all are met."""

    a: float
    rp: float | None
    element: Geneva | None
    totals: EngagementTotals | None
    rows: tuple[Requirement, ...]

    @property
    def ok(self) -> bool:
        return self.element is not None and all(r.met for r in self.rows)

    def failing(self) -> list[Requirement]:
        return [r for r in self.rows if not r.met]


@dataclass(frozen=True)
class GenevaDesign:
    """The result: ``element`` (a ``geneva`` element that validates and exports), ``report``."""

    element: Geneva
    report: DesignReport


def _tidy(x: float) -> float:
    """A grid value without the float noise of k·step (53.300000000000004 -> 53.3)."""
    return float(f"{x:.12g}")


def _dwell(z: int) -> float:
    return (z + 2) / (2 * z)


def parse_requirements(data: Any, element_id: str = "geneva") -> GenevaRequirements:
    """Check a REQ object; :class:`DesignError` lists every problem (key, value, what to change)."""
    if not isinstance(data, dict):
        raise DesignError(f"the requirements must be a JSON object, got {type(data).__name__}")
    problems = [f"unknown key {k!r} (known: {', '.join(KEYS)})" for k in data if k not in KEYS]

    def number(key: str, positive: bool = True) -> float | None:
        v = data.get(key)
        if v is None:
            return None
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
            problems.append(f"{key} must be a {'positive ' if positive else ''}finite number, got {v!r}")
            return None
        return float(v)

    z = data.get("slots")
    dwell = number("dwell_fraction")
    tol = number("dwell_tolerance") or DEFAULT_DWELL_TOLERANCE
    if z is None and dwell is None:
        problems.append("give 'slots' (z) or 'dwell_fraction' (the slot count is then chosen)")
    elif z is not None and dwell is not None:
        problems.append("give 'slots' or 'dwell_fraction', not both")
    elif z is not None and (isinstance(z, bool) or not isinstance(z, int) or z < 3):
        problems.append(f"slots must be a whole number of at least 3, got {z!r}")
    if "speed_rpm" not in data:
        problems.append("speed_rpm (the crank speed, rpm) is required")
    limits = {k: number(k) for k in ("allowable_contact_stress", "life_cycles", "max_center_distance")}
    web = number("min_web") or DEFAULT_MIN_WEB
    rp = number("roller_radius")
    res = data.get("resolution", {})
    if not isinstance(res, dict) or any(k not in ("center_distance", "roller_radius") for k in res):
        problems.append("resolution is {\"center_distance\": mm, \"roller_radius\": mm}")
        res = {}
    steps = [res.get(k) for k in ("center_distance", "roller_radius")]
    for k, v in zip(("center_distance", "roller_radius"), steps):
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 < v < 1e9):
            problems.append(f"resolution.{k} must be a positive number of mm, got {v!r}")
    if dwell is not None and z is None:
        z = _slots_for_dwell(dwell, tol, problems)
    if problems:
        raise DesignError("the requirements cannot be read: " + "; ".join(problems))
    base = {"type": "geneva", "id": element_id, "slots": int(z), "center_distance": 100.0, "roller_radius": 1.0,
            "roller_length": float(data.get("roller_length", DEFAULT_ROLLER_LENGTH)),
            "clearance": {**DEFAULT_CLEARANCE, **data.get("clearance", {})},
            "crank_center": data.get("crank_center", [0.0, 0.0]),
            "wheel_direction_deg": data.get("wheel_direction_deg", 0.0), "speed_rpm": data["speed_rpm"],
            "load": {**DEFAULT_LOAD, **data.get("load", {})},
            "material": {"roller": {**STEEL, **data.get("material", {}).get("roller", {})},
                         "wheel": {**STEEL, **data.get("material", {}).get("wheel", {})}},
            "wear": {**DEFAULT_WEAR, **data.get("wear", {})}, "samples": data.get("samples", DEFAULT_SAMPLES),
            "drawing": {"min_web": web}}
    if "contact_model" in data:
        base["contact_model"] = data["contact_model"]
    _check_fields(base)
    smooth = data.get("smooth")
    if smooth is not None and not isinstance(smooth, dict):
        raise DesignError(f"smooth must be an object (see mechsketch design geneva --help), got {smooth!r}")
    return GenevaRequirements(int(z), dwell, tol, base, limits["allowable_contact_stress"], limits["life_cycles"],
                              limits["max_center_distance"], web, rp, steps[0], steps[1], smooth)


def _slots_for_dwell(dwell: float, tol: float, problems: list[str]) -> int | None:
    """The slot count whose dwell fraction is nearest ``dwell`` (within ``tol``), else a problem."""
    if not 0.5 < dwell < 1.0:
        problems.append(f"dwell_fraction must lie between 0.5 and 1 (a Geneva's is 1/2 + 1/z); got {dwell:g}")
        return None
    exact = 2.0 / (2.0 * dwell - 1.0)
    z = max(3, round(exact))
    if abs(_dwell(z) - dwell) > tol:
        lo, hi = max(3, math.floor(exact)), max(3, math.ceil(exact))
        near = sorted({lo, hi})
        options = " or ".join(f"{_dwell(k):.4g} (z = {k})" for k in near)
        why = (f"a Geneva has at least 3 slots (dwell at most {_dwell(3):.4g})" if exact < 3 else
               f"it needs z = {exact:.4g} slots")
        problems.append(f"dwell_fraction {dwell:g}: {why}; relax dwell_fraction to {options}, or "
                        f"dwell_tolerance (now {tol:g}) to {min(abs(_dwell(k) - dwell) for k in near):.4g}")
        return None
    return z


def _check_fields(base: dict) -> None:
    """Refuse requirements whose element fields are out of range (speed, load, materials, wear),
    with the element's own messages: checked once on a drive every limit accepts."""
    probe = dict(base, center_distance=1e6, roller_radius=10.0 * base["drawing"]["min_web"] + 10.0,
                 drawing={})
    ranges = schema_problems(SCHEMA, base)
    if ranges:
        raise DesignError("the requirements cannot be read: " + "; ".join(ranges))
    try:
        _, problems = parse(probe, "$")
    except (TypeError, ValueError, KeyError) as exc:
        raise DesignError(f"the requirements cannot be read: {exc}") from None
    if problems:
        raise DesignError("the requirements cannot be read: " + "; ".join(
            f"{p.path.removeprefix('$.')}: {p.message}" for p in problems))


class _Search:
    """Evaluates candidates (A on the resolution grid, r_p the largest the wheel allows)."""

    def __init__(self, req: GenevaRequirements, progress: Progress | None, crank: CrankMotion | None = None) -> None:
        self.req = req
        self.progress = progress
        self.crank = crank
        self.evals = 0
        base = req.base
        z = req.slots
        cl = base["clearance"]
        lam = math.sin(math.pi / z)
        bore = base["load"]["journal_radius"]
        w = req.min_web
        lower = (bore + 2 * w + cl["slot"] + cl["bottom"]) / (1.0 - lam)
        friction = base["load"]["journal_friction"] * base["load"]["journal_radius"] / (1.0 - lam)
        self.a_lower = max(lower, friction, 1e-3)
        scale = 10.0 ** math.floor(math.log10(self.a_lower))
        self.step_a = req.step_a or scale / 100.0
        self.step_r = req.step_r or self.step_a / 2.0

    def element(self, a: float, rp: float) -> Geneva | None:
        el, problems = parse(dict(self.req.base, center_distance=a, roller_radius=rp), "$")
        return el if not problems else None

    def roller(self, a: float) -> float | None:
        """The largest roller radius on the grid the wheel of centre distance ``a`` takes (mm)."""
        if self.req.roller_radius is not None:
            return self.req.roller_radius if self.element(a, self.req.roller_radius) else None
        # the rollers the wheel takes form an interval (a pin and the horns bound it below, the
        # slots, lands and hub above): find one inside on a geometric scan, then its upper end
        least = self.req.min_web * (1.0 + 1e-9) + 1e-9
        scan = [least * (a / least) ** (i / SCAN) for i in range(SCAN)] if a > least else []
        lo = next((r for r in scan if self.element(a, r) is not None), None)
        if lo is None:
            return None
        hi = a
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            if self.element(a, mid) is not None:
                lo = mid
            else:
                hi = mid
            if hi - lo <= 1e-3 * self.step_r:
                break
        first = math.ceil(next(r for r in scan if self.element(a, r) is not None) / self.step_r)
        k = math.floor(lo / self.step_r)
        while k >= first and self.element(a, k * self.step_r) is None:   # rounding of the grid
            k -= 1
        if k < first:
            return None
        if self.drawable(a, _tidy(k * self.step_r)):
            return _tidy(k * self.step_r)
        # the exact relief of the locking disc needs more room than the closed-form bound: the
        # largest roller whose drive can be drawn, by bisection on the grid (room shrinks with r_p)
        lo_k, hi_k = first - 1, k
        while hi_k - lo_k > 1:
            mid = (lo_k + hi_k) // 2
            if self.element(a, _tidy(mid * self.step_r)) is not None and self.drawable(a, _tidy(mid * self.step_r)):
                lo_k = mid
            else:
                hi_k = mid
        return _tidy(lo_k * self.step_r) if lo_k >= first else None

    def drawable(self, a: float, rp: float) -> bool:
        """The drive can be drawn (the exact relief leaves room for the crank bore; ~40 ms)."""
        try:
            geometry(self.element(a, rp))
        except GeometryError:
            return False
        return True

    def evaluate(self, k: int) -> Candidate:
        a = _tidy(k * self.step_a)
        self.evals += 1
        rp = self.roller(a)
        if rp is None:
            return Candidate(a, None, None, None, ())
        el = self.element(a, rp)
        tot = engagement_totals(el, el.model, self.crank)
        return Candidate(a, rp, el, tot, self.rows(el, tot))

    def rows(self, el: Geneva, tot: EngagementTotals, web: float | None = None) -> tuple[Requirement, ...]:
        req = self.req
        rows = []
        if req.dwell_fraction is not None:
            rows.append(Requirement("dwell_fraction", f"dwell fraction (z + 2)/(2z) with z = {el.slots}",
                                    _dwell(el.slots), req.dwell_fraction, "==", tolerance=req.dwell_tolerance))
        if req.allowable_contact_stress is not None:
            rows.append(Requirement("allowable_contact_stress", "peak Hertz contact pressure p_max",
                                    tot.pressure_peak, req.allowable_contact_stress, "<=", "MPa"))
        if req.life_cycles is not None:
            life = tot.life.cycles if tot.valid else 0.0
            rows.append(Requirement("life_cycles", f"Archard life ({tot.life.limiting} limiting)", life,
                                    req.life_cycles, ">=", "crank turns"))
        rows.append(Requirement("contact_validity", "peak normal force R_n within the contact model's range",
                                tot.rn_peak, tot.rn_limit, "<=", "N"))
        if req.max_center_distance is not None:
            rows.append(Requirement("max_center_distance", "centre distance A", el.center_distance,
                                    req.max_center_distance, "<=", "mm"))
        if web is not None:
            rows.append(Requirement("min_web", "thinnest web of the parts", web, req.min_web, ">=", "mm"))
        return tuple(rows)

    def tick(self, fraction: float, text: str) -> None:
        report_progress(self.progress, fraction, text)


def _smallest(s: _Search, k_max: int) -> Candidate | None:
    """The smallest feasible grid index up to ``k_max`` (doubling, then bisection); None if none."""
    k = max(1, math.ceil(s.a_lower / s.step_a))
    bad = k - 1
    good: Candidate | None = None
    while k <= k_max:
        s.tick(0.05 + 0.4 * min(1.0, math.log1p(k) / math.log1p(k_max)), f"trying A = {k * s.step_a:.6g} mm")
        cand = s.evaluate(k)
        if cand.element is not None and all(r.met for r in cand.rows if r.name != "max_center_distance"):
            good = cand
            break
        bad = k
        k = min(2 * k, k_max) if k < k_max else k_max + 1
    if good is None:
        return None
    hi = round(good.a / s.step_a)
    while hi - bad > 1:
        mid = (hi + bad) // 2
        s.tick(0.5 + 0.3 * (1.0 - (hi - bad) / max(hi, 1)), f"bisecting A: {bad * s.step_a:.6g} .. {hi * s.step_a:.6g} mm")
        cand = s.evaluate(mid)
        if cand.element is not None and all(r.met for r in cand.rows if r.name != "max_center_distance"):
            hi, good = mid, cand
        else:
            bad = mid
    return good


def design_geneva(requirements: Any, element_id: str = "geneva", progress: Progress | None = None,
                  crank: CrankMotion | None = None) -> GenevaDesign:
    """The smallest Geneva drive meeting ``requirements`` (a REQ dict or :class:`GenevaRequirements`).

    Returns a :class:`GenevaDesign`; raises :class:`~.design_report.DesignError` (infeasible: the
    message and ``relax`` name what to change and by how much) or
    :class:`~.design_report.DesignCancelled`. Thread-safe; see :mod:`.design_report` for
    ``progress``. ``crank``: a crank driven at varying speed (the smooth drive's gears), whose
    loads the contact requirements then use.
    """
    t0 = time.perf_counter()
    req = requirements if isinstance(requirements, GenevaRequirements) else parse_requirements(requirements, element_id)
    s = _Search(req, progress, crank)
    s.tick(0.0, f"z = {req.slots}: searching the centre distance from {s.a_lower:.4g} mm")
    cap = req.max_center_distance
    k_max = math.floor((cap if cap is not None else SEARCH_LIMIT) / s.step_a + 1e-9)
    best = _smallest(s, k_max)
    if best is None or (cap is not None and best.a > cap):
        raise _refusal(s, k_max)
    s.tick(0.85, f"drawing the drive at A = {best.a:.6g} mm and checking its parts")
    best, web, drawn_note = _drawn(s, best, k_max)
    below = s.evaluate(round(best.a / s.step_a) - 1) if best.a - s.step_a >= s.a_lower else None
    binding = _binding(below)
    rows = tuple(replace(r, binding=(r.name == binding)) for r in s.rows(best.element, best.totals, web))
    el = best.element
    d = el.dimensions()
    notes = [f"z = {el.slots}, A = {el.center_distance:g} mm (crank r = A·sin(π/z) = {el.crank_radius:.6g} mm), "
             f"roller r_p = {el.roller_radius:g} mm × l = {el.roller_length:g} mm, slot width {2 * d.w:.4g} mm, "
             f"outer radius {d.outer_radius:.6g} mm, hub limit {d.hub_max:.6g} mm around the bore "
             f"{req.base['load']['journal_radius']:g} mm",
             f"resolution: A in steps of {s.step_a:g} mm, r_p of {s.step_r:g} mm (the roller is the largest the "
             f"wheel takes with the web {req.min_web:g} mm); {s.evals} candidates evaluated",
             f"contact model: peak R_n {best.totals.rn_peak:.6g} N at φ = {math.degrees(best.totals.u_peak):.4g}°, "
             f"p_max {best.totals.pressure_peak:.6g} MPa, L_s {best.totals.slip_path * 1e3:.6g} µm per engagement"]
    if binding is None:
        notes.append("binding: none — the smallest drive the geometry allows (every requirement has margin)")
    if drawn_note:
        notes.append(drawn_note)
    s.tick(1.0, "done")
    report = DesignReport(f"Geneva drive {el.id!r} designed from requirements (smallest centre distance)", rows,
                          tuple(notes), time.perf_counter() - t0)
    return GenevaDesign(el, report)


def _drawn(s: _Search, best: Candidate, k_max: int) -> tuple[Candidate, float, str]:
    """Draw the drive (exact relief) and check its parts with the web; step A up until they pass.
    Returns the candidate, its thinnest web (mm) and a note when A had to grow."""
    start = best.a
    k = round(best.a / s.step_a)
    for _ in range(DRAW_STEPS):
        if best.ok:
            try:
                checks = check_parts(geneva_parts(best.element, geo=geometry(best.element)).parts, s.req.min_web)
            except GeometryError:
                checks = None
            if checks is not None and all(c.ok for c in checks):
                web = min(c.web for c in checks if math.isfinite(c.web))
                note = (f"the drawn parts (exact relief) needed A = {best.a:g} mm, above the closed-form limits' "
                        f"{start:g} mm" if best.a > start else "")
                return best, web, note
        k += 1
        if k > k_max:
            break
        best = s.evaluate(k)
    raise DesignError(f"no drawable drive up to A = {k * s.step_a:g} mm: the parts fail their check with the web "
                      f"{s.req.min_web:g} mm; relax min_web or max_center_distance")


def _binding(below: Candidate | None) -> str | None:
    """The requirement that fails one step below the design (its most violated), or the geometry."""
    if below is None:
        return None
    if below.element is None:
        return "min_web"
    failing = below.failing()
    if not failing:
        return None
    return min(failing, key=lambda r: r.margin).name


def _refusal(s: _Search, k_max: int) -> DesignError:
    """Why nothing fits within the cap, and each single relaxation that would do (checked)."""
    req = s.req
    at = s.evaluate(k_max)
    relax: list[Relaxation] = []
    cap = req.max_center_distance
    if cap is not None:
        free = _smallest(_Search(replace(req, max_center_distance=None), None, s.crank),
                         math.floor(SEARCH_LIMIT / s.step_a))
        if free is not None:
            relax.append(Relaxation("max_center_distance", cap, free.a, "mm"))
    where = f"at the largest centre distance allowed (A = {at.a:g} mm)" if cap is not None else \
        f"up to A = {at.a:g} mm"
    if at.element is None:
        web = _largest_web(s, k_max)
        if web is not None:
            relax.append(Relaxation("min_web", req.min_web, web, "mm"))
        return infeasible(f"no Geneva drive meets the requirements: {where} no roller fits the wheel with the "
                          f"web {req.min_web:g} mm (slots, lands, hub and bores)", relax)
    failing = [r for r in at.failing() if r.name != "max_center_distance"]
    if len(failing) == 1 and failing[0].name in ("allowable_contact_stress", "life_cycles"):
        r = failing[0]
        needed = r.value * (1 + 1e-9) if r.sense == "<=" else r.value * (1 - 1e-9)
        relax.append(Relaxation(r.name, r.limit, needed, r.unit))
    what = "; ".join(f"{r.name}: {r.what} {r.value:.6g} {r.unit} against {r.limit:.6g} {r.unit}" for r in failing)
    return infeasible(f"no Geneva drive meets the requirements: {where}, with the largest roller the wheel takes "
                      f"(r_p = {at.rp:g} mm), {what}", relax)


def _largest_web(s: _Search, k_max: int) -> float | None:
    """The largest web (mm, 3 digits) with which a roller fits at the largest A; None if none."""
    lo, hi = 0.0, s.req.min_web
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        base = dict(s.req.base, drawing={"min_web": mid})
        trial = _Search(replace(s.req, base=base, min_web=mid), None, s.crank)
        trial.step_a, trial.step_r = s.step_a, s.step_r
        if trial.roller(k_max * s.step_a) is not None:
            lo = mid
        else:
            hi = mid
    return float(f"{lo:.3g}") if lo > 0 else None
