"""Geometry of the rolling lever in any pose (α, θ): the shared kernel of every synthesis method.

Conventions (notes, section C): the rocker pivot G, rocker length ℓ = |f − G|, rocker angle α, the
pin F = G + ℓ e(α), the lever rotation θ (0 in the drawn pose), and the lever map
X(p) = F + Rot(θ)(p − f) taking a lever point p (drawn-pose coordinates, "lever frame") to the
ground. Pair D: the contact P = G + g e(α) is the chosen intersection of the rocker line with the
moved lever circle; the exact motion obeys dα/dθ = 1 − g/ℓ. Pair E: P0 = P + t2 n, n = J d_s, on
the moved slider circle; k53 = dS5/dθ = −t2.

Where pair D can be built is decided in the lever frame. There the rocker line is the line through
the pin f with direction ψ = α − θ and the pivot sits at f − ℓ e(ψ), so the whole of pair D (both
intersections, g, the discriminant) is a function of ψ alone, and ψ falls strictly along any motion
(dψ/dθ = α′ − 1 = −g/ℓ < 0). The ends of pair D are therefore fixed directions ψ, found in closed
form by :func:`pair_d_limits`: a tangent from the pin to the circle (the rocker line becomes
tangent to the moved circle), the tangent at the pin when the pin lies on the circle (the contact
reaches the pin), or a direction putting the pivot on the circle (g = 0; since dψ/dθ = −g/ℓ
vanishes there, that direction is only approached asymptotically, and the range ends where the
contact comes within κ of the pivot: a drawing with the contact on the pivot is refused).
Testing ψ against them cannot be stepped over, unlike testing the discriminant: with the pin just
outside the circle the line misses it only over a sliver of ψ of width ~2√(2δ/R1) (δ the pin's
gap), and with the pin on the circle the discriminant touches 0 without changing sign.

Every function takes numpy arrays of shape (N,) for α and θ (radians) and returns (N,) or (N, 2)
arrays in millimetres. Poses where a pair cannot be built give NaN (data, not exceptions).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model.rolling_lever import RollingLever, coincidence_tolerance
from .slider_law import LawCurve

FloatArray = np.ndarray


@dataclass(frozen=True)
class LeverGeometry:
    """The constants of a rolling lever (mm, rad) taken from the element's drawn pose."""

    G: tuple[float, float]
    f: tuple[float, float]
    c1: tuple[float, float]
    R1: float
    c2: tuple[float, float]
    R2: float
    ds: tuple[float, float]  # unit slider direction
    side: int  # +1 / −1: branch of the slider-circle intersection along n = J ds
    branch: int  # −1 near, +1 far: branch of the rocker-line intersection
    ell: float
    alpha0: float
    #: a prescribed slider law (pair E from k53 = S5'(θ), :mod:`.law`) instead of the slider circle;
    #: then ``c2`` is the pin and ``R2`` 0 (unused)
    law: LawCurve | None = None

    @classmethod
    def from_element(cls, el: RollingLever) -> "LeverGeometry":
        sc, law = el.slider_circle, None
        if el.slider_law is not None:
            c2, r2, law = el.pin, 0.0, LawCurve(el.slider_law, el.stroke)
        else:
            c2, r2 = sc.center, sc.radius
        return cls(G=el.rocker_pivot, f=el.pin, c1=el.lever_circle.center, R1=el.lever_circle.radius,
                   c2=c2, R2=r2, ds=el.slider_axis,
                   side=int(el.slider_side), branch=1 if el.contact_branch == "far" else -1,
                   ell=el.rocker_length, alpha0=el.rocker_angle0, law=law)

    @property
    def n(self) -> tuple[float, float]:
        """Unit normal of the slider axis, J d_s."""
        return (-self.ds[1], self.ds[0])

    @property
    def scale(self) -> float:
        """A length typical of the mechanism (mm), for relative tolerances."""
        return max(self.ell, self.R1, self.R2)

    @property
    def kappa(self) -> float:
        """κ (mm): a pin closer than this to the lever circle lies on it."""
        return coincidence_tolerance(self.ell, self.R1, self.G, self.c1)


