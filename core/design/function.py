"""Function synthesis: a four-bar whose rocker angle, or a slider-crank whose slider position,
follows given input–output pairs of the crank angle.

Three pairs are met exactly with Freudenstein's equation (:mod:`.freudenstein`), solved at once
for a grid of the free starting angles (φ0, ψ0; for a slider-crank φ0 and the slider's start
s0). More pairs: the linear least-squares solution of the same equations over the grid gives the
starting designs, which Levenberg–Marquardt refines on the true output error (the closed-form
output of :mod:`.families` and its exact derivatives) over the lengths and both starting values.
Designs are screened in closed form for circuit defects (the output at the pairs is not the
function: the other closure), dead points and the transmission angle over the span, ranked, and
the best are built and driven by the product's solver (:func:`~.finish.finish`).

``synthesize_function(target, options, topology, size, progress)``: each candidate's output link
is named ``output``; the crank turns counter-clockwise when the inputs increase.
"""
from __future__ import annotations

import math

import numpy as np

from ..solver.plan import Plan
from . import families as F
from . import freudenstein as FR
from .candidates import Stopwatch
from .finish import Design, finish, refusal_text, relax_text
from .function_atlas import atlas_starts
from .options import DesignResult, LinkageOptions
from .refine import floor_penalty, levenberg_marquardt
from .targets import DesignError, FunctionTarget, Progress, report

#: starting values per axis of the grid
GRID = 72
SPAN_SAMPLES = 32


def _wrap(a):
    return np.remainder(a + math.pi, 2 * math.pi) - math.pi


def _errors(target: FunctionTarget, topology: str, x, sigma, theta) -> np.ndarray:
    """(G,) the largest output error at the pairs (rad or mm), from the first pair's output."""
    out = F.evaluate(topology, x, theta, sigma).out
    d = out - out[:, :1] - target.outputs[None, :]
    if target.angular:
        d = _wrap(d)
    e = np.abs(d).max(axis=1)
    return np.where(np.isfinite(e), e, np.inf)


def _starts(target: FunctionTarget, topology: str, scale: float):
    """Designs over the grid of starting values: (x, sigma, theta)."""
    g = np.linspace(0.0, 2 * math.pi, GRID, endpoint=False)
    x_in = target.inputs_rad[None, :]
    if topology == F.FOURBAR:
        p0, q0 = np.meshgrid(g, g, indexing="ij")
        phi = p0.reshape(-1, 1) + x_in
        psi = q0.reshape(-1, 1) + target.outputs[None, :]
        return FR.fourbar(phi, psi, scale)
    span = max(target.output_span, 1e-9)
    s0 = np.concatenate([np.linspace(-4.0, -0.25, 30), np.linspace(0.25, 4.0, 30)]) * span
    p0, q0 = np.meshgrid(g, s0, indexing="ij")
    return FR.slider_crank(p0.reshape(-1, 1) + x_in, q0.reshape(-1, 1) + target.outputs[None, :])


