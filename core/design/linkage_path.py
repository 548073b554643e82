"""Path synthesis: linkages whose coupler point ``P`` traces a target path.

1. **Retrieve** starting designs from the atlas of each topology asked for and **align** them
   to the target (:mod:`.path_starts`: nearest Fourier descriptors for a closed path, a window
   scan for an open arc).
2. **Refine** all starts at once by Levenberg–Marquardt (:mod:`.refine`) on the distance of
   P(θ_k) from each target point, over the design's world parameters and the crank angle θ_k of
   each point (untimed) or one start angle (timed: θ_k = θ_0 ± the given inputs), with the exact
   derivatives of the closed form (:mod:`.families`, the input-angle column being the kernels'
   velocity over ω); link lengths are bounded by the size guard and the transmission angle over
   the span is held above the minimum by a penalty.
3. **Filter and rank** (:func:`~.finish.finish`): by the RMS deviation; each candidate is built
   and driven by the product's solver over the span (a whole turn for a closed path), and kept
   only without a dead point or branch jump, in order, with its pivots where allowed, its
   transmission angle above the minimum, of the asked Grashof type, and cuttable.

``synthesize_path(target, options, topology, progress=...)`` returns a
:class:`~.options.DesignResult`; it runs on any thread and reports progress and honours cancel
through ``progress`` (see :class:`~.targets.Progress`).
"""
from __future__ import annotations

import math

import numpy as np

from ..solver.plan import Plan
from . import families as F
from .atlas import load_atlas
from .candidates import Stopwatch
from .finish import Design, finish, fixed_pivots, refusal_text, relax_text
from .options import DesignResult, LinkageOptions
from .path_starts import Start, closed_starts, open_starts
from .refine import floor_penalty, levenberg_marquardt
from .targets import DesignError, PathTarget, Progress, report

TOPOLOGIES = (F.FOURBAR, F.SLIDER_CRANK, F.INVERTED) + F.ALL_SIXBARS
#: what --topology takes: "sixbar" means every six-bar (Stephenson III and Watt II, their second
#: dyad an RRR, a slider's RRP or a guided rocker's RPR)
CHOICES = (F.FOURBAR, F.SLIDER_CRANK, F.INVERTED, F.SIXBAR, "any")
#: starts refined per topology
STARTS = 32
#: samples of the transmission-angle penalty over the span
PENALTY_SAMPLES = 48
#: Levenberg–Marquardt iterations of the refinement (the six-bar's 15 parameters converge slower)
ITERATIONS = {top: 120 for top in F.ALL_SIXBARS}
DEFAULT_ITERATIONS = 40
#: weight of the transmission-angle penalty (per unit of sin μ below the floor, per sample)
MU_WEIGHT = 2.0
#: weight of the order penalty (per radian of a step against the crank's direction)
ORDER_WEIGHT = 0.1


def _unknowns(target: PathTarget, st: Start) -> np.ndarray:
    if target.timed:
        th0 = np.angle(np.mean(np.exp(1j * (st.theta - st.direction * target.inputs_rad))))
        return np.concatenate([st.x, [th0]])
    return np.concatenate([st.x, st.theta])


def _thetas(target: PathTarget, u: np.ndarray, k: int, direction: np.ndarray) -> np.ndarray:
    """(D, M) crank angles at the target points from the unknowns."""
    if target.timed:
        return u[:, k:k + 1] + direction[:, None] * target.inputs_rad[None, :]
    return u[:, k:]