def _pair_d_valid(geom: LeverGeometry, psi: float, kappa: float) -> bool:
    """Pair D in the lever frame for the rocker direction ψ: the line meets the circle, the chosen
    contact is in front of the pivot and is not the pin itself."""
    ex, ey = math.cos(psi), math.sin(psi)
    wx = geom.c1[0] - geom.f[0] + geom.ell * ex  # c1 − G with G = f − ℓ e(ψ)
    wy = geom.c1[1] - geom.f[1] + geom.ell * ey
    b = wx * ex + wy * ey
    c = wx * ey - wy * ex  # distance of the circle's centre from the rocker line: D1 = R1² − c²
    d1 = (geom.R1 - c) * (geom.R1 + c)
    if not d1 > 0.0:
        return False
    g = b + geom.branch * math.sqrt(d1)
    return g > kappa and abs(g - geom.ell) > kappa


def pair_d_limits(geom: LeverGeometry) -> tuple[float, float, int, int]:
    """(ψ_lo, ψ_hi, reason_lo, reason_hi): the rocker directions in the lever frame, ψ = α − θ (rad,
    continuous from α0), below and above the drawn one, where pair D stops (±inf: never within
    the searched turn), and the :attr:`ScalarKernel.REASONS` key of each.

    Candidates, from the centre-to-pin vector u = f − c1 (|u| = d): the tangents from the pin,
    at ±β from the direction to the centre, sin β = R1/d, modulo π (pin outside, reason 1; on the
    circle within κ, β = π/2, the tangent at the pin, reason 4; inside: none); the directions with
    the pivot on the circle, |u − ℓ e(ψ)| = R1, i.e. u·e(ψ) = (d² + ℓ² − R1²)/(2ℓ) (reason 2).
    Between consecutive candidates pair D is either possible throughout or nowhere (checked at the
    midpoint); the end is the first candidate followed by an impossible stretch.
    """
    kappa = geom.kappa
    ux, uy = geom.f[0] - geom.c1[0], geom.f[1] - geom.c1[1]
    d = math.hypot(ux, uy)
    cands: list[tuple[float, int]] = []
    gap = d - geom.R1
    if gap >= -kappa:
        to_centre = math.atan2(-uy, -ux)
        if gap <= kappa:
            beta, why = 0.5 * math.pi, 4
        else:
            beta, why = math.atan2(geom.R1, math.sqrt(gap * (d + geom.R1))), 1
        cands += [(to_centre + beta, why), (to_centre - beta, why),
                  (to_centre + beta + math.pi, why), (to_centre - beta + math.pi, why)]
    if d > 0.0:
        m = (gap * (d + geom.R1) + geom.ell ** 2) / (2.0 * geom.ell * d)
        if abs(m) <= 1.0:
            a, phi = math.acos(m), math.atan2(uy, ux)
            cands += [(phi + a, 2), (phi - a, 2)]
    a0 = geom.alpha0
    # over |θ| ≤ 2π, ψ moves by at most 2π·max g/ℓ ≤ 2π(1 + (d + R1)/ℓ)
    reach = 2.0 * math.pi * (2.0 + (d + geom.R1) / geom.ell) + math.pi
    pts = sorted((c + 2.0 * math.pi * k, why) for c, why in cands
                 for k in range(math.ceil((a0 - reach - c) / (2.0 * math.pi)),
                                math.floor((a0 + reach - c) / (2.0 * math.pi)) + 1))
    merged: list[tuple[float, int]] = []
    for c, why in pts:  # coincident candidates (e.g. the two tangents at a pin on the circle) count once
        if merged and c - merged[-1][0] <= 1e-12:
            continue
        merged.append((c, why))
    up = [p for p in merged if p[0] > a0]
    down = [p for p in reversed(merged) if p[0] < a0]
    hi, why_hi = math.inf, 0
    for (c, why), (c2, _) in zip(up, up[1:]):
        if not _pair_d_valid(geom, 0.5 * (c + c2), kappa):
            hi, why_hi = c, why
            break
    lo, why_lo = -math.inf, 0
    for (c, why), (c2, _) in zip(down, down[1:]):
        if not _pair_d_valid(geom, 0.5 * (c + c2), kappa):
            lo, why_lo = c, why
            break
    return lo, hi, why_lo, why_hi


