"""The smooth Geneva drive (issue 25, item 4): a Geneva whose crank is driven through a synthesised
non-circular gear pair that slows the crank at entry and exit, at the same index time and dwell.

The gears' function is ψ(θ) = θ + Σ_{k=1..K} c_k·sin(kθ) (odd: entry and exit alike), the crank's
progress angle u as a function of the input's θ. Its coefficients solve (SLSQP) the minimax problem

    minimise t  subject to  |jerk(θ_j)|/|jerk_0| ≤ t on a grid over the engagement,
                            ψ(φ0) = φ0                      (the same index time and dwell),
                            ψ'(φ0)² ≤ 1 − jump_reduction    (the acceleration step at entry/exit),
                            min_ratio ≤ ψ' ≤ max_ratio       (the gears' speed ratio, a whole turn),
                            |ψ''|/(ψ'(1 + ψ')) ≤ tan(max_pressure)   (both pitch curves' inclination
                                                    to their radius: the teeth's pressure-angle swing),

with jerk_0 the constant crank's peak jerk (at mid-indexing, j̃(0)·ω1³) and the wheel's jerk from
:func:`~..analyses.geneva.driven.wheel_rates`. The reductions found are then measured on the
continuous motion (:func:`~..analyses.geneva.driven.smoothness`) and the design is refused when
they fall short, naming what to relax: the reduction (to what is reached), more harmonics, or
fewer slots (the bang-bang bound makes ≥ 50 % on both out of reach above z ≈ 5).

The drive itself is sized as :mod:`.geneva` does, with the contact loads of the geared motion
(the normal force from J2·(ε̃·u̇² + i·ü) + M_ext); the gears sit on the crank shaft, their input
pivot ``gear_center_distance`` away on the side opposite the wheel.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analyses.gears.pitch import PitchChecks, checks
from ..analyses.geneva.driven import GearCrank, Smoothness, smoothness, wheel_rates
from ..analyses.geneva.kinematics import jerk_ratio
from ..model.gear_function import GearFunction, ratio_problem
from ..model.geared_geneva import GearedGeneva
from .design_report import DesignError, DesignReport, Progress, Relaxation, Requirement, infeasible, report_progress
from .geneva import GenevaDesign, design_geneva, parse_requirements

SMOOTH_KEYS = ("harmonics", "jump_reduction", "jerk_reduction", "min_ratio", "max_ratio", "max_pressure_deg",
               "gear_center_distance", "input_direction_deg", "grid")
DEFAULTS = {"harmonics": 10, "jump_reduction": 0.5, "jerk_reduction": 0.5, "min_ratio": 0.3, "max_ratio": 3.5,
            "max_pressure_deg": 45.0, "grid": 121}
#: the optimiser aims this much beyond the required reductions (the continuous peaks are then checked)
AIM = 0.02


@dataclass(frozen=True)
class SmoothDesign:
    """The result: ``element`` (a ``geared_geneva``), ``report``, the ``smoothness`` measured, the
    gears' ``pitch`` checks and the Geneva sizing (``geneva``)."""

    element: GearedGeneva
    report: DesignReport
    smoothness: Smoothness
    pitch: PitchChecks
    geneva: GenevaDesign