def _bounds(topology: str, unknowns: int, size: float, options: LinkageOptions) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the unknowns: link lengths from 1e-3 to ``max_size`` target sizes, else free."""
    lower = np.full(unknowns, -np.inf)
    upper = np.full(unknowns, np.inf)
    for name in F.POSITIVE[topology]:
        j = F.PARAMS[topology].index(name)
        lower[j], upper[j] = 1e-3 * size, options.max_size * size
    return lower, upper


def _order_penalty(th: np.ndarray, direction: np.ndarray, k: int, unknowns: int) -> tuple[np.ndarray, np.ndarray]:
    """The points in order: a residual for each step of the crank (th (D, M)) against its
    direction (D,), and its Jacobian over the unknowns (the crank angles from column k)."""
    back = -direction[:, None] * np.diff(th, axis=1)
    act = back > 0.0
    m = th.shape[1]
    ro = np.where(act, ORDER_WEIGHT * back, 0.0)
    Jo = np.zeros((th.shape[0], m - 1, unknowns))
    ar = np.arange(m - 1)
    Jo[:, ar, k + ar] = np.where(act, ORDER_WEIGHT * direction[:, None], 0.0)
    Jo[:, ar, k + ar + 1] = np.where(act, -ORDER_WEIGHT * direction[:, None], 0.0)
    return ro, Jo


def refine(topology: str, starts: list[Start], target: PathTarget, options: LinkageOptions,
           stop=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Refined designs of the ``starts`` (all of one topology): (x (D, K), theta (D, M),
    RMS deviation (D,) mm)."""
    z = target.points[:, 0] + 1j * target.points[:, 1]
    size = target.size
    k = len(F.PARAMS[topology])
    m = len(z)
    sigma = np.array([s.sigma for s in starts])
    direction = np.array([s.direction for s in starts])
    u0 = np.stack([_unknowns(target, s) for s in starts])
    U = u0.shape[1]
    lower, upper = _bounds(topology, U, size, options)
    floor = math.sin(math.radians(min(options.min_transmission_deg + 3.0, 89.0)))
    whole = target.closed or options.full_turn       # the penalty watches the whole turn, else the span
    frac = np.linspace(0.0, 1.0, PENALTY_SAMPLES, endpoint=not whole)

    def fun(u, rows):
        th = _thetas(target, u, k, direction[rows])
        if whole:
            span = th[:, :1] + direction[rows, None] * 2 * math.pi * frac[None, :]
        else:
            span = th[:, :1] + (th[:, -1:] - th[:, :1]) * frac[None, :]
        ev = F.evaluate(topology, u[:, :k], np.concatenate([th, span], axis=1), sigma[rows], grad=True)
        d = (ev.P[:, :m] - z[None, :]) / size
        dP = ev.dP[:, :m] / size
        n = len(u)
        J = np.zeros((n, 2 * m, U))
        J[:, :m, :k], J[:, m:, :k] = dP[..., :k].real, dP[..., :k].imag
        rp, Jp_full = floor_penalty(ev.sin_mu[:, m:], ev.dsin_mu[:, m:], floor, MU_WEIGHT)
        Jp = np.zeros((n, rp.shape[1], U))
        Jp[:, :, :k] = Jp_full[..., :k]
        if target.timed:
            J[:, :m, k], J[:, m:, k] = dP[..., k].real, dP[..., k].imag
            Jp[:, :, k] = Jp_full[..., k]
        else:
            ar = np.arange(m)
            J[:, ar, k + ar] = dP[..., k].real
            J[:, m + ar, k + ar] = dP[..., k].imag
            Jp[:, :, k] += Jp_full[..., k] * (np.ones_like(frac) if whole else 1.0 - frac)[None, :]
            if not whole:
                Jp[:, :, U - 1] += Jp_full[..., k] * frac[None, :]
        if target.timed:
            return (np.concatenate([d.real, d.imag, rp], axis=1), np.concatenate([J, Jp], axis=1))
        ro, Jo = _order_penalty(th, direction[rows], k, U)
        return (np.concatenate([d.real, d.imag, rp, ro], axis=1), np.concatenate([J, Jp, Jo], axis=1))

    u, _ = levenberg_marquardt(fun, u0, iterations=ITERATIONS.get(topology, DEFAULT_ITERATIONS), stop=stop,
                               lower=lower, upper=upper)
    th = _thetas(target, u, k, direction)
    P = F.evaluate(topology, u[:, :k], th, sigma).P
    rms = np.sqrt(np.mean(np.abs(P - z[None, :]) ** 2, axis=1))
    return u[:, :k], th, np.where(np.isfinite(rms), rms, np.inf)


def _fits(topology: str, options: LinkageOptions, size: float, centre: complex):
    """Whether a world design keeps within the size guard (links) and the pivot region."""
    cols = [F.PARAMS[topology].index(n) for n in F.POSITIVE[topology]]

    def fits(x: np.ndarray) -> bool:
        return bool(np.all(np.abs(x[cols]) <= options.max_size * size)
                    and options.pivot_ok(fixed_pivots(topology, x), centre, size).all())

    return fits