def rot(theta: FloatArray, v: FloatArray) -> FloatArray:
    """Rotate vectors ``v`` (N, 2) or (2,) by angles ``theta`` (N,) rad -> (N, 2)."""
    c, s = np.cos(theta), np.sin(theta)
    v = np.asarray(v, dtype=float)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def lever_map(geom: LeverGeometry, alpha: FloatArray, theta: FloatArray, p: FloatArray) -> FloatArray:
    """X(p): lever points ``p`` (drawn-pose coordinates, (2,) or (N, 2) mm) in the ground, (N, 2) mm."""
    alpha = np.asarray(alpha, dtype=float)
    F = np.stack([geom.G[0] + geom.ell * np.cos(alpha), geom.G[1] + geom.ell * np.sin(alpha)], axis=-1)
    return F + rot(theta, np.asarray(p, dtype=float) - np.asarray(geom.f))


def to_lever_frame(geom: LeverGeometry, alpha: FloatArray, theta: FloatArray, X: FloatArray) -> FloatArray:
    """Inverse of :func:`lever_map`: ground points X (N, 2) mm -> lever-frame points (N, 2) mm."""
    alpha = np.asarray(alpha, dtype=float)
    F = np.stack([geom.G[0] + geom.ell * np.cos(alpha), geom.G[1] + geom.ell * np.sin(alpha)], axis=-1)
    return rot(-np.asarray(theta, dtype=float), X - F) + np.asarray(geom.f)


@dataclass
class PoseState:
    """Everything about the lever in poses (α, θ), arrays over N poses (mm, rad).

    ``D1``: discriminant of the rocker-line/lever-circle intersection (mm²; ≤ 0: rocker tangent or
    missing the circle). ``D2``: the same for the slider normal and the slider circle. ``rate`` is
    dα/dθ = 1 − g/ℓ of the exact motion. ``u1``/``u2``: contact angles on the lever circles in the
    lever frame (rad, atan2). ``k53`` = −t2 (mm/rad).
    """

    alpha: FloatArray
    theta: FloatArray
    F: FloatArray
    C1: FloatArray
    D1: FloatArray
    g: FloatArray
    P: FloatArray
    rate: FloatArray
    u1: FloatArray
    C2: FloatArray
    D2: FloatArray
    t2: FloatArray
    P0: FloatArray
    u2: FloatArray

    @property
    def k53(self) -> FloatArray:
        return -self.t2


def contact_distance(geom: LeverGeometry, alpha: FloatArray, theta: FloatArray, b: FloatArray,
                     D1: FloatArray) -> FloatArray:
    """g (mm) from b and the discriminant D1 (as :class:`ScalarKernel`): NaN outside the directions
    of :func:`pair_d_limits` and where the contact is within κ of the pivot; within them a
    non-positive D1 is round-off at a tangent and counts as 0."""
    lo, hi, _, _ = pair_d_limits(geom)
    psi = alpha - theta
    d = np.where((psi > lo) & (psi < hi), np.maximum(D1, 0.0), np.nan)
    with np.errstate(invalid="ignore"):
        g = b + geom.branch * np.sqrt(d)
    return np.where(g > geom.kappa, g, np.nan)


