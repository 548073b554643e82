"""Measures of residual slip of synthesised rolling profiles (notes, section C).

On the N + 1 points of any construction (exact, paper, corrected), all lengths in mm:

- *arc-length mismatch*: Σ|P_kP_{k+1}| − R1|u_N − u_0| (the curvimeter on the polygon; it converges
  like N⁻² for every method because chords are copied, so it cannot reveal the paper's error);
- *kinematic slip*: Σ_k |X_{k+1}(m_k) − X_k(m_k)|, m_k the lever point at mid-arc between π_k and
  π_{k+1}: the distance slid by the lever material at the contact of pair D (and, for pair E, the
  same for the slider-circle point relative to the slider);
- *IC offset*: the largest distance of P_k from the rocker line G F_k (0 for a true instant centre);
- *deviation*: the largest distance of P_k from the exact centrode (a tight reference integration);
- *physical slip*: the real mechanism run on the constructed profile (a natural cubic spline
  through P_k): the lever circle kept tangent to the profile, F on the rocker circle, driven by θ;
  Σ | |Δs_profile| − R1|Δu| | over the run.

On the exact method's continuous solution (dense output), the measures of the computed motion
itself, independent of N: the distance slid by the lever material at the pair-D contact,
∫ ℓ|α′ − (1 − g/ℓ)| dθ with α′ differentiated from the computed α(θ); the same for pair E
(lever point at P0 against the slider); and the arc lengths of both centrode pairs, measured along
the computed curves, against R1∫|u1′| and R2∫|u2′|.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import GeometryError
from .exact import ExactPath, WorkingRange, integrate
from .geometry import LeverGeometry, pose_state, rot

_GL_X, _GL_W = np.polynomial.legendre.leggauss(6)


# -- natural cubic spline ----------------------------------------------------------------------
class NaturalSpline:
    """Natural cubic spline through points (N, 2) mm, parametrised by cumulative chord length s (mm)."""

    def __init__(self, points: np.ndarray) -> None:
        pts = np.asarray(points, dtype=float)
        h = np.hypot(*np.diff(pts, axis=0).T)
        if np.any(h <= 0.0):
            raise GeometryError("spline points must be distinct")
        self.s = np.concatenate([[0.0], np.cumsum(h)])
        n = len(pts)
        m = np.zeros((n, 2))  # second derivatives; natural ends: m_0 = m_{n-1} = 0
        if n > 2:
            diag = 2.0 * (h[:-1] + h[1:])
            rhs = 6.0 * ((pts[2:] - pts[1:-1]) / h[1:, None] - (pts[1:-1] - pts[:-2]) / h[:-1, None])
            sub = h[1:-1].copy()  # Thomas algorithm on the (n-2) interior unknowns
            c = np.zeros(n - 2)
            d = np.zeros((n - 2, 2))
            c_prev, d_prev = 0.0, np.zeros(2)
            for i in range(n - 2):
                lo = h[i] if i > 0 else 0.0
                den = diag[i] - lo * c_prev
                c_prev = (sub[i] / den) if i < n - 3 else 0.0
                d_prev = (rhs[i] - lo * d_prev) / den
                c[i], d[i] = c_prev, d_prev
            for i in range(n - 4, -1, -1):
                d[i] -= c[i] * d[i + 1]
            m[1:-1] = d
        self.pts, self.h, self.m = pts, h, m

    @property
    def length_param(self) -> float:
        return float(self.s[-1])

    def _seg(self, s):
        s = np.asarray(s, dtype=float)
        i = np.clip(np.searchsorted(self.s, s, side="right") - 1, 0, len(self.h) - 1)
        return i, s - self.s[i]

    def eval(self, s: np.ndarray, der: int = 0) -> np.ndarray:
        """Point (der 0), first or second derivative w.r.t. s (der 1, 2) at s (M,) -> (M, 2)."""
        i, t = self._seg(s)
        h = self.h[i][:, None]
        p0, p1, m0, m1 = self.pts[i], self.pts[i + 1], self.m[i], self.m[i + 1]
        t = t[:, None]
        b = (p1 - p0) / h - h * (2.0 * m0 + m1) / 6.0
        if der == 0:
            return p0 + b * t + 0.5 * m0 * t ** 2 + (m1 - m0) / (6.0 * h) * t ** 3
        if der == 1:
            return b + m0 * t + 0.5 * (m1 - m0) / h * t ** 2
        return m0 + (m1 - m0) / h * t

    def arc(self, s0: np.ndarray, s1: np.ndarray) -> np.ndarray:
        """Arc length between parameters s0 and s1 (M,), Gauss–Legendre, mm (≥ 0)."""
        mid, half = 0.5 * (s0 + s1), 0.5 * (s1 - s0)
        tot = np.zeros_like(mid)
        for x, w in zip(_GL_X, _GL_W):
            d = self.eval(mid + half * x, 1)
            tot += w * np.hypot(d[:, 0], d[:, 1])
        return np.abs(half) * tot


# -- reference exact centrode -------------------------------------------------------------------
class ExactReference:
    """The exact fixed centrode over θ ∈ [lo, hi], integrated tightly, for distance queries."""

    def __init__(self, geom: LeverGeometry, lo: float, hi: float, tol: float = 1e-12, samples: int = 1000) -> None:
        self.geom = geom
        self.lo, self.hi = lo, hi
        n_lo = max(2, int(samples * abs(lo) / (hi - lo)) + 1)
        n_hi = max(2, int(samples * abs(hi) / (hi - lo)) + 1)
        self._neg = integrate(geom, lo, tol, max_step=0.01) if lo < 0.0 else None
        self._pos = integrate(geom, hi, tol, max_step=0.01) if hi > 0.0 else None
        self.theta = np.unique(np.concatenate([np.linspace(lo, 0.0, n_lo), np.linspace(0.0, hi, n_hi)]))
        self.P = self.point(self.theta)

    def point(self, theta: np.ndarray) -> np.ndarray:
        """Exact P(θ) (M, 2) mm for θ in [lo, hi]."""
        theta = np.clip(np.atleast_1d(np.asarray(theta, dtype=float)), self.lo, self.hi)
        alpha = np.empty_like(theta)
        neg = theta < 0.0
        if np.any(neg):
            alpha[neg] = self._neg.at(theta[neg])[0]
        if np.any(~neg):
            alpha[~neg] = self._pos.at(theta[~neg])[0] if self._pos is not None else self.geom.alpha0
        return pose_state(self.geom, alpha, theta).P

    def distance(self, X: np.ndarray) -> np.ndarray:
        """Distance (M,) mm of points X (M, 2) from the exact centrode (foot of the perpendicular)."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        j = np.empty(len(X), dtype=int)
        for a in range(0, len(X), 256):
            d = np.linalg.norm(X[a:a + 256, None, :] - self.P[None, :, :], axis=-1)
            j[a:a + 256] = np.argmin(d, axis=1)
        t = self.theta[j]
        eps = 1e-6
        for _ in range(12):
            p = self.point(t)
            dp = (self.point(t + eps) - self.point(t - eps)) / (2.0 * eps)
            step = np.einsum("ij,ij->i", X - p, dp) / np.einsum("ij,ij->i", dp, dp)
            t = np.clip(t + step, self.lo, self.hi)
            if np.all(np.abs(step) < 1e-13):
                break
        return np.linalg.norm(X - self.point(t), axis=1)