def _topologies(topology: str) -> tuple[str, ...]:
    if topology == "any":
        return TOPOLOGIES
    if topology == F.SIXBAR:
        return F.ALL_SIXBARS
    if topology not in TOPOLOGIES:
        raise DesignError(f"unknown topology {topology!r}; choose one of {', '.join(CHOICES)}")
    return (topology,)


def synthesize_path(target: PathTarget, options: LinkageOptions = LinkageOptions(), topology: str = "any",
                    progress: Progress | None = None, atlas_designs: int | None = None,
                    starts: int = STARTS) -> DesignResult:
    """Linkages whose joint ``P`` (on link ``coupler``) traces the target (see the module
    docstring). ``atlas_designs``: the atlas size to use (default: the installed one, built on
    first use); ``starts``: designs retrieved and refined per topology (the effort). Raises
    DesignError naming what to relax when nothing passes."""
    options.check()
    tops = _topologies(topology)
    watch = Stopwatch()
    z = target.points[:, 0] + 1j * target.points[:, 1]
    size, centre = target.size, complex(z.mean())
    ranked: list[tuple[float, Design]] = []
    notes: list[str] = []
    timings = {"atlas": 0.0, "retrieve": 0.0, "refine": 0.0}
    for n, top in enumerate(tops):
        lo = n / len(tops)
        t0 = watch.elapsed
        atlas = load_atlas(top, atlas_designs, _sub(progress, lo * 0.3, (lo + 1 / len(tops)) * 0.3))
        atlas.tree()
        timings["atlas"] += watch.elapsed - t0
        report(progress, 0.3 + 0.4 * lo, f"{top}: retrieving and aligning")
        t0 = watch.elapsed
        find = closed_starts if target.closed else open_starts
        found_starts = find(atlas, target, starts, options.min_transmission_deg, _fits(top, options, size, centre))
        timings["retrieve"] += watch.elapsed - t0
        if not found_starts:
            notes.append(f"{top}: no atlas design passes the transmission angle asked")
            continue
        report(progress, 0.3 + 0.4 * (lo + 0.5 / len(tops)), f"{top}: refining {len(found_starts)} designs")
        t0 = watch.elapsed
        x, th, rms = refine(top, found_starts, target, options,
                            stop=lambda: report(progress, 0.3 + 0.4 * (lo + 0.5 / len(tops)), f"{top}: refining"))
        timings["refine"] += watch.elapsed - t0
        per = (watch.elapsed - t0) / len(found_starts)
        for j, st in enumerate(found_starts):
            if np.isfinite(rms[j]):
                ranked.append((float(rms[j]), Design(top, x[j], st.sigma, st.direction, th[j], -float(rms[j]), per)))
        notes.append(f"{top}: {len(atlas):,} designs in the atlas, {len(found_starts)} retrieved and refined, best RMS "
                     f"{np.min(rms) / size:.2e} of the size")
    ranked.sort(key=lambda r: r[0])

    def measure(plan: Plan, d: Design):
        sol = plan.evaluate(d.inputs, order=0, joints=["P"])
        p = sol.position("P")
        e = np.hypot(p[:, 0] - target.points[:, 0], p[:, 1] - target.points[:, 1])
        return float(np.max(e)), "mm", None, float(np.sqrt(np.mean(e * e)))

    found, refused = finish((d for _, d in ranked), options, size, target.closed, measure, progress=progress,
                            fraction=(0.7, 1.0), centre=centre, timings=timings)
    if not found:
        raise DesignError("path: no defect-free linkage traces the target (" + "; ".join(notes)
                          + (f"; refused: {refusal_text(refused)}" if refused else "")
                          + "): " + relax_text(refused, "lower the minimum transmission angle, widen the pivot "
                                                          "region, allow another topology (--topology any) or "
                                                          "simplify the path"))
    if refused:
        notes.append(f"refused after building: {refusal_text(refused)}")
    report(progress, 1.0, "done")
    return DesignResult(found, watch.elapsed, notes, timings)


def _sub(progress: Progress | None, lo: float, hi: float) -> Progress | None:
    """``progress`` mapped onto [lo, hi] (for a step inside a longer task)."""
    if progress is None:
        return None
    return lambda f, msg: progress(lo + (hi - lo) * f, msg)


__all__ = ["CHOICES", "TOPOLOGIES", "refine", "synthesize_path"]