def smooth_function(z: int, harmonics: int = 10, jump_reduction: float = 0.5, jerk_target: float = 0.5,
                    min_ratio: float = 0.3, max_ratio: float = 3.5, grid: int = 121,
                    max_pressure_deg: float = 45.0) -> GearFunction:
    """The gears' function for ``z`` slots (see the module docstring); ``jerk_target`` the peak
    jerk aimed at, relative to the constant crank's. Raises :class:`DesignError` when the optimiser
    finds no function within the ratio limits."""
    from scipy.optimize import minimize   # heavy; only when a smooth drive is designed

    lam, phi0 = math.sin(math.pi / z), math.pi / 2 - math.pi / z
    ks = np.arange(1, harmonics + 1, dtype=float)
    th = np.linspace(-phi0, phi0, grid)
    whole = np.linspace(-math.pi, math.pi, 4 * grid)
    j0 = abs(float(jerk_ratio(0.0, lam)))
    s_th, c_th = np.sin(np.outer(th, ks)), np.cos(np.outer(th, ks))
    c_all = np.cos(np.outer(whole, ks))

    def jerk(c):
        u = th + s_th @ c
        p1, p2, p3 = 1 + c_th @ (ks * c), -(s_th @ (ks ** 2 * c)), -(c_th @ (ks ** 3 * c))
        return wheel_rates(u, lam, p1, p2, p3)[2] / j0

    s_all = np.sin(np.outer(whole, ks))
    tp = math.tan(math.radians(0.995 * max_pressure_deg))   # a little inside: the grid is not the curve
    lo, hi = min_ratio * 1.01, max_ratio / 1.01     # the grid's limits, a little inside the continuous ones

    def pressure(c):   # tan(max)·ψ'(1 + ψ') ∓ ψ'' ≥ 0 (smooth: no absolute value)
        p1, p2 = 1.0 + c_all @ (ks * c), -(s_all @ (ks ** 2 * c))
        room = tp * p1 * (1.0 + p1)
        return np.concatenate([room - p2, room + p2])

    entry = np.cos(ks * phi0) * ks
    cons = [{"type": "eq", "fun": lambda x: np.sin(ks * phi0) @ x[:-1]},
            {"type": "ineq", "fun": lambda x: x[-1] - jerk(x[:-1])},
            {"type": "ineq", "fun": lambda x: x[-1] + jerk(x[:-1])},
            {"type": "ineq", "fun": lambda x: math.sqrt(1.0 - jump_reduction) - (1.0 + entry @ x[:-1])},
            {"type": "ineq", "fun": lambda x: (1.0 + c_all @ (ks * x[:-1])) - lo},
            {"type": "ineq", "fun": lambda x: hi - (1.0 + c_all @ (ks * x[:-1]))},
            {"type": "ineq", "fun": lambda x: pressure(x[:-1])}]
    x0 = np.zeros(harmonics + 1)
    x0[-1] = 1.0
    res = minimize(lambda x: x[-1], x0, constraints=cons, method="SLSQP",
                   options={"maxiter": 1000, "ftol": 1e-12})
    fn = GearFunction("fourier", 1.0, tuple(float(v) for v in res.x[:-1]), ())
    if not res.success or ratio_problem(fn) is not None:
        raise DesignError(f"no gear function found for z = {z} with {harmonics} harmonics and the speed ratio in "
                          f"[{min_ratio:g}, {max_ratio:g}] ({res.message}); relax min_ratio/max_ratio or the reductions")
    return fn


def _options(data: dict) -> dict:
    smooth = dict(data.get("smooth") or {})
    unknown = [k for k in smooth if k not in SMOOTH_KEYS]
    if unknown:
        raise DesignError(f"unknown smooth key(s) {', '.join(map(repr, unknown))} (known: {', '.join(SMOOTH_KEYS)})")
    out = {**DEFAULTS, **smooth}
    for k in ("jump_reduction", "jerk_reduction"):
        if not (isinstance(out[k], (int, float)) and 0.0 <= out[k] < 1.0):
            raise DesignError(f"smooth.{k} must lie in [0, 1), got {out[k]!r}")
    if not (isinstance(out["harmonics"], int) and 1 <= out["harmonics"] <= 32):
        raise DesignError(f"smooth.harmonics must be a whole number from 1 to 32, got {out['harmonics']!r}")
    if not 0.05 <= out["min_ratio"] < 1.0 < out["max_ratio"] <= 20.0:
        raise DesignError("smooth.min_ratio must lie in [0.05, 1) and max_ratio in (1, 20]")
    return out


