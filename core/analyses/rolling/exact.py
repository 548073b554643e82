"""The exact rolling-lever synthesis: the ODE dα/dθ = 1 − g(α, θ)/ℓ with dS5/dθ = k53 = −t2.

Integrator: the classical fourth-order Runge–Kutta scheme with step doubling. Every step is taken
once whole and once as two halves; the difference of the contacts P and Q (mm) over 15 estimates
the local error of the halved result, which is kept. A step is accepted when that estimate is
below ``tol·|h|/|span|``, so the sum of local errors over the stroke stays below ``tol`` mm (the
stated tolerance); the sum is reported as ``error_mm``. The scalar loop runs on plain Python
floats (faster than numpy for one state). The mesh is chosen by the error control alone; values at
any θ (the N + 1 output samples, DXF fitting, projections) come from the dense output
(:meth:`ExactPath.at`): two vectorised half RK4 steps from the preceding mesh node, i.e. exactly
what the integrator would have computed for a step ending there, so no less accurate than the mesh.

The working range ends where the rocker line becomes tangent to the moved lever circle (the
discriminant of pair D reaches 0: the paper's π6 for the *moved* lever), where the contact reaches
the pin (only with the pin on the lever circle), where the contact would pass behind the rocker
pivot (pair D's ends are fixed rocker directions in the lever frame, found in closed form, see
:func:`~.geometry.pair_d_limits`), or where the normal to the slider axis leaves the slider
circle. :func:`working_range` finds both ends by marching with plain RK4 steps and halving the step
at the boundary (about 1e-8 rad); an end of pair D, where the fixed steps lose ~1e-7 rad in the
square-root singularity, is then placed by a quadrature over ψ to about 1e-9 rad. A stroke whose
integration stops before the end the march found is refused with the nearer of the two ends,
never with a range contradicting it.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ...errors import GeometryError
from .geometry import LeverGeometry, ScalarKernel, contact_distance, rot

#: a lever rotation beyond one turn is never searched for a working-range end (rad)
SEARCH_CAP = 2.0 * math.pi
#: marching step and final resolution of the working-range search (rad)
_LIMIT_STEP = 0.02
_LIMIT_RESOLUTION = 1e-12
#: after the first failed step, good steps in a row before the step is halved anyway
_LIMIT_PATIENCE = 8
#: a pair-D end is placed from the state this many steps before the first failed one
_LIMIT_BACK = 16
_END_X, _END_W = np.polynomial.legendre.leggauss(40)
#: budget of one adaptive integration (:func:`_march`): attempted steps (a stroke takes ~100 at
#: 1e-10 mm; each attempt costs 14 evaluations, ~40 µs) and wall-clock seconds
MAX_STEPS = 50_000
MAX_SECONDS = 20.0
#: roundings enter the error bound with this many standard deviations of their quadrature sum
ROUNDING_SIGMAS = 4.0


class _Budget(Exception):
    """Internal: :func:`_march` used up its step or time budget at θ = ``theta`` with steps of
    ``step`` rad (``what``: "steps" or "time")."""

    def __init__(self, theta: float, step: float, steps: int, seconds: float, what: str) -> None:
        super().__init__(theta)
        self.theta, self.step, self.steps, self.seconds, self.what = theta, step, steps, seconds, what


class _OutOfRange(Exception):
    """Internal: the march met the working-range boundary after ``theta`` (the last good state)."""

    def __init__(self, theta: float, alpha: float, s5: float, reason: int) -> None:
        super().__init__(theta)
        self.theta, self.alpha, self.s5, self.reason = theta, alpha, s5, reason


def _rk4(k: ScalarKernel, a: float, s: float, th: float, h: float):
    """One RK4 step of (α, S5) over θ → θ + h; None if a stage leaves the working range."""
    d = _rk4_increment(k, a, s, th, h)
    return None if d is None else (a + d[0], s + d[1])


def _two_sum(x: float, y: float) -> tuple[float, float]:
    """x + y as a rounded sum and its exact rounding error (Knuth)."""
    t = x + y
    z = t - x
    return t, (x - (t - z)) + (y - z)


def _rk4_increment(k: ScalarKernel, a: float, s: float, th: float, h: float):
    """The increments (Δα, ΔS5) of one RK4 step over θ → θ + h; None outside the working range."""
    r1 = k.rhs(a, th)
    if r1 is None:
        return None
    h2 = 0.5 * h
    r2 = k.rhs(a + h2 * r1[0], th + h2)
    if r2 is None:
        return None
    r3 = k.rhs(a + h2 * r2[0], th + h2)
    if r3 is None:
        return None
    r4 = k.rhs(a + h * r3[0], th + h)
    if r4 is None:
        return None
    h6 = h / 6.0
    return h6 * (r1[0] + 2.0 * r2[0] + 2.0 * r3[0] + r4[0]), h6 * (r1[1] + 2.0 * r2[1] + 2.0 * r3[1] + r4[1])


@dataclass
class _March:
    """Mesh recorded by :func:`_march` (lists of floats), its error sum and evaluation count."""

    theta: list
    alpha: list
    s5: list
    error: float = 0.0
    evaluations: int = 0
    #: running bounds of the global errors of α (rad) and S5 (mm) at each node (see :func:`_bound`):
    #: truncation (and carried-in) errors summed as they grow, ``ea``, ``es``; roundings of α, as
    #: independent errors, in quadrature, ``er`` (rms, rad)
    ea: list = field(default_factory=lambda: [0.0])
    es: list = field(default_factory=lambda: [0.0])
    er: list = field(default_factory=lambda: [0.0])
    #: growth Π max(|∂α_{k+1}/∂α_k|, 1) of α errors over the mesh
    growth: float = 1.0
    #: second pass: mm per rad of α error as the worst node sees it (0: first pass, no α control)
    weight: float = 0.0
    #: attempted steps allowed to this march (None: :data:`MAX_STEPS`)
    limit: int | None = None


def _march(k: ScalarKernel, m: _March, target: float, rate: float, h: float, hmin: float,
           accept_below: float = 0.0, hmax: float = 0.05) -> float:
    """Advance the mesh ``m`` from its last state to θ = ``target`` with step doubling.

    ``rate``: allowed local error per radian (mm/rad); steps shorter than ``accept_below`` are
    accepted whatever their error; no step is longer than ``hmax`` (rad). Returns the last step
    size. Raises :class:`_OutOfRange` when a step no longer than ``hmin`` still leaves the working
    range, :class:`_Budget` after :data:`MAX_STEPS` attempted steps or :data:`MAX_SECONDS`. A
    rest of the span that θ cannot resolve (below one ulp of θ, or than ``hmin``, where no step
    can be taken) is covered by taking the state as it is (it changes by less than rounding).
    """
    th, a, s = m.theta[-1], m.alpha[-1], m.s5[-1]
    a_lo = s_lo = 0.0   # compensated sums: α and S5 lose no bits to the many small increments
    # the right-hand side's arithmetic acts like a perturbation of the pose by a few roundings of
    # the coordinates it combines, relative to the rocker length (rad)
    ulps = 4.0 * np.finfo(float).eps * (1.0 + (math.hypot(k.gx, k.gy) + math.hypot(*k.v1)
                                                + math.hypot(*k.v2)) / max(k.ell, 1e-300))
    floor = 4.0 * np.finfo(float).eps * max(k.ell, 1.0)  # round-off level of one step (mm)
    direction = 1.0 if target > th else -1.0
    t0 = time.perf_counter()
    tries = 0
    while (target - th) * direction > 0.0:
        rest = abs(target - th)
        step = min(abs(h), hmax, rest)
        if th + direction * step == th:   # no step θ can resolve: a zero step, or one below its ulp
            if rest <= max(hmin, 4.0 * math.ulp(th)):
                m.theta.append(float(target))
                m.alpha.append(a)
                m.s5.append(s)
                m.ea.append(m.ea[-1])
                m.es.append(m.es[-1])
                m.er.append(m.er[-1])
                break
            step = max(step, 4.0 * math.ulp(th), hmin)
        tries += 1
        if tries > (MAX_STEPS if m.limit is None else min(m.limit, MAX_STEPS)):
            raise _Budget(th, step, tries - 1, time.perf_counter() - t0, "steps")
        if tries % 64 == 0 and time.perf_counter() - t0 > MAX_SECONDS:
            raise _Budget(th, step, tries, time.perf_counter() - t0, "time")
        last = step == abs(target - th)
        nxt = float(target) if last else th + direction * step
        hs = nxt - th   # the step the mesh records (exact: no drift of θ by its roundings)
        m.evaluations += 14
        k.reason = 0
        full = _rk4(k, a, s, th, hs)
        d1 = _rk4_increment(k, a, s, th, 0.5 * hs)
        d2 = _rk4_increment(k, a + d1[0], s + d1[1], th + 0.5 * hs, 0.5 * hs) if d1 is not None else None
        inc = (d1[0] + d2[0], d1[1] + d2[1]) if d2 is not None else None
        half = (a + inc[0], s + inc[1]) if inc is not None else None
        cf = k.contacts(full[0], full[1], th + hs) if full is not None else None
        ch = k.contacts(half[0], half[1], th + hs) if half is not None else None
        if cf is None or ch is None:
            if step <= hmin:
                raise _OutOfRange(th, a, s, k.reason)
            h = 0.25 * step
            continue
        err = max(math.hypot(cf[0] - ch[0], cf[1] - ch[1]), math.hypot(cf[2] - ch[2], cf[3] - ch[3])) / 15.0
        allowed = max(rate * step, floor)
        if m.weight:   # second pass: α's local error as the most sensitive node will see it
            rnd = 8.0 * m.weight * math.ulp(inc[0])
            seen = 2.0 * m.weight * abs(full[0] - half[0]) / 15.0
            if seen > max(rate * step, rnd) and err <= allowed:
                err, allowed = seen, max(rate * step, rnd)
        if err > allowed and step > max(hmin, accept_below):
            h = step * max(0.1, 0.9 * (allowed / err) ** 0.2)
            continue
        # the new state, summed with compensation
        a_new, c = _two_sum(a, inc[0] + a_lo)
        a_new, a_lo = _two_sum(a_new, c)
        s_new, c = _two_sum(s, inc[1] + s_lo)
        s_new, s_lo = _two_sum(s_new, c)
        # local errors of α (rad) and S5 (mm): Richardson, plus the rounding of the increment, of
        # the compensation and of the right-hand side (its arithmetic perturbs the pose by some
        # ulps, seen through ∂f/∂α, which grows like 1/√D1 at the tangent); an α error at the
        # step's start grows over it by 1 + h·∂f/∂α and feeds S5 by h·∂g/∂α
        fa, ga = _rate_slopes(k, a_new, th + hs, direction)
        m.evaluations += 4
        rnd = 2.0 * math.ulp(inc[0]) + math.ulp(a_lo) + abs(hs) * ulps * (1.0 + abs(fa))
        ea = abs(full[0] - half[0]) / 15.0
        es = abs(full[1] - half[1]) / 15.0 + 2.0 * math.ulp(inc[1]) + math.ulp(s_lo) + abs(hs) * ulps * abs(ga)
        grow = abs(1.0 + hs * fa)
        m.growth *= max(grow, 1.0)
        m.ea.append(grow * m.ea[-1] + ea)
        m.er.append(math.hypot(grow * m.er[-1], rnd))
        m.es.append(m.es[-1] + abs(hs * ga) * (m.ea[-2] + ROUNDING_SIGMAS * m.er[-2]) + es)
        a, s = a_new, s_new
        th = nxt
        m.error += err
        m.theta.append(th)
        m.alpha.append(a)
        m.s5.append(s)
        h = step * (4.0 if err == 0.0 else min(4.0, 0.9 * (allowed / err) ** 0.2))
    return h


def _rate_slopes(k: ScalarKernel, a: float, th: float, direction: float) -> tuple[float, float]:
    """(∂(dα/dθ)/∂α, ∂(dS5/dθ)/∂α) at (α, θ) by central differences, the step shrunk (down to
    one-sided, away from the range end ahead) where α ± ε leaves the working range."""
    eps = 1e-7 * max(1.0, abs(a))
    for _ in range(6):
        up, dn = k.rhs(a + eps, th), k.rhs(a - eps, th)
        if up is not None and dn is not None:
            return (up[0] - dn[0]) / (2.0 * eps), (up[1] - dn[1]) / (2.0 * eps)
        mid = k.rhs(a, th)
        one = up if up is not None else dn
        if one is not None and mid is not None:
            sg = eps if up is not None else -eps
            return (one[0] - mid[0]) / sg, (one[1] - mid[1]) / sg
        eps *= 0.01
    return 0.0, 0.0


def _contact_slopes(k: ScalarKernel, a: float, s: float, th: float) -> tuple[float, float]:
    """(|∂P/∂α|, |∂Q/∂α|) in mm/rad at a node, by differences as in :func:`_rate_slopes`."""
    eps = 1e-7 * max(1.0, abs(a))
    c0 = k.contacts(a, s, th)
    for _ in range(6):
        up, dn = k.contacts(a + eps, s, th), k.contacts(a - eps, s, th)
        if up is not None and dn is not None:
            d = [(x - y) / (2.0 * eps) for x, y in zip(up, dn)]
            return math.hypot(d[0], d[1]), math.hypot(d[2], d[3])
        one = up if up is not None else dn
        if one is not None and c0 is not None:
            sg = eps if up is not None else -eps
            d = [(x - y) / sg for x, y in zip(one, c0)]
            return math.hypot(d[0], d[1]), math.hypot(d[2], d[3])
        eps *= 0.01
    return math.inf, math.inf


def _bound(k: ScalarKernel, m: _March) -> tuple[float, float, float]:
    """(bound on the error of P and Q over the mesh (mm), the part of it due to rounding, the
    worst contact sensitivity |∂(P, Q)/∂α| (mm/rad)).

    P depends on the pose (α, θ) only and θ is exact, so P's error is |∂P/∂α|·δα; Q's is
    |∂Q/∂α|·δα + δS5. δα and δS5 are bounded node by node by the local (Richardson) errors, summed,
    and the roundings (of the update, of the compensation, of the right-hand side, whose effect
    grows like ∂f/∂α), in quadrature with :data:`ROUNDING_SIGMAS` standard deviations (the
    probabilistic bound of rounding analysis: linear sums of thousands of roundings overstate
    them ~√N-fold), each carried along by the growth of α errors over the following steps. Near
    an end of the working range |∂P/∂α| grows like 1/√(distance): α errors made early are seen
    there magnified, which the sum of the local contact errors missed (issue 13, item 11)."""
    worst, rounding, sens = 0.0, 0.0, 0.0
    for th, a, s, ea, es, er in zip(m.theta, m.alpha, m.s5, m.ea, m.es, m.er):
        sp, sq = _contact_slopes(k, a, s, th)
        sens = max(sens, sp, sq)
        da = ea + ROUNDING_SIGMAS * er
        here = max(sp * da, sq * da + es)
        if here > worst:
            worst, rounding = here, max(sp, sq) * ROUNDING_SIGMAS * er
    return worst, rounding, sens


@dataclass(frozen=True)
class WorkingRange:
    """Reachable lever rotations θ ∈ [lower, upper] (rad) from the drawn pose, and why each ends.

    A reason is None when no end was found within one turn (|θ| ≤ 2π).
    """

    lower: float
    upper: float
    lower_reason: str | None
    upper_reason: str | None

    def contains(self, theta: float) -> bool:
        return self.lower <= theta <= self.upper

    def describe(self) -> str:
        def end(th, why):
            return f"{th:.6f} rad ({why})" if why else f"{th:.6f} rad (searched no further)"
        return f"θ ∈ [{end(self.lower, self.lower_reason)}, {end(self.upper, self.upper_reason)}]"


def march_limit(geom: LeverGeometry, theta: float, alpha: float, s5: float, direction: float
                ) -> tuple[float, str | None]:
    """March from the state (θ, α, S5) in ``direction`` (±1) to the end of the working range.

    Plain RK4 steps of ``_LIMIT_STEP`` rad (α error ~1e-9 rad), halved each time a step would
    leave the range, down to ``_LIMIT_RESOLUTION``. Once a step has failed, the step is also halved
    after every ``_LIMIT_PATIENCE`` good steps in a row, so the search ends even where round-off
    makes the boundary ragged (near the rocker pivot the contact creeps on ever more slowly and
    α − θ changes by less than its last bit), yet may still pass a failure that was only an RK4
    stage overshooting a boundary just ahead. An end of pair D is then placed by
    :func:`_pair_d_end` (the fixed steps lose ~1e-7 rad in its square-root singularity). Returns
    (θ_end, reason); the reason is None if no end was met within |θ| ≤ 2π.
    """
    k = ScalarKernel(geom)
    a, s, th = alpha, s5, theta
    h = direction * _LIMIT_STEP
    cap = direction * SEARCH_CAP
    reason = None
    run = 0
    back = [(th, a)]  # states before the first failed step, the last few kept
    while abs(h) > _LIMIT_RESOLUTION:
        if (th + h - cap) * direction > 0.0:
            if abs(cap - th) <= _LIMIT_RESOLUTION:
                return cap, None
            h = cap - th
        k.reason = 0
        y = _rk4(k, a, s, th, h)
        if y is None or k.rhs(y[0], th + h) is None:
            reason = k.reason
            h *= 0.5
            run = 0
            continue
        a, s = y
        th += h
        if reason is None:
            back = (back + [(th, a)])[-_LIMIT_BACK:]
        else:
            run += 1
            if run == _LIMIT_PATIENCE:
                h *= 0.5
                run = 0
    if reason in (1, 4):  # the rocker direction ψ reached its limit ahead (ψ falls as θ grows)
        th = _pair_d_end(geom, k, back[0], th, direction)
    return th, ScalarKernel.REASONS.get(reason)


def _pair_d_end(geom: LeverGeometry, k: ScalarKernel, back: tuple[float, float], found: float,
                direction: float) -> float:
    """θ at the pair-D end, from a state (θ_b, α_b) a few steps before it: pair D depends on
    ψ = α − θ alone and dθ/dψ = −ℓ/g(ψ), so θ_end = θ_b + ℓ ∫ dψ/g from ψ_end to ψ_b,
    with ψ = ψ_end + (ψ_b − ψ_end)t² to take out the square root at the tangent (Gauss–Legendre).
    Returns ``found`` (the march's end) unless the two agree to 1e-5 rad."""
    th_b, a_b = back
    psi_end = k.psi_lo if direction > 0.0 else k.psi_hi
    delta = (a_b - th_b) - psi_end
    t = 0.5 * (_END_X + 1.0)
    psi = psi_end + delta * t * t
    ex, ey = np.cos(psi), np.sin(psi)
    wx = geom.c1[0] - geom.f[0] + geom.ell * ex  # c1 − G in the lever frame, G = f − ℓ e(ψ)
    wy = geom.c1[1] - geom.f[1] + geom.ell * ey
    b = wx * ex + wy * ey
    c = wx * ey - wy * ex
    d1 = np.maximum((geom.R1 - c) * (geom.R1 + c), 0.0)
    g = b + geom.branch * np.sqrt(d1)
    end = th_b + geom.ell * float(np.sum(0.5 * _END_W * 2.0 * delta * t / g))
    return end if abs(end - found) <= 1e-5 else found


def working_range(geom: LeverGeometry) -> WorkingRange:
    """Both ends of the working range from the drawn pose (θ = 0), see :class:`WorkingRange`."""
    k = ScalarKernel(geom)
    if k.rhs(geom.alpha0, 0.0) is None:
        raise GeometryError(f"the drawn pose is outside the working range: {ScalarKernel.REASONS[k.reason]}")
    lo, lo_why = march_limit(geom, 0.0, geom.alpha0, 0.0, -1.0)
    hi, hi_why = march_limit(geom, 0.0, geom.alpha0, 0.0, 1.0)
    return WorkingRange(lo, hi, lo_why, hi_why)


def rates(geom: LeverGeometry, alpha: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(dα/dθ, dS5/dθ) of the exact ODE at poses (α, θ), (M,) each; NaN outside the working range."""
    ca, sa = np.cos(alpha), np.sin(alpha)
    F = np.stack([geom.G[0] + geom.ell * ca, geom.G[1] + geom.ell * sa], axis=-1)
    f = np.asarray(geom.f)
    w = F + rot(theta, np.asarray(geom.c1) - f) - np.asarray(geom.G)
    b = w[:, 0] * ca + w[:, 1] * sa
    c = w[:, 0] * sa - w[:, 1] * ca
    d1 = (geom.R1 - c) * (geom.R1 + c)   # = b² − (|w|² − R1²), without the cancellation
    g = contact_distance(geom, alpha, theta, b, d1)
    if geom.law is not None:   # pair E from the prescribed law: dS5/dθ = S5'(θ)
        return 1.0 - g / geom.ell, geom.law.rates(theta) + 0.0 * g
    z = np.asarray(geom.G) + g[:, None] * np.stack([ca, sa], axis=-1) - (F + rot(theta, np.asarray(geom.c2) - f))
    n = np.asarray(geom.n)
    zn = z @ n
    d2 = zn * zn - (z[:, 0] ** 2 + z[:, 1] ** 2) + geom.R2 ** 2
    with np.errstate(invalid="ignore"):
        t2 = -zn + geom.side * np.sqrt(np.where(d2 >= 0.0, d2, np.nan))
    return 1.0 - g / geom.ell, -t2


@dataclass
class ExactPath:
    """The integrated exact motion: the adaptive mesh (θ, α, S5) in integration order (rad, rad, mm).

    ``error_mm`` bounds the error of P and Q over the mesh (mm; see :func:`integrate`);
    ``evaluations`` counts right-hand-side calls of the integration.
    """

    geom: LeverGeometry
    theta: np.ndarray
    alpha: np.ndarray
    S5: np.ndarray
    error_mm: float
    evaluations: int
    #: bounds on the errors of α (rad) and S5 (mm) at the last node (see :func:`integrate`)
    alpha_error: float = 0.0
    s5_error: float = 0.0

    def base_index(self, theta_q: np.ndarray) -> np.ndarray:
        """Index of the mesh node each θ (M,) is stepped from (the preceding node, clipped)."""
        q = np.atleast_1d(np.asarray(theta_q, dtype=float))
        th = self.theta
        direction = 1.0 if th[-1] >= th[0] else -1.0
        return np.clip(np.searchsorted(th * direction, q * direction, side="right") - 1, 0, len(th) - 2)

    def at(self, theta_q: np.ndarray, base: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Dense output: (α, S5) at any θ (M,) rad in the integrated span, two half RK4 steps each.

        ``base`` forces the mesh node each value is stepped from (smooth finite differences).
        """
        q = np.atleast_1d(np.asarray(theta_q, dtype=float))
        j = self.base_index(q) if base is None else np.asarray(base)
        a, s, t = self.alpha[j], self.S5[j], self.theta[j]
        h = 0.5 * (q - t)
        geom = self.geom
        for _ in range(2):
            k1 = rates(geom, a, t)
            k2 = rates(geom, a + 0.5 * h * k1[0], t + 0.5 * h)
            k3 = rates(geom, a + 0.5 * h * k2[0], t + 0.5 * h)
            k4 = rates(geom, a + h * k3[0], t + h)
            a = a + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
            s = s + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
            t = t + h
        return a, s

    @property
    def span(self) -> tuple[float, float]:
        return float(self.theta[0]), float(self.theta[-1])


def integrate(geom: LeverGeometry, end: float, tol: float, start: tuple[float, float, float] | None = None,
              max_step: float = 0.05, carried: tuple[float, float] = (0.0, 0.0)) -> ExactPath:
    """Integrate the exact ODE from ``start`` = (θ, α, S5) (default the drawn pose (0, α0, 0)) to θ = ``end``.

    ``tol``: bound on the error of P and Q over the span (mm); ``max_step`` (rad); ``carried``:
    bounds on the errors of the start's α (rad) and S5 (mm) (from a lead-in). The mesh is chosen
    by the local contact errors; when the resulting bound (:func:`_bound`) exceeds ``tol`` — the
    α errors seen magnified near a working-range end — the span is integrated once more with α's
    local errors weighted by the worst sensitivity. The bound is ``error_mm``; it exceeds ``tol``
    only where rounding (or the budget) does not allow better.
    Raises :class:`_OutOfRange` (internal) when the span leaves the working range, and
    :class:`GeometryError` naming the inputs to change when the step or time budget runs out.
    """
    k = ScalarKernel(geom)
    th, a, s = start if start is not None else (0.0, geom.alpha0, 0.0)
    span = abs(end - th)
    if span == 0.0:
        raise GeometryError("empty integration span")
    if k.rhs(a, th) is None:
        raise _OutOfRange(th, a, s, k.reason)
    h0 = min(max_step, 0.01 * span) or span   # (0.01·span underflows for a subnormal span)
    # first pass: steps by the local contact error; a second, tighter one only when the bound over
    # the span misses the tolerance by what smaller steps can remove (not the rounding part)
    best = None
    evaluations = 0
    rate = tol / span
    weight, limit = 0.0, None
    for attempt in range(2):
        m = _March([th], [a], [s], ea=[carried[0]], es=[carried[1]], weight=weight, limit=limit)
        try:
            _march(k, m, end, rate, h0, 1e-13 * max(1.0, span), hmax=max_step)
        except _Budget as b:
            if best is not None:   # the tighter pass is out of budget: keep the first, bound stated
                break
            rng = working_range(geom)   # steps that collapse near a range end the stroke passes
            if not rng.contains(end):
                limit, why = (rng.lower, rng.lower_reason) if end < rng.lower else (rng.upper, rng.upper_reason)
                raise GeometryError(f"θ = {end:g} rad is beyond the working range: after θ ≈ {limit:.6f} rad {why}. "
                                    f"Reachable range from the drawn pose: {rng.describe()}; change the "
                                    f"stroke (`stroke.from`, `stroke.to`)") from None
            raise GeometryError(_budget_message(geom, th, end, tol, b)) from None
        evaluations += m.evaluations
        bound, rounding, sens = _bound(k, m)
        if best is None or bound < best[1]:
            best = (m, bound)
        trunc = bound - rounding   # what smaller steps remove (rounding is counted in full: a bound)
        if bound <= tol or trunc <= 0.25 * tol or attempt or not math.isfinite(sens):
            break
        # again, α's local errors weighted by the worst sensitivity and growth, within the step
        # budget (else the first pass stands, with its bound)
        weight, limit = sens * m.growth, None
    m, bound = best
    return ExactPath(geom, np.array(m.theta), np.array(m.alpha), np.array(m.s5), bound, evaluations,
                     m.ea[-1] + ROUNDING_SIGMAS * m.er[-1], m.es[-1])


def _budget_message(geom: LeverGeometry, start: float, end: float, tol: float, b: _Budget) -> str:
    """Why an integration ran out of budget, and which input to change."""
    size = max(geom.scale, *(math.hypot(*p) for p in (geom.G, geom.f, geom.c1, geom.c2)))
    noise = np.finfo(float).eps * size
    spent = (f"{b.steps:,} steps" if b.what == "steps" else f"{b.seconds:.1f} s of computing") + \
        f" (limit {MAX_STEPS:,} steps, {MAX_SECONDS:g} s)"
    head = (f"the exact integration of θ from {start:g} to {end:g} rad did not finish: after {spent} "
            f"it had reached θ = {b.theta:.6g} rad with steps of {b.step:.1e} rad. ")
    if tol < noise:
        return head + (f"The tolerance {tol:g} mm is below what the arithmetic resolves at this lever's "
                       f"size ({size:.3g} mm, where one rounding is {noise:.1e} mm): raise `tolerance` to "
                       f"at least {100 * noise:.1g} mm, or draw the lever smaller and nearer the origin "
                       f"(`pin`, `rocker_pivot`, `lever_circle`, `slider_circle`)")
    return head + (f"The motion is nearly singular there (an end of the working range, or a contact "
                   f"that all but stops): end the stroke (`stroke.from`, `stroke.to`) before θ = "
                   f"{b.theta:.6g} rad, or raise `tolerance` (now {tol:g} mm)")


def _beyond_message(geom: LeverGeometry, start: float, end: float, stop: _OutOfRange, direction: float) -> str:
    """The refusal of a stroke whose integration (in ``direction``) stopped at ``stop``.

    The reachable range comes from :func:`working_range`; on the side the integration ran, its end
    is the nearer of the two findings (the integration's stop is a pose proven to fail), so the
    message never names a range that contradicts the limit it reports.
    """
    rng = working_range(geom)
    why = ScalarKernel.REASONS.get(stop.reason, "the pose cannot be built")
    if stop.theta * direction >= 0.0:
        if direction < 0.0 and stop.theta > rng.lower:
            rng = WorkingRange(stop.theta, rng.upper, why, rng.upper_reason)
        elif direction > 0.0 and stop.theta < rng.upper:
            rng = WorkingRange(rng.lower, stop.theta, rng.lower_reason, why)
        limit, why = (rng.lower, rng.lower_reason) if direction < 0.0 else (rng.upper, rng.upper_reason)
    else:  # (cannot happen: the part of the stroke up to the drawn pose was integrated already)
        limit = stop.theta
    return (f"the stroke θ from {start:g} to {end:g} rad goes beyond the working range: after θ ≈ "
            f"{limit:.6f} rad {why}. Reachable range from the drawn pose: {rng.describe()}")


def exact_path(geom: LeverGeometry, start: float, end: float, tol: float) -> ExactPath:
    """The exact motion over the stroke θ ∈ start → end (rad), integrated to ``tol`` mm.

    When the stroke does not start at the drawn pose, θ = 0 → ``start`` is integrated first (to the
    same tolerance) and only its end state kept, with the bounds of its errors, which the stroke
    carries on (when they make the stroke's bound exceed twice the tolerance — magnified near a
    range end — the lead-in is integrated again, tighter); ``error_mm`` bounds the errors over both. Raises :class:`GeometryError` with the reachable
    range when the stroke leaves the working range.
    """
    direction = 1.0 if start > 0.0 else -1.0  # of the integration under way
    try:
        origin = None
        lead = None
        carried = (0.0, 0.0)
        if start != 0.0:
            lead = integrate(geom, start, tol)
            origin = (start, float(lead.alpha[-1]), float(lead.S5[-1]))
            carried = (lead.alpha_error, lead.s5_error)
        direction = 1.0 if end > start else -1.0
        path = integrate(geom, end, tol, start=origin, carried=carried)
        if lead is not None and path.error_mm > 2.0 * tol:
            # the lead-in's errors, magnified over the stroke (near a range end), are what miss:
            # integrate the lead-in again, to the tolerance the stroke needs of it
            without = integrate(geom, end, tol, start=origin)
            if path.error_mm > 2.0 * without.error_mm:
                spent = lead.evaluations + path.evaluations + without.evaluations
                lead = integrate(geom, start, tol * max(without.error_mm, 0.1 * tol) / path.error_mm)
                origin = (start, float(lead.alpha[-1]), float(lead.S5[-1]))
                path = integrate(geom, end, tol, start=origin, carried=(lead.alpha_error, lead.s5_error))
                path.evaluations += spent
        if lead is not None:   # the bound covers all that was integrated, the lead-in too
            path.evaluations += lead.evaluations
            path.error_mm = max(path.error_mm, lead.error_mm)
    except _OutOfRange as stop:
        raise GeometryError(_beyond_message(geom, start, end, stop, direction)) from None
    return path