def reference_for(geom: LeverGeometry, start: float, end: float, wr: WorkingRange) -> ExactReference:
    """A reference covering the stroke with 25 % margins, inside the working range."""
    lo, hi = min(start, end, 0.0), max(start, end, 0.0)
    pad = 0.25 * (hi - lo)
    margin = 1e-3
    lo = max(lo - pad, min(lo, wr.lower + margin))
    hi = min(hi + pad, max(hi, wr.upper - margin))
    return ExactReference(geom, lo, hi)


# -- measures ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PointMeasures:
    """Residual-slip measures of N + 1 construction points (mm); see the module docstring."""

    n: int
    arc_mismatch: float
    kinematic_slip: float
    kinematic_slip_e: float
    ic_offset: float
    deviation: float


def _lever_points(geom: LeverGeometry, theta, F, P0) -> np.ndarray:
    """Pair-E contacts P0 (N, 2) mm moved into the lever frame (the lever element Π30's points)."""
    return rot(-np.asarray(theta, dtype=float), np.asarray(P0, dtype=float) - np.asarray(F, dtype=float)) \
        + np.asarray(geom.f)


def kinematic_slip_terms(geom: LeverGeometry, theta, F, u1, u2, S5, P0=None) -> tuple[np.ndarray, np.ndarray]:
    """Per-interval kinematic slip of pairs D and E (N,) mm between construction points k and k+1.

    Pair D: |X_{k+1}(m_k) − X_k(m_k)|, m_k the lever point at mid-arc of the lever circle between
    u1_k and u1_{k+1}; pair E: the same for the slider-circle point, relative to the slider (its
    travel ΔS5 along the axis removed). ``theta`` (N+1,) rad, ``F`` (N+1, 2) mm, ``u1``/``u2``
    (N+1,) rad unwrapped, ``S5`` (N+1,) mm. The sums are :class:`PointMeasures`' kinematic slips.
    With a slider law (no slider circle) the pair-E lever point is the chord midpoint of the lever
    element between the contacts ``P0`` (N+1, 2) mm of k and k+1 (in the lever frame).
    """
    f = np.asarray(geom.f)
    F = np.asarray(F, dtype=float)
    theta = np.asarray(theta, dtype=float)

    def moved(centre, radius: float, u: np.ndarray) -> np.ndarray:
        um = 0.5 * (u[1:] + u[:-1])
        m = np.asarray(centre) + radius * np.stack([np.cos(um), np.sin(um)], axis=-1)
        return (F[1:] + rot(theta[1:], m - f)) - (F[:-1] + rot(theta[:-1], m - f))

    d = np.linalg.norm(moved(geom.c1, geom.R1, np.asarray(u1, dtype=float)), axis=1)
    if geom.law is not None:
        lev = _lever_points(geom, theta, F, P0)
        m = 0.5 * (lev[1:] + lev[:-1])
        rel = (F[1:] + rot(theta[1:], m - f)) - (F[:-1] + rot(theta[:-1], m - f)) \
            - np.diff(S5)[:, None] * np.asarray(geom.ds)
        return d, np.linalg.norm(rel, axis=1)
    rel = moved(geom.c2, geom.R2, np.asarray(u2, dtype=float)) - np.diff(S5)[:, None] * np.asarray(geom.ds)
    return d, np.linalg.norm(rel, axis=1)


