"""Compiled reductions of a tolerance Monte Carlo: per build its largest deviation, per sample
the histograms of the deviation across the path (numba, cached; see :mod:`.tolerance`).

For build b and sample k the dimensions move the traced point by a (the exact kinematics of the
build minus the nominal); each pin J with radial play r_J (this build's) moves it by S_J·e_J
with |e_J| ≤ r_J, S_J the 2×2 derivative of the point by the pin's displacement (first order:
plays are microns against links of millimetres). The worst direction of every pin at that
sample gives the set a + Σ S_J·disc(r_J); the largest distance from the nominal over it is
max over unit n of n·a + Σ r_J·|S_Jᵀ n|. It lies between |a| + Σ r_J·|S_Jᵀ â| and
|a| + Σ r_J·σ_max(S_J); only samples whose upper bound exceeds the best lower bound are
maximised over n, by Newton's method on the direction's angle (:func:`_newton`) from a's
direction and from the pins' principal direction.
"""
from __future__ import annotations

import math

import numba
import numpy as np

#: Newton steps at most per maximisation (it converges in two or three)
ITER = 40
#: directions scanned for a start where the pins' play rivals the dimensions' deviation
SCAN = 36
_DIRS = np.stack([np.cos(2 * np.pi * np.arange(SCAN) / SCAN), np.sin(2 * np.pi * np.arange(SCAN) / SCAN)], axis=1)


@numba.njit(inline="always")
def _bin(h, k: int, x: float, lo: float, w: float, nb: int) -> None:
    i = math.floor((x - lo) / w)
    h[k, 0 if i < 0 else (nb + 1 if i >= nb else i + 1)] += 1


@numba.njit(inline="always")
def _record(hist_up, hist_lo, ext, k: int, s: float, G: float, lo: float, w: float, nb: int) -> None:
    """Sample k of one build: its band s ± G (mm) binned into the upper and lower histograms and
    the band's extremes (ext[k] = min/max of s − G, min/max of s + G) updated."""
    _bin(hist_up, k, s + G, lo, w, nb)
    _bin(hist_lo, k, s - G, lo, w, nb)
    ext[k, 0] = min(ext[k, 0], s - G)
    ext[k, 1] = max(ext[k, 1], s - G)
    ext[k, 2] = min(ext[k, 2], s + G)
    ext[k, 3] = max(ext[k, 3], s + G)


@numba.njit(inline="always")
def _newton(nx: float, ny: float, ax: float, ay: float, r, S, k: int):
    """The local maximum over unit n of f(φ) = n·a + Σ r_J |S_Jᵀ n| near (nx, ny), by a safeguarded
    Newton's method on φ (f', f'' in closed form; the step turns n by Δφ = −f'/f'' along n⊥,
    renormalised, at most 0.5 rad, uphill where f'' ≥ 0; a step that lowers f is halved from the
    best direction). Stops when the step is below 1e-10 rad (the value is then exact to ~1e-20
    relative). Returns the maximum and its direction."""
    best, bx, by = -np.inf, nx, ny
    sx = sy = step = 0.0
    for _ in range(ITER):
        px, py = -ny, nx                       # n⊥ = dn/dφ
        f, d1, d2 = nx * ax + ny * ay, px * ax + py * ay, -(nx * ax + ny * ay)
        for j in range(r.shape[0]):
            tx = S[j, k, 0, 0] * nx + S[j, k, 1, 0] * ny
            ty = S[j, k, 0, 1] * nx + S[j, k, 1, 1] * ny
            ux = S[j, k, 0, 0] * px + S[j, k, 1, 0] * py
            uy = S[j, k, 0, 1] * px + S[j, k, 1, 1] * py
            t2 = tx * tx + ty * ty
            t = math.sqrt(t2)
            f += r[j] * t
            if t > 0.0:
                tu = tx * ux + ty * uy
                w = r[j] / t
                d1 += w * tu
                d2 += w * (ux * ux + uy * uy - t2 - tu * tu / t2)
        if f < best:         # overshot: back to the best direction, half the step
            step *= 0.5
            if step < 1e-12:
                break
            nx, ny = bx + step * sx, by + step * sy
            nn = math.sqrt(nx * nx + ny * ny)
            nx, ny = nx / nn, ny / nn
            continue
        best, bx, by = f, nx, ny
        if d2 < 0.0:
            dphi = max(-0.5, min(0.5, -d1 / d2))
        else:                # not concave here: a step up the slope
            dphi = 0.5 if d1 > 0.0 else -0.5
        if abs(dphi) < 1e-10:
            break
        sx, sy, step = px, py, dphi
        nx, ny = nx + dphi * px, ny + dphi * py
        nn = math.sqrt(nx * nx + ny * ny)
        nx, ny = nx / nn, ny / nn
    return best, bx, by


