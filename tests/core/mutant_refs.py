"""Independent references for :mod:`test_mutant_killers` (nothing here calls mechsketch's solvers).

* :func:`rpp_on_rocker` — a four-bar whose rocker carries a guide; a yoke slides on that guide and
  a block pinned at a coupler point slides in the yoke's slot: an RPP group whose guide turns
  (with angular acceleration) with the rocker.
* :class:`RppChainMp` — that linkage solved in closed form in mpmath (circle intersection for the
  four-bar, the intersection of two lines for the RPP), written from the geometry alone; rates
  are derivatives of the position functions of the crank angle (``mpmath.diffs``) times the
  crank speed (and its square: the crank turns uniformly).
* :func:`rrr_valid_count` — how many samples of a sweep of a four-bar fall where the coupler
  and rocker can close the loop, counted from the interval of crank angles given by the law of
  cosines (no solver).
"""
from __future__ import annotations

import cmath
import math

import mpmath

from linkage_builders import _extend, e, fourbar, xy
from mechsketch.core import Linkage

DPS = 50


# ---------------------------------------------------------------------------------------------
# RPP with its guide on a moving link
# ---------------------------------------------------------------------------------------------
def rpp_on_rocker(guide_deg: float = 70.0, slot_deg: float = 130.0, rpm: float = 95.4929658551372,
                  eid: str = "rpp_rocker") -> Linkage:
    """Four-bar A–B–C–D (crank 40, coupler 140 with the point E, rocker 120, ground 160) plus an
    RPP group: the block is pinned at the coupler point E and slides in a slot (``slot_deg``) of
    the yoke; the yoke slides on a guide of the rocker (axis through Qg at ``guide_deg``). The crank
    turns at ``rpm``."""
    fb = fourbar(coupler_point=(70.0, 30.0), eid=eid, rpm=rpm)
    at = {j.id: complex(*j.at) for j in fb.joints}
    Qg = at["D"] + 0.4 * (at["C"] - at["D"]) + 25j
    Qs = at["E"] + 8.0 * e(slot_deg)   # the slot passes through the pin E in the drawn pose
    # the slot must cross the guide line: the yoke carries both (Qs on the slot, Qg on the guide)
    Y = Qg + 30.0 * e(guide_deg + 90.0)
    return _extend(fb, eid, [("Qs", "P", xy(Qs), slot_deg), ("Qg", "P", xy(Qg), guide_deg),
                             ("Y", "R", xy(Y))],
                   {"rocker": ["Qg"], "block": ["E", "Qs"], "yoke": ["Qs", "Qg", "Y"]})


def _mpc(p) -> mpmath.mpc:
    return mpmath.mpc(mpmath.mpf(p[0]), mpmath.mpf(p[1]))


def _cross(a, b):
    return (mpmath.conj(a) * b).imag