def running_sum(terms: np.ndarray) -> np.ndarray:
    """(N+1,) running sum of (N,) per-interval terms, starting at 0; its last value is the total."""
    return np.concatenate([[0.0], np.cumsum(terms)])


def point_measures(geom: LeverGeometry, theta, alpha, F, P, u1, u2, S5, ref: ExactReference | None,
                   P0=None) -> PointMeasures:
    """Measures of construction points k = 0…N (arrays (N+1,) rad / (N+1, 2) mm); u1, u2 unwrapped
    (``P0``: the pair-E contacts, needed with a slider law)."""
    arc = float(np.sum(np.hypot(*np.diff(P, axis=0).T)) - geom.R1 * abs(u1[-1] - u1[0]))
    d, e_terms = kinematic_slip_terms(geom, theta, F, u1, u2, S5, P0)
    slip, slip_e = float(running_sum(d)[-1]), float(running_sum(e_terms)[-1])
    e = (F - np.asarray(geom.G)) / geom.ell
    r = P - np.asarray(geom.G)
    off = np.abs(e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0])
    dev = float(np.max(ref.distance(P))) if ref is not None else math.nan
    return PointMeasures(len(P) - 1, arc, slip, slip_e, float(off.max()), dev)


@dataclass(frozen=True)
class SlipSamples:
    """Slip accumulated along the stroke, per sample (what the slip plots draw).

    ``theta`` (N+1,) rad: the synthesis' samples, in stroke order; ``slip_d`` / ``slip_e`` (N+1,)
    mm: the slip of pairs D and E from the start of the stroke to each sample (0 at the first).
    ``source`` says which measure: ``"continuous"`` - the exact method's computed motion (its last
    values are :class:`ContinuousMeasures` ``slip_d``/``slip_e``, the figures the summary reports),
    ``"points"`` - the kinematic slip of the construction points (last values
    :class:`PointMeasures` ``kinematic_slip``/``kinematic_slip_e``).
    """

    theta: np.ndarray
    slip_d: np.ndarray
    slip_e: np.ndarray
    source: str


