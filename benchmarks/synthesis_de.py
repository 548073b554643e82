"""The reference for unreachable path targets in bench_synthesis.py: the targets themselves, an
accurate point-to-curve measure, and scipy's differential evolution over the four-bar.

Targets (mm): the letter D (closed), a foot path of a straight stroke and a lift (closed), the
letter S (an open arc), 48 points each, equally spaced along their outline.

``measure(x, sigma, pts, closed)``: each target point's distance to the coupler curve of the
four-bar (:mod:`mechsketch.core.design.families` parameters), from 3,600 samples of a turn
refined by golden-section search around the nearest sample — the same measure for the reference
and for the synthesis. Both are given the same constraints: the crank turns fully and the
transmission angle stays above MIN_MU_DEG over the turn.

``differential_evolution_reference(pts, closed, seconds)``: scipy's differential evolution
(vectorised: the population is one (P, 9) array of four-bars, evaluated in closed form at 240
crank angles), both assembly modes (σ as a tenth variable), bounds scaled to the target, a
penalty for designs that do not turn fully or fall below the transmission angle; stopped by its
callback after ``seconds`` of this process's CPU time (so that a loaded machine does not starve
the reference), then polished by scipy's L-BFGS-B; returns its best design and its RMS and
largest distance by :func:`measure`.
"""
from __future__ import annotations

import math
import time

import numpy as np

from mechsketch.core.design import families as F

MIN_MU_DEG = 25.0
SAMPLES = 240


def _outline(segments: list[np.ndarray], n: int, closed: bool) -> np.ndarray:
    z = np.concatenate(segments)
    seg = np.abs(np.diff(np.concatenate([z, z[:1]]) if closed else z))
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.linspace(0.0, s[-1], n, endpoint=not closed)
    zz = np.concatenate([z, z[:1]]) if closed else z
    return np.stack([np.interp(t, s, zz.real), np.interp(t, s, zz.imag)], axis=1)


def targets() -> dict[str, tuple[np.ndarray, bool]]:
    """name -> (points (48, 2) mm, closed)."""
    u = np.linspace(0, 1, 200)
    letter_d = [1j * 100 * u, 50j + 50 * np.exp(1j * (math.pi / 2 - math.pi * u))]        # stroke, bowl
    foot = [-50 + 100 * u + 0j, 50 * np.cos(math.pi * u) + 25j * np.sin(math.pi * u)]      # stroke, lift
    s_top = 25 + 25j + 25 * np.exp(1j * (1.5 * math.pi * u))
    s_bot = 25 - 25j + 25 * np.exp(1j * (0.5 * math.pi - 1.5 * math.pi * u))
    return {"letter D": (_outline(letter_d, 48, True), True),
            "foot path": (_outline(foot, 48, True), True),
            "letter S": (_outline([s_top[::-1], s_bot], 48, False), False)}


def measure(x: np.ndarray, sigma: float, pts: np.ndarray, closed: bool = True) -> tuple[float, float]:
    """(RMS, largest) distance of the points to the four-bar's coupler curve, mm."""
    th = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    P = F.evaluate("fourbar", x[None], th[None], sigma).P[0]
    z = pts[:, 0] + 1j * pts[:, 1]
    d = np.abs(P[None, :] - z[:, None])
    k = np.nanargmin(d, axis=1)
    h = 2 * math.pi / 3600
    a, b = th[k] - h, th[k] + h
    g = (math.sqrt(5) - 1) / 2

    def f(t):
        return np.abs(F.evaluate("fourbar", x[None], t[None], sigma).P[0] - z)

    c, e = b - g * (b - a), a + g * (b - a)
    fc, fe = f(c), f(e)
    for _ in range(60):
        left = fc < fe
        b = np.where(left, e, b)
        a = np.where(left, a, c)
        c, e = b - g * (b - a), a + g * (b - a)
        fc, fe = f(c), f(e)
    dist = np.minimum(np.minimum(fc, fe), d[np.arange(len(z)), k])
    return float(np.sqrt(np.mean(dist ** 2))), float(np.max(dist))


