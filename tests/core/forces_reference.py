"""Independent references for the kinetostatics tests: the whole mechanism's equilibrium, one
linear system per sample, knowing nothing of Assur groups.

Unknowns: for every revolute joint the force on each of its links after the first (file order)
from the joint (the first link takes minus their sum); for every prismatic joint (links a, b in
file order) the size N of the force on b along n = J·R(θ_a)·u0 at b's point of the joint, and the
couple C on b (a gets the opposite); the driver torque. Equations: force and moment balance of
every moving link (3 each), with gravity, d'Alembert inertia and the loads written out here again
from the scene's fields (not the core's code). The kinematics come from an adaptor:

* :class:`FloatKin` — the float :class:`Solution` at one sample (numpy solve: the "independent
  linear solve" of the issue);
* :class:`MpKin` — the 50-digit mpmath reference of :mod:`reference` at one sample (mpmath
  ``lu_solve``: the mpmath reference, independent of the float kinematics too);
* :class:`DriveKin` — the 50-digit reference of :mod:`reference_drive` for any driver (a crank, a
  cylinder of driven length, a slider driven along its guide): positions by Newton at 80 digits,
  rates by five-point differences in the input.

The driver's unknown is a torque T on the crank (N·m, counter-clockwise), or for a linear actuator
a force P (N, positive extending): a slider's push along its guide's direction u0 at its point of
the guide (the frame takes −P·u0 there); a cylinder's push on its rod along the slide axis
u = R(θ_barrel)·u0 turned towards the rod's pivot H, at the rod's point of the slide, and the
opposite on the barrel.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np

from mechsketch.core import JointKind, Linkage
from mechsketch.core.model.drivers import DriverKind
from reference import MpReference
from reference_drive import WORK, DriveReference

R = JointKind.R


class FloatKin:
    """Kinematics of ``sol`` at sample ``k`` (mm, mm/s, mm/s², rad, rad/s, rad/s²)."""

    def __init__(self, sol, k: int) -> None:
        self.sol, self.k = sol, k
        self.num = float

    def pva(self, link, p0):
        s, k = self.sol, self.k
        return (tuple(s.point(link, p0)[k]), tuple(s.point_velocity(link, p0)[k]),
                tuple(s.point_acceleration(link, p0)[k]))

    def omega(self, link):
        return float(self.sol.omega(link)[self.k])

    def alpha(self, link):
        return float(self.sol.alpha(link)[self.k])

    def theta(self, link):
        return float(self.sol.rotation(link)[self.k])

    def cos(self, x):
        return math.cos(x)

    def sin(self, x):
        return math.sin(x)

    def sqrt(self, x):
        return math.sqrt(x)

    def solve(self, A, b):
        return list(np.linalg.solve(np.array(A, dtype=float), np.array(b, dtype=float)))


class MpKin:
    """The 50-digit reference kinematics at the input and speed of ``sol``'s sample ``k``."""

    def __init__(self, ref: MpReference, sol, k: int) -> None:
        self.st = ref.solve(float(sol.input[k]), sol.omega_driver, ref.guess_from(sol, k))
        self.ref = ref
        self.num = mpmath.mpf

    def pva(self, link, p0):
        return self.st.point(link, p0)

    def omega(self, link):
        return self.st.rate[link][2]

    def alpha(self, link):
        return self.st.acc[link][2]

    def theta(self, link):
        return self.st.pose[link][2]

    def cos(self, x):
        return mpmath.cos(x)

    def sin(self, x):
        return mpmath.sin(x)

    def sqrt(self, x):
        return mpmath.sqrt(x)

    def solve(self, A, b):
        x = mpmath.lu_solve(mpmath.matrix(A), mpmath.matrix(b))
        return [x[i] for i in range(len(b))]