def point_slip_samples(geom: LeverGeometry, theta, F, u1, u2, S5, P0=None) -> SlipSamples:
    """:class:`SlipSamples` of construction points (running sums of :func:`kinematic_slip_terms`)."""
    d, e = kinematic_slip_terms(geom, theta, F, u1, u2, S5, P0)
    return SlipSamples(np.asarray(theta, dtype=float), running_sum(d), running_sum(e), "points")


@dataclass(frozen=True)
class PhysicalSlip:
    """The real mechanism run on a spline profile: slip (mm) over θ ∈ [start, end] rolling ``rolled``
    mm. ``slip`` is NaN only when no run of two samples exists; ``reason`` then says why."""

    slip: float
    rolled: float
    start: float
    end: float
    samples: int
    reason: str = ""

    @property
    def ratio(self) -> float:
        return self.slip / self.rolled if self.rolled > 0.0 else math.nan


def physical_slip(geom: LeverGeometry, P: np.ndarray, theta_nodes: np.ndarray, alpha_nodes: np.ndarray,
                  start: float | None = None,
                  end: float | None = None, samples: int = 2000) -> PhysicalSlip:
    """Run the lever on the natural cubic spline through ``P`` (N+1, 2) mm, driven by θ.

    ``theta_nodes``, ``alpha_nodes`` (N+1,) rad: the construction's poses, used for the side of the
    profile the lever lies on, the first guesses and the default range (first to last pose).
    Per sample the one unknown is the profile parameter s: the lever circle tangent to the profile
    at S(s) has its centre at S + σR1·N(s), and that centre must put the pin on the rocker circle,
    |C1 − Rot(θ)(c1 − f) − G| = ℓ (Newton, vectorised over θ). The contact angle u on the circle
    follows; the slip is Σ | |Δs_profile| − R1|Δu| | over the samples. The run covers the longest
    stretch of samples where a tangent pose exists with the contact on the profile (0.5 %
    extrapolation allowed): with few points the spline's end tangents are off and the lever may
    meet the profile only beyond its first or last point, so the run starts a little later.
    """
    sp = NaturalSpline(P)
    th_n = np.asarray(theta_nodes, dtype=float)
    start = th_n[0] if start is None else start
    end = th_n[-1] if end is None else end
    theta = np.linspace(start, end, samples + 1)
    order = np.argsort(th_n)
    s_guess = np.interp(theta, th_n[order], sp.s[order])
    v1 = rot(theta, np.asarray(geom.c1) - np.asarray(geom.f))
    G = np.asarray(geom.G)
    t0 = sp.eval(np.array([0.0]), 1)[0]
    sigma = _side(geom, th_n[0], alpha_nodes[0], P[0], np.array([-t0[1], t0[0]]))
    s = s_guess
    ok = np.zeros(len(theta), dtype=bool)
    for _ in range(30):
        S, d1, d2 = sp.eval(s), sp.eval(s, 1), sp.eval(s, 2)
        sp2 = np.einsum("ij,ij->i", d1, d1)
        spn = np.sqrt(sp2)
        N = np.stack([-d1[:, 1], d1[:, 0]], axis=-1) / spn[:, None]
        dT = (d2 * sp2[:, None] - d1 * np.einsum("ij,ij->i", d1, d2)[:, None]) / (spn ** 3)[:, None]
        dN = np.stack([-dT[:, 1], dT[:, 0]], axis=-1)
        W = S + sigma * geom.R1 * N - v1 - G
        h = np.einsum("ij,ij->i", W, W) - geom.ell ** 2
        dh = 2.0 * np.einsum("ij,ij->i", W, d1 + sigma * geom.R1 * dN)
        step = h / np.where(dh != 0.0, dh, np.nan)
        s = s - np.clip(np.nan_to_num(step, nan=0.0), -0.1 * sp.length_param, 0.1 * sp.length_param)
        ok = np.isfinite(step) & (np.abs(h) < 1e-12 * geom.ell ** 2)
        if np.all(np.abs(np.nan_to_num(step, nan=1.0)) < 1e-12):
            break
    margin = 0.005 * sp.length_param
    inside = ok & (s >= -margin) & (s <= sp.length_param + margin)
    first, last = _longest_run(inside)
    if last - first < 2:
        if not ok.any():
            why = "the lever finds no pose tangent to the spline profile at any sample"
        else:
            why = ("the lever touches the spline profile only beyond its ends (the spline through "
                   f"{len(P)} points is too coarse there): use more points")
        return PhysicalSlip(math.nan, 0.0, float(start), float(start), 0, why)
    s, theta = s[first:last], theta[first:last]
    d1 = sp.eval(s, 1)
    N = np.stack([-d1[:, 1], d1[:, 0]], axis=-1) / np.hypot(d1[:, 0], d1[:, 1])[:, None]
    dirn = rot(-theta, -sigma * N)
    u = np.unwrap(np.arctan2(dirn[:, 1], dirn[:, 0]))
    ds = sp.arc(s[:-1], s[1:])
    slip = float(np.sum(np.abs(ds - geom.R1 * np.abs(np.diff(u)))))
    return PhysicalSlip(slip, float(np.sum(ds)), float(theta[0]), float(theta[-1]), last - first - 1)


