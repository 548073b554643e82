"""An independent 50-digit reference for linkages with any driver: a crank of any number of joints,
a cylinder (driven distance between two pivots) or a slider driven along a fixed guide.

Every moving link (the driver included) has a pose (x, y, θ): the point drawn at p0 is at
(x, y) + R(θ)(p0 − c), c the drawn position of the link's first joint. The frame does not move.
Equations: an R joint shared by links a, b gives P_a(p0) = P_b(p0); a P joint gives
sin(θ_a − θ_b) = 0 and cross(R(θ_a)u0, P_b(p0) − P_a(p0)) = 0; the driver adds one equation:

- crank: θ_crank = q − q0 (q0 the drawn angle of the pivot → first other joint);
- cylinder: |P_rod(H) − P_barrel(M)|² = q² (M, H the end pivots);
- slider: u0 · (P_slider(s0) − s0) = q (the guide through s0 along u0, on the frame).

Positions: Newton's method in mpmath with a central-difference Jacobian (step 1e-30 at 80
digits). Rates: the positions' first and second derivatives with respect to the input q by
five-point differences at 80 digits (step 1e-12 relative), then v = x'·q̇ and a = x''·q̇² + x'·q̈
with the solution's own input rates. Nothing here knows about dyads, modes or Cramer's rule.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np

from mechsketch.core import JointKind, Linkage
from mechsketch.core.model.drivers import DriverKind

DPS = 50
WORK = 80


class DriveReference:
    """The constraint equations of ``linkage`` with its driver's equation, in mpmath."""

    def __init__(self, linkage: Linkage):
        self.lk = lk = linkage
        mp = mpmath.mp
        with mpmath.workdps(WORK):
            self.at = {j.id: (mp.mpf(j.at[0]), mp.mpf(j.at[1])) for j in lk.joints}
            self.moving = [k.id for k in lk.links if k.id != lk.ground]
            self.col = {k: 3 * i for i, k in enumerate(self.moving)}
            self.c = {k.id: self.at[k.joints[0]] for k in lk.links}
            self.rc, self.pc = [], []
            for j in lk.joints:
                carriers = lk.links_of(j.id)
                if j.kind is JointKind.R:
                    self.rc += [(j.id, carriers[0], b) for b in carriers[1:]]
                else:
                    a, b = carriers
                    ang = mpmath.radians(mp.mpf(j.axis_deg))
                    self.pc.append((j.id, a, b, (mpmath.cos(ang), mpmath.sin(ang))))
            drv = lk.driver
            self.kind = drv.kind
            if drv.kind is DriverKind.CRANK:
                tip = next(x for x in lk.link(drv.link).joints if x != drv.pivot)
                (px, py), (tx, ty) = self.at[drv.pivot], self.at[tip]
                self.q0 = mpmath.atan2(ty - py, tx - px)
            elif drv.kind is DriverKind.CYLINDER:
                rod = next(k for k in lk.links_of(drv.pivot) if k != drv.link)
                self.barrel, self.rod = drv.link, rod
                self.m = next(x for x in lk.link(drv.link).joints if x != drv.pivot)
                self.h = next(x for x in lk.link(rod).joints if x != drv.pivot)
            else:
                ang = mpmath.radians(mp.mpf(lk.joint(drv.pivot).axis_deg))
                self.u0 = (mpmath.cos(ang), mpmath.sin(ang))
            self.n = 3 * len(self.moving)
            m = 2 * len(self.rc) + 2 * len(self.pc) + 1
            if m != self.n:
                raise ValueError(f"reference needs a square system: {m} equations, {self.n} unknowns")

    def point(self, q, link: str, p0):
        """Position of the point of ``link`` drawn at p0 (mp pair), for unknowns ``q``."""
        if link == self.lk.ground:
            return (mpmath.mpf(p0[0]), mpmath.mpf(p0[1]))
        i = self.col[link]
        x, y, th = q[i], q[i + 1], q[i + 2]
        cx, cy = self.c[link]
        dx, dy = p0[0] - cx, p0[1] - cy
        co, si = mpmath.cos(th), mpmath.sin(th)
        return (x + co * dx - si * dy, y + si * dx + co * dy)

    def theta(self, q, link: str):
        return mpmath.mpf(0) if link == self.lk.ground else q[self.col[link] + 2]

    def residual(self, q, inp):
        out = []
        for jid, a, b in self.rc:
            pa, pb = self.point(q, a, self.at[jid]), self.point(q, b, self.at[jid])
            out += [pa[0] - pb[0], pa[1] - pb[1]]
        for jid, a, b, u0 in self.pc:
            ta = self.theta(q, a)
            ux = mpmath.cos(ta) * u0[0] - mpmath.sin(ta) * u0[1]
            uy = mpmath.sin(ta) * u0[0] + mpmath.cos(ta) * u0[1]
            pa, pb = self.point(q, a, self.at[jid]), self.point(q, b, self.at[jid])
            out += [mpmath.sin(ta - self.theta(q, b)), ux * (pb[1] - pa[1]) - uy * (pb[0] - pa[0])]
        drv = self.lk.driver
        if self.kind is DriverKind.CRANK:
            out.append(self.theta(q, drv.link) - (inp - self.q0))
        elif self.kind is DriverKind.CYLINDER:
            pm = self.point(q, self.barrel, self.at[self.m])
            ph = self.point(q, self.rod, self.at[self.h])
            out.append((ph[0] - pm[0]) ** 2 + (ph[1] - pm[1]) ** 2 - inp * inp)
        else:
            s0 = self.at[drv.pivot]
            p = self.point(q, drv.link, s0)
            out.append(self.u0[0] * (p[0] - s0[0]) + self.u0[1] * (p[1] - s0[1]) - inp)
        return out

    def positions(self, inp, guess):
        """Unknowns q (mp list) at input ``inp`` by Newton from the float ``guess``."""
        mp = mpmath.mp
        with mpmath.workdps(WORK):
            q = mp.matrix([mp.mpf(v) for v in guess])
            inp = mp.mpf(inp)
            if self.kind is DriverKind.CRANK:   # the crank's angle as the input says, not 2π away
                q[self.col[self.lk.driver.link] + 2] = inp - self.q0
            h = mp.mpf("1e-30")
            for _ in range(60):
                F = mp.matrix(self.residual(q, inp))
                J = mp.matrix(self.n, self.n)
                for i in range(self.n):
                    qp, qm = q.copy(), q.copy()
                    qp[i] += h
                    qm[i] -= h
                    col = (mp.matrix(self.residual(qp, inp)) - mp.matrix(self.residual(qm, inp))) / (2 * h)
                    for r in range(self.n):
                        J[r, i] = col[r]
                dq = mp.lu_solve(J, -F)
                q = q + dq
                if max(abs(v) for v in dq) < mp.mpf(10) ** (-(WORK - 8)):
                    break
            else:
                raise RuntimeError("reference Newton did not converge")
            return q

    def guess_from(self, sol, k: int) -> list[float]:
        """Float unknowns at sample ``k`` of a solution (from ``sol.point`` only)."""
        out = []
        for link in self.moving:
            c = (float(self.c[link][0]), float(self.c[link][1]))
            p = sol.point(link, c)[k]
            px = sol.point(link, (c[0] + 1.0, c[1]))[k]
            out += [p[0], p[1], math.atan2(px[1] - p[1], px[0] - p[0])]
        return out

    def joint_pva(self, sol, k: int, links_points):
        """Reference (P, V, A) at sample ``k`` of ``sol`` for each (link, p0) of ``links_points``:
        mp pairs, the rates from the solution's input rate and acceleration."""
        mp = mpmath.mp
        guess = self.guess_from(sol, k)
        qd = float(np.broadcast_to(sol.omega_driver, (len(sol),))[k])
        qdd = float(np.broadcast_to(sol.alpha_driver, (len(sol),))[k])
        with mpmath.workdps(WORK):
            q0 = mp.mpf(float(sol.input[k]))
            step = mp.mpf("1e-12") * max(abs(q0), mp.one)
            qs = {j: self.positions(q0 + j * step, guess) for j in (-2, -1, 0, 1, 2)}
            out = []
            for link, p0 in links_points:
                pts = {j: self.point(qs[j], link, (mp.mpf(p0[0]), mp.mpf(p0[1]))) for j in qs}
                P, V, A = [], [], []
                for c in (0, 1):
                    f = {j: pts[j][c] for j in pts}
                    d1 = (f[-2] - 8 * f[-1] + 8 * f[1] - f[2]) / (12 * step)
                    d2 = (-f[-2] + 16 * f[-1] - 30 * f[0] + 16 * f[1] - f[2]) / (12 * step * step)
                    P.append(f[0])
                    V.append(d1 * qd)
                    A.append(d2 * qd * qd + d1 * qdd)
                out.append((tuple(P), tuple(V), tuple(A)))
            return out


