"""Exact first derivatives of a linkage's motion by its variables and by pin play, in one solve.

The batch engine's arithmetic is analytic (:mod:`.vec`, :mod:`.bkernels`, :mod:`.geometry`), so
a complex step gives exact derivatives: the nominal design is solved once as P + 1 designs, the
i-th with its i-th variable perturbed by i·h (h = 1e-30 of its unit), and Im(result)/h is the
derivative to machine precision — no difference quotient, no step to choose. Pins are treated the
same way: a pin's play displaces the joint on its later links by e = (ex, ey) from its place on
the first link solved (:meth:`~.engine.BatchPlan.run`), and the derivatives by ex and ey are the
2×2 matrix S_J that maps a play to the traced point's displacement.

:class:`Nominal` holds the nominal motion and these derivatives over one cycle; the linearised
tolerance band (:class:`LinearBand`) is their first-order propagation: a variable with standard
deviation σ_i moves a point along the normal ν of its path by σ_i·(ν·∂p/∂x_i), independent
variables add in quadrature; a pin with radial play r moves it by at most r·|S_Jᵀ ν| either way.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import RequestError
from ..solver.branches import flip_factor
from ..solver.drive import linear_flip
from .engine import BatchPlan, Inputs
from .geometry import build_geometry
from .keys import variables

H = 1e-30


def _imag(x, h: float) -> np.ndarray:
    return np.imag(x) / h


class Nominal:
    """The nominal motion over one cycle (N samples) and its exact derivatives.

    ``pos[j]`` (N, 2) mm, ``normal[j]`` (N, 2) the unit left normal of j's path, ``ang[k]`` (N,)
    rad, ``valid`` (N,); ``dpos[j]`` (V, N, 2) by each variable (mm per unit), ``dang[k]`` (V, N);
    ``S[j]`` (P, N, 2, 2) by each pin's play: column c of S[j][p, k] is ∂p/∂e_c; ``T[k]`` (P, N, 2)
    ∂θ/∂e. ``keys`` the variables, ``pins`` the joints with play."""

    def __init__(self, keys: list, pins: list, N: int) -> None:
        self.keys, self.pins, self.N = list(keys), list(pins), N
        self.pos: dict = {}
        self.normal: dict = {}
        self.ang: dict = {}
        self.dpos: dict = {}
        self.dang: dict = {}
        self.S: dict = {}
        self.T: dict = {}
        self.valid = np.zeros(N, dtype=bool)


def _flips(bp: BatchPlan, q: np.ndarray) -> dict:
    """The nominal design's mode flips (group -> (1, N)) from its branch points."""
    out = {}
    for name, off in bp.plan.branch_points().items():
        if off.size:
            f = (linear_flip(off, q, bp.drive.input0) if bp.linkage.driver.linear else
                 flip_factor(off, q, bp.plan.theta0, bp.plan.direction))
            out[name] = f.reshape(1, -1)
    return out


def _normals(p: np.ndarray, v: np.ndarray | None) -> np.ndarray:
    """(N, 2) unit left normals of a path p (N, 2) from its velocity v (N, 2), or where the point
    stands still from the chord of its neighbours; (0, 1) where both vanish."""
    t = v.copy() if v is not None else np.zeros_like(p)
    chord = np.roll(p, -1, axis=0) - np.roll(p, 1, axis=0)
    n = np.hypot(t[:, 0], t[:, 1])
    still = ~(n > 1e-12 * (np.nanmax(np.abs(p)) + 1.0))
    t[still] = chord[still]
    n = np.hypot(t[:, 0], t[:, 1])
    out = np.stack([-t[:, 1], t[:, 0]], axis=1) / np.where(n > 0, n, 1.0)[:, None]
    out[~(n > 0)] = (0.0, 1.0)
    return np.where(np.isfinite(out), out, 0.0)


