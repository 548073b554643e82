"""Starting designs for path synthesis: retrieved from the atlas and aligned to the target.

- **Closed paths**: the target's Fourier descriptor, in its eight variants (as given, reversed,
  mirrored, both; either sign of the even harmonics), queries the atlas's k-d tree
  (:meth:`~.atlas_store.Atlas.nearest`); each retrieved coupler curve is aligned to the target
  by :func:`~.descriptors.align` (similarity, start and direction by one FFT correlation).
- **Open arcs**: an arc is a part of a coupler curve of unknown extent, which a whole-curve
  descriptor cannot match; instead a spread subset of the atlas's curves is scanned: every window
  of every span fraction and start along each curve is compared with the arc by the
  similarity-invariant fit |⟨w, z⟩|²/(|w|²|z|²), all at once in numpy.

Either way a start is a world-frame design of :mod:`.families` (the normalised design moved by
the similarity, mirrored if so) with its crank direction and the crank angle at each target
point, found by matching arc-length positions (so the points stay in order).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from . import families as F
from .atlas import closed_form_solver
from .atlas_store import POINTS, Atlas
from .descriptors import align, query_variants, resample_closed, similarity
from .targets import PathTarget

#: crank-angle samples of a retrieved curve
DENSE = 256
#: arc-length samples of the alignment
ARC = 128


@dataclass
class Start:
    """A world-frame design aligned to the target: parameters ``x``, mode ``sigma``, crank
    ``direction`` (±1), crank angles ``theta`` (M,) rad at the target's points, and ``fit``
    (relative RMS of the alignment, smaller is better)."""

    topology: str
    x: np.ndarray
    sigma: float
    direction: float
    theta: np.ndarray
    fit: float


def _arc_fractions(z: np.ndarray, closed: bool) -> np.ndarray:
    """(M,) each point's arc-length position along the polygon z, 0 at the first, as a fraction
    of the whole length (closed: including the closing side)."""
    seg = np.abs(np.diff(np.concatenate([z, z[:1]]) if closed else z))
    s = np.concatenate([[0.0], np.cumsum(seg)])
    return s[:-1] / s[-1] if closed else s / s[-1]


def _theta_at(curve: np.ndarray, theta: np.ndarray, frac: np.ndarray) -> np.ndarray:
    """Crank angles where the closed ``curve`` (samples at ``theta``, one turn) is at arc
    fractions ``frac`` (wrapped into [0, 1))."""
    s = _arc_fractions(curve, True)
    ext_s = np.concatenate([s, [1.0]])
    ext_t = np.concatenate([theta, [theta[0] + 2 * math.pi * np.sign(theta[-1] - theta[0] or 1.0)]])
    return np.interp(np.remainder(frac, 1.0), ext_s, ext_t)


def _design(atlas: Atlas, row: int, mirrored: bool) -> tuple[np.ndarray, float]:
    x = atlas.params(np.array([row]))
    sigma = 1.0
    if mirrored:
        x, sig = F.mirror(atlas.topology, x, np.array([sigma]))
        sigma = float(sig[0])
    return x[0], sigma


def _world(topology: str, x: np.ndarray, sigma: float, theta: np.ndarray, s: complex, t: complex,
           direction: float, fit: float) -> Start:
    """The start in the world frame, its crank angles unwrapped from the first in ``direction``."""
    xw = F.transform(topology, x[None], s, t)[0]
    th = theta[0] + direction * np.remainder(direction * (theta - theta[0]), 2 * math.pi)
    return Start(topology, xw, sigma, direction, th + math.atan2(s.imag, s.real), fit)


def closed_starts(atlas: Atlas, target: PathTarget, count: int, min_mu_deg: float,
                  fits: Callable[[np.ndarray], bool] | None = None) -> list[Start]:
    """Up to ``count`` starts for a closed target from the atlas's nearest descriptors (only
    those whose world design ``fits``, when given: e.g. the size guard and pivot region)."""
    z = target.points[:, 0] + 1j * target.points[:, 1]
    q, mir, _ = query_variants(z)
    dist, rows = atlas.nearest(q, k=max(4 * count, 64))
    order = np.argsort(dist, axis=None)
    seen: set[tuple[int, bool]] = set()
    theta = 2 * math.pi * np.arange(DENSE) / DENSE
    tau = _arc_fractions(z, True)
    out = []
    for flat in order:
        v, k = divmod(int(flat), rows.shape[1])
        row = int(rows[v, k])
        key = (row // POINTS, bool(mir[v]))
        if key in seen or float(atlas.mu[row // POINTS]) < min_mu_deg:
            continue
        seen.add(key)
        x, sigma = _design(atlas, row, bool(mir[v]))
        curve = F.evaluate(atlas.topology, x[None], theta[None], sigma).P[0]
        j, rev, s, t, fit = align(curve, z, ARC)
        i = tau * ARC - j
        frac = (np.remainder(i, ARC) if not rev else (ARC - 1) - np.remainder(i, ARC)) / ARC
        th = _theta_at(curve, theta, frac)
        st = _world(atlas.topology, x, sigma, th, s, t, -1.0 if rev else 1.0, fit)
        if fits is None or fits(st.x):
            out.append(st)
        if len(out) >= count:
            break
    return out


#: span fractions of a curve an open arc may cover, and the arc's resampling for the scan
SPANS = (0.12, 0.2, 0.3, 0.42, 0.55, 0.7, 0.85)
ARC_POINTS = 16
#: curves scanned for an open arc
SCAN_CURVES = 6000


def _resample_open(z: np.ndarray, m: int) -> np.ndarray:
    s = _arc_fractions(z, False)
    t = np.linspace(0.0, 1.0, m)
    return np.interp(t, s, z.real) + 1j * np.interp(t, s, z.imag)


def _correlate(Fw: np.ndarray, g: np.ndarray) -> np.ndarray:
    """c[:, j] = Σ_k w[:, j + k]·g[k] (cyclic) for every start j, from Fw = fft(w) (C, L)."""
    L = Fw.shape[1]
    return np.fft.ifft(Fw * (L * np.fft.ifft(g))[None, :], axis=1)


def _scan(w: np.ndarray, arcs: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The best window of each closed curve ``w`` (C, L) (arc-length samples) for any of the
    ``arcs`` (each (m,) centred, unit norm): (fit (C,) in [0, 1], (span index, start, arc) (C, 3)).
    A window of span f starting at j takes the samples j + round(i·f·L/(m − 1)); every start is
    scored at once by FFT correlation (numerator |Σ conj(w)·z|², denominator the window's
    centred energy)."""
    C, L = w.shape
    m = len(arcs[0])
    Fw, Fa = np.fft.fft(w, axis=1), np.fft.fft(np.abs(w) ** 2, axis=1)
    best = np.full(C, -1.0)
    how = np.zeros((C, 3), dtype=int)
    for si, f in enumerate(SPANS):
        offs = np.round(np.arange(m) * f * L / (m - 1)).astype(int) % L
        ind = np.bincount(offs, minlength=L).astype(float)
        mean = _correlate(Fw, ind) / m
        energy = _correlate(Fa, ind).real - m * np.abs(mean) ** 2
        for vi, zv in enumerate(arcs):
            h = np.zeros(L, dtype=complex)
            np.add.at(h, offs, np.conj(zv))
            fit = np.abs(_correlate(Fw, h)) ** 2 / np.maximum(energy, 1e-300)
            j = np.argmax(fit, axis=1)
            fb = fit[np.arange(C), j]
            better = fb > best
            best[better] = fb[better]
            how[better] = np.stack([np.full(int(better.sum()), si), j[better], np.full(int(better.sum()), vi)], axis=1)
    return best, how


