"""Kinetostatics of D designs × N samples: driving effort, pin forces, shaking force and moment.

The batch twin of :mod:`mechsketch.core.analyses.forces` (the same conventions and units: forces
N, moments N·m, the pass from the last Assur group back to the driver in closed form, d'Alembert
inertia from the accelerations), on the link states of :mod:`.bkernels` with each design's drawn
constants as arrays (D, 1), and its masses and loads changed by the variables ``mass:LINK``,
``inertia:LINK``, ``com:LINK:x|y`` and ``load:ID:...`` (:mod:`.keys`). Points and forces are
complex here (x + iy, (D, N)); moments about each link's anchor, N·mm inside the pass.

Crank, slider and cylinder drivers. A cylinder's barrel and rod are locked into the bar V of its
group at the current length (the rod's loads moved to the barrel's pivot), and the rod's own balance
gives the push along the slide axis, as :mod:`mechsketch.core.analyses.forces.passes` does. The
results are the frictionless ones (``ForceResult.driver``, ``pins``, ``shaking_*`` of the
one-design path); its friction iteration (``ForceResult.friction``) is not in the batch.
"""
from __future__ import annotations

import numpy as np

from ..model.linkage import JointKind, Linkage
from ..model.loads import Damper, PointForce, Spring, Torque, default_inertia
from ..solver.structure import GroupKind
from .engine import BatchPlan, Constants, Run

MM = 1e-3


def _c(p) -> np.ndarray:
    """A pair as a complex array."""
    return np.asarray(p[0]) + 1j * np.asarray(p[1])


def _cross(a, b):
    return (np.conj(a) * b).imag


class _Links:
    """The complex views of the link states of one chunk, and each link's drawn anchor."""

    def __init__(self, run: Run, K: Constants, plan: BatchPlan) -> None:
        self.st = run.states
        self.K = K
        lk = plan.linkage
        self.ground = lk.ground
        self.pivot = _c(K.at[lk.driver.pivot])
        self.A, self.rot, self.a0, self.v, self.w, self.acc, self.al = {}, {}, {}, {}, {}, {}, {}
        for k, s in run.states.items():
            self.A[k], self.rot[k], self.a0[k] = _c(s.A), _c(s.cs), _c(s.a0)
            self.v[k], self.w[k], self.acc[k], self.al[k] = _c(s.v), s.w, _c(s.acc), s.al
        #: the drawn joints (complex (D, 1)); the arms below are keyed by these very arrays
        self.at = {j: _c(K.at[j]) for j in lk.joint_ids}
        #: a cylinder: (barrel, rod, M, H, slide joint, mode (D, 1)); the bar V (named as the barrel)
        #: reaches from M to H, its arm to H is H − M whatever the length
        self.cyl = None
        if plan.kind == "cylinder":
            d = plan.drive
            mode = K.steps[plan.plan.steps[plan.cyl_step].group.name]["cyl"]["mode"]
            self.cyl = (d.link, d.rod, d.m, d.h, d.slide, mode)
            self._v_arm = self.A[d.rod] - self.A[d.link]

    def ref(self, k):
        return self.pivot if k == self.ground else self.A[k]

    def arm(self, k: str, p0):
        """From the reference of ``k`` to its point drawn at p0 (complex (D, 1))."""
        if k == self.ground:
            return p0 - self.pivot
        if self.cyl is not None and k == self.cyl[0] and p0 is self.at[self.cyl[3]]:
            return self._v_arm
        return self.rot[k] * (p0 - self.a0[k])

    def point(self, k, p0):
        return self.ref(k) + self.arm(k, p0)

    def normal(self, k: str, joint: str):
        u = _c(self.K.axis[joint])
        return 1j * u * (1.0 if k == self.ground else self.rot[k])

    def velocity(self, k, arm):
        if k == self.ground:
            return 0j
        return self.v[k] + 1j * self.w[k] * arm


