"""The last step of every linkage synthesis: from designs ranked by their closed form to checked
candidates, best first, each a linkage element that passed the product's solver.

:func:`finish` walks the ranked designs, builds each as a linkage (:func:`~.candidates.build_linkage`),
drives it over its target span with :func:`~.candidates.drive_check`, measures the deviation
from the target with the solver's own motion (a ``measure`` callback of the synthesis), drops
near-duplicates, and stops at K. Refusals are counted by reason for the notes (and for the error
message when nothing passes).
"""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace
from typing import Callable, Iterable

import numpy as np

from ..solver.plan import Plan
from . import families as F
from .candidates import Candidate, Stopwatch, build_linkage, cut_check, drive_check, kind_text, span_inputs
from .options import LinkageOptions
from .targets import Progress, report


@dataclass
class Design:
    """A design ranked by its closed form: ``x`` (:mod:`.families` parameters), mode ``sigma``,
    crank ``direction`` (±1), ``inputs`` (n,) the crank angles (rad, world) at the target's
    points in order, ``score`` (larger is better), ``seconds`` spent on it so far."""

    topology: str
    x: np.ndarray
    sigma: float
    direction: float
    inputs: np.ndarray
    score: float = 0.0
    seconds: float = 0.0


#: two designs whose pivots and pins all lie closer than this fraction of the size are one
DISTINCT = 0.03

#: measure(plan, design) -> (deviation, unit, angle deviation or None, rms or None) with the solver
Measure = Callable[[Plan, Design], tuple[float, str, "float | None", "float | None"]]


def _signature(d: Design, size: float) -> tuple[str, np.ndarray]:
    """Its topology and where its pivots and pins are (world, mm / size): two designs this close
    are the same."""
    ev = F.evaluate(d.topology, d.x[None], np.array([[d.inputs[0]]]), d.sigma)
    skip = ("e", "u", "F") if d.topology in F.SLIDER_SIXBARS else ("e", "u")   # (F: any point of a guide)
    pts = [v[0, 0] for k, v in sorted(ev.joints.items()) if np.iscomplexobj(v) and k not in skip]
    return d.topology, np.array([p for z in pts for p in (z.real, z.imag)]) / size


def fixed_pivots(topology: str, x: np.ndarray) -> np.ndarray:
    """(2,) or (1,) the design's pivots on the frame (complex mm)."""
    if topology == F.SLIDER_CRANK:
        return np.array([x[0] + 1j * x[1]])
    if topology in F.SIXBARS + F.GUIDE_SIXBARS:
        return np.array([x[0] + 1j * x[1], x[2] + 1j * x[3], x[9] + 1j * x[10]])
    if topology in F.SLIDER_SIXBARS:     # F is any point of the slider's guide: not a pivot
        return np.array([x[0] + 1j * x[1], x[2] + 1j * x[3]])
    return np.array([x[0] + 1j * x[1], x[2] + 1j * x[3]])


def finish(designs: Iterable[Design], options: LinkageOptions, size: float, closed: bool, measure: Measure,
           output: bool = False, point: bool = True, progress: Progress | None = None,
           limit: int = 200, fraction: tuple[float, float] = (0.8, 1.0), centre: complex | None = None,
           timings: dict | None = None) -> tuple[list[Candidate], Counter]:
    """Checked candidates from ``designs`` (best first), at most ``options.candidates``; tries at
    most ``limit`` designs. ``centre``: the target's centre, for the pivot guard (None: not
    checked here). Designs are first driven by the solver (cheap) until K pass; then the parts
    ``validate`` would cut are checked for those K (the expensive step), and the drive checks go
    on for as many as failed. ``timings`` (if given) gets the seconds of both stages ("drive",
    "cut"). Returns the candidates, renumbered ``prefix_1``.., and the refusals by reason."""
    out: list[Candidate] = []
    seen: list[tuple[str, np.ndarray]] = []
    refused: Counter = Counter()
    k = options.candidates
    designs = list(designs)[:limit]
    lo, hi = fraction
    clock = {"drive": 0.0, "cut": 0.0} if timings is None else timings
    clock.setdefault("drive", 0.0)
    clock.setdefault("cut", 0.0)
    todo = iter(enumerate(designs))
    pending: list[tuple[Candidate, tuple[str, np.ndarray]]] = []
    over: list[tuple[float, str]] = []
    while True:
        watch = Stopwatch()
        for n, d in todo:
            report(progress, lo + (hi - lo) * n / max(len(designs), 1), f"checking design {n + 1} of {len(designs)}")
            got = _drive(d, options, size, closed, measure, output, point, centre, seen + [p[1] for p in pending],
                         refused, over)
            if got is not None:
                pending.append(got)
                if len(out) + len(pending) >= k:
                    break
        clock["drive"] += watch.elapsed
        if not pending:
            break
        watch = Stopwatch()
        for cand, sig in pending:
            t0 = watch.elapsed
            why = cut_check(cand.linkage)
            cand.seconds += watch.elapsed - t0
            if why:
                refused[_reason(why)] += 1
            else:
                out.append(cand)
                seen.append(sig)
        clock["cut"] += watch.elapsed
        pending = []
        if len(out) >= k:
            break
    for j, c in enumerate(out):
        c.linkage = replace(c.linkage, id=f"{options.prefix}_{j + 1}")
    if over:
        dev, unit = min(over)
        n = refused.pop(_OVER, 0)
        why = f"{_OVER_PREFIX} {options.max_deviation:g} {unit} asked (the closest: {dev:.4g} {unit})"
        refused[why] = n
    return out, refused