def _objective(pop: np.ndarray, z: np.ndarray, size: float) -> np.ndarray:
    """(P,) RMS point-to-curve distance / size of four-bars pop (P, 10) (σ the last, ±), with a
    penalty for designs that do not turn fully or drop below the transmission angle."""
    x, sigma = pop[:, :9], np.where(pop[:, 9] >= 0, 1.0, -1.0)
    th = np.linspace(0, 2 * math.pi, SAMPLES, endpoint=False)
    ev = F.evaluate("fourbar", x, th[None, :], sigma)
    P = np.where(ev.ok, ev.P, 1e9)
    d = np.abs(P[:, None, :] - z[None, :, None]).min(axis=2)
    rms = np.sqrt(np.mean(d ** 2, axis=1)) / size
    smin = np.min(np.where(ev.ok, ev.sin_mu, 0.0), axis=1)
    short = np.maximum(math.sin(math.radians(MIN_MU_DEG)) - smin, 0.0)
    bad = ~ev.ok.all(axis=1)
    return np.where(bad, 10.0 + np.mean(~ev.ok, axis=1), rms + 10.0 * short)


def differential_evolution_reference(pts: np.ndarray, closed: bool, seconds: float, seed: int = 1,
                                     checkpoint=None, every: float = 60.0) -> dict:
    """Run scipy's differential evolution for ``seconds`` (see the module docstring);
    ``checkpoint(record)``, if given, gets the best design so far (unpolished, measured as the
    result) after every ``every`` seconds of CPU time, so that a run stopped early still counts."""
    from scipy.optimize import differential_evolution

    z = pts[:, 0] + 1j * pts[:, 1]
    c = z.mean()
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    size = float(np.hypot(*(hi - lo)))
    span = 2.0 * size
    bounds = [(c.real - span, c.real + span), (c.imag - span, c.imag + span),
              (c.real - span, c.real + span), (c.imag - span, c.imag + span),
              (0.02 * size, 2 * size), (0.05 * size, 4 * size), (0.05 * size, 4 * size),
              (-3 * size, 3 * size), (-3 * size, 3 * size), (-1.0, 1.0)]
    start, cpu = time.perf_counter(), time.process_time()
    evaluations = [0]

    def f(pop):
        pop = np.atleast_2d(pop.T) if pop.ndim == 2 else pop[None]
        evaluations[0] += pop.shape[0]
        return _objective(pop, z, size)

    last = [0.0]

    def stop(xk=None, *_args, **_kw):
        used = time.process_time() - cpu
        if checkpoint is not None and xk is not None and used - last[0] >= every:
            last[0] = used
            rms, worst = measure(xk[:9], 1.0 if xk[9] >= 0 else -1.0, pts, closed)
            checkpoint({"rms_mm": rms, "max_mm": worst, "size_mm": size, "seconds": used, "cpu_s": used,
                        "wall_s": time.perf_counter() - start, "evaluations": int(evaluations[0]),
                        "x": [float(v) for v in xk[:9]], "sigma": 1.0 if xk[9] >= 0 else -1.0, "seed": seed,
                        "min_mu_deg": MIN_MU_DEG, "polished": False})
        return used > seconds

    res = differential_evolution(f, bounds, strategy="best1bin", popsize=40, tol=0, atol=0, maxiter=10 ** 9,
                                 mutation=(0.5, 1.0), recombination=0.9, seed=seed, polish=True,
                                 vectorized=True, updating="deferred", callback=stop, init="sobol")
    x, sigma = res.x[:9], 1.0 if res.x[9] >= 0 else -1.0
    rms, worst = measure(x, sigma, pts, closed)
    return {"rms_mm": rms, "max_mm": worst, "size_mm": size, "objective": float(res.fun), "seconds": seconds,
            "cpu_s": time.process_time() - cpu, "wall_s": time.perf_counter() - start,
            "evaluations": int(evaluations[0]), "generations": int(res.nit),
            "x": [float(v) for v in x], "sigma": sigma, "seed": seed, "min_mu_deg": MIN_MU_DEG}
