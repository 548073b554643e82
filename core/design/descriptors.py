"""Similarity-invariant descriptors of curves and their alignment.

A closed curve (complex points, in order) is resampled at ``L`` points equally spaced in arc
length (:func:`resample_closed`), and its Fourier coefficients c_k = (1/L)·Σ z_j·e^{−2πijk/L}
normalised (:func:`fourier_descriptor`):

- translation: c_0 dropped;
- scale: divided by the RMS radius √(Σ_{k≠0}|c_k|²);
- rotation by e^{iα} and a start shifted by s along the curve multiply c_k by e^{i(α + k·s)}:
  both are fixed by making c_1 and c_{−1} real and positive, which leaves one ambiguity
  (α + π, s + π: the even harmonics change sign), settled by querying both;
- the direction of travel (c_k → c_{−k}) and the mirror image (c_k → conj c_{−k}) are queried
  as variants of the target (:func:`query_variants`).

The descriptor is (|c_1|, |c_{−1}|, c_{±2}, c_{±3}) as 10 reals (:data:`DESC_DIM`). Arrays: curves
(..., N) complex; descriptors (..., 10) float.

:func:`align` finds the similarity transform (complex scale·rotation ``s`` and shift ``t``), the
start and the direction that best map one closed curve onto another by one FFT correlation over
all cyclic shifts; :func:`similarity` is the least-squares map between two point lists.
"""
from __future__ import annotations

import math

import numpy as np

#: harmonics kept (besides ±1, which fix the normalisation)
HARMONICS = (2, -2, 3, -3)
DESC_DIM = 2 + 2 * len(HARMONICS)
#: arc-length samples of a closed curve
ARC_SAMPLES = 64


def resample_closed(z: np.ndarray, samples: int = ARC_SAMPLES, compiled: bool = False,
                    min_rows: int = 4096) -> np.ndarray:
    """(..., samples) points equally spaced in arc length along the closed polygon z (..., N),
    starting at z[..., 0]. Rows of zero length come back as their first point. ``compiled``
    (the atlas build: a million rows): a numba-compiled loop (:func:`_resample_compiled`) from
    ``min_rows`` rows on (where numba pays for its start-up; the atlas gives 0, so that a
    design's descriptor does not depend on how many are described with it); the numpy form is
    the reference (:func:`resample_closed_numpy`, tested equal to 1e-12)."""
    z = np.asarray(z, dtype=complex)
    if compiled and z.ndim > 1 and z.size // max(z.shape[-1], 1) >= min_rows:
        fn = _resample_compiled()
        if fn is not None:
            flat = np.ascontiguousarray(z.reshape(-1, z.shape[-1]))
            return fn(flat, samples).reshape(z.shape[:-1] + (samples,))
    return resample_closed_numpy(z, samples)


_COMPILED: list = []


def _resample_compiled():
    """The resampling as a numba loop over rows (compiled on first use; None without numba)."""
    if _COMPILED:
        return _COMPILED[0]
    try:
        import numba
    except ImportError:   # pragma: no cover - numba is a dependency; numpy is the fallback
        _COMPILED.append(None)
        return None

    @numba.njit(cache=True, fastmath=False)
    def resample(z, samples):
        rows, n = z.shape
        out = np.empty((rows, samples), dtype=np.complex128)
        cum = np.empty(n + 1)
        for r in range(rows):
            cum[0] = 0.0
            for i in range(n):
                cum[i + 1] = cum[i] + abs(z[r, (i + 1) % n] - z[r, i])
            total = cum[n]
            i = 0
            for j in range(samples):
                t = j / samples
                if total > 0.0:
                    while i < n - 1 and cum[i + 1] / total <= t:
                        i += 1
                    s0, s1 = cum[i] / total, cum[i + 1] / total
                    f = (t - s0) / (s1 - s0) if s1 > s0 else 0.0
                else:
                    i, f = 0, 0.0
                out[r, j] = z[r, i] + f * (z[r, (i + 1) % n] - z[r, i])
        return out

    _COMPILED.append(resample)
    return resample