_OVER_PREFIX = "a largest deviation above the"
_OVER = _OVER_PREFIX + " maximum asked"


def _drive(d: Design, options: LinkageOptions, size: float, closed: bool, measure: Measure, output: bool,
           point: bool, centre: complex | None, seen: list, refused: Counter, over: list):
    """(candidate, signature) of design ``d`` if it passes every check but the cut, else None
    (the reason counted in ``refused``; a deviation above ``options.max_deviation`` also goes to
    ``over`` as (deviation, unit))."""
    watch = Stopwatch()
    sig = _signature(d, size)
    if any(t == sig[0] and np.max(np.abs(sig[1] - s)) < DISTINCT for t, s in seen):
        refused["a near-duplicate of a better one"] += 1
        return None
    if centre is not None and not options.pivot_ok(fixed_pivots(d.topology, d.x), centre, size).all():
        refused["a fixed pivot outside the pivot region or too far away"] += 1
        return None
    theta = span_inputs(d.inputs, d.direction, closed)
    if theta is None:
        refused["order defect (the targets are not met in order)"] += 1
        return None
    try:
        lk = build_linkage(d.topology, d.x, d.sigma, float(d.inputs[0]), options.prefix, d.direction, output, point,
                           options.speed_rpm, options.samples)
    except ValueError as exc:   # GeometryError: not assembled at the drawn input
        refused[str(exc)] += 1
        return None
    chk = drive_check(lk, d.topology, d.x, d.sigma, theta, options.min_transmission_deg, size, parts=False)
    if not chk.ok:
        refused[_reason(chk.reason)] += 1
        return None
    if options.full_turn and not chk.full_turn:
        refused["the crank does not turn fully"] += 1
        return None
    kind = kind_text(d.topology, d.x)
    if options.grashof is not None and not kind.startswith(options.grashof):
        refused[f"not a {options.grashof}"] += 1
        return None
    dev, unit, adev, rms = measure(chk.plan, d)
    if options.max_deviation is not None and not dev <= options.max_deviation:
        refused[_OVER] += 1
        over.append((dev, unit))
        return None
    cand = Candidate(lk, d.topology, d.x, d.sigma, d.direction, d.inputs, dev, unit, chk.min_transmission_deg, kind,
                     chk.full_turn, d.seconds + watch.elapsed, adev, rms)
    return cand, sig


def _reason(text: str) -> str:
    """A refusal's reason without its numbers (so that they count together)."""
    if "transmission angle" in text:
        return "transmission angle below the minimum in the span"
    if "cannot be assembled" in text:
        return "a dead point or an unassemblable pose inside the span"
    if "branch" in text:
        return "branch defect (the solver's motion leaves the design's branch)"
    if "cannot be cut" in text:
        return "its parts cannot be cut (validate)"
    return text.split(":")[0]


def relax_text(refused: Counter, advice: str) -> str:
    """What to relax: ``advice``, first raising the maximum deviation when that refused designs."""
    if any(why.startswith(_OVER_PREFIX) for why in refused):
        return "raise the maximum deviation (--max-deviation), " + advice
    return advice


def refusal_text(refused: Counter) -> str:
    """The refusals as ``"12 for <reason>, ..."`` (most frequent first)."""
    return "; ".join(f"{n} for {why}" for why, n in refused.most_common())


__all__ = ["Design", "Measure", "finish", "fixed_pivots", "refusal_text", "relax_text"]