class RppChainMp:
    """The linkage of :func:`rpp_on_rocker` in closed form, in mpmath.

    ``points(theta)`` maps each link to {joint id: position (mpc)} for the crank's absolute angle
    ``theta`` (rad); ``rotation(theta)`` maps each link to its rotation exp(iρ) from the drawn pose.
    """

    def __init__(self, linkage: Linkage, dps: int = DPS):
        self.lk = linkage
        self.dps = dps
        with mpmath.workdps(dps):
            self.at = {j.id: _mpc(j.at) for j in linkage.joints}
            self.ax = {j.id: mpmath.expjpi(mpmath.mpf(j.axis_deg) / 180) for j in linkage.joints
                       if j.axis_deg is not None}
            at = self.at
            self.crank = abs(at["B"] - at["A"])
            self.coupler = abs(at["C"] - at["B"])
            self.rocker = abs(at["C"] - at["D"])
            # assembly mode of the four-bar as drawn: C left (+1) or right (−1) of B→D
            self.mode = 1 if _cross(at["D"] - at["B"], at["C"] - at["B"]) > 0 else -1
            self.theta0 = mpmath.arg(at["B"] - at["A"])
        self._cache: dict = {}

    def _solve(self, theta):
        key = (mpmath.nstr(theta, self.dps + 30), mpmath.mp.prec)
        if key in self._cache:
            return self._cache[key]
        at, ax = self.at, self.ax
        A, D = at["A"], at["D"]
        B = A + self.crank * mpmath.expj(theta)
        # C: |C − B| = coupler, |C − D| = rocker, on the drawn side of B→D
        d = D - B
        dd = abs(d)
        a = (self.coupler ** 2 - self.rocker ** 2 + dd ** 2) / (2 * dd)
        h = mpmath.sqrt(self.coupler ** 2 - a ** 2)
        C = B + d / dd * (a + 1j * self.mode * h)
        r_crank = mpmath.expj(theta - self.theta0)
        r_coupler = (C - B) / (at["C"] - at["B"])
        r_rocker = (C - D) / (at["C"] - D)
        E = B + r_coupler * (at["E"] - at["B"])
        # guide on the rocker: through the rocker point drawn at Qg, direction R·u_g; the yoke
        # turns with the rocker and slides by s along the guide; its slot (direction R·u_s)
        # passes through the yoke point drawn at Qs. The block turns with the yoke (P joint) and is
        # pinned at E, so its point drawn at Qs is E + R(Qs − E0): it lies on the slot.
        R = r_rocker
        G = D + R * (at["Qg"] - D)
        ug, us = R * ax["Qg"], R * ax["Qs"]
        # yoke point drawn at p: G + s·ug + R(p − Qg0); block point drawn at p: E + R(p − E0)
        # cross(us, [E + R(Qs0 − E0)] − [G + s·ug + R(Qs0 − Qg0)]) = 0
        w = E + R * (at["Qg"] - at["E"]) - G
        s = _cross(us, w) / _cross(us, ug)
        yoke_anchor = G + s * ug          # the yoke point drawn at Qg
        out = {
            "rot": {"crank": r_crank, "coupler": r_coupler, "rocker": R, "block": R, "yoke": R},
            "anchor": {"crank": (A, at["A"]), "coupler": (B, at["B"]), "rocker": (D, at["D"]),
                       "block": (E, at["E"]), "yoke": (yoke_anchor, at["Qg"])},
        }
        self._cache[key] = out
        return out

    def point(self, link: str, p0, theta):
        """Position (mpc) of the point of ``link`` drawn at p0, crank angle theta."""
        st = self._solve(theta)
        anchor, a0 = st["anchor"][link]
        return anchor + st["rot"][link] * (_mpc(p0) - a0)

    def pva(self, link: str, p0, theta, omega):
        """(P, V, A) of a link point (mpc each) at crank angle theta (rad), crank speed omega (rad/s)
        constant: V = ω dP/dθ, A = ω² d²P/dθ² (mpmath.diffs of the closed form)."""
        with mpmath.workdps(self.dps):
            th, w = mpmath.mpf(theta), mpmath.mpf(omega)
            p, d1, d2 = mpmath.diffs(lambda t: self.point(link, p0, t), th, 2)
            return p, w * d1, w * w * d2

    def omega_alpha(self, link: str, theta, omega):
        """(ω, α) of ``link``: ω·dρ/dθ and ω²·d²ρ/dθ² with ρ = arg of its rotation."""
        with mpmath.workdps(self.dps):
            th, w = mpmath.mpf(theta), mpmath.mpf(omega)
            ref = self._solve(th)["rot"][link]

            def rho(t):   # the rotation's angle, continuous near th
                return mpmath.arg(self._solve(t)["rot"][link] / ref)
            _, d1, d2 = mpmath.diffs(rho, th, 2)
            return w * d1, w * w * d2