def design_smooth_geneva(requirements: Any, element_id: str = "smooth_geneva",
                         progress: Progress | None = None) -> SmoothDesign:
    """The smooth Geneva drive for ``requirements`` (a Geneva REQ with ``"smooth": {...}``; see
    :mod:`.geneva` and the module docstring). Returns a :class:`SmoothDesign`; raises
    :class:`~.design_report.DesignError` or :class:`~.design_report.DesignCancelled`."""
    t0 = time.perf_counter()
    opts = _options(requirements if isinstance(requirements, dict) else {})
    base = {k: v for k, v in requirements.items() if k != "smooth"}
    req = parse_requirements(base, element_id)
    z = req.slots
    omega1 = float(req.base["speed_rpm"]) * math.pi / 30.0
    report_progress(progress, 0.0, f"synthesising the gear function for z = {z}")
    fn = smooth_function(z, opts["harmonics"], opts["jump_reduction"] + AIM, 1.0 - opts["jerk_reduction"] - AIM,
                         opts["min_ratio"], opts["max_ratio"], opts["grid"], opts["max_pressure_deg"])
    sm = smoothness(fn, z, omega1)
    short = []
    if sm.jump_reduction < opts["jump_reduction"]:
        short.append(Relaxation("smooth.jump_reduction", opts["jump_reduction"], sm.jump_reduction, ""))
    if sm.jerk_reduction < opts["jerk_reduction"]:
        short.append(Relaxation("smooth.jerk_reduction", opts["jerk_reduction"], sm.jerk_reduction, ""))
    if short:
        raise infeasible(f"z = {z}: the gears reach {100 * sm.jump_reduction:.1f} % less acceleration jump and "
                         f"{100 * sm.jerk_reduction:.1f} % less peak jerk at the same index time; the rest-to-rest "
                         "bound (a bang-bang jerk) allows ≥ 50 % on both only for z ≤ 5 (z = 6 reaches about 49 %): "
                         "use fewer slots, more harmonics, a wider ratio range, or relax", short)
    report_progress(progress, 0.3, "sizing the drive with the geared crank's loads")
    crank = GearCrank(fn, omega1)
    sized = design_geneva(req, element_id, _scaled_progress(progress, 0.3, 0.9), crank=crank)
    a_g = float(opts.get("gear_center_distance") or sized.element.center_distance)
    direction = float(opts.get("input_direction_deg", sized.element.wheel_direction_deg + 180.0))
    el = GearedGeneva(element_id, sized.element, a_g, fn, direction, min_web=req.min_web)
    pitch = checks(fn, a_g, -1.0 if omega1 > 0 else 1.0)
    rows = list(sized.report.requirements) + [
        Requirement("smooth.jump_reduction", "acceleration jump at entry/exit below the constant crank's",
                    sm.jump_reduction, opts["jump_reduction"], ">="),
        Requirement("smooth.jerk_reduction", "peak jerk below the constant crank's", sm.jerk_reduction,
                    opts["jerk_reduction"], ">="),
        Requirement("smooth.index_time", "index time against the constant crank's (s)", sm.index_time,
                    sm.index_time_constant, "==", "s", tolerance=1e-9 * sm.index_time_constant),
        Requirement("smooth.min_ratio", "smallest gear speed ratio ψ'", pitch.ratio_min, opts["min_ratio"] * (1 - 1e-9),
                    ">="),
        Requirement("smooth.max_ratio", "largest gear speed ratio ψ'", pitch.ratio_max, opts["max_ratio"] * (1 + 1e-9),
                    "<="),
        Requirement("smooth.max_pressure_deg", "largest swing of the pitch curves' pressure angle",
                    max(pitch.pressure_input_deg, pitch.pressure_output_deg), opts["max_pressure_deg"],
                    "<=", "°"),
    ]
    notes = list(sized.report.notes) + sm.lines() + pitch.lines() + [
        f"gears: ψ(θ) = θ + Σ c_k sin kθ, c = [{', '.join(f'{c:.6g}' for c in fn.sin)}]; centre distance "
        f"{a_g:g} mm, input at {direction:g}° from the crank centre, turning at {abs(omega1) * 30 / math.pi:g} rpm "
        "against the crank"]
    report_progress(progress, 1.0, "done")
    rep = DesignReport(f"smooth Geneva drive {element_id!r}: z = {z} driven through non-circular gears", tuple(rows),
                       tuple(notes), time.perf_counter() - t0)
    return SmoothDesign(el, rep, sm, pitch, sized)


def _scaled_progress(progress: Progress | None, lo: float, hi: float) -> Progress | None:
    if progress is None:
        return None
    return lambda f, text: progress(lo + (hi - lo) * f, text)

