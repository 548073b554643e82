"""What the Study dock runs on its worker thread, and what it makes of the results (Qt-free).

- :func:`tolerance_work` — the tolerance and pin-clearance Monte Carlo of one linkage
  (:func:`mechsketch.core.studies.tolerance.tolerance`) and its first-order band
  (``linearised_tolerance``) for the agreement, as a :class:`ToleranceOutcome`;
- :func:`optimise_work` — an optimisation study (:func:`mechsketch.core.studies.study.run_study`:
  NSGA-II for two objectives, differential evolution for one) as an :class:`OptimiseOutcome`;
- :func:`band` — the envelope of the traced point at a confidence, magnified so that it can be
  seen on the canvas (:func:`magnification`), as the canvas layer takes it;
- :func:`objectives` — the metrics a linkage can be optimised for, in words.

The core modules are imported when a study runs (numba, scipy and pymoo are not loaded before).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechsketch.core.model.linkage import JointKind, Linkage

#: confidences offered for the band: label -> two-sided coverage
CONFIDENCES = {"95 %": 0.95, "99 %": 0.99, "99.7 %": 0.997}
#: the auto magnification makes the band's widest half-width this fraction of the path's size
BAND_FRACTION = 0.025


def traced_default(linkage: Linkage) -> list[str]:
    """The points a tolerance run traces by default: revolute joints on one moving link only
    (coupler points), else every joint off the frame (the core's ``default_joints``)."""
    frame = set(linkage.link(linkage.ground).joints) if linkage.ground in linkage.link_ids else set()
    single = [j.id for j in linkage.joints if len(linkage.links_of(j.id)) == 1 and j.id not in frame
              and j.kind is JointKind.R]
    return single or [j for j in linkage.joint_ids if j not in frame]


@dataclass
class ToleranceOutcome:
    """A finished tolerance run: the studied ``linkage`` record, the traced ``joint``, the core's
    ``result`` (:class:`~mechsketch.core.studies.tolerance.ToleranceResult`), the agreement of
    the linearised 3σ band with the Monte Carlo (relative, or None without dimension tolerances)."""

    linkage: Linkage
    joint: str
    result: Any
    agreement: float | None
    spec: dict


def tolerance_work(linkage: Linkage, spec: dict, builds: int, samples: int, seed: int, joint: str, ticket):
    """Run the Monte Carlo of ``spec`` on the worker thread (``ticket``: :class:`~.jobs.Ticket`)."""
    from mechsketch.core.studies.tolerance import BLOCK, linearised_tolerance, tolerance

    ticket.report(0.0, f"setting up {builds:,} builds × {samples} samples")
    res = tolerance(linkage, spec, builds=builds, samples=samples, seed=seed, joints=[joint],
                    progress=lambda d, n: ticket.study_progress(d, n, f"{min(d * BLOCK, builds):,} of {builds:,} builds"),
                    cancel=ticket.event)
    agree = None
    if any(k != "clearance" for k in spec):
        lin = linearised_tolerance(linkage, spec, samples=samples, joints=[joint])
        agree = lin.agreement(res, joint)
    return ToleranceOutcome(linkage, joint, res, agree, spec)


def magnification(half_width: float, size: float) -> float:
    """A round factor (1, 2, 5 × 10^n, at least 1) that shows a band of ``half_width`` (mm) at
    about :data:`BAND_FRACTION` of ``size`` (mm)."""
    if not (half_width > 0 and math.isfinite(half_width)):
        return 1.0
    want = BAND_FRACTION * size / half_width
    if want <= 1.0:
        return 1.0
    exp = math.floor(math.log10(want))
    for m in (5, 2, 1):
        if m * 10 ** exp <= want:
            return float(m * 10 ** exp)
    return float(10 ** exp)


def band(out: ToleranceOutcome, confidence: float, factor: float | None = None) -> dict:
    """The envelope of ``out.joint`` covering ``confidence`` of the builds (two-sided), magnified
    by ``factor`` (None: :func:`magnification`): the canvas layer's band dict, with ``factor``,
    ``half_width`` (the true widest half-width, mm) and ``label``."""
    res, j = out.result, out.joint
    q = 0.5 * (1.0 + confidence)
    nominal = np.asarray(res.nominal.pos[j], dtype=float)
    upper, lower = res.envelope(j, q), res.envelope(j, 1.0 - q)
    with np.errstate(invalid="ignore"):
        half = np.nanmax(np.maximum(np.hypot(*(upper - nominal).T), np.hypot(*(lower - nominal).T))) \
            if np.isfinite(upper).any() else float("nan")
    fin = nominal[np.isfinite(nominal).all(axis=1)]
    size = float(np.hypot(*(fin.max(axis=0) - fin.min(axis=0)))) if len(fin) else 1.0
    k = magnification(float(half), size) if factor is None else float(factor)
    label = f"{100 * confidence:g} % band of {j}" + (f", ×{k:g} magnified" if k != 1 else "") + \
        (f" (true width ±{half:.3g} mm)" if math.isfinite(half) else "")
    return {"nominal": nominal, "lower": nominal + k * (lower - nominal), "upper": nominal + k * (upper - nominal),
            "label": label, "closed": True, "factor": k, "half_width": float(half)}


def objectives(linkage: Linkage) -> list[tuple[str, str, str]]:
    """(sense, metric, words) of what ``linkage`` can be optimised for: its least transmission
    angle, each moving link's swing, the driving effort and shaking (with masses or loads), the
    cut parts' thinnest web and envelope."""
    out = [("maximize", "min_transmission_angle", "maximise the least transmission angle μ (°)")]
    for k in linkage.moving_links:
        out.append(("maximize", f"swing:{k}", f"maximise the swing of {k} (°)"))
        out.append(("minimize", f"swing:{k}", f"minimise the swing of {k} (°)"))
    if linkage.masses or linkage.loads:
        out += [("minimize", "peak_torque", "minimise the peak driving torque (N·m)"),
                ("minimize", "rms_torque", "minimise the RMS driving torque (N·m)"),
                ("minimize", "peak_shaking_force", "minimise the peak shaking force (N)")]
    out += [("maximize", "thinnest_web", "maximise the parts' thinnest web (mm)"),
            ("minimize", "part_envelope", "minimise the largest part (mm)")]
    return out


@dataclass
class OptimiseOutcome:
    """A finished optimisation: the studied ``linkage``, the core's ``result``
    (:class:`~mechsketch.core.studies.study.StudyResult`), the objective metrics, and the front as
    (evaluation row, variant record) pairs, best first by the first objective."""

    linkage: Linkage
    result: Any
    metrics: list[str]
    front: list = field(default_factory=list)

    def front_xy(self) -> tuple[np.ndarray, np.ndarray]:
        """The front (F, 2) and the other feasible evaluations (E, 2) in the scatter's axes: the two
        objectives, or (evaluation, objective) for one."""
        cols = self.result.columns
        rows = np.array([r for r, _ in self.front], dtype=int)
        feas = np.flatnonzero(cols["feasible"] > 0)
        others = np.setdiff1d(feas, rows)
        if len(self.metrics) > 1:
            x, y = cols[self.metrics[0]], cols[self.metrics[1]]
        else:
            x, y = cols["evaluation"].astype(float), cols[self.metrics[0]]
        xy = np.column_stack([x, y])
        return xy[rows], xy[others]


def study_dict(variables: dict, objectives_: list[tuple[str, str]], min_mu: float | None, samples: int, seed: int,
               population: int, generations: int) -> dict:
    """The study file's dict of an optimisation (:mod:`mechsketch.core.studies.study`)."""
    opt: dict = {"objectives": [{sense: metric} for sense, metric in objectives_], "population": population,
                 "generations": generations, "pareto_scenes": 500}
    if min_mu is not None:
        opt["constraints"] = [{"metric": "min_transmission_angle", "min": float(min_mu)}]
    return {"samples": samples, "seed": seed, "variables": variables, "optimize": opt}


def optimise_work(linkage: Linkage, data: dict, ticket) -> OptimiseOutcome:
    """Run the optimisation ``data`` on the worker thread. Progress counts the population's
    evaluations (one a generation) against the generations asked for."""
    from mechsketch.core.studies.study import load_study, run_study

    st = load_study(data, linkage)
    total = int(data["optimize"]["generations"]) + 1
    seen = {"gen": 0}

    def progress(done: int, n: int) -> None:
        if done == 0:
            seen["gen"] += 1
        g = seen["gen"]
        ticket.report(min((g - 1 + (done / n if n else 1.0)) / total, 0.99),
                      f"generation {min(g, total)} of about {total}")

    ticket.report(0.0, "checking the study")
    res = run_study(st, progress=progress, cancel=ticket.event)
    metrics = [next(iter(o.values())) for o in data["optimize"]["objectives"]]
    return OptimiseOutcome(linkage, res, metrics, list(res.pareto))


__all__ = ["CONFIDENCES", "OptimiseOutcome", "ToleranceOutcome", "band", "magnification", "objectives",
           "optimise_work", "study_dict", "tolerance_work", "traced_default"]
