"""Starting designs for function synthesis from the atlas: for harder functions than the
Freudenstein grid starts reach.

Each atlas design stores the harmonics of its output over one crank turn
(:func:`~.atlas_store.function_values`). For a spread subset of the designs, every starting
crank angle φ0 of a grid and both hands (the design and its mirror image, whose output is
−out(−θ) for a rocker angle, out(−θ) for a slider's position), the output changes at the
target's inputs are compared with the target's: a four-bar's rocker angle directly (angles do
not scale), a slider-crank's position after the best least-squares scale (positions scale with
the linkage; a negative scale would need the crank to turn the other way, and is left out). The
best matches become designs in the frame of :mod:`.freudenstein` (crank pivot at the origin; a
four-bar's ground along +x, ``size`` long; a slider-crank's guide along +x).
"""
from __future__ import annotations

import math

import numpy as np

from . import families as F
from .atlas import load_atlas
from .atlas_store import FUNC_HARMONICS, family_params
from .targets import FunctionTarget, Progress

#: designs compared, starting angles per turn, chunk of designs per pass
SUBSET, PHASES, CHUNK = 40_000, 36, 2_000


def _values(func: np.ndarray, turns: np.ndarray, th: np.ndarray) -> np.ndarray:
    """(R, G, n) outputs of designs (harmonics ``func`` (R, 2H+1), ``turns`` (R,)) at ``th`` (G, n)."""
    out = func[:, 0, None, None] + turns[:, None, None] * th[None]
    for k in range(1, FUNC_HARMONICS + 1):
        out = out + func[:, 2 * k - 1, None, None] * np.cos(k * th)[None] + func[:, 2 * k, None, None] * np.sin(k * th)[None]
    return out


def atlas_starts(target: FunctionTarget, topology: str, size: float, count: int = 64,
                 designs: int | None = None, progress: Progress | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Up to ``count`` starting designs: (x (S, K), modes (S,), crank angles (S, n))."""
    atlas = load_atlas(topology, designs, progress)
    rows = np.unique(np.linspace(0, len(atlas) - 1, min(SUBSET, len(atlas))).astype(int))
    phi0 = 2 * math.pi * np.arange(PHASES) / PHASES
    xin, y = target.inputs_rad, target.outputs
    found = []          # (error, row, phase, mirrored, scale)
    for start in range(0, len(rows), CHUNK):
        r = rows[start:start + CHUNK]
        f = np.asarray(atlas.func[r], float)
        w = np.asarray(atlas.turns[r], float)
        for mirrored in (False, True):
            th = phi0[:, None] + xin[None, :]
            hand = -1.0 if target.angular else 1.0
            out = hand * _values(f, w, -th) if mirrored else _values(f, w, th)
            d = out - out[..., :1]
            if target.angular:
                k = np.ones(d.shape[:2])
            else:
                k = np.sum(d * y, axis=2) / np.maximum(np.sum(d * d, axis=2), 1e-300)
            err = np.max(np.abs(k[..., None] * d - y), axis=2)
            err[k <= 0] = np.inf
            g = np.argmin(err, axis=1)
            e = err[np.arange(len(r)), g]
            found += [(float(e[i]), int(r[i]), int(g[i]), mirrored, float(k[i, g[i]])) for i in range(len(r))]
    found.sort(key=lambda t: t[0])
    xs, sig, ths = [], [], []
    for _, row, g, mirrored, k in found[:count]:
        shape = np.asarray(atlas.shape[row], float)[None]
        x = family_params(topology, shape, np.zeros((1, 2)))
        sigma = np.array([1.0])
        th = phi0[g] + xin                      # the mirrored design turns the same way
        if mirrored:
            x, sigma = F.mirror(topology, x, sigma)
        x = F.transform(topology, x, complex(size if target.angular else k), 0j)
        xs.append(x[0])
        sig.append(float(sigma[0]))
        ths.append(th)
    return np.array(xs), np.array(sig), np.array(ths)


__all__ = ["atlas_starts"]