def _longest_run(mask: np.ndarray) -> tuple[int, int]:
    """[first, last) of the longest run of True in ``mask`` ((0, 0) if none)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(np.int8), [0]))))
    if edges.size == 0:
        return 0, 0
    starts, stops = edges[::2], edges[1::2]
    k = int(np.argmax(stops - starts))
    return int(starts[k]), int(stops[k])


def _side(geom: LeverGeometry, theta0: float, alpha0: float, p0: np.ndarray, n0: np.ndarray) -> float:
    """σ = ±1: the side of the profile normal n0 at p0 on which the first pose's lever centre lies."""
    F = np.asarray(geom.G) + geom.ell * np.array([math.cos(alpha0), math.sin(alpha0)])
    c1 = F + rot(np.array([theta0]), np.asarray(geom.c1) - np.asarray(geom.f))[0]
    return 1.0 if float(np.dot(c1 - p0, n0)) >= 0.0 else -1.0


@dataclass(frozen=True)
class ContinuousMeasures:
    """Slip of the exact method's computed continuous motion (mm); see the module docstring."""

    slip_d: float  # lever material at the pair-D contact
    slip_e: float  # lever point at P0 against the slider
    length_fixed: float  # ∫|dP/dθ|
    length_moving: float  # R1 ∫|du1/dθ|
    length_slider: float  # ∫|dQ/dθ|
    length_lever_e: float  # R2 ∫|du2/dθ| (with a slider law: ∫|dΠ30/dθ| in the lever frame)

    @property
    def mismatch_d(self) -> float:
        return self.length_fixed - self.length_moving

    @property
    def mismatch_e(self) -> float:
        return self.length_slider - self.length_lever_e

    @property
    def worst(self) -> float:
        """The largest of the four slip figures (mm)."""
        return max(abs(self.slip_d), abs(self.slip_e), abs(self.mismatch_d), abs(self.mismatch_e))


def _wrap(x: np.ndarray) -> np.ndarray:
    return (x + np.pi) % (2.0 * np.pi) - np.pi


def continuous_measures(path: ExactPath, start: float, end: float) -> ContinuousMeasures:
    """Measures of the computed motion over θ ∈ start → end (inside the path), Gauss–Legendre on
    each mesh interval, derivatives by fourth-order central differences of the dense output; any
    jump of the computed motion at a mesh node (dense value from the left against the node value)
    is added to the slip and to the lengths."""
    return continuous_slip(path, start, end)[0]