# ---------------------------------------------------------------------------------------------
# PRP whose two guides both turn (one on the rocker, one on the crank)
# ---------------------------------------------------------------------------------------------
def prp_both_guides_turn(g1_deg: float = 75.0, g2_deg: float = -15.0, rpm: float = 95.4929658551372,
                         eid: str = "prp_turning") -> Linkage:
    """Four-bar A–B–C–D (crank 40, coupler 140, rocker 120, ground 160) plus a PRP group: block 1
    slides on a guide of the rocker (axis through Q1 at ``g1_deg``), block 2 on a guide of the
    coupler (through Q2 at ``g2_deg``), the two blocks pinned together at L, where the two guide
    lines meet in the drawn pose. Both guides turn with angular acceleration; their angle changes
    as the transmission angle does (by ~46°), so they stay far from parallel. (A guide on the
    crank would turn fully against the rocker's: parallel twice a turn.)"""
    fb = fourbar(eid=eid, rpm=rpm)
    at = {j.id: complex(*j.at) for j in fb.joints}
    Q1 = at["D"] + 0.5 * (at["C"] - at["D"]) + 10j
    Q2 = at["B"] + 0.4 * (at["C"] - at["B"]) - 5j
    u1, u2 = e(g1_deg), e(g2_deg)
    t1 = ((Q2 - Q1).conjugate() * u2).imag / (u1.conjugate() * u2).imag   # L = Q1 + t1·u1 = Q2 + t2·u2
    L = Q1 + t1 * u1
    return _extend(fb, eid, [("Q1", "P", xy(Q1), g1_deg), ("L", "R", xy(L)), ("Q2", "P", xy(Q2), g2_deg)],
                   {"rocker": ["Q1"], "coupler": ["Q2"], "block1": ["Q1", "L"], "block2": ["L", "Q2"]})


class PrpBothTurnMp:
    """The linkage of :func:`prp_both_guides_turn` in closed form, in mpmath: the four-bar by
    circle intersection, L as the meeting point of the two guide lines as the rocker and the crank
    carry them, each block turning with its guide's link (written from the geometry alone).
    ``point(link, p0, theta)``, ``pva`` and ``omega_alpha`` as :class:`RppChainMp`; ``slide(i,
    theta)``: block i's displacement along its guide from the drawn pose (mm)."""

    def __init__(self, linkage: Linkage, dps: int = DPS):
        self.lk, self.dps = linkage, dps
        with mpmath.workdps(dps):
            self.at = at = {j.id: _mpc(j.at) for j in linkage.joints}
            self.ax = {j.id: mpmath.expjpi(mpmath.mpf(j.axis_deg) / 180) for j in linkage.joints
                       if j.axis_deg is not None}
            self.crank, self.coupler = abs(at["B"] - at["A"]), abs(at["C"] - at["B"])
            self.rocker = abs(at["C"] - at["D"])
            self.mode = 1 if _cross(at["D"] - at["B"], at["C"] - at["B"]) > 0 else -1
            self.theta0 = mpmath.arg(at["B"] - at["A"])

    def _solve(self, theta):
        at, ax = self.at, self.ax
        A, D = at["A"], at["D"]
        B = A + self.crank * mpmath.expj(theta)
        d = D - B
        dd = abs(d)
        a = (self.coupler ** 2 - self.rocker ** 2 + dd ** 2) / (2 * dd)
        C = B + d / dd * (a + 1j * self.mode * mpmath.sqrt(self.coupler ** 2 - a ** 2))
        Rc, Rr = mpmath.expj(theta - self.theta0), (C - D) / (at["C"] - D)
        Rk = (C - B) / (at["C"] - at["B"])
        Z1, w1 = D + Rr * (at["Q1"] - D), Rr * ax["Q1"]       # guide 1 (rocker): point and direction
        Z2, w2 = B + Rk * (at["Q2"] - at["B"]), Rk * ax["Q2"]  # guide 2 (coupler)
        t1 = _cross(Z2 - Z1, w2) / _cross(w1, w2)
        L = Z1 + t1 * w1
        rot = {"crank": Rc, "coupler": Rk, "rocker": Rr, "block1": Rr, "block2": Rk}
        anchor = {"crank": (A, A), "coupler": (B, at["B"]), "rocker": (D, D), "block1": (L, at["L"]),
                  "block2": (L, at["L"])}
        slides = (_cross(L - Z1, 1j * w1), _cross(L - Z2, 1j * w2))   # along each guide (−cross(·, J·w) = dot)
        return rot, anchor, slides

    def point(self, link: str, p0, theta):
        rot, anchor, _ = self._solve(theta)
        a, a0 = anchor[link]
        return a + rot[link] * (_mpc(p0) - a0)

    def pva(self, link: str, p0, theta, omega):
        with mpmath.workdps(self.dps):
            th, w = mpmath.mpf(theta), mpmath.mpf(omega)
            p, d1, d2 = mpmath.diffs(lambda t: self.point(link, p0, t), th, 2)
            return p, w * d1, w * w * d2

    def omega_alpha(self, link: str, theta, omega):
        with mpmath.workdps(self.dps):
            th, w = mpmath.mpf(theta), mpmath.mpf(omega)
            ref = self._solve(th)[0][link]
            _, d1, d2 = mpmath.diffs(lambda t: mpmath.arg(self._solve(t)[0][link] / ref), th, 2)
            return w * d1, w * w * d2

    def slide(self, i: int, theta, omega):
        """Block i's (0: on the rocker's guide, 1: on the coupler's) displacement along its guide from
        the drawn pose and its first two time derivatives (mm, mm/s, mm/s²)."""
        with mpmath.workdps(self.dps):
            th, w = mpmath.mpf(theta), mpmath.mpf(omega)
            s0 = self._solve(self.theta0)[2][i]
            p, d1, d2 = mpmath.diffs(lambda t: self._solve(t)[2][i] - s0, th, 2)
            return p, w * d1, w * w * d2