def pose_state(geom: LeverGeometry, alpha: FloatArray, theta: FloatArray) -> PoseState:
    """Contacts, rates and angles of both pairs for poses (α, θ), each (N,) rad; see :class:`PoseState`."""
    alpha = np.atleast_1d(np.asarray(alpha, dtype=float))
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    alpha, theta = np.broadcast_arrays(alpha, theta)
    e = np.stack([np.cos(alpha), np.sin(alpha)], axis=-1)
    G = np.asarray(geom.G)
    F = G + geom.ell * e
    f = np.asarray(geom.f)
    C1 = F + rot(theta, np.asarray(geom.c1) - f)
    w = C1 - G
    b = np.einsum("ij,ij->i", w, e)
    c = w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]
    D1 = (geom.R1 - c) * (geom.R1 + c)   # = b² − (|w|² − R1²), without the cancellation
    g = contact_distance(geom, alpha, theta, b, D1)
    P = G + g[:, None] * e
    rate = 1.0 - g / geom.ell
    r1 = rot(-theta, P - C1)
    u1 = np.arctan2(r1[:, 1], r1[:, 0])
    C2, D2, t2, P0, u2 = pair_e(geom, F, theta, P)
    return PoseState(alpha, theta, F, C1, D1, g, P, rate, u1, C2, D2, t2, P0, u2)


def pair_e(geom: LeverGeometry, F: FloatArray, theta: FloatArray, P: FloatArray):
    """Pair E for lever poses (pin F (N, 2) mm, rotation θ (N,) rad) and pair-D contacts P (N, 2).

    Returns (C2, D2, t2, P0, u2): the moved slider-circle centre (N, 2), the discriminant (N,) mm²,
    the signed distance t2 = (P0 − P)·n (N,) mm (k53 = −t2), the contact P0 (N, 2) on the normal to
    the slider axis through P, and its angle u2 on the slider circle in the lever frame (N,) rad.
    NaN where the normal misses the circle. With a slider law: t2 = −S5'(θ) (P0 is the relative
    instant centre, :mod:`.law`), D2 = 1, C2 the pin and u2 = θ (the profile's parameter).
    """
    C2 = F + rot(theta, np.asarray(geom.c2) - np.asarray(geom.f))
    if geom.law is not None:
        t2 = -geom.law.rates(theta)
        return C2, np.ones_like(t2), t2, P + t2[:, None] * np.asarray(geom.n), np.array(theta, dtype=float)
    n = np.asarray(geom.n)
    z = P - C2
    zn = z @ n
    D2 = zn * zn - np.einsum("ij,ij->i", z, z) + geom.R2 ** 2
    with np.errstate(invalid="ignore"):
        t2 = -zn + geom.side * np.sqrt(np.where(D2 >= 0.0, D2, np.nan))
    P0 = P + t2[:, None] * n
    r2 = rot(-theta, P0 - C2)
    u2 = np.arctan2(r2[:, 1], r2[:, 0])
    return C2, D2, t2, P0, u2


def slider_point(geom: LeverGeometry, P0: FloatArray, S5: FloatArray) -> FloatArray:
    """Q = P0 − S5 d_s: the contact of pair E in the slider frame (N, 2) mm."""
    return np.asarray(P0) - np.asarray(S5)[:, None] * np.asarray(geom.ds)