def _quadrature(path: ExactPath, lo: float, hi: float, extra: np.ndarray):
    """Knots (mesh nodes and grid points inside [lo, hi]), Gauss–Legendre points q (rad) and
    weights w, the dense output's base index of each q, and the central-difference step per q
    (rad; the ±2-step stencil stays inside the stroke: beyond its ends the working range may be
    over)."""
    th = path.theta
    inside = extra[(extra > lo) & (extra < hi)]
    knots = np.unique(np.concatenate([[lo, hi], th[(th > lo) & (th < hi)], inside]))
    mid, half = 0.5 * (knots[1:] + knots[:-1]), 0.5 * np.diff(knots)
    q = (mid[:, None] + half[:, None] * _GL_X[None, :]).ravel()
    w = (half[:, None] * _GL_W[None, :]).ravel()
    base = path.base_index(q)
    eta = np.minimum(1e-4, 0.5 * np.repeat(half, len(_GL_X)))  # FD step per point (rad)
    eta = np.minimum(eta, 0.45 * np.minimum(q - lo, hi - q))
    return knots, q, w, base, eta


@dataclass
class _Rates:
    """The computed motion at the quadrature points and its θ-derivatives (fourth-order central
    differences): lever angle a, slider s5, pose state st, and d/dθ of a, s5, P, Q (the slider
    point), u1, u2 and (with a slider law) the lever-frame point Π30 times η."""

    a: np.ndarray
    st: object
    da: np.ndarray
    ds5: np.ndarray
    dP: np.ndarray
    dQ: np.ndarray
    du1: np.ndarray
    du2: np.ndarray
    dL: np.ndarray


def _rates(path: ExactPath, q: np.ndarray, base: np.ndarray, eta: np.ndarray, law: bool) -> _Rates:
    """:class:`_Rates` at the points q (M,) rad with steps eta (M,) rad."""
    geom = path.geom
    offs = (-2.0, -1.0, 1.0, 2.0)
    coef = (1.0 / 12.0, -8.0 / 12.0, 8.0 / 12.0, -1.0 / 12.0)

    def evaluate(t):
        a, s5 = path.at(t, base=base)
        st = pose_state(geom, a, t)
        return a, s5, st

    a_c, s_c, st_c = evaluate(q)
    da = np.zeros_like(q)
    ds5 = np.zeros_like(q)
    dP = np.zeros((len(q), 2))
    dQ = np.zeros((len(q), 2))
    du1 = np.zeros_like(q)
    du2 = np.zeros_like(q)
    ds = np.asarray(geom.ds)
    Qc = st_c.P0 - s_c[:, None] * ds
    dL = np.zeros((len(q), 2))       # the lever element Π30 (slider law): its lever-frame points
    Lc = _lever_points(geom, q, st_c.F, st_c.P0) if law else None
    for o, c in zip(offs, coef):
        a, s5, st = evaluate(q + o * eta)
        da += c * (a - a_c)
        ds5 += c * (s5 - s_c)
        dP += c * (st.P - st_c.P)
        dQ += c * ((st.P0 - s5[:, None] * ds) - Qc)
        du1 += c * _wrap(st.u1 - st_c.u1)
        du2 += c * _wrap(st.u2 - st_c.u2)
        if law:
            dL += c * (_lever_points(geom, q + o * eta, st.F, st.P0) - Lc)
    da, ds5, du1, du2 = (x / eta for x in (da, ds5, du1, du2))
    dP, dQ = dP / eta[:, None], dQ / eta[:, None]
    return _Rates(a_c, st_c, da, ds5, dP, dQ, du1, du2, dL)


def _add_node_jumps(path: ExactPath, lo: float, hi: float, knots: np.ndarray, law: bool,
                    step_d: np.ndarray, step_e: np.ndarray, out: list) -> None:
    """Add the jumps of the computed motion at inner mesh nodes (dense value from the left against
    the node) to the slip per knot interval (step_d, step_e, mm) and to the lengths out[2:] (mm)."""
    geom, th = path.geom, path.theta
    ds = np.asarray(geom.ds)
    inner = np.flatnonzero((th > lo) & (th < hi))
    inner = inner[inner > 0]
    if not len(inner):
        return
    a_l, s_l = path.at(th[inner], base=inner - 1)
    left = pose_state(geom, a_l, th[inner])
    node = pose_state(geom, path.alpha[inner], th[inner])
    dF = node.F - left.F
    at_knot = np.searchsorted(knots, th[inner]) - 1   # the interval ending at the node
    np.add.at(step_d, at_knot, np.linalg.norm(dF, axis=1))
    np.add.at(step_e, at_knot, np.linalg.norm(dF - (path.S5[inner] - s_l)[:, None] * ds, axis=1))
    out[2] += float(np.sum(np.linalg.norm(node.P - left.P, axis=1)))
    out[3] += float(geom.R1 * np.sum(np.abs(_wrap(node.u1 - left.u1))))
    qn = node.P0 - path.S5[inner][:, None] * ds
    ql = left.P0 - s_l[:, None] * ds
    out[4] += float(np.sum(np.linalg.norm(qn - ql, axis=1)))
    if law:
        jump = _lever_points(geom, th[inner], node.F, node.P0) - _lever_points(geom, th[inner], left.F, left.P0)
        out[5] += float(np.sum(np.linalg.norm(jump, axis=1)))
    else:
        out[5] += float(geom.R2 * np.sum(np.abs(_wrap(node.u2 - left.u2))))