#: cos 10°: a's direction this near the best scanned direction starts the same climb
NEAR = math.cos(2 * math.pi / SCAN)


@numba.njit(inline="always")
def _worst_once(ax: float, ay: float, r, S, T, M: float, k: int, wx: float, wy: float):
    """:func:`_worst` less a climb that would repeat another: where the pins rival the dimensions, the
    second Newton's method (from a's direction) runs only if that direction is more than one scan
    step (10°) from the best scanned one — within it both climb the same slope to the same maximum."""
    na = math.sqrt(ax * ax + ay * ay)
    if (wx != 0.0 or wy != 0.0) and na > 2.0 * M:
        return _newton(wx, wy, ax, ay, r, S, k)
    if na > 2.0 * M:
        return _newton(ax / na, ay / na, ax, ay, r, S, k)
    bestv, px, py = -np.inf, 1.0, 0.0
    for i in range(SCAN):
        c, sn = _DIRS[i, 0], _DIRS[i, 1]
        v = c * ax + sn * ay
        for j in range(r.shape[0]):
            v += r[j] * T[j, k, i]
        if v > bestv:
            bestv, px, py = v, c, sn
    f, fx, fy = _newton(px, py, ax, ay, r, S, k)
    if na > 0.0 and px * ax + py * ay < NEAR * na:
        g, gx, gy = _newton(ax / na, ay / na, ax, ay, r, S, k)
        if g > f:
            return g, gx, gy
    return f, fx, fy


@numba.njit(cache=True, nogil=True, error_model="numpy")
def scan_table(S):
    """(P, N, SCAN) |S_Jᵀ d_i| of each pin J at each sample for the scanned directions d_i: what
    :func:`_worst`'s scan would compute for every build (the same operations, so the same bits)."""
    P, N = S.shape[0], S.shape[1]
    T = np.empty((P, N, SCAN))
    for j in range(P):
        for k in range(N):
            for i in range(SCAN):
                c, sn = _DIRS[i, 0], _DIRS[i, 1]
                tx = S[j, k, 0, 0] * c + S[j, k, 1, 0] * sn
                ty = S[j, k, 0, 1] * c + S[j, k, 1, 1] * sn
                T[j, k, i] = math.sqrt(tx * tx + ty * ty)
    return T


@numba.njit(inline="always")
def _worst(ax: float, ay: float, r, S, T, M: float, k: int, wx: float, wy: float):
    """max over unit n of n·a + Σ r_J |S_Jᵀ n| at sample k and its direction: Newton from the
    direction (wx, wy) (the neighbouring sample's optimum; 0, 0 for none) or else from a's
    direction where the dimensions dominate (|a| > 2M: f has one maximum within 60° of a), and where the pins can rival the dimensions (|a| ≤ 2M, M = Σ r_J σ_max) also from
    the best of a scan of 36 directions (f is then not sure to have one maximum)."""
    na = math.sqrt(ax * ax + ay * ay)
    if (wx != 0.0 or wy != 0.0) and na > 2.0 * M:
        return _newton(wx, wy, ax, ay, r, S, k)
    if na > 2.0 * M:
        return _newton(ax / na, ay / na, ax, ay, r, S, k)
    bestv, px, py = -np.inf, 1.0, 0.0      # the pins rival the dimensions: a scan of directions first
    for i in range(SCAN):
        c, sn = _DIRS[i, 0], _DIRS[i, 1]
        v = c * ax + sn * ay
        for j in range(r.shape[0]):
            v += r[j] * T[j, k, i]
        if v > bestv:
            bestv, px, py = v, c, sn
    f, fx, fy = _newton(px, py, ax, ay, r, S, k)
    if na > 0.0:
        g, gx, gy = _newton(ax / na, ay / na, ax, ay, r, S, k)
        if g > f:
            return g, gx, gy
    return f, fx, fy


