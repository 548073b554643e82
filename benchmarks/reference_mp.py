"""Independent reference kinematics of a planar linkage: its loop equations in mpmath (50 digits).

Nothing here uses mechsketch's kernels, its Assur decomposition or its solving order. The linkage
is written as a generic multibody system in reference-point coordinates:

* every moving link k other than the driver has unknowns q_k = (x_k, y_k, ρ_k): the position of
  its anchor (the drawn position a0_k of its first joint) and its rotation from the drawn pose.
  A point drawn at p0 on link k is at  P = X_k + R(ρ_k)(p0 − a0_k);
* the frame is the identity. The driver is prescribed: it turns about its pivot with ρ = θ − θ0,
  θ the absolute angle of pivot→tip and θ0 that angle in the drawn pose (atan2 in mpmath),
  ρ̇ = ω (the driver speed of the file), ρ̈ = α (0 unless given);
* an R joint carried by links c0, c1, … gives P_c0 = P_ci (two equations each);
* a P joint between links b (first in the file) and a gives ρ_a − ρ_b = 0 and
  cross(R(ρ_b)·u0, P_a − P_b) = 0 (the joint's point on a stays on b's axis through it).

Positions: Newton on Φ(q) = 0 at ``DPS`` digits, seeded from a float answer. Velocities and
accelerations: the once and twice differentiated constraints, J·q̇ = −Φ̇(q̇ = 0) and
J·q̈ = −Φ̈(q̈ = 0) (all quadratic velocity terms included), solved in mpmath with the same LU.
:func:`selftest` checks them against ``mpmath.diff`` of the position solution along time.

The arithmetic is written once for any number type (``num``, ``cos``, ``sin`` are passed in): run
with floats it is the generic Newton baseline of :mod:`newton_baseline`.

A joint's reported point: an R joint is the same point on every carrier; a P joint is reported on
the later of its two links in file order (mechsketch's documented convention).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import mpmath

from mechsketch.core.model.linkage import JointKind, Linkage

DPS = 50

GROUND, DRIVER = -1, -2


@dataclass(frozen=True)
class Ref:
    """A point of a link: link index (GROUND, DRIVER or an unknown link ≥ 0) and the drawn
    position of the point (the joint's ``at``)."""

    link: int
    x: float
    y: float


class LoopSystem:
    """The constraint equations Φ(q, θ) = 0 of a mobility-1 linkage (any number type)."""

    def __init__(self, linkage: Linkage):
        self.linkage = linkage
        drv = linkage.driver
        self.unknown = [k.id for k in linkage.links if k.id not in (linkage.ground, drv.link)]
        self.n = 3 * len(self.unknown)
        index = {lid: i for i, lid in enumerate(self.unknown)}
        index[linkage.ground], index[drv.link] = GROUND, DRIVER
        at = {j.id: (float(j.at[0]), float(j.at[1])) for j in linkage.joints}
        self.pivot = at[drv.pivot]
        self.tip = at[next(j for j in linkage.link(drv.link).joints if j != drv.pivot)]
        self.omega = float(drv.omega)
        self.anchor = {GROUND: (0.0, 0.0), DRIVER: self.pivot}
        for i, lid in enumerate(self.unknown):
            self.anchor[i] = at[linkage.link(lid).joints[0]]
        self.cons: list[tuple] = []        # ("R", ref_a, ref_b) | ("P", ref_a, ref_b, axis_deg)
        self.report: dict[str, Ref] = {}  # joint -> the link point that reports it
        for j in linkage.joints:
            refs = [Ref(index[c], *at[j.id]) for c in linkage.links_of(j.id)]
            if not refs:
                continue
            if j.kind is JointKind.R:
                self.report[j.id] = refs[0]
                for r in refs[1:]:
                    if refs[0].link >= 0 or r.link >= 0:  # frame–driver at the pivot: identity
                        self.cons.append(("R", refs[0], r))
            else:
                if len(refs) != 2:
                    raise ValueError(f"P joint {j.id!r} must join exactly two links")
                b, a = refs
                self.report[j.id] = a
                self.cons.append(("P", a, b, float(j.axis_deg or 0.0)))
        if 2 * len(self.cons) != self.n:
            raise ValueError(f"{2 * len(self.cons)} equations for {self.n} unknowns: "
                             f"linkage {linkage.id!r} is not a mobility-1 linkage with one driver")
        self._consts: dict = {}

    # ------------------------------------------------------------------------------------
    def seed_drawn(self) -> list[float]:
        """q of the drawn pose."""
        q: list[float] = []
        for i in range(len(self.unknown)):
            q += [self.anchor[i][0], self.anchor[i][1], 0.0]
        return q

    def drawn_theta(self, num=float, atan2=math.atan2):
        return atan2(num(self.tip[1]) - num(self.pivot[1]), num(self.tip[0]) - num(self.pivot[0]))

    def _constants(self, num, cos, sin, pi):
        """Drawn offsets p0 − a0 and axis directions in the working number type (cached)."""
        key = (num, cos)
        c = self._consts.get(key)
        if c is None:
            off = {}
            for con in self.cons:
                for ref in con[1:3]:
                    ax, ay = self.anchor[ref.link]
                    off[ref] = (num(ref.x) - num(ax), num(ref.y) - num(ay))
            for ref in self.report.values():
                ax, ay = self.anchor[ref.link]
                off[ref] = (num(ref.x) - num(ax), num(ref.y) - num(ay))
            axes = {}
            for con in self.cons:
                if con[0] == "P":
                    a = num(con[3]) * pi / 180
                    axes[con[3]] = (cos(a), sin(a))
            c = self._consts[key] = (off, axes, num(self.pivot[0]), num(self.pivot[1]))
        return c

    def poses(self, num, cos, sin, pi, theta0, theta, q, qd=None, qdd=None, omega=None, alpha=None):
        """Per link: (ρ, cos ρ, sin ρ, x, y, ρ̇, ρ̈, ẋ, ẏ, ẍ, ÿ)."""
        zero = num(0.0)
        _, _, px, py = self._constants(num, cos, sin, pi)
        rho = theta - theta0
        w = zero if omega is None else omega
        al = zero if alpha is None else alpha
        P = {GROUND: (zero, num(1.0), zero, zero, zero, zero, zero, zero, zero, zero, zero),
             DRIVER: (rho, cos(rho), sin(rho), px, py, w, al, zero, zero, zero, zero)}
        for i in range(len(self.unknown)):
            k = 3 * i
            r = q[k + 2]
            d = (qd[k], qd[k + 1], qd[k + 2]) if qd is not None else (zero, zero, zero)
            dd = (qdd[k], qdd[k + 1], qdd[k + 2]) if qdd is not None else (zero, zero, zero)
            P[i] = (r, cos(r), sin(r), q[k], q[k + 1], d[2], dd[2], d[0], d[1], dd[0], dd[1])
        return P

    @staticmethod
    def point(poses, off, ref):
        """Position, velocity, acceleration of a link point, and its rotated offset R·r."""
        _, c, s, X, Y, w, a, Xd, Yd, Xdd, Ydd = poses[ref.link]
        rx, ry = off[ref]
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        return ((X + Rx, Y + Ry), (Xd - w * Ry, Yd + w * Rx),
                (Xdd - a * Ry - w * w * Rx, Ydd + a * Rx - w * w * Ry), (Rx, Ry))

    def evaluate(self, num, cos, sin, pi, theta0, theta, q, qd=None, qdd=None, omega=None,
                 alpha=None, jac: bool = True, rates: bool = False):
        """Φ, J = ∂Φ/∂q (rows; if ``jac``) and, if ``rates``, Φ̇ and Φ̈ (with the given qd/qdd).

        Returns (phi, J, phid, phidd).
        """
        off, axes, _, _ = self._constants(num, cos, sin, pi)
        ps = self.poses(num, cos, sin, pi, theta0, theta, q, qd, qdd, omega, alpha)
        n = self.n
        zero = num(0.0)
        phi: list = []
        phid: list = []
        phidd: list = []
        J = [[zero] * n for _ in range(n)] if jac else None
        row = 0
        point = self.point
        for con in self.cons:
            ra, rb = con[1], con[2]
            Pa, Va, Aa, Ra = point(ps, off, ra)
            Pb, Vb, Ab, Rb = point(ps, off, rb)
            if con[0] == "R":
                phi += [Pa[0] - Pb[0], Pa[1] - Pb[1]]
                if rates:
                    phid += [Va[0] - Vb[0], Va[1] - Vb[1]]
                    phidd += [Aa[0] - Ab[0], Aa[1] - Ab[1]]
                if jac:
                    for ref, R, sg in ((ra, Ra, 1), (rb, Rb, -1)):
                        if ref.link >= 0:
                            k = 3 * ref.link
                            J[row][k] += sg
                            J[row + 1][k + 1] += sg
                            J[row][k + 2] -= sg * R[1]
                            J[row + 1][k + 2] += sg * R[0]
            else:
                rho_a, rho_b = ps[ra.link][0], ps[rb.link][0]
                cb, sb = ps[rb.link][1], ps[rb.link][2]
                u0x, u0y = axes[con[3]]
                ux, uy = cb * u0x - sb * u0y, sb * u0x + cb * u0y
                dx, dy = Pa[0] - Pb[0], Pa[1] - Pb[1]
                ud = ux * dx + uy * dy          # u · d
                uxd = ux * dy - uy * dx         # u × d
                phi += [rho_a - rho_b, uxd]
                if rates:
                    wa, wb = ps[ra.link][5], ps[rb.link][5]
                    aa, ab = ps[ra.link][6], ps[rb.link][6]
                    ddx, ddy = Va[0] - Vb[0], Va[1] - Vb[1]
                    d2x, d2y = Aa[0] - Ab[0], Aa[1] - Ab[1]
                    # d/dt (u × d) with u̇ = ρ̇_b J u:  −ρ̇_b (u·d) + u × ḋ
                    phid += [wa - wb, -wb * ud + (ux * ddy - uy * ddx)]
                    phidd += [aa - ab, -ab * ud - wb * wb * uxd - 2 * wb * (ux * ddx + uy * ddy)
                              + (ux * d2y - uy * d2x)]
                if jac:
                    if ra.link >= 0:
                        k = 3 * ra.link
                        J[row][k + 2] += 1
                        J[row + 1][k] -= uy
                        J[row + 1][k + 1] += ux
                        J[row + 1][k + 2] += ux * Ra[0] + uy * Ra[1]
                    if rb.link >= 0:
                        k = 3 * rb.link
                        J[row][k + 2] -= 1
                        J[row + 1][k] += uy
                        J[row + 1][k + 1] -= ux
                        J[row + 1][k + 2] += -ud - (ux * Rb[0] + uy * Rb[1])
            row += 2
        return phi, J, phid, phidd

    def joints(self, num, cos, sin, pi, theta0, theta, q, qd=None, qdd=None, omega=None,
               alpha=None, names: Sequence[str] | None = None):
        """{joint: (P, V, A)} of the reported points (V, A meaningful only if qd/qdd given)."""
        off, _, _, _ = self._constants(num, cos, sin, pi)
        ps = self.poses(num, cos, sin, pi, theta0, theta, q, qd, qdd, omega, alpha)
        out = {}
        for j in names if names is not None else self.report:
            P, V, A, _ = self.point(ps, off, self.report[j])
            out[j] = (P, V, A)
        return out


# ----------------------------------------------------------------------------------------------
class RefPose:
    """Reference kinematics at one driver angle (mpf values)."""

    def __init__(self, theta, q, qd, qdd, joints, iterations, seed_step):
        self.theta, self.q, self.qd, self.qdd = theta, q, qd, qdd
        self.joints = joints            # {joint: ((x, y), (vx, vy), (ax, ay))}
        self.iterations = iterations
        self.seed_step = seed_step      # |q − seed|∞ (mm or rad): how far the float seed was

    def position(self, j):
        return self.joints[j][0]

    def velocity(self, j):
        return self.joints[j][1]

    def acceleration(self, j):
        return self.joints[j][2]


class MPReference:
    """``DPS``-digit reference solutions of a linkage's loop equations."""

    def __init__(self, linkage: Linkage, dps: int = DPS, max_iter: int = 40):
        self.system = LoopSystem(linkage)
        self.dps = dps
        self.max_iter = max_iter
        with mpmath.workdps(dps):
            self.theta0 = self.system.drawn_theta(mpmath.mpf, mpmath.atan2)

    def _ev(self, th, q, **kw):
        mp = mpmath.mp
        return self.system.evaluate(mp.mpf, mp.cos, mp.sin, mp.pi, self.theta0, th, q, **kw)

    def newton(self, th, q, tol_digits: int | None = None):
        """Refine q at the mp angle ``th``; returns (q, iterations, max |Δq| total)."""
        mp = mpmath.mp
        tol = mp.mpf(10) ** (-(tol_digits if tol_digits is not None else self.dps // 2 + 8))
        q0 = list(q)
        for it in range(1, self.max_iter + 1):
            phi, J, _, _ = self._ev(th, q)
            dq = mp.lu_solve(mp.matrix(J), mp.matrix([-v for v in phi]))
            q = [q[k] + dq[k] for k in range(len(q))]
            step = max(abs(v) for v in dq)
            if not mp.isfinite(step):
                break
            if step < tol * (1 + max(abs(v) for v in q)):   # the error after this step is ~tol²
                return q, it, max(abs(a - b) for a, b in zip(q, q0))
        raise RuntimeError(f"reference Newton did not converge at θ = {mpmath.nstr(th, 17)}")

    def solve(self, theta: float, seed: Sequence[float], order: int = 2, omega: float | None = None,
              alpha: float = 0.0) -> RefPose:
        """Solve at the float driver angle ``theta`` (rad, taken exactly) from the float ``seed``."""
        mp = mpmath.mp
        with mpmath.workdps(self.dps):
            th = mp.mpf(theta)
            q, it, moved = self.newton(th, [mp.mpf(float(v)) for v in seed])
            return self._finish(th, q, it, moved, order, omega, alpha)

    def _finish(self, th, q, it, moved, order, omega, alpha):
        mp = mpmath.mp
        s = self.system
        qd = qdd = None
        w = mp.mpf(s.omega if omega is None else omega)
        a = mp.mpf(alpha)
        if order >= 1:
            z = [mp.mpf(0)] * len(q)
            _, J, phid, _ = self._ev(th, q, qd=z, qdd=z, omega=w, alpha=a, rates=True)
            Jm = mp.matrix(J)
            qd = list(mp.lu_solve(Jm, mp.matrix([-v for v in phid])))
            if order >= 2:
                _, _, _, phidd = self._ev(th, q, qd=qd, qdd=z, omega=w, alpha=a, jac=False, rates=True)
                qdd = list(mp.lu_solve(Jm, mp.matrix([-v for v in phidd])))
        joints = s.joints(mp.mpf, mp.cos, mp.sin, mp.pi, self.theta0, th, q, qd, qdd, w, a)
        return RefPose(th, q, qd, qdd, joints, it, moved)


# ----------------------------------------------------------------------------------------------
def selftest(linkage: Linkage, dtheta: float = 0.3, verbose: bool = False) -> float:
    """Largest relative difference between the reference's analytic q̇, q̈ and ``mpmath.diff``
    of its position solution along time, θ(t) = θ1 + ω t, at θ1 = drawn angle + ``dtheta``.
    Expected ≲ 1e-40: it validates the differentiated constraints independently."""
    ref = MPReference(linkage, dps=60)
    s = ref.system
    th1 = s.drawn_theta() + dtheta
    base = ref.solve(th1, _continue(ref, th1), order=2)
    w = s.omega
    memo: dict = {}

    def q_at(t):
        key = mpmath.nstr(t, mpmath.mp.dps + 5)
        if key not in memo:
            memo[key] = ref.newton(base.theta + w * t, list(base.q), tol_digits=mpmath.mp.dps)[0]
        return memo[key]

    worst = 0.0
    with mpmath.workdps(60):
        sv = max(abs(v) for v in base.qd) + 1
        sa = max(abs(v) for v in base.qdd) + 1
        for k in range(s.n):
            d1 = mpmath.diff(lambda t: q_at(t)[k], 0, 1)
            d2 = mpmath.diff(lambda t: q_at(t)[k], 0, 2)
            e1, e2 = float(abs(d1 - base.qd[k]) / sv), float(abs(d2 - base.qdd[k]) / sa)
            worst = max(worst, e1, e2)
            if verbose:
                print(f"  q[{k}]: q̇ {e1:.1e}  q̈ {e2:.1e}")
    return worst


def _continue(ref: MPReference, theta: float, steps: int = 30) -> list[float]:
    """A float seed at ``theta`` by continuation from the drawn pose (mp Newton, 20 digits)."""
    s = ref.system
    th0 = s.drawn_theta()
    q = s.seed_drawn()
    with mpmath.workdps(20):
        qm = [mpmath.mpf(v) for v in q]
        for k in range(1, steps + 1):
            th = mpmath.mpf(th0 + (theta - th0) * k / steps)
            qm = ref.newton(th, qm, tol_digits=15)[0]
    return [float(v) for v in qm]


if __name__ == "__main__":  # .venv/bin/python benchmarks/reference_mp.py  -> self-test
    import sys
    from pathlib import Path

    from mechsketch.core.io.scene_file import load_scene

    root = Path(__file__).resolve().parents[1] / "resources" / "examples"
    names = sys.argv[1:] or ["fourbar_crank_rocker", "slider_crank_offset", "sixbar_moving_guide",
                             "inverted_slider_crank", "double_rocker"]
    for name in names:
        lk = load_scene(root / f"{name}.json").elements[0]
        print(f"{name}: {LoopSystem(lk).n} unknowns; analytic q̇, q̈ vs mpmath.diff: "
              f"max rel diff {selftest(lk):.1e}")