def compare(linkage: Linkage, sol, samples) -> dict:
    """Largest errors of ``sol`` (order 2) against the reference at sample indices ``samples``,
    over every joint of every link (``sol.point``, ``point_velocity``, ``point_acceleration``) and
    every joint's reported position, velocity and acceleration; with the reference scales."""
    ref = DriveReference(linkage)
    err = dict(pos=0.0, vel=0.0, acc=0.0)
    scale = dict(pos=0.0, vel=0.0, acc=0.0)
    pairs = [(lk.id, linkage.joint(j).at) for lk in linkage.links for j in lk.joints]
    for k in samples:
        got = ref.joint_pva(sol, k, pairs)
        for (link, p0), (P, V, A) in zip(pairs, got):
            for name, f, r in (("pos", sol.point(link, p0)[k], P), ("vel", sol.point_velocity(link, p0)[k], V),
                               ("acc", sol.point_acceleration(link, p0)[k], A)):
                err[name] = max(err[name], float(mpmath.hypot(mpmath.mpf(f[0]) - r[0], mpmath.mpf(f[1]) - r[1])))
                scale[name] = max(scale[name], float(mpmath.hypot(*r)))
        for j in linkage.joints:   # the reported joints agree with some carrying link's point
            for name, f in (("pos", sol.position(j.id)[k]), ("vel", sol.velocity(j.id)[k]),
                            ("acc", sol.acceleration(j.id)[k])):
                best = min(float(mpmath.hypot(mpmath.mpf(f[0]) - r[0], mpmath.mpf(f[1]) - r[1]))
                           for (link, p0), rs in zip(pairs, got) if p0 == j.at and link in linkage.links_of(j.id)
                           for r in (rs[("pos", "vel", "acc").index(name)],))
                err[name] = max(err[name], best)
    err["scale"] = scale
    return err


def relative(err: dict, size: float) -> dict:
    """Positions relative to the mechanism's size, rates to the largest reference value."""
    s = err["scale"]
    return dict(pos=err["pos"] / size, vel=err["vel"] / max(s["vel"], 1e-300),
                acc=err["acc"] / max(s["acc"], 1e-300))