def resample_closed_numpy(z: np.ndarray, samples: int = ARC_SAMPLES) -> np.ndarray:
    """:func:`resample_closed` in numpy over all rows at once (the reference)."""
    z = np.asarray(z, dtype=complex)
    lead, n = z.shape[:-1], z.shape[-1]
    flat = z.reshape(-1, n)
    closed = np.concatenate([flat, flat[:, :1]], axis=1)
    seg = np.abs(np.diff(closed, axis=1))
    s = np.concatenate([np.zeros((flat.shape[0], 1)), np.cumsum(seg, axis=1)], axis=1)
    total = s[:, -1:]
    with np.errstate(invalid="ignore", divide="ignore"):
        s = s / np.where(total > 0, total, 1.0)
    t = np.arange(samples) / samples
    # one flat searchsorted: rows lifted apart by 2 (s rises from 0 to 1 within a row)
    rows = np.arange(flat.shape[0])[:, None]
    pos = np.searchsorted((s + 2.0 * rows).ravel(), (t[None, :] + 2.0 * rows).ravel(), side="right") - 1
    i = np.clip(pos.reshape(flat.shape[0], samples) - rows * (n + 1), 0, n - 1)
    s0 = np.take_along_axis(s, i, axis=1)
    s1 = np.take_along_axis(s, i + 1, axis=1)
    z0 = np.take_along_axis(closed, i, axis=1)
    z1 = np.take_along_axis(closed, i + 1, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        f = np.where(s1 > s0, (t[None, :] - s0) / (s1 - s0), 0.0)
    return (z0 + f * (z1 - z0)).reshape(lead + (samples,))


def coefficients(z: np.ndarray) -> np.ndarray:
    """c_k (..., L) of arc-length samples z (..., L): numpy's FFT order (k = 0, 1, ..., −1)."""
    return np.fft.fft(z, axis=-1) / z.shape[-1]


def normalise(c: np.ndarray, ks: tuple[int, ...] | None = None) -> np.ndarray:
    """Fourier coefficients (..., L) normalised for translation, scale, rotation and start (see
    the module docstring); the branch with c_1, c_{−1} real positive. ``ks``: only these
    harmonics (in that order, (..., len(ks))); None: all, in FFT order."""
    c = np.asarray(c, dtype=complex)
    e = np.sqrt(np.sum(np.abs(c) ** 2, axis=-1, keepdims=True) - np.abs(c[..., :1]) ** 2)
    p1, pm = np.angle(c[..., 1]), np.angle(c[..., -1])
    alpha, s = -(p1 + pm) / 2.0, (pm - p1) / 2.0
    L = c.shape[-1]
    k = np.fft.fftfreq(L, 1.0 / L) if ks is None else np.array(ks, dtype=float)
    sel = c.copy() if ks is None else c[..., [kk % L for kk in ks]]
    if ks is None:
        sel[..., 0] = 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        return sel / np.where(e > 0, e, 1.0) * np.exp(1j * (alpha[..., None] + k * s[..., None]))


#: the harmonics a descriptor reads, in :func:`descriptor_of`'s order after ±1
_KS = (1, -1) + HARMONICS


def descriptor_of(cn: np.ndarray, ks: tuple[int, ...] | None = None) -> np.ndarray:
    """(..., DESC_DIM) the descriptor vector of normalised coefficients ``cn``: all harmonics in
    FFT order (``ks`` None) or just ``ks`` in that order."""
    pick = (lambda k: cn[..., k]) if ks is None else (lambda k: cn[..., ks.index(k)])
    parts = [np.abs(pick(1)), np.abs(pick(-1))]
    for k in HARMONICS:
        parts += [pick(k).real, pick(k).imag]
    return np.stack(parts, axis=-1)


def fourier_descriptor(z: np.ndarray, samples: int = ARC_SAMPLES, compiled: bool = False,
                       min_rows: int = 4096) -> np.ndarray:
    """(..., DESC_DIM) descriptors of closed curves z (..., N) complex (``compiled``,
    ``min_rows``: see :func:`resample_closed`)."""
    return descriptor_of(normalise(coefficients(resample_closed(z, samples, compiled, min_rows)), _KS), _KS)


def query_variants(z: np.ndarray, samples: int = ARC_SAMPLES) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The target's descriptor as the atlas may hold it: (descriptors (8, DESC_DIM), mirror (8,)
    bool, reverse (8,) bool) for the curve as given, reversed, mirrored and both, each with both
    signs of the even harmonics."""
    out, mir, rev = [], [], []
    for m in (False, True):
        for r in (False, True):
            w = np.conj(z) if m else z
            w = w[::-1] if r else w
            cn = normalise(coefficients(resample_closed(w, samples)))
            for flip in (1.0, -1.0):
                k = np.fft.fftfreq(cn.shape[-1], 1.0 / cn.shape[-1])
                c = cn * np.where(k % 2 == 0, flip, 1.0) if flip < 0 else cn
                out.append(descriptor_of(c))
                mir.append(m)
                rev.append(r)
    return np.array(out), np.array(mir), np.array(rev)


def similarity(src: np.ndarray, dst: np.ndarray) -> tuple[complex, complex, float]:
    """The least-squares similarity dst ≈ s·src + t (s complex: scale and rotation) between two
    point lists (N,) complex; returns (s, t, RMS residual)."""
    ms, md = src.mean(), dst.mean()
    a, b = src - ms, dst - md
    den = np.vdot(a, a).real
    s = np.vdot(a, b) / den if den > 0 else 0j
    t = md - s * ms
    res = math.sqrt(float(np.mean(np.abs(s * src + t - dst) ** 2)))
    return complex(s), complex(t), res


def align(curve: np.ndarray, target: np.ndarray, samples: int = 128) -> tuple[int, bool, complex, complex, float]:
    """Best map of the closed ``curve`` (N,) onto the closed ``target`` (M,) by a similarity,
    a start and a direction: (shift, reversed, s, t, RMS/size) where the curve's arc-length
    resample (``samples`` points), reversed if so and rolled by ``shift`` (``np.roll``), maps
    onto the target's by s·w + t."""
    w = resample_closed(curve, samples)
    z = resample_closed(target, samples)
    zc = z - z.mean()
    best = None
    for rev in (False, True):
        wr = w[::-1] if rev else w
        wc = wr - wr.mean()
        # corr[j] = Σ_b conj(wc[b − j])·zc[b]: |corr| is the fit of every cyclic start at once
        corr = np.fft.ifft(np.conj(np.fft.fft(wc)) * np.fft.fft(zc)) * samples
        j = int(np.argmax(np.abs(corr)))
        fit = abs(corr[j]) ** 2 / (np.vdot(wc, wc).real * np.vdot(zc, zc).real + 1e-300)
        if best is None or fit > best[0]:
            best = (fit, j, rev)
    _, j, rev = best
    wr = (w[::-1] if rev else w)
    wr = np.roll(wr, j)
    s, t, res = similarity(wr, z)
    size = float(np.sqrt(np.mean(np.abs(zc) ** 2))) or 1.0
    return j, rev, s, t, res / size


__all__ = ["ARC_SAMPLES", "DESC_DIM", "HARMONICS", "align", "coefficients", "descriptor_of", "fourier_descriptor",
           "normalise", "query_variants", "resample_closed", "similarity"]