class ScalarKernel:
    """The exact ODE's right-hand side for one pose, in plain floats (fast inside a Python loop).

    ``rhs(α, θ)`` returns (dα/dθ, dS5/dθ) or None outside the working range; ``reason`` then names
    the pair that failed. ``contacts(α, S5, θ)`` returns (P.x, P.y, Q.x, Q.y) in mm.
    """

    REASONS = {1: "the rocker line becomes tangent to the moved lever circle",
               2: "the contact point reaches the rocker pivot (it comes within the coincidence tolerance; "
                  "the approach is asymptotic, lever and rocker turning ever more as one body about the "
                  "pivot)",
               3: "the normal to the slider axis through the contact leaves the slider circle",
               4: "the contact reaches the pin (the pin lies on the lever circle, so there the rocker line "
                  "touches the moved lever circle)"}

    def __init__(self, geom: LeverGeometry) -> None:
        self.gx, self.gy = geom.G
        self.ell = geom.ell
        self.psi_lo, self.psi_hi, self.why_lo, self.why_hi = pair_d_limits(geom)
        self.kappa = geom.kappa
        self.v1 = (geom.c1[0] - geom.f[0], geom.c1[1] - geom.f[1])
        self.v2 = (geom.c2[0] - geom.f[0], geom.c2[1] - geom.f[1])
        self.r1sq = geom.R1 ** 2
        self.r1 = geom.R1
        self.r2sq = geom.R2 ** 2
        self.branch = float(geom.branch)
        self.side = float(geom.side)
        self.nx, self.ny = geom.n
        self.dsx, self.dsy = geom.ds
        self.law = geom.law
        self.reason = 0

    def _pair_d(self, a: float, th: float):
        psi = a - th
        if not self.psi_lo < psi < self.psi_hi:
            self.reason = self.why_lo if psi <= self.psi_lo else self.why_hi
            return None
        ca, sa = math.cos(a), math.sin(a)
        ct, st = math.cos(th), math.sin(th)
        fx = self.gx + self.ell * ca
        fy = self.gy + self.ell * sa
        wx = fx + ct * self.v1[0] - st * self.v1[1] - self.gx
        wy = fy + st * self.v1[0] + ct * self.v1[1] - self.gy
        b = wx * ca + wy * sa
        c = wx * sa - wy * ca
        # R1² − c² (= b² − (|w|² − R1²)), factored: no cancellation at the tangent, where the
        # expanded form loses eps·b²/D1 of D1 and its square root drives the ODE (issue 13, item 11)
        d1 = (self.r1 - c) * (self.r1 + c)
        # within the limits the line cuts the circle: a non-positive value is round-off at a tangent
        g = b + self.branch * math.sqrt(d1) if d1 > 0.0 else b
        if not g > self.kappa:  # the contact is (within κ) the pivot
            self.reason = 2
            return None
        return g, ca, sa, ct, st, fx, fy

    def _t2(self, g, ca, sa, ct, st, fx, fy):
        px = self.gx + g * ca
        py = self.gy + g * sa
        zx = px - (fx + ct * self.v2[0] - st * self.v2[1])
        zy = py - (fy + st * self.v2[0] + ct * self.v2[1])
        zn = zx * self.nx + zy * self.ny
        d2 = zn * zn - (zx * zx + zy * zy) + self.r2sq
        if d2 < 0.0:
            self.reason = 3
            return None
        return -zn + self.side * math.sqrt(d2), px, py

    def rhs(self, a: float, th: float) -> tuple[float, float] | None:
        """(dα/dθ, dS5/dθ) at the pose, or None outside the working range."""
        d = self._pair_d(a, th)
        if d is None:
            return None
        if self.law is not None:   # pair E from the prescribed law: dS5/dθ = k53 = S5'(θ)
            return 1.0 - d[0] / self.ell, self.law.rate(th)
        e = self._t2(*d)
        if e is None:
            return None
        return 1.0 - d[0] / self.ell, -e[0]

    def contacts(self, a: float, s5: float, th: float) -> tuple[float, float, float, float] | None:
        """(P.x, P.y, Q.x, Q.y) in mm, or None outside the working range."""
        d = self._pair_d(a, th)
        if d is None:
            return None
        e = self._t2(*d) if self.law is None else (-self.law.rate(th), self.gx + d[0] * d[1], self.gy + d[0] * d[2])
        if e is None:
            return None
        t2, px, py = e
        return px, py, px + t2 * self.nx - s5 * self.dsx, py + t2 * self.ny - s5 * self.dsy