def continuous_slip(path: ExactPath, start: float, end: float,
                    grid: np.ndarray | None = None) -> tuple[ContinuousMeasures, SlipSamples | None]:
    """:func:`continuous_measures`, and with ``grid`` (M,) rad (inside the stroke, in stroke order)
    the slip of pairs D and E accumulated from ``start`` to each grid point (:class:`SlipSamples`,
    source "continuous"). The grid points are added to the integration knots, so the slip at the
    last grid point equal to ``end`` is the measures' ``slip_d``/``slip_e`` to the last bit."""
    geom = path.geom
    lo, hi = min(start, end), max(start, end)
    extra = np.zeros(0) if grid is None else np.asarray(grid, dtype=float)
    knots, q, w, base, eta = _quadrature(path, lo, hi, extra)
    law = geom.law is not None
    r8 = _rates(path, q, base, eta, law)
    st_c, a_c, da = r8.st, r8.a, r8.da
    slip_d = geom.ell * np.abs(da - st_c.rate)
    e = np.stack([np.cos(a_c), np.sin(a_c)], axis=-1)
    ep = np.stack([-e[:, 1], e[:, 0]], axis=-1)
    r = st_c.P0 - st_c.F
    v_lever = geom.ell * da[:, None] * ep + np.stack([-r[:, 1], r[:, 0]], axis=-1)
    slip_e = np.linalg.norm(v_lever - r8.ds5[:, None] * np.asarray(geom.ds), axis=1)
    # slip per knot interval (ascending θ), then the jumps at inner mesh nodes added at those knots
    n_int = len(knots) - 1
    step_d = (w * slip_d).reshape(n_int, -1).sum(axis=1)
    step_e = (w * slip_e).reshape(n_int, -1).sum(axis=1)
    out = [0.0, 0.0, float(w @ np.linalg.norm(r8.dP, axis=1)),
           float(geom.R1 * (w @ np.abs(r8.du1))), float(w @ np.linalg.norm(r8.dQ, axis=1)),
           float(w @ np.linalg.norm(r8.dL / eta[:, None], axis=1)) if law else float(geom.R2 * (w @ np.abs(r8.du2)))]
    _add_node_jumps(path, lo, hi, knots, law, step_d, step_e, out)
    cum_d, cum_e = running_sum(step_d), running_sum(step_e)
    out[0], out[1] = float(cum_d[-1]), float(cum_e[-1])
    if not all(math.isfinite(x) for x in out):
        bad = q[~np.isfinite(st_c.rate) | ~np.isfinite(st_c.t2)]
        where = f" near θ ≈ {bad[0]:.6f} rad" if len(bad) else ""
        raise GeometryError(f"the continuous slip measures over θ from {start:g} to {end:g} rad cannot be "
                            f"evaluated{where}: the computed motion leaves the working range there")
    samples = None
    if grid is not None:
        k = np.clip(np.searchsorted(knots, extra), 0, len(knots) - 1)
        if start <= end:
            sd, se = cum_d[k], cum_e[k]
        else:   # the stroke runs down: accumulate from the upper end
            sd, se = cum_d[-1] - cum_d[k], cum_e[-1] - cum_e[k]
        samples = SlipSamples(extra, sd, se, "continuous")
    return ContinuousMeasures(*out), samples