# ---------------------------------------------------------------------------------------------
# the four-bar whose coupler cannot always reach the rocker
# ---------------------------------------------------------------------------------------------
def rrr_feasible_cos(crank: float, ground: float, coupler: float, rocker: float):
    """The interval [c_lo, c_hi] of cos(φ) (φ: crank angle from the ground line A→D) where the loop
    closes: by the law of cosines |B − D|² = crank² + ground² − 2·crank·ground·cos φ must lie in
    [(rocker − coupler)², (rocker + coupler)²]. mpf endpoints (clamped to [−1, 1])."""
    with mpmath.workdps(DPS):
        a, g, l1, l2 = (mpmath.mpf(x) for x in (crank, ground, coupler, rocker))
        far, near = (l1 + l2) ** 2, (l1 - l2) ** 2
        c_lo = (a * a + g * g - far) / (2 * a * g)      # |B − D| ≤ l1 + l2
        c_hi = (a * a + g * g - near) / (2 * a * g)     # |B − D| ≥ |l1 − l2|
        return max(c_lo, mpmath.mpf(-1)), min(c_hi, mpmath.mpf(1))


def rrr_valid_count(crank, ground, coupler, rocker, theta0_deg: float, n: int) -> tuple[int, float]:
    """(count, margin): how many of the n sweep angles φ_k = φ0 + 2πk/n (φ measured from A→D)
    close the loop, counted in closed form: φ feasible ⇔ c_lo ≤ cos φ ≤ c_hi, i.e. φ mod 2π in
    [β, γ] ∪ [2π − γ, 2π − β] with β = acos(c_hi), γ = acos(c_lo); the number of k in an interval
    [x, y] of φ0 + 2πk/n is ⌊(y − φ0)n/2π⌋ − ⌈(x − φ0)n/2π⌉ + 1 (over the wrap-around shifts).
    ``margin`` is the smallest distance (in units of the sample spacing) of an interval end from a
    sample: the count is unambiguous when it is well above the float rounding of the sweep."""
    with mpmath.workdps(DPS):
        c_lo, c_hi = rrr_feasible_cos(crank, ground, coupler, rocker)
        beta, gamma = mpmath.acos(c_hi), mpmath.acos(c_lo)
        two_pi = 2 * mpmath.pi
        phi0 = mpmath.radians(mpmath.mpf(theta0_deg))
        step = two_pi / n
        count = 0
        margin = mpmath.inf
        for x, y in ((beta, gamma), (two_pi - gamma, two_pi - beta)):
            for shift in (-two_pi, 0, two_pi):   # k in [0, n): φ0 + 2πk/n spans one turn
                lo = (x + shift - phi0) / step
                hi = (y + shift - phi0) / step
                k_lo = max(int(mpmath.ceil(lo)), 0)
                k_hi = min(int(mpmath.floor(hi)), n - 1)
                if k_hi >= k_lo:
                    count += k_hi - k_lo + 1
                for v in (lo, hi):
                    margin = min(margin, abs(v - mpmath.nint(v)))
        return count, float(margin)


def angle_deg(z: complex) -> float:
    return math.degrees(cmath.phase(z))


