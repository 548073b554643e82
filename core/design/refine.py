"""Least-squares refinement of many designs at once (Levenberg–Marquardt, batched).

``x, cost = levenberg_marquardt(fun, x0)``: ``x0`` (D, U) starting points of D independent
problems with U unknowns each; ``fun(x, rows)`` returns, for the problems ``rows`` (indices into
the D, one per row of ``x``), the residuals (len(rows), R) and their exact Jacobian (…, R, U) (from :mod:`.families` through :class:`~.dual.Dual`). Each problem keeps its own
damping λ: a step that lowers its cost is taken and λ shrinks, else λ grows and the step is
retried. A residual that is NaN (a design that cannot be assembled) counts as an infinite cost,
so a step never leaves the assemblable region. Bounds (``lower``, ``upper``: (U,) or (D, U)) clip
each step (a projected method). Stops per problem when the cost stops falling
(relative 1e-12) or the step is below ``xtol`` relative to the unknowns.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

Fun = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def _cost(r: np.ndarray) -> np.ndarray:
    c = 0.5 * np.sum(r * r, axis=1)
    return np.where(np.isfinite(c), c, np.inf)


def levenberg_marquardt(fun: Fun, x0: np.ndarray, iterations: int = 60, xtol: float = 1e-15,
                        stop: Callable[[], None] | None = None, lower: np.ndarray | None = None,
                        upper: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Minimise ½‖r(x)‖² for each row of ``x0`` (D, U); returns (x (D, U), cost (D,)).
    ``stop()`` is called once per iteration (it may raise to cancel)."""
    x = np.array(x0, dtype=float)
    lo = None if lower is None else np.broadcast_to(np.asarray(lower, float), x.shape)
    hi = None if upper is None else np.broadcast_to(np.asarray(upper, float), x.shape)
    if lo is not None or hi is not None:
        x = np.clip(x, lo, hi)
    r, J = fun(x, np.arange(x.shape[0]))
    cost = _cost(r)
    lam = np.full(x.shape[0], 1e-3)
    active = np.isfinite(cost)
    U = x.shape[1]
    eye = np.eye(U)
    for _ in range(iterations):
        if stop is not None:
            stop()
        if not active.any():
            break
        idx = np.flatnonzero(active)
        Ja, ra = J[idx], r[idx]
        Ja = np.where(np.isfinite(Ja), Ja, 0.0)
        Jt = Ja.transpose(0, 2, 1)
        JtJ = Jt @ Ja
        g = (Jt @ ra[..., None])[..., 0]
        diag = np.einsum("dii->di", JtJ)
        scale = np.maximum(diag, 1e-12 * (diag.max(axis=1, keepdims=True) + 1e-300))
        A = JtJ + lam[idx, None, None] * scale[:, :, None] * eye
        try:
            step = -np.linalg.solve(A, g[..., None])[..., 0]
        except np.linalg.LinAlgError:
            step = -np.stack([np.linalg.lstsq(a, b, rcond=None)[0] for a, b in zip(A, g)])
        xn = x[idx] + step
        if lo is not None or hi is not None:
            xn = np.clip(xn, None if lo is None else lo[idx], None if hi is None else hi[idx])
            step = xn - x[idx]
        rn, Jn = fun(xn, idx)
        cn = _cost(rn)
        better = cn < cost[idx]
        acc = idx[better]
        rel = (cost[acc] - cn[better]) / np.maximum(cost[acc], 1e-300)
        x[acc], r[acc], J[acc], cost[acc] = xn[better], rn[better], Jn[better], cn[better]
        lam[acc] = np.maximum(lam[acc] / 3.0, 1e-12)
        rej = idx[~better]
        lam[rej] = lam[rej] * 4.0
        small = np.max(np.abs(step), axis=1) <= xtol * (1.0 + np.max(np.abs(x[idx]), axis=1))
        done = np.zeros(x.shape[0], dtype=bool)
        done[acc[rel < 1e-12]] = True
        done[idx[small]] = True
        done[rej[lam[rej] > 1e12]] = True
        done |= cost <= 1e-32
        active &= ~done
    return x, cost


def floor_penalty(v: np.ndarray, dv: np.ndarray, floor: float, weight: float) -> tuple[np.ndarray, np.ndarray]:
    """A residual that is 0 while ``v`` (D, S) ≥ ``floor`` and grows as ``weight``·(floor − v)
    below it, with its Jacobian from ``dv`` (D, S, U): a soft lower bound (e.g. on sin μ). Where
    ``v`` is NaN (not assembled) the residual is NaN, so a step that goes there is refused."""
    short = floor - v
    act = ~(short <= 0.0)
    r = np.where(act, weight * short, 0.0)
    J = np.where(act[..., None], -weight * np.where(np.isfinite(dv), dv, 0.0), 0.0)
    return r, J


__all__ = ["floor_penalty", "levenberg_marquardt"]
