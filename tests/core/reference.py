"""The independent 50-digit reference for the linkage solver tests (no solver formula is reused).

* :class:`MpReference` — the whole linkage as raw rigid-body constraint equations, solved in
  mpmath at 50 digits by Newton's method from the float solution. Each moving link has a pose
  (x, y, θ): the point drawn at ``p0`` is at (x, y) + R(θ)(p0 − c), c the drawn position of the
  link's first joint. Constraints: an R joint shared by links a, b gives P_a(p0) = P_b(p0); a P
  joint gives θ_a = θ_b and cross(R(θ_a)u0, P_b(p0) − P_a(p0)) = 0. Velocities and accelerations
  solve the once and twice time-differentiated equations (linear in the rates), in mpmath.
  Nothing here knows about dyads, modes or Cramer's rule.
* :func:`compare`, :func:`relative` — a solution's errors against that reference.
* :func:`continuation` — a generic float Newton continuation from the drawn pose, the same
  equations as the mpmath reference: an independent check of assembly-mode selection.

The test linkages are built in :mod:`linkage_builders`; checks from the public Solution API alone
(closure, finite differences, assembly-mode signs) are in :mod:`solution_checks`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath
import numpy as np

from linkage_builders import size_of
from mechsketch.core import JointKind, Linkage

R, P = JointKind.R, JointKind.P
DPS = 50


# ---------------------------------------------------------------------------------------------
# the 50-digit reference
# ---------------------------------------------------------------------------------------------
@dataclass
class RefState:
    """Poses and rates of every link at one driver angle, mpmath numbers."""

    pose: dict      # link -> (x, y, th)
    rate: dict      # link -> (xd, yd, thd)
    acc: dict       # link -> (xdd, ydd, thdd)
    c: dict         # link -> (cx, cy) drawn reference point
    iterations: int

    def point(self, link: str, p0):
        """(P, V, A) of the point of ``link`` drawn at p0, each an (x, y) pair of mpf."""
        x, y, th = self.pose[link]
        xd, yd, thd = self.rate[link]
        xdd, ydd, thdd = self.acc[link]
        cx, cy = self.c[link]
        dx, dy = mpmath.mpf(p0[0]) - cx, mpmath.mpf(p0[1]) - cy
        co, si = mpmath.cos(th), mpmath.sin(th)
        rx, ry = co * dx - si * dy, si * dx + co * dy
        P = (x + rx, y + ry)
        V = (xd - thd * ry, yd + thd * rx)
        A = (xdd - thdd * ry - thd * thd * rx, ydd + thdd * rx - thd * thd * ry)
        return P, V, A


class _Num:
    """Arithmetic backend of the constraint system: mpmath (reference) or float (continuation)."""

    def __init__(self, kind: str):
        self.kind = kind
        if kind == "mp":
            self.cos, self.sin, self.num = mpmath.cos, mpmath.sin, mpmath.mpf
            self.zero, self.one = mpmath.mpf(0), mpmath.mpf(1)
        else:
            self.cos, self.sin, self.num = math.cos, math.sin, float
            self.zero, self.one = 0.0, 1.0

    def zeros(self, n):
        return mpmath.mp.zeros(n, n) if self.kind == "mp" else np.zeros((n, n))


class MpReference:
    """The linkage's constraint equations, in mpmath at ``dps`` digits (see the module docstring).

    ``backend="float"`` evaluates the same equations in float64 (for :func:`continuation`).
    """

    def __init__(self, linkage: Linkage, dps: int = DPS, backend: str = "mp"):
        self.lk = linkage
        self.dps = dps
        self.N = N = _Num(backend)
        self._cos, self._sin = N.cos, N.sin
        with mpmath.workdps(dps):
            self.ground = linkage.ground
            self.driver = linkage.driver.link
            self.unknown = [k.id for k in linkage.links if k.id not in (self.ground, self.driver)]
            self.col = {k: 3 * i for i, k in enumerate(self.unknown)}
            at = {j.id: (N.num(j.at[0]), N.num(j.at[1])) for j in linkage.joints}
            self.at = at
            self.c = {k.id: at[k.joints[0]] for k in linkage.links}
            drv = linkage.driver
            self.c[self.driver] = at[drv.pivot]
            tip = next(x for x in linkage.link(drv.link).joints if x != drv.pivot)
            pv, tp = linkage.joint(drv.pivot).at, linkage.joint(tip).at
            self.theta0 = mpmath.atan2(mpmath.mpf(tp[1]) - pv[1], mpmath.mpf(tp[0]) - pv[0])
            known = (self.ground, self.driver)
            self.rc = []    # (joint, link a, link b)
            self.pc = []    # (joint, link a, link b, u0)
            for j in linkage.joints:
                carriers = sorted(linkage.links_of(j.id), key=lambda k: (k not in known,))
                if j.kind is R:
                    for b in carriers[1:]:
                        if {carriers[0], b} == set(known):
                            continue
                        self.rc.append((j.id, carriers[0], b))
                else:
                    a, b = carriers
                    ang = mpmath.radians(mpmath.mpf(j.axis_deg))
                    self.pc.append((j.id, a, b, (N.num(mpmath.cos(ang)), N.num(mpmath.sin(ang)))))
            self.n = 3 * len(self.unknown)
            m = 2 * len(self.rc) + 2 * len(self.pc)
            if m != self.n:
                raise ValueError(f"reference needs a square system: {m} equations, {self.n} unknowns")

    # -- kinematics of one link's points ----------------------------------------------------
    def _r(self, link, pose, p0):
        x, y, th = pose[link]
        cx, cy = self.c[link]
        dx, dy = p0[0] - cx, p0[1] - cy
        co, si = self._cos(th), self._sin(th)
        return co * dx - si * dy, si * dx + co * dy

    def _u(self, th, u0):
        co, si = self._cos(th), self._sin(th)
        return co * u0[0] - si * u0[1], si * u0[0] + co * u0[1]

    def _poses(self, q, rho):
        N = self.N
        pose = {self.ground: (self.c[self.ground][0], self.c[self.ground][1], N.zero),
                self.driver: (self.c[self.driver][0], self.c[self.driver][1], rho)}
        for k in self.unknown:
            i = self.col[k]
            pose[k] = (q[i], q[i + 1], q[i + 2])
        return pose

    def _rates(self, qd, w):
        N = self.N
        rate = {self.ground: (N.zero, N.zero, N.zero), self.driver: (N.zero, N.zero, w)}
        for k in self.unknown:
            i = self.col[k]
            rate[k] = (qd[i], qd[i + 1], qd[i + 2])
        return rate

    def _pva(self, link, p0, pose, rate=None, acc=None):
        rx, ry = self._r(link, pose, p0)
        P = (pose[link][0] + rx, pose[link][1] + ry)
        if rate is None:
            return P, None, None
        xd, yd, thd = rate[link]
        V = (xd - thd * ry, yd + thd * rx)
        if acc is None:
            return P, V, None
        xdd, ydd, thdd = acc[link]
        return P, V, (xdd - thdd * ry - thd * thd * rx, ydd + thdd * rx - thd * thd * ry)

    # -- the equations ----------------------------------------------------------------------
    def residual(self, q, rho):
        """F(q; ρ): R joints P_a − P_b (2 rows); P joints sin(θa − θb), cross(u_a, P_b − P_a)."""
        pose = self._poses(q, rho)
        out = []
        for jid, a, b in self.rc:
            (pa, _, _), (pb, _, _) = self._pva(a, self.at[jid], pose), self._pva(b, self.at[jid], pose)
            out += [pa[0] - pb[0], pa[1] - pb[1]]
        for jid, a, b, u0 in self.pc:
            ux, uy = self._u(pose[a][2], u0)
            (pa, _, _), (pb, _, _) = self._pva(a, self.at[jid], pose), self._pva(b, self.at[jid], pose)
            out += [self._sin(pose[a][2] - pose[b][2]), ux * (pb[1] - pa[1]) - uy * (pb[0] - pa[0])]
        return out

    def jacobian(self, q, rho):
        """∂F/∂q, written out by hand."""
        pose = self._poses(q, rho)
        J = self.N.zeros(self.n)
        row = 0

        def put(r, link, ddx, ddy, dth):
            if link in self.col:
                i = self.col[link]
                J[r, i] += ddx
                J[r, i + 1] += ddy
                J[r, i + 2] += dth

        for jid, a, b in self.rc:
            ra, rb = self._r(a, pose, self.at[jid]), self._r(b, pose, self.at[jid])
            put(row, a, 1, 0, -ra[1])
            put(row + 1, a, 0, 1, ra[0])
            put(row, b, -1, 0, rb[1])
            put(row + 1, b, 0, -1, -rb[0])
            row += 2
        for jid, a, b, u0 in self.pc:
            ux, uy = self._u(pose[a][2], u0)
            ra, rb = self._r(a, pose, self.at[jid]), self._r(b, pose, self.at[jid])
            dx = pose[b][0] + rb[0] - pose[a][0] - ra[0]
            dy = pose[b][1] + rb[1] - pose[a][1] - ra[1]
            cd = self._cos(pose[a][2] - pose[b][2])
            put(row, a, 0, 0, cd)
            put(row, b, 0, 0, -cd)
            # g = ux·dy − uy·dx; ∂u/∂θa = (−uy, ux); ∂d/∂(xb, yb, θb) = (1, 0), (0, 1), J rb;
            # ∂d/∂(xa, ya, θa) = −(1, 0), −(0, 1), −J ra
            put(row + 1, b, -uy, ux, ux * rb[0] + uy * rb[1])
            put(row + 1, a, uy, -ux, -(ux * ra[0] + uy * ra[1]) - uy * dy - ux * dx)
            row += 2
        return J

    def vel_residual(self, q, qd, rho, w):
        """dF/dt for unknown rates qd and driver speed w (linear in qd; P rows at cos(θa−θb) = 1)."""
        pose, rate = self._poses(q, rho), self._rates(qd, w)
        out = []
        for jid, a, b in self.rc:
            (_, va, _), (_, vb, _) = self._pva(a, self.at[jid], pose, rate), self._pva(b, self.at[jid], pose, rate)
            out += [va[0] - vb[0], va[1] - vb[1]]
        for jid, a, b, u0 in self.pc:
            thd = rate[a][2]
            ux, uy = self._u(pose[a][2], u0)
            (pa, va, _), (pb, vb, _) = self._pva(a, self.at[jid], pose, rate), self._pva(b, self.at[jid], pose, rate)
            dx, dy = pb[0] - pa[0], pb[1] - pa[1]
            dvx, dvy = vb[0] - va[0], vb[1] - va[1]
            udx, udy = -thd * uy, thd * ux
            out += [rate[a][2] - rate[b][2], (udx * dy - udy * dx) + (ux * dvy - uy * dvx)]
        return out

    def acc_residual(self, q, qd, qdd, rho, w, al):
        """d²F/dt² (linear in the unknown accelerations qdd)."""
        N = self.N
        pose, rate = self._poses(q, rho), self._rates(qd, w)
        acc = {self.ground: (N.zero, N.zero, N.zero), self.driver: (N.zero, N.zero, al)}
        for k in self.unknown:
            i = self.col[k]
            acc[k] = (qdd[i], qdd[i + 1], qdd[i + 2])

        def cr(p, r):
            return p[0] * r[1] - p[1] * r[0]

        out = []
        for jid, a, b in self.rc:
            (_, _, aa), (_, _, ab) = (self._pva(a, self.at[jid], pose, rate, acc),
                                      self._pva(b, self.at[jid], pose, rate, acc))
            out += [aa[0] - ab[0], aa[1] - ab[1]]
        for jid, a, b, u0 in self.pc:
            thd, thdd = rate[a][2], acc[a][2]
            ux, uy = self._u(pose[a][2], u0)
            (pa, va, aa), (pb, vb, ab) = (self._pva(a, self.at[jid], pose, rate, acc),
                                          self._pva(b, self.at[jid], pose, rate, acc))
            d = (pb[0] - pa[0], pb[1] - pa[1])
            dv = (vb[0] - va[0], vb[1] - va[1])
            da = (ab[0] - aa[0], ab[1] - aa[1])
            ud = (-thd * uy, thd * ux)
            udd = (-thdd * uy - thd * thd * ux, thdd * ux - thd * thd * uy)
            out += [acc[a][2] - acc[b][2], cr(udd, d) + 2 * cr(ud, dv) + cr((ux, uy), da)]
        return out

    # -- solving (mpmath backend) -----------------------------------------------------------
    @staticmethod
    def _lu(J):
        """LU factors with partial pivoting of a square mp.matrix, on plain lists (fast)."""
        n = J.rows
        a = [[J[i, k] for k in range(n)] for i in range(n)]
        perm = list(range(n))
        for c in range(n):
            piv = max(range(c, n), key=lambda r: abs(a[r][c]))
            if a[piv][c] == 0:
                raise ZeroDivisionError("singular Jacobian")
            a[c], a[piv] = a[piv], a[c]
            perm[c], perm[piv] = perm[piv], perm[c]
            inv = 1 / a[c][c]
            rowc = a[c]
            for r in range(c + 1, n):
                f = a[r][c] * inv
                if f:
                    rowr = a[r]
                    rowr[c] = f
                    for k in range(c + 1, n):
                        rowr[k] -= f * rowc[k]
                else:
                    a[r][c] = f
        return a, perm

    @staticmethod
    def _lu_solve(lu, b):
        a, perm = lu
        n = len(a)
        y = [b[p] for p in perm]
        for i in range(n):
            row = a[i]
            y[i] = y[i] - sum((row[k] * y[k] for k in range(i)), mpmath.mpf(0))
        for i in range(n - 1, -1, -1):
            row = a[i]
            y[i] = (y[i] - sum((row[k] * y[k] for k in range(i + 1, n)), mpmath.mpf(0))) / row[i]
        return mpmath.mp.matrix(y)

    def solve_positions(self, rho, guess):
        """Chord-Newton from ``guess`` (3 floats per unknown link; the Jacobian factored at the
        guess), then one full Newton step; returns (q, iterations, LU of the final Jacobian)."""
        mp = mpmath.mp
        if not self.n:
            return [], 0, None
        q = mp.matrix([mp.mpf(v) for v in guess])
        scale = max([abs(mp.mpf(c)) for p in self.at.values() for c in p] + [mp.one])
        tol = mp.mpf(10) ** (-(mp.dps - 6)) * scale
        lu = self._lu(self.jacobian(q, rho))
        for it in range(1, 80):
            dq = self._lu_solve(lu, [-v for v in self.residual(q, rho)])
            q = q + dq
            if max(abs(v) for v in dq) <= tol:
                break
            if it % 10 == 0:  # slow chord convergence: refresh the Jacobian
                lu = self._lu(self.jacobian(q, rho))
        else:
            raise RuntimeError("reference Newton did not converge")
        lu = self._lu(self.jacobian(q, rho))
        q = q + self._lu_solve(lu, [-v for v in self.residual(q, rho)])
        return q, it, lu

    def solve(self, inp: float, w: float, guess, al: float = 0.0) -> RefState:
        """Positions, rates and accelerations at driver angle ``inp`` (rad), speed ``w`` (rad/s)
        and driver angular acceleration ``al``, from a float ``guess`` (see :meth:`guess_from`)."""
        mp = mpmath.mp
        with mpmath.workdps(self.dps):
            rho = mp.mpf(inp) - self.theta0
            q, its, lu = self.solve_positions(rho, guess)
            w, al = mp.mpf(w), mp.mpf(al)
            zero = [mp.zero] * self.n
            if self.n:
                qd = self._lu_solve(lu, [-v for v in self.vel_residual(q, zero, rho, w)])
                qdd = self._lu_solve(lu, [-v for v in self.acc_residual(q, qd, zero, rho, w, al)])
            else:
                qd = qdd = []
            pose = self._poses(q, rho)
            rate = self._rates(qd, w)
            acc = {self.ground: (mp.zero,) * 3, self.driver: (mp.zero, mp.zero, al)}
            for k in self.unknown:
                i = self.col[k]
                acc[k] = (qdd[i], qdd[i + 1], qdd[i + 2])
            return RefState(pose, rate, acc, self.c, its)

    def guess_from(self, sol, k: int, arr=None) -> list[float]:
        """Float initial guess at sample ``k`` of a Solution, from sol.point only."""
        out = []
        pt = (lambda link, p0: arr("point", link, p0)) if arr else sol.point
        for link in self.unknown:
            c = (float(self.c[link][0]), float(self.c[link][1]))
            p = pt(link, c)[k]
            px = pt(link, (c[0] + 1.0, c[1]))[k]
            out += [p[0], p[1], math.atan2(px[1] - p[1], px[0] - p[0])]
        return out


def compare(linkage: Linkage, sol, samples, ref: MpReference | None = None) -> dict:
    """Errors of ``sol`` (order 2) against the 50-digit reference at sample indices ``samples``.

    Every link's joints (via sol.point/point_velocity/point_acceleration), every joint via
    sol.position/velocity/acceleration (P joints: the later link in the file), and every moving
    link's angle (mod 2π), omega, alpha. Returns absolute maxima and the reference scales.
    """
    ref = ref or MpReference(linkage)
    mp = mpmath.mp
    err = dict(pos=0.0, vel=0.0, acc=0.0, ang=0.0, omega=0.0, alpha=0.0)
    scale = dict(vel=0.0, acc=0.0, omega=0.0, alpha=0.0)
    order = linkage.link_ids
    arrays = {}

    def arr(kind, link, p0):
        key = (kind, link, p0)
        if key not in arrays:
            fn = getattr(sol, kind)
            arrays[key] = fn(link) if p0 is None else fn(link, p0)
        return arrays[key]

    for k in samples:
        st = ref.solve(float(sol.input[k]), sol.omega_driver, ref.guess_from(sol, k, arr))
        with mpmath.workdps(ref.dps):
            for lk in linkage.links:
                for p0 in [linkage.joint(j).at for j in lk.joints]:
                    Pr, Vr, Ar = st.point(lk.id, p0)
                    fp = arr("point", lk.id, p0)[k]
                    fv = arr("point_velocity", lk.id, p0)[k]
                    fa = arr("point_acceleration", lk.id, p0)[k]
                    for name, f, r in (("pos", fp, Pr), ("vel", fv, Vr), ("acc", fa, Ar)):
                        d = float(mp.hypot(mp.mpf(f[0]) - r[0], mp.mpf(f[1]) - r[1]))
                        err[name] = max(err[name], d)
                        if name != "pos":
                            scale[name] = max(scale[name], float(mp.hypot(*r)))
                if lk.id == linkage.ground:
                    continue
                th = st.pose[lk.id][2]
                if lk.id == linkage.driver.link:
                    th = mp.mpf(sol.input[k]) - ref.theta0
                pv = [complex(*linkage.joint(j).at) for j in lk.joints[:2]]
                a0 = (mp.atan2(mp.mpf(pv[1].imag) - pv[0].imag, mp.mpf(pv[1].real) - pv[0].real)
                      if len(pv) == 2 and pv[1] != pv[0] else 0)
                dang = mp.mpf(arr("angle", lk.id, None)[k]) - (th + a0)
                dang = dang - 2 * mp.pi * mp.nint(dang / (2 * mp.pi))
                err["ang"] = max(err["ang"], float(abs(dang)))
                for name, f, r in (("omega", arr("omega", lk.id, None)[k], st.rate[lk.id][2]),
                                   ("alpha", arr("alpha", lk.id, None)[k], st.acc[lk.id][2])):
                    err[name] = max(err[name], float(abs(mp.mpf(f) - r)))
                    scale[name] = max(scale[name], float(abs(r)))
            for j in linkage.joints:
                carriers = linkage.links_of(j.id)
                rep = max(carriers, key=order.index) if j.kind is P else carriers[0]
                Pr, Vr, Ar = st.point(rep, j.at)
                for name, f, r in (("pos", arr("position", j.id, None)[k], Pr),
                                   ("vel", arr("velocity", j.id, None)[k], Vr),
                                   ("acc", arr("acceleration", j.id, None)[k], Ar)):
                    d = float(mp.hypot(mp.mpf(f[0]) - r[0], mp.mpf(f[1]) - r[1]))
                    err[name] = max(err[name], d)
    err["scale"] = scale
    err["size"] = size_of(linkage)
    err["w"] = abs(sol.omega_driver)
    return err


def relative(err: dict) -> dict:
    """Relative errors: positions to the mechanism's size, angles in rad, rates to the largest
    reference value of their kind (ω floored at |ω_driver|, α at ω_driver²)."""
    s = err["scale"]
    size = err["size"]
    w = err["w"]
    return dict(pos=err["pos"] / size, ang=err["ang"],
                vel=err["vel"] / max(s["vel"], 1e-300), acc=err["acc"] / max(s["acc"], 1e-300),
                omega=err["omega"] / max(s["omega"], w), alpha=err["alpha"] / max(s["alpha"], w * w))


# ---------------------------------------------------------------------------------------------
# a generic float Newton continuation (independent branch following)
# ---------------------------------------------------------------------------------------------
def continuation(linkage: Linkage, inputs, substeps: int = 4):
    """Follow the constraint equations from the drawn pose through ``inputs`` (rad; inputs[0]
    must be the drawn input) by Newton steps with a tangent predictor, in float64.

    Returns ({link: (N, 3) poses (x, y, θ)}, reference); rows are NaN from the first sample
    where Newton fails (e.g. past an assembly limit)."""
    ref = MpReference(linkage, backend="float")
    n = ref.n
    q = np.zeros(n)
    for link in ref.unknown:
        i = ref.col[link]
        q[i], q[i + 1] = ref.c[link]
    th0 = float(ref.theta0)
    out = np.full((len(inputs), n), np.nan)
    out[0] = q
    scale = size_of(linkage)
    zero = np.zeros(n)
    for k in range(1, len(inputs)):
        a, b = inputs[k - 1] - th0, inputs[k] - th0
        ok = True
        for s in range(1, substeps + 1):
            rho0 = a + (b - a) * (s - 1) / substeps
            rho = a + (b - a) * s / substeps
            try:
                tangent = np.linalg.solve(ref.jacobian(q, rho0), -np.array(ref.vel_residual(q, zero, rho0, 1.0)))
                qn = q + tangent * (rho - rho0)
                for _ in range(20):
                    dq = np.linalg.solve(ref.jacobian(qn, rho), -np.array(ref.residual(qn, rho)))
                    qn = qn + dq
                    if np.max(np.abs(dq)) < 1e-12 * scale:
                        break
            except np.linalg.LinAlgError:
                ok = False
            if not ok or not np.all(np.isfinite(qn)) or np.max(np.abs(ref.residual(qn, rho))) > 1e-9 * scale:
                ok = False
                break
            q = qn
        if not ok:
            break
        out[k] = q
    return {link: out[:, ref.col[link]:ref.col[link] + 3] for link in ref.unknown}, ref


def continuation_point(ref: MpReference, poses: dict, link: str, p0) -> np.ndarray:
    """(N,) complex positions of the point of ``link`` drawn at p0, from :func:`continuation`."""
    pz = poses[link]
    c = complex(*ref.c[link])
    return pz[:, 0] + 1j * pz[:, 1] + np.exp(1j * pz[:, 2]) * (complex(*p0) - c)