@numba.njit(cache=True, nogil=True, error_model="numpy")
def reduce_point(pos, ok, nom, nrm, nvalid, S, T, smax, g, r, lo, width, hist_up, hist_lo, ext, mom, fails, dev):
    """One traced point over a chunk of builds.

    pos (B, N, 2) mm and ok (B, N) (the build assembled there); nom, nrm (N, 2) the nominal
    point and the unit normal of its path; nvalid (N,) the nominal assembled there; S (P, N, 2, 2)
    the pins' derivative matrices, T (P, N, SCAN) their :func:`scan_table`, smax (P, N) σ_max(S),
    g (P, N) |Sᵀ·nrm|; r (B, P) the builds' radial plays (mm). Adds to hist_up/hist_lo (N, nb + 2)
    (bins of width ``width`` from ``lo``, under- and overflow at the ends) the signed deviation
    along the normal with the pins' worst case one way and the other, to ext (N, 4) its least and
    greatest values (lo min, lo max, up min, up max), to mom (N, 2) Σ and Σ² of the dimensions'
    normal deviation, to fails (N,) the builds not assembled where the nominal is; writes dev (B,)
    the largest distance from the nominal over the cycle (inf for a build that fails somewhere).

    The largest distance: a first pass bounds every sample by |a| + M (M = Σ r_J σ_max); the exact
    worst case is found first where that bound is largest; only samples whose
    bound exceeds the best so far are looked at again — with the tighter bound
    min(|a| + M, L + M²/(2|a|)), L = |a| + Σ r_J |S_Jᵀ â| — and maximised exactly where that
    still exceeds it (Newton from the neighbouring sample's optimum)."""
    B, N = pos.shape[0], pos.shape[1]
    P = r.shape[1]
    nb = hist_up.shape[1] - 2
    na_ = np.empty(N)
    mk = np.empty(N)
    for b in range(B):
        failed = False
        rb = r[b]
        kmax, amax, umax = -1, -1.0, -1.0
        for k in range(N):
            na_[k] = -1.0
            if not nvalid[k]:
                continue
            if not ok[b, k]:
                failed = True
                fails[k] += 1
                continue
            ax, ay = pos[b, k, 0] - nom[k, 0], pos[b, k, 1] - nom[k, 1]
            na = math.sqrt(ax * ax + ay * ay)
            s = nrm[k, 0] * ax + nrm[k, 1] * ay
            mom[k, 0] += s
            mom[k, 1] += s * s
            G = 0.0
            M = 0.0
            for j in range(P):
                G += rb[j] * g[j, k]
                M += rb[j] * smax[j, k]
            na_[k], mk[k] = na, M
            if na + M > umax:
                umax, kmax = na + M, k
            amax = max(amax, na)
            _record(hist_up, hist_lo, ext, k, s, G, lo[k], width[k], nb)
        # a failed build is infinitely off; one with no assembled sample 0; without pins |a|
        dev[b] = np.inf if failed else 0.0 if kmax < 0 else amax if P == 0 else _exact(pos, nom, b, rb, S, T, na_, mk,
                                                                                       kmax)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _exact(pos, nom, b: int, rb, S, T, na_, mk, kmax: int) -> float:
    """Build b's largest distance with its pins at their worst, from the first pass's |a| (na_,
    −1 where not assembled) and M (mk) per sample (see :func:`reduce_point`)."""
    N, P = pos.shape[1], rb.shape[0]
    ax, ay = pos[b, kmax, 0] - nom[kmax, 0], pos[b, kmax, 1] - nom[kmax, 1]
    best, wx, wy = _worst(ax, ay, rb, S, T, mk[kmax], kmax, 0.0, 0.0)
    last = -2
    for k in range(N):
        na = na_[k]
        if k == kmax or na < 0.0 or na + mk[k] <= best:
            continue
        ax, ay = pos[b, k, 0] - nom[k, 0], pos[b, k, 1] - nom[k, 1]
        U = na + mk[k]
        if na > 0.0:
            L = na
            ux, uy = ax / na, ay / na
            for j in range(P):
                tx = S[j, k, 0, 0] * ux + S[j, k, 1, 0] * uy
                ty = S[j, k, 0, 1] * ux + S[j, k, 1, 1] * uy
                L += rb[j] * math.sqrt(tx * tx + ty * ty)
            best = max(best, L)
            U = min(U, L + mk[k] * mk[k] / (2.0 * na))
        if U > best:
            warm = last == k - 1
            v, wx, wy = _worst(ax, ay, rb, S, T, mk[k], k, wx if warm else 0.0, wy if warm else 0.0)
            last = k
            if v > best:
                best = v
    return best