def _static(lk: Linkage, L: _Links, K: Constants, values: dict, n: int) -> dict:
    """What no sample changes, per design (arrays (D, 1)): per link its constant force (gravity,
    point forces; N), ``W`` = Σ conj(p0 − anchor)·f of those forces on a moving link (their moment
    about the anchor is Im(conj(rot)·W), N·mm), its torques (N·mm; the frame's point forces' moment
    about the pivot there too); the massive links [(link, d, mk, α coefficient)]; the springs and
    dampers [(ends, coefficients)]."""
    at = {j: _c(K.at[j]) for j in lk.joint_ids}
    g = complex(*lk.gravity) if lk.gravity is not None else 0j
    F = {k: np.zeros((n, 1), dtype=complex) for k in lk.link_ids}
    W = {k: np.zeros((n, 1), dtype=complex) for k in lk.link_ids}
    T = {k: np.zeros((n, 1)) for k in lk.link_ids}
    masses = []
    for link in lk.links:
        k = link.id
        if k == lk.ground:
            continue
        m0 = lk.mass_of(k)
        mass = values.get(f"mass:{k}", np.full((n, 1), m0.mass if m0 is not None else 0.0))
        pts = [at[j] for j in link.joints]
        c0 = sum(pts) / len(pts) if m0 is None or m0.com is None else np.full((n, 1), complex(*m0.com))
        if f"com:{k}:x" in values or f"com:{k}:y" in values:
            c0 = values.get(f"com:{k}:x", c0.real) + 1j * values.get(f"com:{k}:y", c0.imag)
        span = np.zeros((n, 1))
        for p in pts:
            for q in pts:
                span = np.maximum(span, np.abs(p - q))
        if f"inertia:{k}" in values:
            inertia = values[f"inertia:{k}"]
        elif m0 is not None and m0.inertia is not None:
            inertia = np.full((n, 1), m0.inertia)
        else:
            inertia = default_inertia(mass, span)
        if not (np.any(mass != 0.0) or np.any(inertia != 0.0)):
            continue
        d = c0 - L.a0[k]
        mk = -mass * MM
        masses.append((k, d, mk, mk * np.abs(d) ** 2 - inertia / MM))
        if g != 0:
            F[k] = F[k] + mass * g
            W[k] = W[k] + np.conj(d) * (mass * g)
    springs = []
    for ld in lk.loads:
        if isinstance(ld, PointForce):
            f = values.get(f"load:{ld.id}:fx", ld.force[0]) + 1j * values.get(f"load:{ld.id}:fy", ld.force[1])
            p0 = complex(*ld.at)
            F[ld.link] = F[ld.link] + f
            if ld.link == lk.ground:
                T[ld.link] = T[ld.link] + (np.conj(p0 - L.pivot) * f).imag
            else:
                W[ld.link] = W[ld.link] + np.conj(p0 - L.a0[ld.link]) * f
        elif isinstance(ld, Torque):
            T[ld.link] = T[ld.link] + values.get(f"load:{ld.id}:torque", ld.torque) / MM
        elif isinstance(ld, Spring):
            k_ = values.get(f"load:{ld.id}:stiffness", ld.stiffness)
            free = values.get(f"load:{ld.id}:free_length", ld.rest_length)
            springs.append((ld.ends, (k_, k_ * free)))
        elif isinstance(ld, Damper):
            springs.append((ld.ends, (values.get(f"load:{ld.id}:damping", ld.damping),)))
    return {"F": F, "W": W, "T": T, "masses": masses, "springs": springs}


def _applied(L: _Links, S: dict) -> tuple[dict, dict]:
    """Gravity, inertia and applied loads per link: force (N) and moment about its reference
    (N·mm), as ``Kinetostatics.applied``."""
    F, M = {}, {}
    for k in S["F"]:
        F[k] = S["F"][k]
        M[k] = S["T"][k] if k == L.ground else S["T"][k] + (np.conj(L.rot[k]) * S["W"][k]).imag
    for k, d, mk, coef in S["masses"]:
        r = L.rot[k] * d
        aA = L.acc[k]
        F[k] = F[k] + mk * (aA + (1j * L.al[k] - L.w[k] * L.w[k]) * r)
        M[k] = M[k] + mk * _cross(r, aA) + coef * L.al[k]
    for (e0, e1), coef in S["springs"]:
        a, pa0, b, pb0 = e0.link, complex(*e0.at), e1.link, complex(*e1.at)
        arm_a, arm_b = L.arm(a, pa0), L.arm(b, pb0)
        d = (L.ref(b) + arm_b) - (L.ref(a) + arm_a)
        if len(coef) == 2:
            t = coef[0] - coef[1] / np.abs(d)
        else:
            dv = L.velocity(b, arm_b) - L.velocity(a, arm_a)
            t = coef[0] * (np.conj(d) * dv).real / (np.abs(d) ** 2)
        fa = t * d
        F[a] = F[a] + fa
        F[b] = F[b] - fa
        M[a] = M[a] + _cross(arm_a, fa)
        M[b] = M[b] - _cross(arm_b, fa)
    return F, M


