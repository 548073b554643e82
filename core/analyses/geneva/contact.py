"""Roller/slot contact and wear of a Geneva drive after Stetsiv (second paper), with corrections B1–B9.

Everything is computed over the engagement as a function of the *progress angle* u = sign(ω1)·φ,
which runs from −φ0 (entry) to +φ0 (exit) in either direction of rotation; by mirror symmetry
all formulas below hold for u. Quantities (seeds/NOTES.md, section B):

- moment M = J2·ε̃(u)·ω1² + M_ext (N·m), positive while the roller drives the wheel;
- normal force, derived (B3): R_n = |M| / (ρ − sgn(M)·f02·r02), ρ = A√D, the friction helping the
  roller only while it brakes; the paper's eq. (3): R_n = λ|M| / (r√D + f02·r02);
- the paper's strip width a = 2.16·√(R_n·D_r/(l·E')) (eq. 2; it is the full width, B2), with
  E' = 2E1E2/(E1 + E2) for two materials; the Hertz half-width b = √(4 R_n r_p/(π l E*)),
  1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 (roller on a flat wall);
- roller deformation Δ (eq. 6 as printed, roller's E and ν, a = the paper's full width; Δ = 0 at
  R_n = 0, the limit);
- rolling ratio ω_pi = (r/r_p)·sin u/√D (the robust form of eq. 5, B5), signed: negative while
  the roller centre moves towards the wheel centre;
- slip speed v_s = |ω1|·ρ_eff·|ω_pi|·sin²ψ with sin ψ = b/r_p (B7; slip zones reaching the strip
  edges, an upper bound), its invariant v_s/(|ω1| r_p), and the cumulative slip path
  L_s(u) = ∫_{−φ0}^{u} ρ_eff |ω_pi| sin²ψ du' (the spurious ω1 of eq. 7 removed); the paper's
  symmetric form ∫_{−φ}^{0} + ∫_{0}^{φ} is L_s(φ) − L_s(−φ);
- the paper's wear invariant T_i = π R_n z/(30 |ω1| L_s,total) in N·min/m (eq. 8, B8);
- peak Hertz pressure p_max = 2R_n/(π b l) and mean pressure p̄ = R_n/(2 b l) (MPa, Hertz b);
- an Archard life (B1): wear depth per engagement h = k ∫ p̄ dL_s on each slot flank (the driving
  flank while M > 0, the braking flank while M < 0), slot life z·[h]/h_worst crank revolutions,
  roller life [h]/(h_drive + h_brake) revolutions (all the roller's wear on one spot: a bound).

Validity range (issue 20, item 3). The line-contact model holds while the contact is small
against the bodies: the roller's deformation Δ ≤ :data:`DEFORMATION_LIMIT`·r_p and the contact
half-width b ≤ :data:`HALF_WIDTH_LIMIT`·r_p and ≤ :data:`HALF_WIDTH_LIMIT`·l (b the larger of the
two estimates a_paper/2 and the Hertz b, whatever the slip model uses). Every quantity grows with
R_n, so the range is R_n ≤ R_n,lim (:func:`normal_force_limit`). A row with a larger R_n is
flagged (``contact_valid`` False) and its strip, half-width, deformation, slip speed and pressure
are NaN; the running slip path is NaN from where the engagement first leaves the range (checked at
the quadrature nodes between samples too); the per-engagement totals, the wear invariant and the
Archard life are NaN unless the whole engagement is inside (the peak of R_n over the continuous
engagement, :func:`peak_normal_force`, at most R_n,lim). R_n, M and ω_pi are rigid-body results and
stay. So no length, path or wear is ever negative (outside the range the printed Δ exceeds r_p and
the ln of eq. 6 turns negative).

The integrals are taken with breaks at u = 0 (kink of |ω_pi|) and where M changes sign (kink of
|M|): Gauss–Legendre on each interval between consecutive samples and break points gives the
cumulative column (as accurate as the total: its last value is the total to rounding), and
Gauss–Legendre on each smooth piece gives the per-engagement total (used in T_i) and the wear
depths; the trapezoid rule on the same points is reported beside them for comparison. Vectorised
over samples; no loop over samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Protocol

import numpy as np

from ...errors import GeometryError
from .kinematics import EDGE_TOL

if TYPE_CHECKING:
    from ...model.geneva import ContactModel, Geneva

#: Gauss–Legendre nodes per smooth piece of the engagement
GAUSS_NODES = 48
#: Gauss–Legendre nodes per interval between samples of the running slip path (each interval is
#: at most one piece's width; the integrand is smooth on it)
INTERVAL_NODES = 8
#: grid used to bracket the sign changes of M before bisection
ROOT_GRID = 513
#: the constant of the paper's strip width (eq. 2)
PAPER_STRIP = 2.16
#: validity range: the roller's deformation Δ at most this fraction of its radius r_p
DEFORMATION_LIMIT = 0.05
#: validity range: the contact half-width b at most this fraction of r_p and of the roller length l
HALF_WIDTH_LIMIT = 0.1


@lru_cache(maxsize=8)
def _gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [−1, 1], each shape (n,), n ≥ 1: the eigenvalues of the
    Jacobi matrix (Golub–Welsch), one Newton step on P_n, weights 2/((1 − x²)·P_n'(x)²), made
    symmetric and scaled to sum to 2 (as numpy's ``leggauss``, without importing numpy.polynomial,
    which costs a cold process ~2 ms)."""
    k = np.arange(1.0, n)
    x = np.linalg.eigvalsh(np.diag(k / np.sqrt(4.0 * k * k - 1.0), 1), UPLO="U")
    p, dp = _legendre(n, x)
    x = x - p / dp
    _, dp = _legendre(n, x)
    w = 2.0 / ((1.0 - x * x) * dp * dp)
    w, x = (w + w[::-1]) / 2, (x - x[::-1]) / 2
    return x, w * (2.0 / w.sum())