@numba.njit(cache=True, nogil=True, error_model="numpy")
def reduce_angle(ang, ok, nom, nvalid, t, r, dev):
    """One link's angle: dev (B,) the largest |Δθ| + Σ r_J·|∂θ/∂e_J| over the cycle (rad; inf
    for a build that fails where the nominal is assembled); ang (B, N), nom (N,), t (P, N)."""
    B, N = ang.shape[0], ang.shape[1]
    P = r.shape[1]
    for b in range(B):
        best = 0.0
        for k in range(N):
            if not nvalid[k]:
                continue
            if not ok[b, k]:
                best = np.inf
                break
            d = ang[b, k] - nom[k]
            d = d - 2.0 * math.pi * math.floor(d / (2.0 * math.pi) + 0.5)
            v = abs(d)
            for j in range(P):
                v += r[b, j] * t[j, k]
            if v > best:
                best = v
        dev[b] = best


@numba.njit(cache=True, nogil=True, error_model="numpy")
def build_point(b: int, pos, ok, nom, nrm, nvalid, S, T, Q, smax, g, r, lo, width, hist_up, hist_lo, ext, mom,
                fails, dev, na_, mk, sg) -> None:
    """:func:`reduce_point` for one build b whose traced point is pos (1, N, 2) and validity ok
    (N,) (the fused kernel's scratch, :mod:`.tol_fused`): the same values, so the same histograms
    and moments; the largest distance by :func:`_exact_tight` (Q (P, N, 3) the pins' S_J S_Jᵀ);
    na_, mk (N,) and sg (2, N) scratch. The arithmetic per sample is a loop of its own (it
    vectorises), the histograms and the per-build maxima another."""
    N = pos.shape[1]
    P = r.shape[1]
    nb = hist_up.shape[1] - 2
    rb = r[b]
    for k in range(N):
        ax, ay = pos[0, k, 0] - nom[k, 0], pos[0, k, 1] - nom[k, 1]
        na_[k] = math.sqrt(ax * ax + ay * ay)
        s = nrm[k, 0] * ax + nrm[k, 1] * ay
        G = 0.0
        M = 0.0
        for j in range(P):
            G += rb[j] * g[j, k]
            M += rb[j] * smax[j, k]
        sg[0, k], sg[1, k], mk[k] = s, G, M
        use = nvalid[k] & ok[k]
        mom[k, 0] += s if use else 0.0
        mom[k, 1] += s * s if use else 0.0
    failed = False
    kmax, amax, umax = -1, -1.0, -1.0
    for k in range(N):
        if not nvalid[k]:
            na_[k] = -1.0
            continue
        if not ok[k]:
            na_[k] = -1.0
            failed = True
            fails[k] += 1
            continue
        na, M, s, G = na_[k], mk[k], sg[0, k], sg[1, k]
        if na + M > umax:
            umax, kmax = na + M, k
        amax = max(amax, na)
        _record(hist_up, hist_lo, ext, k, s, G, lo[k], width[k], nb)
    dev[b] = np.inf if failed else 0.0 if kmax < 0 else amax if P == 0 else _exact_tight(pos, nom, rb, S, T, Q, na_, mk,
                                                                                          kmax)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _exact_tight(pos, nom, rb, S, T, Q, na_, mk, kmax: int) -> float:
    """:func:`_exact` for the build of pos (1, N, 2) with tighter upper bounds, so that fewer samples
    are maximised (a quarter to a half as many). The set of worst cases at sample k is
    a + Y, Y = Σ r_J·S_J·disc, centrally symmetric; with p = Σ r_J |S_Jᵀ â| and p⊥ the same across
    â, every point y of Y has |y∥| ≤ p and |y⊥| ≤ p⊥, so |a + y| ≤ √((|a| + p)² + p⊥²); and
    |a + y|² ≤ |a|² + 2|a|p + ρ², ρ² = max |y|² ≤ min(M², Σr_J · λ_max(Σ r_J S_J S_Jᵀ)) (Cauchy–
    Schwarz). Q (P, N, 3) holds S_J S_Jᵀ per sample (xx, xy, yy). The value found is the same as
    :func:`_exact`'s: only samples whose bound cannot beat the best are skipped."""
    N, P = pos.shape[1], rb.shape[0]
    ax, ay = pos[0, kmax, 0] - nom[kmax, 0], pos[0, kmax, 1] - nom[kmax, 1]
    best, wx, wy = _worst_once(ax, ay, rb, S, T, mk[kmax], kmax, 0.0, 0.0)
    R = 0.0
    for j in range(P):
        R += rb[j]
    last = -2
    for k in range(N):
        na = na_[k]
        M = mk[k]
        if k == kmax or na < 0.0 or na + M <= best:
            continue
        ax, ay = pos[0, k, 0] - nom[k, 0], pos[0, k, 1] - nom[k, 1]
        U = na + M
        if na > 0.0:
            ux, uy = ax / na, ay / na
            p = pp = w0 = w1 = w2 = 0.0
            for j in range(P):
                tx = S[j, k, 0, 0] * ux + S[j, k, 1, 0] * uy
                ty = S[j, k, 0, 1] * ux + S[j, k, 1, 1] * uy
                p += rb[j] * math.sqrt(tx * tx + ty * ty)
                tx = S[j, k, 1, 0] * ux - S[j, k, 0, 0] * uy
                ty = S[j, k, 1, 1] * ux - S[j, k, 0, 1] * uy
                pp += rb[j] * math.sqrt(tx * tx + ty * ty)
                w0 += rb[j] * Q[j, k, 0]
                w1 += rb[j] * Q[j, k, 1]
                w2 += rb[j] * Q[j, k, 2]
            L = na + p
            best = max(best, L)
            h = 0.5 * (w0 - w2)
            rho2 = min(M * M, R * (0.5 * (w0 + w2) + math.sqrt(h * h + w1 * w1)))
            U = min(U, math.sqrt(L * L + pp * pp), math.sqrt(na * na + 2.0 * na * p + rho2))
            U *= 1.0 + 1e-14          # the bounds' own rounding
        if U > best:
            warm = last == k - 1
            v, wx, wy = _worst_once(ax, ay, rb, S, T, M, k, wx if warm else 0.0, wy if warm else 0.0)
            last = k
            if v > best:
                best = v
    return best


@numba.njit(cache=True, nogil=True, error_model="numpy")
def build_angle(b: int, ang, a0: float, ok, nom, nvalid, t, r, dev) -> None:
    """:func:`reduce_angle` for one build b: ang (N,) the link's angle less its drawn angle a0
    (rad; any turn), ok (N,)."""
    N = ang.shape[0]
    P = r.shape[1]
    best = 0.0
    for k in range(N):
        if not nvalid[k]:
            continue
        if not ok[k]:
            best = np.inf
            break
        d = (ang[k] + a0) - nom[k]
        d = d - 2.0 * math.pi * math.floor(d / (2.0 * math.pi) + 0.5)
        v = abs(d)
        for j in range(P):
            v += r[b, j] * t[j, k]
        if v > best:
            best = v
    dev[b] = best


__all__ = ["build_angle", "build_point", "reduce_angle", "reduce_point", "scan_table"]