class _Pass:
    """The reactions group by group, last first (see :mod:`mechsketch.core.analyses.forces.passes`):
    ``F``/``M`` the links' loads (consumed as the groups are solved), ``pairs`` [(joint, on, by,
    force on ``on``)] of the revolute joints."""

    def __init__(self, L: _Links, F: dict, M: dict, at: dict) -> None:
        self.L, self.F, self.M, self.at = L, dict(F), dict(M), at
        self.pairs: list = []

    def about(self, k, q0):
        return self.M[k] - _cross(self.L.arm(k, q0), self.F[k])

    def mom(self, k, q0, f):
        return _cross(self.L.arm(k, q0), f)

    def take(self, k, f, q0) -> None:
        self.F[k] = self.F[k] - f
        self.M[k] = self.M[k] - _cross(self.L.arm(k, q0), f)

    def take_at(self, k, f, q, c) -> None:
        self.F[k] = self.F[k] - f
        self.M[k] = self.M[k] - (_cross(q - self.L.ref(k), f) + c)

    def rrr(self, g, i, j, Fi, Fj, tot) -> None:
        L, at = self.L, self.at
        m0, h0, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
        ai, aj = L.arm(i, l0) - L.arm(i, m0), L.arm(j, l0) - L.arm(j, h0)
        b = self.M[j] + self.mom(j, l0, Fi) - self.mom(j, h0, tot)
        inv = 1.0 / _cross(ai, aj)
        X = self.about(i, l0) * inv * aj + b * inv * ai
        Z = -tot - X
        self.pairs += [(g.outer_i, i, g.known_i, X), (g.outer_j, j, g.known_j, Z), (g.inner, j, i, X + Fi)]
        self.take(g.known_i, X, m0)
        self.take(g.known_j, Z, h0)

    def rrp(self, g, i, j, Fi, Fj, tot) -> None:
        L, at = self.L, self.at
        m0, l0 = at[g.outer_i], at[g.inner]
        n = L.normal(j, g.outer_j)
        ri = L.arm(i, m0) - L.arm(i, l0)
        f = (self.about(i, l0) - _cross(ri, tot)) / _cross(ri, n) * n
        X = -f - tot
        self.pairs += [(g.outer_i, i, g.known_i, X), (g.inner, j, i, X + Fi)]
        q = L.point(i, l0)
        self.take(g.known_i, X, m0)
        self.take_at(g.known_j, f, q, -self.about(j, l0))

    def rpr(self, g, i, j, Fi, Fj, tot) -> None:
        L, at = self.L, self.at
        m0, h0 = at[g.outer_i], at[g.outer_j]
        n = L.normal(i, g.inner)
        qm = L.point(i, m0)
        f = (self.about(i, m0) + self.about(j, h0)) / _cross(n, qm - L.point(j, h0)) * n
        X, Z = f - Fi, -f - Fj
        self.pairs += [(g.outer_i, i, g.known_i, X), (g.outer_j, j, g.known_j, Z)]
        self.take(g.known_i, X, m0)
        self.take(g.known_j, Z, h0)

    def prp(self, g, i, j, Fi, Fj, tot) -> None:
        L = self.L
        l0 = self.at[g.inner]
        n1, n2 = L.normal(i, g.outer_i), L.normal(j, g.outer_j)
        det = _cross(n1, n2)
        f1 = _cross(n2, tot) / det * n1
        f2 = _cross(tot, n1) / det * n2
        c1, c2 = -self.about(i, l0), -self.about(j, l0)
        q = L.point(i, l0)
        self.pairs.append((g.inner, j, i, f1 + Fi))
        self.take_at(g.known_i, f1, q, c1)
        self.take_at(g.known_j, f2, q, c2)

    def rpp(self, g, i, j, Fi, Fj, tot) -> None:
        L = self.L
        m0 = self.at[g.outer_i]
        n1, n2 = L.normal(i, g.inner), L.normal(j, g.outer_j)
        det = _cross(n1, n2)
        f1 = _cross(n2, Fj) / det * n1
        f2 = _cross(Fj, n1) / det * n2
        c1 = self.about(i, m0)
        q = L.point(i, m0)
        c2 = -(c1 + self.M[j] + _cross(L.ref(j) - q, self.F[j]))
        X = f1 - Fi
        self.pairs.append((g.outer_i, i, g.known_i, X))
        self.take(g.known_i, X, m0)
        self.take_at(g.known_j, f2, q, c2)

    def cylinder(self, first: int, rod_f):
        """After the group of the cylinder's bar V: the pairs at H name the rod instead of the
        barrel, and the driving force (N, + extending) is the barrel's push on the rod along the
        slide axis, from the rod's balance (its loads ``rod_f``, the pin force at H)."""
        barrel, rod, _m, h, slide, mode = self.L.cyl
        r_h = 0j
        for n in range(first, len(self.pairs)):
            j, on, by, f = self.pairs[n]
            if j != h:
                continue
            if on == barrel:
                on, r_h = rod, r_h + f
            elif by == barrel:
                by, r_h = rod, r_h - f
            self.pairs[n] = (j, on, by, f)
        t = -(rod_f + r_h)                       # the barrel's force on the rod
        u = -1j * self.L.normal(barrel, slide)
        return mode * (t * np.conj(u)).real

    def driver(self, plan: BatchPlan):
        """The driving effort (N·m for a crank, N for a slider) once every group is solved."""
        lk, L, at = plan.linkage, self.L, self.at
        drv = lk.driver
        pv = at[drv.pivot]
        if plan.kind == "crank":
            effort = -self.about(drv.link, pv)
            reaction = -self.F[drv.link]
            self.pairs.append((drv.pivot, drv.link, lk.ground, reaction))
            self.take(lk.ground, reaction, pv)
            self.M[lk.ground] = self.M[lk.ground] - effort
            return effort * MM
        k = drv.link              # a slider driven along its guide
        u = -1j * L.normal(k, drv.pivot)
        effort = -(self.F[k] * np.conj(u)).real
        push = effort * u
        f = -self.F[k] - push
        self.take_at(lk.ground, f + push, L.point(k, pv), -self.about(k, pv))
        return effort