def _refine(target: FunctionTarget, topology: str, x, sigma, theta, scale: float, options: LinkageOptions, stop):
    """Levenberg–Marquardt on the output errors over the lengths and the starting values, the
    lengths bounded by the size guard and the transmission angle over the span kept above the
    minimum by a penalty (a soft bound)."""
    cols = [4, 5, 6] if topology == F.FOURBAR else [3, 4, 5]
    n = len(target.inputs_rad)
    out0 = F.evaluate(topology, x, theta[:, :1], sigma).out[:, 0]
    u0 = np.concatenate([x[:, cols], theta[:, :1], out0[:, None]], axis=1)
    w = 1.0 if target.angular else 1.0 / scale
    k = len(cols)
    big = options.max_size * scale
    lower = np.array([1e-3 * scale] * k + [-np.inf, -np.inf])
    if topology == F.SLIDER_CRANK:
        lower[0] = -big                      # the offset h may take either sign
    upper = np.array([big] * k + [np.inf, np.inf])
    span = target.inputs_rad[-1] * np.linspace(0.0, 1.0, SPAN_SAMPLES // 2)
    inputs = np.concatenate([target.inputs_rad, span])
    floor = math.sin(math.radians(min(options.min_transmission_deg + 3.0, 89.0)))

    def fun(u, rows):
        xx = x[rows].copy()
        xx[:, cols] = u[:, :k]
        th = u[:, k:k + 1] + inputs[None, :]
        ev = F.evaluate(topology, xx, th, sigma[rows], grad=True)
        r = ev.out[:, :n] - u[:, k + 1:k + 2] - target.outputs[None, :]
        if target.angular:
            r = _wrap(r)
        J = np.zeros((len(u), n, k + 2))
        J[:, :, :k] = ev.dout[:, :n, cols]
        J[:, :, k] = ev.dout[:, :n, -1]
        J[:, :, k + 1] = -1.0
        rp, Jp_full = floor_penalty(ev.sin_mu[:, n:], ev.dsin_mu[:, n:], floor, 0.05)
        Jp = np.zeros((len(u), rp.shape[1], k + 2))
        Jp[:, :, :k] = Jp_full[:, :, cols]
        Jp[:, :, k] = Jp_full[:, :, -1]
        return np.concatenate([r * w, rp], axis=1), np.concatenate([J * w, Jp], axis=1)

    u, _ = levenberg_marquardt(fun, u0, iterations=100, stop=stop, lower=lower, upper=upper)
    x = x.copy()
    x[:, cols] = u[:, :k]
    flip = x[:, 4] < 0          # a negative crank: the same design with the crank turned by π
    th = u[:, k:k + 1] + target.inputs_rad[None, :] + np.where(flip, math.pi, 0.0)[:, None]
    x[:, 4] = np.abs(x[:, 4])
    return x, th


def _screen(topology: str, x, sigma, theta, direction: float):
    """(min sin μ over the span (G,), assembled over it (G,), the crank turns fully (G,))."""
    off = direction * (theta[:, -1:] - theta[:, :1])
    th = theta[:, :1] + off * np.linspace(0.0, 1.0, SPAN_SAMPLES)[None, :]
    ev = F.evaluate(topology, x, th, sigma)
    full = F.evaluate(topology, x, theta[:, :1] + np.linspace(0, 2 * math.pi, 37)[None, :], sigma)
    return (np.where(ev.ok, ev.sin_mu, 0.0).min(axis=1), ev.ok.all(axis=1),
            (full.ok & (full.sin_mu > 1e-6)).all(axis=1))


def _check_request(target: FunctionTarget, topology: str, size: float | None) -> None:
    if topology not in (F.FOURBAR, F.SLIDER_CRANK):
        raise DesignError(f"function synthesis makes a fourbar or a slider_crank, not {topology!r}")
    if (topology == F.FOURBAR) != target.angular:
        want = "output_deg (a rocker angle) for a fourbar" if topology == F.FOURBAR else \
            "output_mm (a slider position) for a slider_crank"
        raise DesignError(f"function: the output must be {want}")
    if size is not None and not (math.isfinite(size) and size > 0):
        raise DesignError(f"function: the size must be a positive number of millimetres, got {size}")


def _designs(target: FunctionTarget, topology: str, scale: float, options: LinkageOptions, notes: list[str],
             progress: Progress | None, atlas: bool, atlas_designs: int | None):
    """Designs meeting the pairs (exactly for 3, refined for more): (x, sigma, theta, error)."""
    x, sigma, theta = _starts(target, topology, scale)
    ok = np.all(np.isfinite(x), axis=1) & (sigma != 0)
    x, sigma, theta = x[ok], sigma[ok], theta[ok]
    err = _errors(target, topology, x, sigma, theta)
    notes.append(f"{len(x)} designs from {GRID}² starting values")
    if len(target.inputs_rad) <= 3:
        tol = 1e-9 if target.angular else 1e-9 * scale
        exact = err <= 1e3 * tol
        notes.append(f"{int((~exact).sum())} with a circuit defect")
        return x[exact], sigma[exact], theta[exact], err[exact]
    best = np.argsort(err)[:256]
    x, sigma, theta = x[best], sigma[best], theta[best]
    if atlas:
        report(progress, 0.1, "atlas designs with a similar output")
        xa, sa, ta = atlas_starts(target, topology, scale, designs=atlas_designs,
                                  progress=lambda f, m: progress(0.1 + 0.2 * f, m) if progress else None)
        if len(xa):
            x, sigma, theta = np.concatenate([x, xa]), np.concatenate([sigma, sa]), np.concatenate([theta, ta])
            notes.append(f"{len(xa)} starting designs from the {topology} atlas")
    report(progress, 0.3, f"least squares on {len(x)} designs")
    x, theta = _refine(target, topology, x, sigma, theta, scale, options,
                       lambda: report(progress, 0.5, "least squares"))
    err = _errors(target, topology, x, sigma, theta)
    keep = np.isfinite(err)
    return x[keep], sigma[keep], theta[keep], err[keep]


def synthesize_function(target: FunctionTarget, options: LinkageOptions = LinkageOptions(),
                        topology: str = F.FOURBAR, size: float | None = None,
                        progress: Progress | None = None, atlas: bool = True,
                        atlas_designs: int | None = None) -> DesignResult:
    """Linkages whose output link ``output`` follows the target (see the module docstring).
    ``topology``: "fourbar" (output in degrees) or "slider_crank" (output in mm); ``size``: the
    four-bar's ground length, mm (default 100; a slider-crank's scale is the output's);
    ``atlas``: with more than 3 pairs, add starting designs from the atlas (built on first use)."""
    options.check()
    _check_request(target, topology, size)
    watch = Stopwatch()
    n = len(target.inputs_rad)
    scale = (size or 100.0) if target.angular else max(target.output_span, 1e-9)
    direction = 1.0 if target.inputs_rad[-1] > 0 else -1.0
    report(progress, 0.0, "Freudenstein's equations over the starting angles")
    notes: list[str] = []
    x, sigma, theta, err = _designs(target, topology, scale, options, notes, progress, atlas, atlas_designs)
    report(progress, 0.6, f"transmission angles of {len(x)} designs")
    mu, span_ok, full = _screen(topology, x, sigma, theta, direction) if len(x) else \
        (np.empty(0), np.zeros(0, bool), np.zeros(0, bool))
    mu_deg = np.degrees(np.arcsin(np.clip(mu, 0.0, 1.0)))
    longest = np.max(np.abs(x[:, 4:7] if topology == F.FOURBAR else x[:, 3:6]), axis=1) if len(x) else np.empty(0)
    good = span_ok & (mu_deg >= options.min_transmission_deg) & (longest <= options.max_size * scale)
    if options.full_turn:
        good &= full
    notes.append(f"{int((~good).sum())} with a dead point, a transmission angle below "
                 f"{options.min_transmission_deg:g}° or a link over {options.max_size:g} × {scale:g} mm")
    tol = 1e-9 if target.angular else 1e-9 * scale
    score = mu_deg + 20.0 * full - (100.0 * np.log10(1.0 + err / tol) if n > 3 else 0.0)
    rank = np.flatnonzero(good)[np.argsort(-score[good])]
    designs = [Design(topology, x[k], float(sigma[k]), direction, theta[k], float(score[k])) for k in rank]
    found, refused = finish(designs, options, scale, False, _measure(target), output=True, point=False,
                            progress=progress)
    if not found:
        raise DesignError(f"function: no defect-free {topology} follows the {n} pairs (" + "; ".join(notes)
                          + (f"; built and refused: {refusal_text(refused)}" if refused else "")
                          + "): " + relax_text(refused, "lower the minimum transmission angle, narrow the input "
                                                          "span or ease the function"))
    if refused:
        notes.append(f"refused after building: {refusal_text(refused)}")
    report(progress, 1.0, "done")
    return DesignResult(found, watch.elapsed, notes)


def _measure(target: FunctionTarget):
    """The largest output error of a candidate at the pairs, by the solver (° or mm)."""
    def measure(plan: Plan, d: Design):
        sol = plan.evaluate(d.inputs, order=0)
        if target.angular:
            got = sol.angle("output")
            e = _wrap((got - got[0]) - target.outputs)
            return math.degrees(float(np.max(np.abs(e)))), "°", None, None
        got = sol.position("C")[:, 0]     # the pin's position along the guide (x: the guide's axis)
        return float(np.max(np.abs((got - got[0]) - target.outputs))), "mm", None, None

    return measure


__all__ = ["synthesize_function"]