# ---------------------------------------------------------------------------------------------
# the rolling lever: an independent integration and a 30-digit quadrature
# ---------------------------------------------------------------------------------------------
class LeverRef:
    """References for a rolling-lever dict (the scene format), written from the notes (section C)
    without mechsketch's code.

    * :meth:`dop853` — (α, S5) at any θ by scipy's DOP853 at rtol 1e-13, integrated from the drawn
      pose (θ = 0, α0, S5 = 0) separately towards each sign of θ;
    * :meth:`alpha_exact` — α(θ) to ~25 digits from the separable form of pair D: seen from the
      lever, pair D depends only on ψ = α − θ, and dθ/dψ = −ℓ/g(ψ), so θ(ψ) = −ℓ∫_{ψ0}^{ψ} dψ/g is a
      quadrature (mpmath tanh-sinh copes with the square root of g at the tangency), inverted by
      Newton's method. Near an end of the working range the contact P moves ~1/√(distance) times
      faster than α, so only this reference gives P and Q there to 1e-12 mm;
    * :meth:`contacts` — P (ground frame) and Q (slider frame) for poses (α, θ) and S5.
    """

    def __init__(self, d: dict, dps: int = 30):
        import numpy as np

        self.np = np
        self.d = d
        self.dps = dps
        self.G = np.array(d["rocker_pivot"], float)
        self.f = np.array(d["pin"], float)
        self.c1 = np.array(d["lever_circle"]["center"], float)
        self.R1 = float(d["lever_circle"]["radius"])
        self.c2 = np.array(d["slider_circle"]["center"], float)
        self.R2 = float(d["slider_circle"]["radius"])
        ax = math.radians(d.get("slider_axis_deg", 0.0))
        self.ds = np.array([math.cos(ax), math.sin(ax)])
        self.n = np.array([-self.ds[1], self.ds[0]])
        self.side = d.get("slider_side", 1)
        self.br = 1 if d.get("contact_branch", "near") == "far" else -1
        self.ell = float(np.hypot(*(self.f - self.G)))
        self.a0 = math.atan2(self.f[1] - self.G[1], self.f[0] - self.G[0])
        with mpmath.workdps(dps):
            G = [mpmath.mpf(x) for x in d["rocker_pivot"]]
            f = [mpmath.mpf(x) for x in d["pin"]]
            self._mp = dict(G=G, f=f, c=[mpmath.mpf(x) for x in d["lever_circle"]["center"]],
                            R=mpmath.mpf(d["lever_circle"]["radius"]),
                            ell=mpmath.sqrt((f[0] - G[0]) ** 2 + (f[1] - G[1]) ** 2),
                            psi0=mpmath.atan2(f[1] - G[1], f[0] - G[0]))

    # -- float geometry ---------------------------------------------------------------------
    def contacts(self, alpha, theta, s5):
        """(P (M, 2), Q (M, 2)): the pair-D contact in the ground frame and the pair-E contact in
        the slider frame (P0 − S5·d_s) at poses (α, θ) (M,) and slides S5 (M,)."""
        np = self.np
        a, th, s5 = (np.atleast_1d(np.asarray(x, float)) for x in (alpha, theta, s5))
        e = np.stack([np.cos(a), np.sin(a)], -1)
        F = self.G + self.ell * e

        def lever(p):
            v = p - self.f
            return F + np.stack([np.cos(th) * v[0] - np.sin(th) * v[1], np.sin(th) * v[0] + np.cos(th) * v[1]], -1)
        w = lever(self.c1) - self.G
        b = (w * e).sum(1)
        c = w[:, 0] * e[:, 1] - w[:, 1] * e[:, 0]   # b² − |w|² + R1² = R1² − c², factored (tangent)
        g = b + self.br * np.sqrt((self.R1 - c) * (self.R1 + c))
        P = self.G + g[:, None] * e
        z = P - lever(self.c2)
        zn = z @ self.n
        t2 = -zn + self.side * np.sqrt(zn * zn - (z * z).sum(1) + self.R2 ** 2)
        P0 = P + t2[:, None] * self.n
        return P, P0 - s5[:, None] * self.ds

    def _rhs(self, th, y):
        np = self.np
        a = y[0]
        e = np.array([math.cos(a), math.sin(a)])
        F = self.G + self.ell * e
        ct, st = math.cos(th), math.sin(th)

        def lever(p):
            v = p - self.f
            return F + np.array([ct * v[0] - st * v[1], st * v[0] + ct * v[1]])
        w = lever(self.c1) - self.G
        b = w @ e
        c = w[0] * e[1] - w[1] * e[0]
        g = b + self.br * math.sqrt(max((self.R1 - c) * (self.R1 + c), 0.0))
        z = self.G + g * e - lever(self.c2)
        zn = z @ self.n
        t2 = -zn + self.side * math.sqrt(zn * zn - z @ z + self.R2 ** 2)
        return [1.0 - g / self.ell, -t2]

    def dop853(self, theta):
        """(α, S5) (M,) at θ (M,) rad, any order and sign.

        DOP853 at rtol 1e-13 leaves errors of ~rtol·|y| (3e-11 mm on an S5 of 250 mm, 1e-13 rad
        on α), which hides what it is to check near the working-range ends. So it is run twice:
        once plainly, then on the defect v = y − p(θ) from a Chebyshev fit p of the first run
        (v' = f(θ, p + v) − p'), whose small size lets the tolerance act on ~1e-15 instead."""
        np = self.np
        from scipy.integrate import solve_ivp

        th = np.atleast_1d(np.asarray(theta, float))
        a = np.full(th.shape, self.a0)
        s = np.zeros(th.shape)
        for sgn in (-1.0, 1.0):
            idx = np.nonzero(th * sgn > 0)[0]
            if idx.size == 0:
                continue
            idx = idx[np.argsort(np.abs(th[idx]), kind="stable")]
            end = float(th[idx[-1]])
            first = solve_ivp(self._rhs, (0.0, end), [self.a0, 0.0], method="DOP853",
                              rtol=1e-13, atol=1e-14, dense_output=True)
            assert first.success, first.message
            nodes = 0.5 * end * (1.0 - np.cos(np.linspace(0.0, math.pi, 121)))
            fit = [np.polynomial.Chebyshev.fit(nodes, first.sol(nodes)[i], 100, domain=sorted((0.0, end)))
                   for i in (0, 1)]
            dfit = [f.deriv() for f in fit]
            v0 = [self.a0 - fit[0](0.0), 0.0 - fit[1](0.0)]

            def defect(t, v):
                y = self._rhs(t, [fit[0](t) + v[0], fit[1](t) + v[1]])
                return [y[0] - dfit[0](t), y[1] - dfit[1](t)]
            sol = solve_ivp(defect, (0.0, end), v0, method="DOP853", rtol=1e-13, atol=1e-15, t_eval=th[idx])
            assert sol.success, sol.message
            a[idx] = fit[0](th[idx]) + sol.y[0]
            s[idx] = fit[1](th[idx]) + sol.y[1]
        return a, s

    # -- the separable quadrature -----------------------------------------------------------
    def _g(self, psi):
        m = self._mp
        e = (mpmath.cos(psi), mpmath.sin(psi))
        w = (m["c"][0] - m["f"][0] + m["ell"] * e[0], m["c"][1] - m["f"][1] + m["ell"] * e[1])
        b = w[0] * e[0] + w[1] * e[1]
        disc = b * b - (w[0] ** 2 + w[1] ** 2 - m["R"] ** 2)
        return b + self.br * mpmath.sqrt(max(disc, 0))

    def theta_of_psi(self, psi, psi_from=None, theta_from=0):
        """θ at rocker direction ψ (lever frame), from (ψ_from, θ_from) (default the drawn pose)."""
        m = self._mp
        with mpmath.workdps(self.dps):
            start = m["psi0"] if psi_from is None else psi_from
            return theta_from - m["ell"] * mpmath.quad(lambda p: 1 / self._g(p), [start, psi])

    def alpha_exact(self, theta: float, guess: float):
        """α at θ (mpf), Newton on θ(ψ) = θ from ψ = guess − θ (a float α close to the answer)."""
        m = self._mp
        with mpmath.workdps(self.dps):
            th = mpmath.mpf(theta)
            psi = mpmath.mpf(guess) - th
            t_psi = self.theta_of_psi(psi)
            for _ in range(40):
                step = (t_psi - th) * self._g(psi) / m["ell"]   # dψ/dθ = −g/ℓ
                if abs(step) < mpmath.mpf(10) ** (-self.dps + 5):
                    break
                new = psi + step
                t_psi = self.theta_of_psi(new, psi, t_psi)
                psi = new
            else:
                raise RuntimeError("quadrature Newton did not converge")
            return th + psi