def _pass(L: _Links, plan: BatchPlan, F: dict, M: dict, at: dict) -> dict:
    """The reactions group by group, last first, then the driver and the frame."""
    p = _Pass(L, F, M, at)
    solve = {GroupKind.RRR: p.rrr, GroupKind.RRP: p.rrp, GroupKind.RPR: p.rpr, GroupKind.PRP: p.prp,
             GroupKind.RPP: p.rpp}
    cyl, effort = L.cyl, None
    for step in reversed(plan.plan.steps):
        g = step.group
        i, j = g.link_i, g.link_j
        vgroup = cyl is not None and cyl[0] in (i, j)
        if vgroup:   # barrel and rod locked together at the current length: the bar V
            rod_f, rod_m, first = p.F[cyl[1]], p.M[cyl[1]], len(p.pairs)
            p.F[cyl[0]] = p.F[cyl[0]] + rod_f
            p.M[cyl[0]] = p.M[cyl[0]] + rod_m + _cross(L.arm(cyl[0], L.at[cyl[3]]), rod_f)
        Fi, Fj = p.F[i], p.F[j]
        solve[g.kind](g, i, j, Fi, Fj, Fi + Fj)
        if vgroup:
            effort = p.cylinder(first, rod_f)
            p.F[cyl[1]], p.M[cyl[1]] = 0j, 0.0
        p.F[i] = p.F[j] = 0j
        p.M[i] = p.M[j] = 0.0
    if cyl is None:
        effort = p.driver(plan)
    ground = plan.linkage.ground
    return {"effort": effort, "pairs": p.pairs, "frame_force": p.F[ground], "frame_moment": p.M[ground]}