def derivatives(bp: BatchPlan, inp: Inputs, keys: list, pins: list, joints: list, links: list) -> Nominal:
    """The nominal motion of ``bp``'s linkage at the inputs ``inp`` and its exact derivatives by
    the variables ``keys`` and by the plays of ``pins`` (one complex-step solve of
    1 + len(keys) + 2·len(pins) designs)."""
    lk = bp.linkage
    nv, npin = len(keys), len(pins)
    D = 1 + nv + 2 * npin
    nominal = variables(lk)
    hs = {k: H * max(abs(nominal[k].nominal), 1.0) for k in keys}
    values = {}
    for i, k in enumerate(keys):
        v = np.full(D, nominal[k].nominal, dtype=complex)
        v[1 + i] += 1j * hs[k]
        values[k] = v
    geo = build_geometry(lk, bp.plan, values, D, dtype=complex)
    if not geo.ok[0]:
        raise RequestError(f"the nominal design does not assemble: {geo.message(0)}")
    K = bp.constants(geo)
    scale = max(abs(complex(*j.at)) for j in lk.joints) + 1.0
    hp = H * scale
    play = {}
    for m, J in enumerate(pins):
        ex, ey = np.zeros((D, 1), dtype=complex), np.zeros((D, 1), dtype=complex)
        ex[1 + nv + 2 * m] = 1j * hp
        ey[1 + nv + 2 * m + 1] = 1j * hp
        play[J] = (ex, ey)
    q = np.asarray(inp.q, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        run = bp.run(K, q.reshape(1, -1), 0.0, 0.0, 0, flips=_flips(bp, q), play=play)
    out = Nominal(keys, pins, q.size)
    out.valid = np.broadcast_to(run.valid[0], (q.size,)).copy()
    hv = np.array([hs[k] for k in keys]).reshape(-1, 1)
    for j in joints:
        _joint(out, run, bp, K, j, nv, npin, hv, hp)
    for k in links:
        _link(out, run, lk, K, k, nv, npin, hv, hp)
    return out


def _joint(out: Nominal, run, bp: BatchPlan, K, j: str, nv: int, npin: int, hv: np.ndarray, hp: float) -> None:
    """Joint j's nominal path and its derivatives from the complex-step run."""
    D, N = K.n, out.N
    x, y = run.states[bp.plan.reporter[j]].point(j, K.at[j])
    x, y = np.broadcast_to(x, (D, N)), np.broadcast_to(y, (D, N))
    out.pos[j] = np.stack([x[0].real, y[0].real], axis=1)
    out.dpos[j] = (np.stack([_imag(x[1:1 + nv], 1.0) / hv, _imag(y[1:1 + nv], 1.0) / hv], axis=2) if nv else
                   np.zeros((0, N, 2)))
    S = np.zeros((npin, N, 2, 2))
    for m in range(npin):
        for c in range(2):
            r = 1 + nv + 2 * m + c
            S[m, :, 0, c] = _imag(x[r], hp)
            S[m, :, 1, c] = _imag(y[r], hp)
    out.S[j] = S


def _link(out: Nominal, run, lk, K, k: str, nv: int, npin: int, hv: np.ndarray, hp: float) -> None:
    """Link k's nominal angle and its derivatives: Im(log rot) and the drawn angle's own."""
    D, N = K.n, out.N
    c, s = run.states[k].cs
    c, s = np.broadcast_to(c, (D, N)), np.broadcast_to(s, (D, N))
    cr, sr = c.real, s.real
    d = (cr * s.imag - sr * c.imag) / (cr * cr + sr * sr)
    a0, da0 = 0.0, np.zeros(D)
    js = lk.link(k).joints
    if len(js) >= 2:
        px, py = (K.at[js[1]][i][:, 0] - K.at[js[0]][i][:, 0] for i in range(2))
        a0 = math.atan2(py[0].real, px[0].real)
        da0 = (px.real * py.imag - py.real * px.imag) / (px.real ** 2 + py.real ** 2)
    out.ang[k] = np.arctan2(sr[0], cr[0]) + a0
    dd = d + da0[:, None]
    out.dang[k] = dd[1:1 + nv] / hv if nv else np.zeros((0, N))
    T = np.zeros((npin, N, 2))
    for m in range(npin):
        for cc in range(2):
            T[m, :, cc] = dd[1 + nv + 2 * m + cc] / hp
    out.T[k] = T


__all__ = ["H", "Nominal", "derivatives"]