def _legendre(n: int, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """P_n(x) and P_n'(x) by the three-term recurrence (|x| < 1), shape of ``x``."""
    p0, p1 = np.ones_like(x), x
    for m in range(1, n):
        p0, p1 = p1, ((2 * m + 1) * x * p1 - m * p0) / (m + 1)
    return p1, n * (x * p1 - p0) / (x * x - 1.0)


class CrankMotion(Protocol):
    """A crank that does not turn at constant speed (a Geneva driven through gears): its speed
    u̇ (rad/s, ≥ 0 in the progress sense) and acceleration ü (rad/s²) at progress angles u."""

    def rates(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...


class ContactConstants:
    """The element's constants in the units the formulas use (lengths mm except ``fr`` = f02·r02
    in m; moduli MPa; ``j2w2`` = J2·ω1² in N·m; ``w1`` = |ω1| rad/s, the crank's (mean) speed) and
    the model choices; ``crank`` a :class:`CrankMotion` when the crank's speed varies (then the
    moment is J2·(ε̃(u)·u̇² + i(u)·ü) + M_ext and the slip speed is taken at u̇), else None."""

    def __init__(self, el: "Geneva", model: "ContactModel", crank: CrankMotion | None = None) -> None:
        self.crank = crank
        self.z = el.slots
        self.lam = el.lam
        self.phi0 = el.phi0
        self.a = el.center_distance
        self.r = el.crank_radius
        self.rp = el.roller_radius
        self.length = el.roller_length
        self.w1 = abs(el.omega1)
        self.j2w2 = el.load.wheel_inertia * el.omega1 ** 2
        self.m_ext = el.load.external_moment
        self.fr = el.load.journal_friction * el.load.journal_radius * 1e-3  # m
        e1, n1 = el.roller_material.E, el.roller_material.poisson
        e2, n2 = el.wheel_material.E, el.wheel_material.poisson
        for what, e in (("roller", e1), ("wheel", e2)):
            if not (math.isfinite(e) and e > 0.0):
                raise GeometryError(f"{el.id}: the {what} material's Young's modulus E = {e!r} MPa must be a "
                                    "positive finite number")
        # compliances, not products: moduli near the float limit neither overflow nor give inf/inf
        self.e_star = 1.0 / ((1 - n1 * n1) / e1 + (1 - n2 * n2) / e2)  # MPa
        self.e_pair = 2.0 / (1.0 / e1 + 1.0 / e2)  # MPa, the handbook's reduced modulus 2E1E2/(E1 + E2)
        self.defo = 4.0 * (1 - n1 * n1) / e1 / self.length  # mm/N, times (0.41 + ln)
        self.model = model


def _wheel_moment(u: np.ndarray, c: ContactConstants, su: np.ndarray, cu: np.ndarray, d: np.ndarray) -> np.ndarray:
    """J2·ε2 (N·m, indexing sense): J2·ε̃·ω1², or with a varying crank J2·(ε̃·u̇² + i·ü)."""
    eps = -c.lam * (1.0 - c.lam * c.lam) * su / (d * d)
    if c.crank is None:
        return c.j2w2 * eps
    ud, udd = c.crank.rates(u)
    j2 = c.j2w2 / (c.w1 * c.w1) if c.w1 else 0.0
    return j2 * (eps * ud * ud + c.lam * (cu - c.lam) / d * udd)


def moment(u: np.ndarray, c: ContactConstants) -> np.ndarray:
    """M(u) = J2·ε2(u) + M_ext (N·m), indexing sense (ε2 = ε̃(u)·ω1² for a constant-speed crank);
    shape of ``u``."""
    u = np.asarray(u, dtype=float)
    cu = np.cos(u)
    d = 1.0 - 2.0 * c.lam * cu + c.lam * c.lam
    return _wheel_moment(u, c, np.sin(u), cu, d) + c.m_ext


def _normal_force(u: np.ndarray, c: ContactConstants) -> tuple[np.ndarray, ...]:
    """(M, R_n of the model in force, R_n paper, R_n derived, sin u, √D) at progress angles ``u``."""
    cu, su = np.cos(u), np.sin(u)
    d = 1.0 - 2.0 * c.lam * cu + c.lam * c.lam
    sd = np.sqrt(d)
    m = _wheel_moment(u, c, su, cu, d) + c.m_ext
    am = np.abs(m)
    rho_m = c.a * sd * 1e-3
    rn_paper = c.lam * am / (c.r * 1e-3 * sd + c.fr)
    rn_derived = am / (rho_m - np.sign(m) * c.fr)
    rn = rn_paper if c.model.normal_force == "paper" else rn_derived
    return m, rn, rn_paper, rn_derived, su, sd


def _strip_coefficients(c: ContactConstants) -> tuple[float, float]:
    """(κ_a, κ_b): the paper's strip width a = κ_a·√R_n and the physical half-width, the larger of
    a/2 and the Hertz b, = κ_b·√R_n (mm/√N)."""
    k_a = PAPER_STRIP * math.sqrt(2.0 * c.rp / (c.length * c.e_pair))
    k_h = math.sqrt(4.0 * c.rp / (math.pi * c.length * c.e_star))
    return k_a, max(0.5 * k_a, k_h)


def _deformation(rn: float, c: ContactConstants, k_a: float) -> float:
    """Δ(R_n) of eq. 6 (mm) for a scalar R_n ≥ 0 (0 at R_n = 0, the limit)."""
    return c.defo * rn * (0.41 + math.log(4.0 * c.rp / (k_a * math.sqrt(rn)))) if rn > 0 else 0.0


def normal_force_limit(c: ContactConstants) -> float:
    """R_n,lim (N): the largest normal force inside the validity range (module docstring).

    The half-width limits give R_b = (HALF_WIDTH_LIMIT·min(r_p, l)/κ_b)² in closed form; Δ grows
    with R_n there (dΔ/dR_n > 0 while a < 3.6·r_p), so where Δ(R_b) exceeds its limit the root of
    Δ(R_n) = DEFORMATION_LIMIT·r_p is bisected in (0, R_b] to the last bit.
    """
    k_a, k_b = _strip_coefficients(c)
    r_b = (HALF_WIDTH_LIMIT * min(c.rp, c.length) / k_b) ** 2
    target = DEFORMATION_LIMIT * c.rp
    if _deformation(r_b, c, k_a) <= target:
        return r_b
    lo, hi = 0.0, r_b
    for _ in range(2000):
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            break
        lo, hi = (mid, hi) if _deformation(mid, c, k_a) <= target else (lo, mid)
    return lo


def peak_normal_force(c: ContactConstants) -> tuple[float, float]:
    """(max R_n over the continuous engagement in N, its progress angle in rad): the largest of a
    grid of :data:`ROOT_GRID` points, refined twice on a grid of the same size spanning the best
    point's neighbours (a smooth maximum is then found to ~1e-15 relative; an end point is one)."""
    lo, hi = -c.phi0, c.phi0
    best_u, best = lo, -1.0
    for _ in range(3):
        grid = np.linspace(lo, hi, ROOT_GRID)
        rn = _normal_force(grid, c)[1]
        k = int(np.argmax(rn))
        if rn[k] > best:
            best_u, best = float(grid[k]), float(rn[k])
        step = grid[1] - grid[0]
        lo, hi = max(-c.phi0, best_u - step), min(c.phi0, best_u + step)
    return best, best_u


def _fields(u: np.ndarray, c: ContactConstants) -> dict[str, np.ndarray]:
    """All contact quantities at progress angles ``u`` (rad, engaged), each of the shape of ``u``."""
    m, rn, rn_paper, rn_derived, su, sd = _normal_force(u, c)
    strip = PAPER_STRIP * np.sqrt(rn * 2.0 * c.rp / (c.length * c.e_pair))
    hertz_b = np.sqrt(4.0 * rn * c.rp / (math.pi * c.length * c.e_star))
    loaded = rn > 0
    safe_strip = np.where(loaded, strip, 1.0)
    delta = np.where(loaded, c.defo * rn * (0.41 + np.log(4.0 * c.rp / safe_strip)), 0.0)
    hw = c.model.half_width
    b = strip / 2.0 if hw == "paper_half" else hertz_b if hw == "hertz" else strip
    rho_eff = c.rp - delta if c.model.slip_radius == "deformed" else np.full_like(u, c.rp)
    w_pi = (c.r / c.rp) * su / sd
    g = rho_eff * np.abs(w_pi) * (b / c.rp) ** 2  # mm of slip per rad of crank
    safe_b = np.where(loaded, hertz_b, 1.0)
    p_max = np.where(loaded, 2.0 * rn / (math.pi * safe_b * c.length), 0.0)
    p_mean = np.where(loaded, rn / (2.0 * safe_b * c.length), 0.0)
    return {"moment": m, "Rn": rn, "Rn_paper": rn_paper, "Rn_derived": rn_derived,
            "strip_width": strip, "hertz_half_width": hertz_b, "half_width": b, "deformation": delta,
            "rolling_ratio": w_pi, "g": g, "contact_pressure": p_max, "mean_pressure": p_mean}


def moment_sign_changes(c: ContactConstants) -> np.ndarray:
    """Progress angles (rad) inside (−φ0, φ0) where M changes sign, sorted; bracketed on a grid of
    :data:`ROOT_GRID` points, then bisected to machine precision (vectorised over roots)."""
    grid = np.linspace(-c.phi0, c.phi0, ROOT_GRID)
    mg = moment(grid, c)
    idx = np.nonzero(np.sign(mg[:-1]) * np.sign(mg[1:]) < 0)[0]
    if idx.size == 0:
        return np.empty(0)
    lo, hi = grid[idx].copy(), grid[idx + 1].copy()
    mlo = mg[idx]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        mm = moment(mid, c)
        left = np.sign(mm) == np.sign(mlo)
        lo = np.where(left, mid, lo)
        mlo = np.where(left, mm, mlo)
        hi = np.where(left, hi, mid)
    return 0.5 * (lo + hi)


def breakpoints(c: ContactConstants) -> np.ndarray:
    """Sorted u of the engagement ends, u = 0 and the sign changes of M (rad)."""
    u = np.sort(np.concatenate([[-c.phi0, 0.0, c.phi0], moment_sign_changes(c)]))
    return u[np.r_[True, u[1:] != u[:-1]]]  # np.unique without importing numpy.ma (~6 ms cold)


@dataclass(frozen=True)
class ArchardLife:
    """Archard wear per engagement and life (B1: a dimensionally consistent replacement of eq. 1).

    ``depth_drive`` / ``depth_brake``: wear depth per engagement on the slot flank loaded while the
    roller drives (M > 0) / brakes (M < 0), mm; ``slot_cycles``: crank revolutions until the worse
    flank reaches [h] (each slot is engaged once every z revolutions); ``roller_cycles``: crank
    revolutions until the roller reaches [h] if all its wear fell on one spot (a bound);
    ``cycles`` / ``hours``: the smaller of the two, and in hours at the crank speed; ``limiting``:
    ``"slot"`` or ``"roller"``. Infinite when there is no load.
    """

    depth_drive: float
    depth_brake: float
    slot_cycles: float
    roller_cycles: float
    cycles: float
    hours: float
    limiting: str


@dataclass(frozen=True)
class ContactValidity:
    """Where the contact model holds (module docstring, "Validity range").

    ``deformation_limit`` (Δ/r_p) and ``half_width_limit`` (b/r_p and b/l) are the limits;
    ``rn_limit`` (N) the largest normal force inside them; ``rn_peak`` (N) the largest R_n over the
    continuous engagement; ``ok``: the whole engagement is inside (the totals, the wear invariant
    and the life are computed); ``invalid_rows`` of ``engaged_rows`` are flagged; the largest
    ratios the model reaches at the engaged rows, ``max_deformation_ratio`` Δ/r_p (eq. 6 as printed,
    even where it no longer means anything), ``max_half_width_radius_ratio`` b/r_p and
    ``max_half_width_length_ratio`` b/l; ``invalid_runs`` the (first, last) crank angle φ (rad) of
    each run of flagged rows in time order.
    """

    deformation_limit: float
    half_width_limit: float
    rn_limit: float
    rn_peak: float
    ok: bool
    invalid_rows: int
    engaged_rows: int
    max_deformation_ratio: float
    max_half_width_radius_ratio: float
    max_half_width_length_ratio: float
    invalid_runs: tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class GenevaContact:
    """Contact and wear over one crank revolution of N samples (same rows as the kinematics).

    Arrays, shape (N,), NaN outside the engagement (``engaged`` False): ``moment`` M (N·m, positive
    while the roller drives the wheel); ``Rn`` normal force of the model in force (N) and both
    forms ``Rn_paper``, ``Rn_derived`` (N); ``strip_width`` the paper's a (mm, full width);
    ``hertz_half_width`` b (mm); ``half_width`` the b entering the slip model (mm);
    ``deformation`` Δ (mm); ``rolling_ratio`` ω_pi (signed, -); ``slip_speed`` v_s (mm/s);
    ``slip_speed_invariant`` v_s/(|ω1| r_p) (-); ``slip_path`` cumulative L_s from entry (mm);
    ``wear_invariant`` T_i (N·min/m); ``contact_pressure`` p_max (MPa); ``mean_pressure`` p̄ (MPa).
    ``phi`` crank angle (rad), ``u`` progress angle (rad), ``engaged`` (bool), ``contact_valid``
    (bool: engaged and inside the validity range; where False the strip, half-widths,
    deformation, slip speed and pressures are NaN, and the slip path from the first such row on).

    Scalars: ``slip_path_total`` L_s per engagement by Gauss–Legendre on each smooth piece (mm,
    independent of N; it enters T_i; the last value of the ``slip_path`` column, which is
    Gauss–Legendre on every interval between samples and breaks) and ``slip_path_total_trapezoid``
    by the trapezoid rule on the samples with breaks (mm, for comparison);
    ``breaks`` the break points (u, rad); ``Rn_max`` (N) at ``phi_Rn_max`` (rad);
    ``pressure_max`` (MPa) at ``phi_pressure_max``; ``wear_invariant_max`` (N·min/m);
    ``life`` (:class:`ArchardLife`); ``validity`` (:class:`ContactValidity`); ``model`` the choices
    used; ``assumptions`` stated in words. When ``validity.ok`` is False the totals, the wear
    invariant, the life and ``pressure_max`` are NaN (the peak lies outside the range).
    """

    phi: np.ndarray
    u: np.ndarray
    engaged: np.ndarray
    contact_valid: np.ndarray
    moment: np.ndarray
    Rn: np.ndarray
    Rn_paper: np.ndarray
    Rn_derived: np.ndarray
    strip_width: np.ndarray
    hertz_half_width: np.ndarray
    half_width: np.ndarray
    deformation: np.ndarray
    rolling_ratio: np.ndarray
    slip_speed: np.ndarray
    slip_speed_invariant: np.ndarray
    slip_path: np.ndarray
    wear_invariant: np.ndarray
    contact_pressure: np.ndarray
    mean_pressure: np.ndarray
    slip_path_total: float
    slip_path_total_trapezoid: float
    breaks: np.ndarray
    Rn_max: float
    phi_Rn_max: float
    pressure_max: float
    phi_pressure_max: float
    wear_invariant_max: float
    life: ArchardLife
    validity: ContactValidity
    model: "ContactModel"
    assumptions: tuple[str, ...]


def slip_path_gauss(element: "Geneva", model: "ContactModel", nodes: int = GAUSS_NODES) -> float:
    """L_s per engagement (mm) by Gauss–Legendre with ``nodes`` points on each smooth piece."""
    c = ContactConstants(element, model)
    return float(_gauss_integrals(c, breakpoints(c), nodes)[0])


def _gauss_integrals(c: ContactConstants, br: np.ndarray, nodes: int) -> tuple[float, float, float]:
    """(L_s total mm, ∫p̄ dL_s over M > 0, over M < 0 in N/mm²·mm) by Gauss–Legendre per piece."""
    x, w = _gauss(nodes)
    lo, hi = br[:-1], br[1:]
    half = 0.5 * (hi - lo)
    uu = (0.5 * (hi + lo))[:, None] + half[:, None] * x[None, :]
    f = _fields(uu, c)
    ls = (f["g"] @ w) * half
    pw = ((f["mean_pressure"] * f["g"]) @ w) * half
    sign = np.sign(moment(0.5 * (lo + hi), c))
    return float(ls.sum()), float(pw[sign > 0].sum()), float(pw[sign < 0].sum())


def contact(element: "Geneva", samples: int, model: "ContactModel", u: np.ndarray | None = None,
            crank: CrankMotion | None = None) -> GenevaContact:
    """The contact and wear analysis of ``element`` over one crank revolution of ``samples`` points.

    ``u`` (N,) rad: the progress angles of the rows (increasing, within (−π, π]; default equal steps
    from −π), e.g. a geared crank's angles at equal times; ``crank``: its :class:`CrankMotion`
    (default the constant speed of ``element``). See the module docstring for the formulas and the
    validity range, and :class:`GenevaContact` for the result.
    """
    c = ContactConstants(element, model, crank)
    n = int(samples)
    s = 1.0 if element.omega1 > 0 else -1.0
    u_all = -math.pi + 2.0 * math.pi * np.arange(n, dtype=float) / n if u is None else np.asarray(u, dtype=float)
    n = len(u_all)
    eng = np.abs(u_all) <= c.phi0 + EDGE_TOL
    ue = np.clip(u_all[eng], -c.phi0, c.phi0)
    br = breakpoints(c)
    rn_lim = normal_force_limit(c)
    # merged grid: engaged samples plus break points, sorted; Gauss–Legendre on every interval
    # (the integrand is smooth between neighbours), summed, then back to the samples
    grid = np.concatenate([ue, br])
    order = np.argsort(grid, kind="stable")
    ug = grid[order]
    f = _fields(ug, c)
    g = f["g"]
    x, w = _gauss(INTERVAL_NODES)
    half = 0.5 * np.diff(ug)
    mid = 0.5 * (ug[1:] + ug[:-1])
    nodes = _fields(mid[:, None] + half[:, None] * x[None, :], c)
    cum = np.concatenate([[0.0], np.cumsum((nodes["g"] @ w) * half)])
    # the running path is known up to where the engagement first leaves the validity range
    inside = f["Rn"] <= rn_lim
    inside[1:] &= nodes["Rn"].max(axis=1, initial=0.0) <= rn_lim
    cum[~np.logical_and.accumulate(inside)] = np.nan
    trapezoid = float(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(ug)))
    pos = np.empty_like(order)
    pos[order] = np.arange(order.size)
    at = pos[: ue.size]  # where each engaged sample sits in the merged grid
    total, pw_drive, pw_brake = _gauss_integrals(c, br, GAUSS_NODES)

    def full(arr: np.ndarray) -> np.ndarray:
        out = np.full(n, np.nan)
        out[eng] = arr[at]
        return out

    names = ("moment", "Rn", "Rn_paper", "Rn_derived", "strip_width", "hertz_half_width", "half_width",
             "deformation", "rolling_ratio", "contact_pressure", "mean_pressure")
    cols = {k: full(f[k]) for k in names}
    phi = s * u_all
    valid = eng & (cols["Rn"] <= rn_lim)
    validity = _validity(c, cols, eng, valid, phi, rn_lim)
    gs = full(g)
    for name in ("strip_width", "hertz_half_width", "half_width", "deformation", "contact_pressure",
                 "mean_pressure"):
        cols[name][~valid] = np.nan
    gs[~valid] = np.nan
    if not validity.ok:  # the totals need the whole engagement inside the range
        total = trapezoid = pw_drive = pw_brake = math.nan
    ls_m = total * 1e-3
    ti = cols["Rn"] * (math.pi * c.z / (30.0 * c.w1 * ls_m)) if ls_m > 0 else np.full(n, np.nan)
    life = _archard(element, pw_drive, pw_brake)
    rn_max, phi_rn, p_max, phi_p = _peaks(cols, phi, eng, validity.ok)
    return GenevaContact(
        phi=phi, u=u_all, engaged=eng, contact_valid=valid,
        slip_speed=gs * (c.w1 if crank is None else full(crank.rates(ug)[0])),
        slip_speed_invariant=gs / c.rp, slip_path=full(cum), wear_invariant=ti, slip_path_total=total,
        slip_path_total_trapezoid=trapezoid, breaks=br, Rn_max=rn_max, phi_Rn_max=phi_rn,
        pressure_max=p_max, phi_pressure_max=phi_p,
        wear_invariant_max=float(np.nanmax(ti)) if np.isfinite(ti).any() else math.nan,
        life=life, validity=validity, model=model, assumptions=assumptions(element, model), **cols)


def _peaks(cols: dict[str, np.ndarray], phi: np.ndarray, eng: np.ndarray, ok: bool) -> tuple[float, ...]:
    """(R_n max N, its φ, p_max MPa, its φ) over the sampled rows; p_max NaN when the model does
    not hold everywhere (the peak lies where it does not)."""
    rn = cols["Rn"]
    if not (eng.any() and np.nanmax(rn) > 0):
        return 0.0, math.nan, 0.0, math.nan
    k_rn = int(np.nanargmax(rn))
    if not ok:
        return float(rn[k_rn]), float(phi[k_rn]), math.nan, math.nan
    k_p = int(np.nanargmax(cols["contact_pressure"]))
    return float(rn[k_rn]), float(phi[k_rn]), float(cols["contact_pressure"][k_p]), float(phi[k_p])


def _validity(c: ContactConstants, cols: dict[str, np.ndarray], eng: np.ndarray, valid: np.ndarray,
              phi: np.ndarray, rn_lim: float) -> "ContactValidity":
    """The validity record of one analysis (before the out-of-range rows are blanked)."""
    k_a, k_b = _strip_coefficients(c)
    rn = cols["Rn"][eng]
    b = k_b * np.sqrt(rn)
    defo = cols["deformation"][eng]
    peak, _ = peak_normal_force(c)
    bad = eng & ~valid
    runs = []
    idx = np.nonzero(bad)[0]
    if idx.size:
        cut = np.nonzero(np.diff(idx) > 1)[0]
        for lo, hi in zip(np.r_[idx[0], idx[cut + 1]], np.r_[idx[cut], idx[-1]]):
            runs.append((float(phi[lo]), float(phi[hi])))
    mx = (lambda a: float(a.max()) if a.size else 0.0)  # noqa: E731
    return ContactValidity(
        deformation_limit=DEFORMATION_LIMIT, half_width_limit=HALF_WIDTH_LIMIT, rn_limit=rn_lim,
        rn_peak=peak, ok=bool(peak <= rn_lim and not idx.size), invalid_rows=int(idx.size),
        engaged_rows=int(eng.sum()), max_deformation_ratio=mx(defo) / c.rp,
        max_half_width_radius_ratio=mx(b) / c.rp, max_half_width_length_ratio=mx(b) / c.length,
        invalid_runs=tuple(runs))


@dataclass(frozen=True)
class EngagementTotals:
    """The per-engagement figures a design needs, without samples (independent of N).

    ``rn_peak`` (N) the largest normal force over the continuous engagement, at progress angle
    ``u_peak`` (rad); ``pressure_peak`` (MPa) the Hertz p_max there, √(R_n·E*/(π·l·r_p));
    ``rn_limit`` (N) the validity range's force and ``valid`` whether the whole engagement is in
    it; ``slip_path`` L_s (mm) and ``life`` (:class:`ArchardLife`), NaN when not ``valid``.
    """

    rn_peak: float
    u_peak: float
    pressure_peak: float
    rn_limit: float
    valid: bool
    slip_path: float
    life: ArchardLife


def engagement_totals(element: "Geneva", model: "ContactModel", crank: CrankMotion | None = None) -> EngagementTotals:
    """:class:`EngagementTotals` of ``element`` (``crank``: a varying crank speed, as for
    :func:`contact`): the same quadrature (Gauss–Legendre per smooth piece) and the same peak
    search as :func:`contact`, so its figures equal the analysis'."""
    c = ContactConstants(element, model, crank)
    rn_lim = normal_force_limit(c)
    peak, u_peak = peak_normal_force(c)
    total, pw_drive, pw_brake = _gauss_integrals(c, breakpoints(c), GAUSS_NODES)
    valid = peak <= rn_lim
    if not valid:
        total = pw_drive = pw_brake = math.nan
    pressure = math.sqrt(peak * c.e_star / (math.pi * c.length * c.rp))
    return EngagementTotals(peak, u_peak, pressure, rn_lim, valid, total, _archard(element, pw_drive, pw_brake))


def _archard(el: "Geneva", pw_drive: float, pw_brake: float) -> ArchardLife:
    """Archard depths (mm) and lives from ∫p̄ dL_s (N/mm² · mm) per flank."""
    k = el.wear.specific_wear_rate  # mm³/(N·m)
    h_drive = k * pw_drive * 1e-3  # slip path mm -> m
    h_brake = k * pw_brake * 1e-3
    allowed = el.wear.allowed_wear
    if math.isnan(h_drive) or math.isnan(h_brake):  # outside the contact model's validity range
        return ArchardLife(math.nan, math.nan, math.nan, math.nan, math.nan, math.nan, "not computed")
    worst = max(h_drive, h_brake)
    slot = el.slots * allowed / worst if worst > 0 else math.inf
    roller = allowed / (h_drive + h_brake) if worst > 0 else math.inf
    cycles = min(slot, roller)
    return ArchardLife(h_drive, h_brake, slot, roller, cycles, cycles / (60.0 * abs(el.speed_rpm)),
                       "slot" if slot <= roller else "roller")


def assumptions(el: "Geneva", model: "ContactModel") -> tuple[str, ...]:
    """The modelling assumptions in force, in words (printed with every analysis)."""
    nf = {"derived": "derived from the wheel's moment balance, R_n = |M|/(ρ − sgn(M)·f02·r02) "
                     "(note B3: the printed eq. 3 lacks λ on the friction term and always uses '+')",
          "paper": "the paper's eq. (3) as printed, R_n = λ|M|/(r√D + f02·r02)"}[model.normal_force]
    hw = {"paper_half": "a_paper/2 (eq. 2 is the full strip width, note B2)",
          "hertz": "the Hertz half-width b", "paper_full": "the literal a_paper of eq. 2"}[model.half_width]
    rad = {"deformed": "the deformed radius r_p − Δ (eq. 4)",
           "undeformed": "the undeformed radius r_p"}[model.slip_radius]
    return (
        "radial-entry Geneva: λ = r/A = sin(π/z) (note B9)",
        f"validity range of the line-contact model: Δ ≤ {DEFORMATION_LIMIT:g}·r_p, b ≤ {HALF_WIDTH_LIMIT:g}·r_p "
        f"and b ≤ {HALF_WIDTH_LIMIT:g}·l (b the larger of a_paper/2 and the Hertz b); rows beyond it are "
        "flagged (contact_valid 0) and their contact columns left empty",
        f"M = J2·ε2 + M_ext; M_ext = {el.load.external_moment:g} N·m opposes the indexing motion; "
        "the journal reaction equals R_n",
        f"normal force used downstream: {nf}; Rn_paper is eq. (3) as printed",
        f"half-width in the slip model: {hw}; contact pressure uses the Hertz half-width "
        "b = √(4 R_n r_p/(π l E*)) (roller on a flat wall)",
        f"slip radius: {rad}",
        "strip width a = 2.16·√(R_n·D/(l·E')) with E' = 2E1E2/(E1 + E2); deformation Δ by eq. (6) as "
        "printed with the roller's E and Poisson's ratio and a = a_paper (full width); Δ = 0 at R_n = 0",
        "rolling ratio ω_pi = (r/r_p)·sin u/√D, eq. (5) in its robust form (B5); negative while the "
        "roller moves towards the wheel centre",
        "slip at the strip edges, sin ψ = b/r_p (an upper bound; ×≈1/3 if averaged over the slip "
        "zone); eq. (7) without its spurious ω1 (B7); quadrature broken at φ = 0 and where M changes sign",
        "wear invariant T_i = π·R_n·z/(30·ω1·L_s) in N·min/m with L_s per engagement in m (B8)",
        "Archard life (B1): depth per engagement k·∫p̄ dL_s per slot flank with the mean Hertz pressure "
        "p̄ = R_n/(2bl); slot flanks: driving (M > 0) and braking (M < 0), each slot engaged every z "
        "turns; roller: all wear on one spot every turn (a bound)",
    )