def _pin_force(pairs: list, joint: str, link: str):
    total = 0j
    for j, on, by, f in pairs:
        if j == joint:
            if on == link:
                total = total + f
            elif by == link:
                total = total - f
    return total


def chunk_forces(plan: BatchPlan, K: Constants, run: Run, values: dict, valid: np.ndarray) -> dict:
    """The kinetostatics of one chunk (a run of order 2): effort (D, N) (N·m for a crank, N for a
    slider), pins {joint: {link: (D, N) complex N}}, shaking force (D, N) complex N and moment
    (D, N) N·m about the driver's pivot; NaN where ``valid`` is False or the forces are not finite."""
    lk = plan.linkage
    n = K.n
    L = _Links(run, K, plan)
    vals = {k: np.asarray(v, dtype=float).reshape(-1, 1) for k, v in values.items()}
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        F, M = _applied(L, _static(lk, L, K, vals, n))
        p = _pass(L, plan, F, M, L.at)
        shape = valid.shape
        effort = np.broadcast_to(np.real(p["effort"]), shape)
        ff = np.broadcast_to(p["frame_force"], shape)
        fm = np.broadcast_to(p["frame_moment"] * MM, shape)
        ok = valid & np.isfinite(effort) & np.isfinite(ff.real + ff.imag) & np.isfinite(fm)
        pins = {}
        for j in lk.joints:
            carriers = lk.links_of(j.id)
            if len(carriers) < 2 or j.kind is not JointKind.R:
                continue
            pins[j.id] = {b: np.where(ok, np.broadcast_to(_pin_force(p["pairs"], j.id, b), shape), np.nan)
                          for b in carriers[1:]}
        return {"effort": np.where(ok, effort, np.nan), "pins": pins, "shaking_force": np.where(ok, ff, np.nan),
                "shaking_moment": np.where(ok, fm, np.nan), "valid": ok}


class BatchForces:
    """The kinetostatics of D designs over N samples (SI units, NaN where not valid):
    ``effort`` (D, N) the driving torque (N·m, crank) or force (N, slider), ``kind`` "torque" or
    "force"; ``pins`` {joint: {link: (D, N, 2) N}} the force on ``link`` from each revolute joint
    on two or more links (every link after the first in the file); ``shaking_force`` (D, N, 2) N
    and ``shaking_moment`` (D, N) N·m on the frame (about the driver's pivot); ``valid`` (D, N)."""

    def __init__(self, kind: str, effort, pins, shaking_force, shaking_moment, valid) -> None:
        self.kind, self.effort, self.pins = kind, effort, pins
        self.shaking_force, self.shaking_moment, self.valid = shaking_force, shaking_moment, valid

    @staticmethod
    def _peak(a: np.ndarray) -> np.ndarray:
        with np.errstate(invalid="ignore"):
            return np.where(np.isfinite(a).any(axis=1), np.nanmax(np.where(np.isfinite(a), np.abs(a), -np.inf), axis=1),
                            np.nan)

    @property
    def peak_effort(self) -> np.ndarray:
        """(D,) the largest |effort| over the valid samples."""
        return self._peak(self.effort)

    @property
    def rms_effort(self) -> np.ndarray:
        """(D,) the root mean square effort over the valid samples."""
        with np.errstate(invalid="ignore"):
            return np.sqrt(np.nanmean(self.effort ** 2, axis=1))

    @property
    def peak_shaking_force(self) -> np.ndarray:
        """(D,) N."""
        return self._peak(np.hypot(self.shaking_force[..., 0], self.shaking_force[..., 1]))

    @property
    def peak_shaking_moment(self) -> np.ndarray:
        """(D,) N·m."""
        return self._peak(self.shaking_moment)


__all__ = ["BatchForces", "MM", "chunk_forces"]