def open_starts(atlas: Atlas, target: PathTarget, count: int, min_mu_deg: float,
                fits: Callable[[np.ndarray], bool] | None = None) -> list[Start]:
    """Up to ``count`` starts for an open arc by scanning windows of a spread subset of the
    atlas's curves (see the module docstring; ``fits`` as for :func:`closed_starts`)."""
    z = target.points[:, 0] + 1j * target.points[:, 1]
    arc = _resample_open(z, ARC_POINTS)
    zc = arc - arc.mean()
    zn = zc / np.sqrt(np.vdot(zc, zc).real)
    variants = [(False, False, zn), (False, True, zn[::-1]), (True, False, np.conj(zn)), (True, True, np.conj(zn[::-1]))]
    designs = len(atlas)
    pick = np.unique(np.linspace(0, designs - 1, min(SCAN_CURVES // POINTS + 1, designs)).astype(int))
    pick = pick[np.asarray(atlas.mu[pick], float) >= min_mu_deg]
    theta = 2 * math.pi * np.arange(ARC) / ARC
    shape = np.asarray(atlas.shape[pick], float)
    pts = np.asarray(atlas.points[pick], float)
    curves, _, _, ok = closed_form_solver(atlas.topology, shape, pts, theta)
    curves = curves.reshape(-1, ARC)
    rows = (pick[:, None] * POINTS + np.arange(POINTS)[None, :]).reshape(-1)
    good = np.repeat(ok.all(axis=1), POINTS)
    curves, rows = curves[good], rows[good]
    w = resample_closed(curves, ARC)
    best, how = _scan(w, [v[2] for v in variants])
    out = []
    tau = _arc_fractions(z, False)
    dense = 2 * math.pi * np.arange(DENSE) / DENSE
    size = float(np.sqrt(np.mean(np.abs(z - z.mean()) ** 2))) or 1.0
    for c in np.argsort(-best)[: 4 * count]:
        si, j, vi = how[c]
        mirrored, reverse, _ = variants[vi]
        x, sigma = _design(atlas, int(rows[c]), False)
        curve = F.evaluate(atlas.topology, x[None], dense[None], sigma).P[0]
        # the window runs from arc fraction j/ARC over SPANS[si] of the curve; target point k
        # sits at its own fraction τ_k of the arc (1 − τ_k when matched reversed)
        frac = (j + (1.0 - tau if reverse else tau) * SPANS[si] * ARC) / ARC
        th = _theta_at(curve, dense, frac)
        if mirrored:   # the mirrored design traces the mirror image at −θ
            x, sg = F.mirror(atlas.topology, x[None], np.array([sigma]))
            x, sigma, th = x[0], float(sg[0]), -th
        P = F.evaluate(atlas.topology, x[None], th[None], sigma).P[0]
        s, t, res = similarity(P, z)
        direction = 1.0 if np.sum(np.diff(np.unwrap(th))) >= 0 else -1.0
        st = _world(atlas.topology, x, sigma, th, s, t, direction, res / size)
        if fits is None or fits(st.x):
            out.append(st)
    out.sort(key=lambda st: st.fit)
    return out[:count]


__all__ = ["Start", "closed_starts", "open_starts"]