class DriveKin:
    """The 50-digit kinematics of :class:`reference_drive.DriveReference` at the input and input
    rates of ``sol``'s sample ``k``: positions at five inputs q0 + j·h (h = 1e-12·max(|q0|, 1)),
    velocities and accelerations of points and links by five-point differences."""

    def __init__(self, ref: DriveReference, sol, k: int) -> None:
        mp = mpmath.mp
        self.ref, self.k, self.num = ref, k, mpmath.mpf
        self.qd = float(np.broadcast_to(sol.omega_driver, (len(sol),))[k])
        self.qdd = float(np.broadcast_to(sol.alpha_driver, (len(sol),))[k])
        guess = ref.guess_from(sol, k)
        with mpmath.workdps(WORK):
            q0 = mp.mpf(float(sol.input[k]))
            self.h = mp.mpf("1e-12") * max(abs(q0), mp.one)
            self.qs = {j: ref.positions(q0 + j * self.h, guess) for j in (-2, -1, 0, 1, 2)}

    def _pva(self, f: dict):
        with mpmath.workdps(WORK):
            h = self.h
            d1 = (f[-2] - 8 * f[-1] + 8 * f[1] - f[2]) / (12 * h)
            d2 = (-f[-2] + 16 * f[-1] - 30 * f[0] + 16 * f[1] - f[2]) / (12 * h * h)
            return f[0], d1 * self.qd, d2 * self.qd * self.qd + d1 * self.qdd

    def pva(self, link, p0):
        with mpmath.workdps(WORK):
            p0 = (mpmath.mpf(p0[0]), mpmath.mpf(p0[1]))
            pts = {j: self.ref.point(q, link, p0) for j, q in self.qs.items()}
            x, y = (self._pva({j: pts[j][c] for j in pts}) for c in (0, 1))
            return tuple(zip(x, y))

    def _theta(self, link):
        return self._pva({j: self.ref.theta(q, link) for j, q in self.qs.items()})

    def omega(self, link):
        return self._theta(link)[1]

    def alpha(self, link):
        return self._theta(link)[2]

    def theta(self, link):
        return self.ref.theta(self.qs[0], link)

    def cos(self, x):
        return mpmath.cos(x)

    def sin(self, x):
        return mpmath.sin(x)

    def sqrt(self, x):
        return mpmath.sqrt(x)

    def solve(self, A, b):
        x = mpmath.lu_solve(mpmath.matrix(A), mpmath.matrix(b))
        return [x[i] for i in range(len(b))]


def equilibrium(lk: Linkage, kin, couples: dict | None = None) -> dict:
    """Driver torque (N·m; for a linear actuator its force, N, see the module docstring), revolute-joint forces {(joint, link): (Fx, Fy)} N, prismatic
    reactions {joint: (N, C)} (N, N·m about the later link's point of the joint), shaking force
    (Fx, Fy) N and moment N·m about the driver pivot, at one sample of ``kin``. ``couples``:
    further known couples {link: N·m} (the friction moments of a result under test)."""
    num = kin.num
    mm = num(1) / 1000
    moving = [k for k in lk.link_ids if k != lk.ground]
    row = {k: 3 * i for i, k in enumerate(moving)}
    cols: list[tuple] = []
    for j in lk.joints:
        carriers = lk.links_of(j.id)
        if len(carriers) < 2:
            continue
        if j.kind is R:
            for b in carriers[1:]:
                cols += [("pin", j.id, b, 0), ("pin", j.id, b, 1)]
        else:
            cols += [("N", j.id), ("C", j.id)]
    cols.append(("T",))
    n = 3 * len(moving)
    assert len(cols) == n, (len(cols), n)
    A = [[num(0)] * n for _ in range(n)]
    rhs = [num(0)] * n
    qref = {k: kin.pva(k, lk.joint(lk.link(k).joints[0]).at)[0] for k in moving}

    def add(link, col, fx, fy, p):
        """Unknown ``col`` contributes force (fx, fy)·x at point p to ``link``."""
        if link == lk.ground:
            return
        r = row[link]
        q = qref[link]
        A[r][col] += fx
        A[r + 1][col] += fy
        A[r + 2][col] += mm * ((p[0] - q[0]) * fy - (p[1] - q[1]) * fx)

    def add_couple(link, col, c):
        if link != lk.ground:
            A[row[link] + 2][col] += c

    def load(link, fx, fy, p):
        """A known force at point p: moved to the right-hand side."""
        if link == lk.ground:
            return
        r = row[link]
        q = qref[link]
        rhs[r] -= fx
        rhs[r + 1] -= fy
        rhs[r + 2] -= mm * ((p[0] - q[0]) * fy - (p[1] - q[1]) * fx)

    def load_couple(link, c):
        if link != lk.ground:
            rhs[row[link] + 2] -= c

    def axis_normal(link, jid):
        u0 = math.radians(lk.joint(jid).axis_deg)
        th = kin.theta(link) + num(u0)
        return -kin.sin(th), kin.cos(th)

    def actuator():
        """(ex, ey, point, link pushed, link pushing): the direction of a positive driving force."""
        drv = lk.driver
        jid = drv.pivot
        ang = num(math.radians(lk.joint(jid).axis_deg))
        if drv.kind is DriverKind.SLIDER:
            return kin.cos(ang), kin.sin(ang), kin.pva(drv.link, lk.joint(jid).at)[0], drv.link, lk.ground
        rod = next(k for k in lk.links_of(jid) if k != drv.link)
        th = kin.theta(drv.link) + ang
        ux, uy = kin.cos(th), kin.sin(th)
        m = next(x for x in lk.link(drv.link).joints if x != jid)
        h = next(x for x in lk.link(rod).joints if x != jid)
        pm, ph = kin.pva(drv.link, lk.joint(m).at)[0], kin.pva(rod, lk.joint(h).at)[0]
        sign = 1 if ux * (ph[0] - pm[0]) + uy * (ph[1] - pm[1]) >= 0 else -1
        return sign * ux, sign * uy, kin.pva(rod, lk.joint(jid).at)[0], rod, drv.link

    for c, key in enumerate(cols):
        if key[0] == "pin":
            _, jid, b, comp = key
            p = kin.pva(b, lk.joint(jid).at)[0]
            first = lk.links_of(jid)[0]
            fx, fy = (num(1), num(0)) if comp == 0 else (num(0), num(1))
            add(b, c, fx, fy, p)
            add(first, c, -fx, -fy, p)
        elif key[0] == "N":
            jid = key[1]
            a, b = lk.links_of(jid)
            nx, ny = axis_normal(a, jid)
            p = kin.pva(b, lk.joint(jid).at)[0]
            add(b, c, nx, ny, p)
            add(a, c, -nx, -ny, p)
        elif key[0] == "C":
            a, b = lk.links_of(key[1])
            add_couple(b, c, num(1))
            add_couple(a, c, num(-1))
        elif lk.driver.kind is DriverKind.CRANK:
            add_couple(lk.driver.link, c, num(1))
        else:
            ex, ey, p, on, other = actuator()
            add(on, c, ex, ey, p)
            add(other, c, -ex, -ey, p)

    gx, gy = (num(lk.gravity[0]), num(lk.gravity[1])) if lk.gravity else (num(0), num(0))
    for m in lk.masses:
        if m.link == lk.ground:
            continue
        pts = [lk.joint(j).at for j in lk.link(m.link).joints]
        c0 = m.com if m.com is not None else (sum(num(p[0]) for p in pts) / len(pts),
                                              sum(num(p[1]) for p in pts) / len(pts))
        if m.inertia is not None:
            inertia = num(m.inertia)
        else:
            span = max(kin.sqrt((num(p[0]) - q[0]) ** 2 + (num(p[1]) - q[1]) ** 2) for p in pts for q in pts)
            inertia = num(m.mass) * (span * mm) ** 2 / 12
        P, _, Acc = kin.pva(m.link, c0)
        mass = num(m.mass)
        load(m.link, mass * (gx - mm * Acc[0]), mass * (gy - mm * Acc[1]), P)
        load_couple(m.link, -inertia * kin.alpha(m.link))
    for ld in lk.loads:
        if ld.kind == "force":
            P = kin.pva(ld.link, ld.at)[0]
            load(ld.link, num(ld.force[0]), num(ld.force[1]), P)
        elif ld.kind == "torque":
            load_couple(ld.link, num(ld.torque))
        else:
            (Pa, Va, _), (Pb, Vb, _) = (kin.pva(e.link, e.at) for e in ld.ends)
            dx, dy = Pb[0] - Pa[0], Pb[1] - Pa[1]
            length = kin.sqrt(dx * dx + dy * dy)
            ex, ey = dx / length, dy / length
            if ld.kind == "spring":
                free = ld.free_length
                if free is None:
                    (ax, ay), (bx, by) = ld.ends[0].at, ld.ends[1].at
                    free = kin.sqrt((num(bx) - ax) ** 2 + (num(by) - ay) ** 2)
                tension = num(ld.stiffness) * (length - free)
            else:
                tension = num(ld.damping) * ((Vb[0] - Va[0]) * ex + (Vb[1] - Va[1]) * ey)
            load(ld.ends[0].link, tension * ex, tension * ey, Pa)
            load(ld.ends[1].link, -tension * ex, -tension * ey, Pb)

    for link, c in (couples or {}).items():
        load_couple(link, num(c))
    x = kin.solve(A, rhs)
    out = {"T": x[-1], "pins": {}, "slides": {}}
    for c, key in enumerate(cols):
        if key[0] == "pin" and key[3] == 0:
            out["pins"][(key[1], key[2])] = (x[c], x[c + 1])
        elif key[0] == "N":
            out["slides"][key[1]] = (x[c], x[c + 1])
    # the frame: reactions of its joints, spring/damper ends on it, the motor's stator
    pv = kin.pva(lk.ground, lk.joint(lk.driver.pivot).at)[0]
    sfx = sfy = sm = num(0)

    def on_frame(fx, fy, p):
        nonlocal sfx, sfy, sm
        sfx += fx
        sfy += fy
        sm += mm * ((p[0] - pv[0]) * fy - (p[1] - pv[1]) * fx)

    for (jid, b), (fx, fy) in out["pins"].items():
        first = lk.links_of(jid)[0]
        p = kin.pva(b, lk.joint(jid).at)[0]
        if b == lk.ground:
            on_frame(fx, fy, p)
        elif first == lk.ground:
            on_frame(-fx, -fy, p)
    for jid, (N, C) in out["slides"].items():
        a, b = lk.links_of(jid)
        nx, ny = axis_normal(a, jid)
        p = kin.pva(b, lk.joint(jid).at)[0]
        if a == lk.ground:
            on_frame(-N * nx, -N * ny, p)
            sm -= C
        elif b == lk.ground:
            on_frame(N * nx, N * ny, p)
            sm += C
    for ld in lk.loads:
        if ld.kind in ("spring", "damper") and lk.ground in ld.links:
            (Pa, Va, _), (Pb, Vb, _) = (kin.pva(e.link, e.at) for e in ld.ends)
            dx, dy = Pb[0] - Pa[0], Pb[1] - Pa[1]
            length = kin.sqrt(dx * dx + dy * dy)
            ex, ey = dx / length, dy / length
            if ld.kind == "spring":
                tension = num(ld.stiffness) * (length - num(ld.rest_length))
            else:
                tension = num(ld.damping) * ((Vb[0] - Va[0]) * ex + (Vb[1] - Va[1]) * ey)
            if ld.ends[0].link == lk.ground:
                on_frame(tension * ex, tension * ey, Pa)
            else:
                on_frame(-tension * ex, -tension * ey, Pb)
    if lk.driver.kind is DriverKind.CRANK:
        sm -= x[-1]   # the motor's stator
    elif lk.driver.kind is DriverKind.SLIDER:
        ex, ey, p, _on, _by = actuator()
        on_frame(-x[-1] * ex, -x[-1] * ey, p)
    sm -= sum((num(c) for link, c in (couples or {}).items() if link == lk.ground), num(0))
    out["shaking"] = (sfx, sfy, sm)
    return out
