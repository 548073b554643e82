"""The engine of the kinetostatics: each link's applied and inertia loads, then one closed-form
pass over the Assur groups from the last back to the driver (see :mod:`.forces` for the
conventions and the results).

Points and vectors are complex numbers x + iy in mm (arrays (N,) or scalars that broadcast);
forces complex in N; moments here in N·mm (so that mm arms need no scaling; :mod:`.forces`
reports N·m). Each link's loads are kept as a resultant force and a moment about its *reference
point*: the anchor of its kernel state for a moving link, the driver's pivot for the frame.
Points of a link are handled as their *arm* from that reference (the drawn offset turned by the
link's rotation), so a moment costs one complex product; arms and their conjugates are computed
once per call and shared by the friction iterations. Numpy's per-call cost dominates at a few
thousand samples, so the formulas use few array operations: zeros stay scalars (the frame, a
crank at constant speed), the moment of an inertia force uses |r|² = const, and the velocity
terms are left to the lazily computed power balance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...solver.kernels import LinkState, cross
from ...solver.plan import Plan, Solution
from ...solver.structure import GroupKind
from .static import _STATIC, MM, _static



def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


_ND = np.ndarray


def _zero(x) -> bool:
    """``x`` is a scalar zero (not an array): it need not enter an array operation."""
    return type(x) is not _ND and x == 0


def _fz(x):
    """A float array as complex (a copy, cheap), a scalar as is: numpy's mixed float × complex
    array products cast in small buffers and cost three to four complex products."""
    return x.astype(np.complex128) if type(x) is _ND and x.dtype != np.complex128 else x


def _times(a, inv, z):
    """a·inv·z for float a (array or scalar; a scalar zero gives 0j), float inv and complex z,
    with the float factor cast to complex once (see :func:`_fz`)."""
    if _zero(a):
        return 0j
    return _fz(a * inv) * z


def _neg(x):
    """−x. A complex array is negated through its float view: numpy's complex negative runs a
    generic loop element by element; flipping the sign of both parts is the same bits, vectorised."""
    if type(x) is _ND and x.dtype == np.complex128 and x.ndim == 1 and x.flags.c_contiguous:
        return np.negative(x.view(np.float64)).view(np.complex128)
    return -x


def _add(a, b):
    if type(a) is not _ND and a == 0:
        return b
    if type(b) is not _ND and b == 0:
        return a
    return a + b


def _sub(a, b):
    if type(b) is not _ND and b == 0:
        return a
    if type(a) is not _ND and a == 0:
        return _neg(b)
    return a - b


@dataclass
class Pass:
    """What one pass finds: the driving ``effort`` (N·mm, (N,)); ``pairs`` [(joint, on, by,
    force)]: the force (N) on link ``on`` from link ``by`` at a revolute joint; ``slides``
    {joint: (on, force, point, couple)}: a prismatic joint's normal force on ``on`` at ``point``
    (mm) plus a couple (N·mm); the frame's load ``frame_force`` (N) and ``frame_moment`` (N·mm
    about the pivot)."""

    effort: object
    pairs: list
    slides: dict
    frame_force: object
    frame_moment: object


class Kinetostatics:
    """The loads and reactions of ``plan``'s linkage over the samples of ``sol`` (order 2)."""

    def __init__(self, plan: Plan, sol: Solution) -> None:
        self.plan, self.sol = plan, sol
        self.lk = lk = plan.linkage
        self.n = len(sol)
        self.ground = lk.ground
        hit = _STATIC.get(id(plan))
        ids = hit[1].link_ids if hit is not None and hit[0]() is plan else lk.link_ids
        self.st: dict[str, LinkState] = {k: sol.link_state(k) for k in ids}
        self.static = _static(plan, self.st)
        self.at = self.static.at
        drv = lk.driver
        self.kind = str(getattr(drv, "kind", "crank"))
        #: the frame's reference point: the drawn position of the driver's joint (crank pivot,
        #: slider guide, cylinder slide)
        self.pivot = self.at[drv.pivot]
        self._arm: dict[tuple[str, complex], object] = {}
        self._carm: dict[tuple[str, complex], object] = {}
        self._normal: dict[tuple[str, str], object] = {}
        self._crot: dict[str, object] = {}
        #: a cylinder: (barrel, rod, end pivot M, end pivot H, slide joint, mode ±1, offset c mm)
        self.cyl: tuple | None = None
        if self.kind == "cylinder":
            cd = plan.drive
            self.cyl = (cd.link, cd.rod, cd.m, cd.h, cd.slide, cd.geometry.mode, cd.geometry.c)
            # the virtual link V (named as the barrel) reaches from M to H: its arm to H is H − M
            self._arm[(cd.link, self.at[cd.h])] = self.st[cd.rod].A - self.st[cd.link].A
        #: inertia loads per massive link (force N, moment N·mm about its reference), for the power
        self.inertia: dict[str, tuple[object, object]] = {}

    def release(self) -> None:
        """Drop the cached arms, normals and inertia loads (kept only while a pass runs; the
        power balance recomputes what it needs)."""
        keep = {key: v for key, v in self._arm.items() if self.cyl is not None and key[0] == self.cyl[0]}
        self._arm, self._carm, self._crot, self._normal = keep, {}, {}, {}
        self.inertia = {}

    # -- link points ------------------------------------------------------------------------
    def ref(self, k: str):
        """The reference point of link ``k`` (mm)."""
        return self.pivot if k == self.ground else self.st[k].A

    def arm(self, k: str, p0: complex):
        """From the reference of ``k`` to its point drawn at ``p0`` (mm; 0j on the reference)."""
        key = (k, p0)
        v = self._arm.get(key)
        if v is None:
            if k == self.ground:
                v = p0 - self.pivot
            else:
                st = self.st[k]
                v = 0j if p0 == st.a0 else st.rot * (p0 - st.a0)
            self._arm[key] = v
        return v

    def carm(self, k: str, p0: complex):
        """conj(arm): cross(arm, f) is ``(carm * f).imag``."""
        key = (k, p0)
        v = self._carm.get(key)
        if v is None:
            v = self._carm[key] = np.conjugate(self.arm(k, p0))
        return v

    def point(self, k: str, p0: complex):
        """Current position (mm) of the point of ``k`` drawn at ``p0``."""
        return _add(self.ref(k), self.arm(k, p0))

    def normal(self, k: str, joint: str):
        """The unit normal J·u of prismatic ``joint``'s axis as link ``k`` turns it."""
        key = (k, joint)
        v = self._normal.get(key)
        if v is None:
            a = math.radians(self.lk.joint(joint).axis_deg or 0.0)
            v = self._normal[key] = complex(-math.sin(a), math.cos(a)) * self.st[k].rot
        return v

    def velocity(self, k: str, arm):
        """Velocity (mm/s) of the point at ``arm`` of link ``k``."""
        if k == self.ground:
            return 0j
        st = self.st[k]
        if _zero(arm):
            return st.vA
        w = st.omega
        return _add(st.vA, _fz(w) * (1j * arm) if isinstance(w, np.ndarray) else arm * (1j * w))

    # -- applied loads ----------------------------------------------------------------------
    def crot(self, k: str):
        """conj(rot) of link ``k``: cross(rot·w, f) = Im(crot·conj(w)·f) for drawn offsets w."""
        v = self._crot.get(k)
        if v is None:
            v = self._crot[k] = np.conjugate(self.st[k].rot)
        return v

    def applied(self, keep_inertia: bool = False) -> tuple[dict, dict]:
        """Per link the resultant of gravity, inertia and the applied loads: force (complex N)
        and moment about the link's reference (N·mm). Fills :attr:`inertia` when ``keep_inertia``
        (the power balance needs it; the reactions do not, and memory is time at this size).

        Constant forces (point forces, gravity) on a link are summed once per plan, force and
        moment alike (a moment about the reference is Im(conj(rot)·W) with W = Σ conj(p0 − a0)·f
        a constant), so each link costs a few array operations however many loads it carries."""
        S = self.static
        F, M = dict(S.F0), dict(S.M0)
        wconst = dict(S.wconst)
        fuse = not keep_inertia      # then a link's constant moment joins its inertia moment
        n = self.n
        for k, d, mk, alpha_coef in S.masses:
            st = self.st[k]
            # −m·a_c = mk·(a_A + (iα − ω²)·r), r = rot·d; its moment about the anchor is
            # mk·cross(r, a_A) + mk·α·|r|², and the link's own −I·α
            al = st.alpha
            m_in = 0.0 if _zero(al) else alpha_coef * al
            q = 0j if _zero(st.aA) else mk * st.aA
            f_in = 0j
            if d != 0:
                w = st.omega
                if type(w) is _ND or type(al) is _ND:
                    kc = np.empty(n, dtype=np.complex128)      # mk·(iα − ω²), built in place
                    np.multiply(w * w, -mk, out=kc.real)
                    np.multiply(al, mk, out=kc.imag)
                else:
                    kc = mk * complex(-w * w, al)
                f_in = kc * st.rot
                f_in *= d
                if not _zero(q):
                    # mk·cross(r, a_A) = Im(conj(rot)·q·conj(d)) (+ the constant loads' Im(conj(rot)·W))
                    t = q * d.conjugate()
                    if fuse and k in wconst:
                        t += wconst.pop(k)
                    t = self.crot(k) * t
                    m_in = _add(m_in, t.imag)
                if not _zero(q):
                    f_in += q
            else:
                f_in = q
            if keep_inertia:
                self.inertia[k] = (f_in, m_in)
                F[k] = _add(F[k], f_in)
            elif type(f_in) is _ND and type(F[k]) is not _ND:
                if F[k] != 0:
                    f_in += F[k]                                # f_in is this call's own array
                F[k] = f_in
            else:
                F[k] = _add(F[k], f_in)
            M[k] = _add(M[k], m_in)
        for k, w in wconst.items():
            M[k] = _add(M[k], (self.crot(k) * w).imag)
        for a, pa0, b, pb0, coef in S.springs:
            fa = self._spring(a, pa0, b, pb0, coef)
            F[a] = _add(F[a], fa)
            F[b] = _sub(F[b], fa)
            if not _zero(self.arm(a, pa0)):
                M[a] = _add(M[a], (self.carm(a, pa0) * fa).imag)
            if not _zero(self.arm(b, pb0)):
                M[b] = _sub(M[b], (self.carm(b, pb0) * fa).imag)
        return F, M

    def _spring(self, a: str, pa0: complex, b: str, pb0: complex, coef: tuple):
        """The force (N, complex) on end 0 (link ``a``, drawn ``pa0``) of a spring (``coef`` =
        (k N/mm, k·ℓ0 N)) or a damper (``coef`` = (c N·s/mm,)) whose end 1 is on ``b`` at ``pb0``:
        tension/ℓ times the vector d from end 0 to end 1. Float factors are cast to complex once
        before a product with a complex array (numpy's mixed products cost three to four complex
        ones)."""
        # d = (ref_b − ref_a) + arm_b − arm_a, the scalars (a frame or a pivoted link) first
        parts = [(self.ref(b), 1), (self.arm(b, pb0), 1), (self.ref(a), -1), (self.arm(a, pa0), -1)]
        d = 0j
        for x, sign in sorted(parts, key=lambda xs: type(xs[0]) is _ND):
            d = _add(d, x) if sign > 0 else _sub(d, x)
        if len(coef) == 2:
            t = coef[0] - coef[1] / np.abs(d)                              # k·(ℓ − ℓ0)/ℓ
        else:
            dv = _sub(self.velocity(b, self.arm(b, pb0)), self.velocity(a, self.arm(a, pa0)))
            cd = np.conjugate(d)
            t = (dv * cd).real
            t *= coef[0]
            t /= (d * cd).real                                             # c·(dℓ/dt)/ℓ
        return _fz(t) * d

    # -- the pass ---------------------------------------------------------------------------
    def run(self, F0: dict, M0: dict, consume: bool = False) -> Pass:
        """Reactions for the link loads ``F0``/``M0``, last group first. They are not modified
        unless ``consume`` (then they are used up: a solved group's loads are dropped at once)."""
        F, M = (F0, M0) if consume else (dict(F0), dict(M0))
        pairs: list = []
        slides: dict = {}
        at, arm, carm = self.at, self.arm, self.carm

        def about(k: str, q0: complex):
            """Moment (N·mm) of link k's loads about its point drawn at q0."""
            if _zero(arm(k, q0)) or _zero(F[k]):
                return M[k]
            return _sub(M[k], (carm(k, q0) * F[k]).imag)

        def mom(k: str, q0: complex, f):
            """cross(arm of k's point drawn at q0, f) (N·mm; a scalar zero when either is)."""
            if _zero(f) or _zero(arm(k, q0)):
                return 0.0
            return (carm(k, q0) * f).imag

        def about_at(k: str, q):
            """Moment (N·mm) of link k's loads about the absolute point q (mm)."""
            return _add(M[k], cross(_sub(self.ref(k), q), F[k]))

        def take(k: str, f, q0: complex) -> None:
            """Subtract force f at the point of k drawn at q0 (the reaction of a later group)."""
            F[k] = _sub(F[k], f)
            if not _zero(arm(k, q0)):
                M[k] = _sub(M[k], (carm(k, q0) * f).imag)

        def take_at(k: str, f, q, c) -> None:
            """Subtract force f at the absolute point q (mm) and couple c (N·mm) from link k."""
            F[k] = _sub(F[k], f)
            M[k] = _sub(M[k], cross(_sub(q, self.ref(k)), f) + c)

        cyl = self.cyl
        effort = None
        for step in reversed(self.plan.steps):
            g = step.group
            i, j = g.link_i, g.link_j
            vgroup = cyl is not None and cyl[0] in (i, j)
            if vgroup:   # barrel and rod locked together at the current length: the link V
                rod_f, rod_m, first = F[cyl[1]], M[cyl[1]], len(pairs)
                F[cyl[0]] = _add(F[cyl[0]], rod_f)
                if not _zero(rod_f):
                    M[cyl[0]] = _add(M[cyl[0]], _add(rod_m, (carm(cyl[0], at[cyl[3]]) * rod_f).imag))
                else:
                    M[cyl[0]] = _add(M[cyl[0]], rod_m)
            Fi, Fj = F[i], F[j]
            tot = _add(Fi, Fj)
            if g.kind is GroupKind.RRR:
                m0, h0, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
                # ai = L − M, aj = L − H; X (on i at M from known_i) balances i about L and j
                # about H: X = (about_i(L)·aj + b·ai) / cross(ai, aj)
                ai, aj = _sub(arm(i, l0), arm(i, m0)), _sub(arm(j, l0), arm(j, h0))
                # about(j, l0) + cross(aj, tot): j's moment about H once X at L is known
                b = _sub(_add(M[j], mom(j, l0, Fi)), mom(j, h0, tot))
                if _zero(arm(i, m0)):       # 1 / cross(ai, aj) from a cached conjugate arm
                    inv = 1.0 / (carm(i, l0) * aj).imag
                elif _zero(arm(j, h0)):
                    inv = -1.0 / (carm(j, l0) * ai).imag
                else:
                    inv = 1.0 / cross(ai, aj)
                X = _add(_times(about(i, l0), inv, aj), _times(b, inv, ai))
                Z = _sub(_neg(tot), X) if not _zero(tot) else _neg(X)
                pairs += [(g.outer_i, i, g.known_i, X), (g.outer_j, j, g.known_j, Z),
                          (g.inner, j, i, _add(X, Fi))]
                take(g.known_i, X, m0)
                take(g.known_j, Z, h0)
            elif g.kind is GroupKind.RRP:
                m0, l0 = at[g.outer_i], at[g.inner]
                n = self.normal(j, g.outer_j)
                ri = _sub(arm(i, m0), arm(i, l0))
                f = _times(_sub(about(i, l0), cross(ri, tot)), 1.0 / cross(ri, n), n)
                X = _sub(_neg(f), tot)
                pairs += [(g.outer_i, i, g.known_i, X), (g.inner, j, i, _add(X, Fi))]
                q = self.point(i, l0)
                c = -about(j, l0)
                slides[g.outer_j] = (j, f, q, c)
                take(g.known_i, X, m0)
                take_at(g.known_j, f, q, c)
            elif g.kind is GroupKind.RPR:
                m0, h0 = at[g.outer_i], at[g.outer_j]
                n = self.normal(i, g.inner)
                qm = self.point(i, m0)
                c = about(i, m0)
                f = _times(_add(c, about(j, h0)), 1.0 / cross(n, _sub(qm, self.point(j, h0))), n)
                X, Z = _sub(f, Fi), _sub(_neg(f), Fj)
                pairs += [(g.outer_i, i, g.known_i, X), (g.outer_j, j, g.known_j, Z)]
                slides[g.inner] = (j, f, qm, c)
                take(g.known_i, X, m0)
                take(g.known_j, Z, h0)
            elif g.kind is GroupKind.PRP:
                l0 = at[g.inner]
                n1, n2 = self.normal(i, g.outer_i), self.normal(j, g.outer_j)
                det = cross(n1, n2)
                inv = 1.0 / det
                f1 = _times(cross(n2, tot), inv, n1)             # N1·n1 + N2·n2 = −tot
                f2 = _times(cross(tot, n1), inv, n2)
                c1, c2 = -about(i, l0), -about(j, l0)
                q = self.point(i, l0)
                pairs.append((g.inner, j, i, _add(f1, Fi)))
                slides[g.outer_i] = (i, f1, q, c1)
                slides[g.outer_j] = (j, f2, q, c2)
                take_at(g.known_i, f1, q, c1)
                take_at(g.known_j, f2, q, c2)
            else:  # RPP
                m0 = at[g.outer_i]
                n1, n2 = self.normal(i, g.inner), self.normal(j, g.outer_j)
                det = cross(n1, n2)
                inv = 1.0 / det
                f1 = _times(cross(n2, Fj), inv, n1)              # N1·n1 + N2·n2 = −Fj
                f2 = _times(cross(Fj, n1), inv, n2)
                c1 = about(i, m0)
                q = self.point(i, m0)
                c2 = -_add(c1, about_at(j, q))                   # the pin M is not a point of j
                X = _sub(f1, Fi)
                pairs.append((g.outer_i, i, g.known_i, X))
                slides[g.inner] = (j, f1, q, c1)
                slides[g.outer_j] = (j, f2, q, c2)
                take(g.known_i, X, m0)
                take_at(g.known_j, f2, q, c2)
            if vgroup:
                effort = self._cylinder(pairs, first, slides, rod_f, rod_m)
                F[cyl[1]], M[cyl[1]] = 0j, 0.0
            F[i], F[j], M[i], M[j] = 0j, 0j, 0.0, 0.0   # done: their memory goes back for the next group
        drv = self.lk.driver
        pv = at[drv.pivot]
        if self.kind == "crank":
            effort = -about(drv.link, pv)
            reaction = _neg(F[drv.link])
            pairs.append((drv.pivot, drv.link, self.ground, reaction))
            take(self.ground, reaction, pv)
            M[self.ground] = _sub(M[self.ground], effort)
        elif self.kind == "slider":   # the guide's normal force and couple, the actuator's push along u
            k = drv.link
            u = -1j * self.normal(k, drv.pivot)
            effort = -(F[k] * np.conjugate(u)).real          # N along the guide, + extending
            push = _fz(effort) * u
            f = _sub(_neg(F[k]), push)                            # the guide's normal force on the slider
            q = self.point(k, pv)
            c = -about(k, pv)
            slides[drv.pivot] = (k, f, q, c)
            take_at(self.ground, _add(f, push), q, c)
        return Pass(effort, pairs, slides, F[self.ground], M[self.ground])

    def _cylinder(self, pairs: list, first: int, slides: dict, rod_f, rod_m):
        """After the group of the cylinder's link V: name the rod in its pairs at H, put the
        slide's reaction in ``slides`` and return the driving force (N, + extending) from the rod's
        equilibrium (its loads ``rod_f``/``rod_m`` about H, the pin force at H, the barrel's push)."""
        barrel, rod, _m, h, slide, mode, _c0 = self.cyl
        r_h = 0j
        for n in range(first, len(pairs)):
            j, on, by, f = pairs[n]
            if j != h:
                continue
            if on == barrel:
                on, r_h = rod, _add(r_h, f)
            elif by == barrel:
                by, r_h = rod, _sub(r_h, f)
            pairs[n] = (j, on, by, f)
        t = _neg(_add(rod_f, r_h))                                # the barrel's force on the rod
        n_vec = self.normal(barrel, slide)
        u = -1j * n_vec
        axial = (t * np.conjugate(u)).real
        f = _fz((t * np.conjugate(n_vec)).real) * n_vec
        p0 = self.at[slide]
        # the barrel's moment on the rod about H is −rod_m; about the rod's point of the slide:
        c = _sub(-rod_m, (self.carm(rod, p0) * t).imag) if not _zero(self.arm(rod, p0)) else -rod_m
        slides[slide] = (rod, f, self.point(rod, p0), c)
        return mode * axial

    def motor_speed(self):
        """What the driving effort multiplies into the motor power (W): the crank's ω (rad/s,
        effort N·m); for an actuator its extension rate in m/s (effort N): a slider's speed along
        its guide, a cylinder's rod speed out of the barrel d|σ|/dt = L·L̇/√(L² − c²) (L̇ when its
        axis passes through both pivots)."""
        if self.kind == "crank":
            return self.st[self.lk.driver.link].omega
        rate = self.sol.omega_driver
        if self.kind == "cylinder" and self.cyl[6] != 0.0:
            L, c = self.sol.input, self.cyl[6]
            rate = L * rate / np.sqrt((L - c) * (L + c))
        return MM * rate

    # -- checks ---------------------------------------------------------------------------
    def power_terms(self, F: dict, M: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(loads, kinetic, scale), W, (N,): the power of the applied loads on the moving links
        (their part of ``F``/``M`` that is not inertia), d(kinetic energy)/dt (= −power of the
        inertia loads) and the sum of the magnitudes of both per link. A load system F, M (about
        the reference point) on a rigid link has the power F·v_ref + M·ω."""
        n = self.n
        loads, kinetic, scale = np.zeros(n), np.zeros(n), np.zeros(n)
        for k in self.lk.link_ids:
            if k == self.ground:
                continue
            st = self.st[k]

            def power(f, m):
                p = m * st.omega
                if not _zero(st.vA):
                    p = p + (np.conjugate(f) * st.vA).real
                return MM * p

            total = power(F[k], M[k])
            if k in self.inertia:
                p_in = power(*self.inertia[k])
                kinetic = kinetic - p_in
                scale = scale + np.abs(p_in)
                total = total - p_in
            loads = loads + total
            scale = scale + np.abs(total)
        return loads, kinetic, scale

    # -- friction ---------------------------------------------------------------------------
    def friction_pairs(self) -> list[tuple[str, str, str, float]]:
        """(joint, first link, other link, friction-circle radius in mm) for every link after the
        first of each revolute joint with friction."""
        out = []
        for fr in self.lk.friction:
            carriers = self.lk.links_of(fr.joint)
            out += [(fr.joint, carriers[0], b, fr.radius) for b in carriers[1:]]
        return out

    def with_friction(self, F: dict, M: dict, first: Pass, tol: float, max_iter: int
                      ) -> tuple[Pass, dict, dict, int, np.ndarray]:
        """Iterate the pass with each joint's friction moment ρ·|reaction| (N·mm, against the relative
        rotation; 0 where it is 0) taken from the previous pass, until the effort and the
        reactions change by at most ``tol`` relative (or ``max_iter`` passes). Returns the last
        pass, the moments it was run with (as loads M2, with F), the passes and where it
        converged ((N,) bool)."""
        pairs = self.friction_pairs()
        omega = {k: (0.0 if k == self.ground else self.st[k].omega) for k in self.lk.link_ids}
        prev, its, M2 = first, 0, dict(M)
        converged = np.zeros(self.n, dtype=bool)
        for its in range(1, max_iter + 1):
            M2 = dict(M)
            for j, a, b, rho in pairs:
                c = -rho * np.abs(_pin_force(prev.pairs, j, b)) * np.sign(omega[b] - omega[a])  # on b
                M2[b] = M2[b] + c
                M2[a] = M2[a] - c
            cur = self.run(F, M2)
            change = np.abs(cur.effort - prev.effort)
            size = np.abs(cur.effort)
            for (j, on, _by, f), (_j, _on, _b, f0) in zip(cur.pairs, prev.pairs):
                change = np.maximum(change, np.abs(f - f0))
                size = np.maximum(size, np.abs(f))
            top = float(np.nanmax(size, initial=0.0)) if np.isfinite(size).any() else 0.0
            converged = change <= tol * top
            prev = cur
            if bool(np.all(converged | ~np.isfinite(change))):
                break
        return prev, F, M2, its, converged


def _pin_force(pairs: list, joint: str, link: str):
    """The force on ``link`` at revolute ``joint`` from all the others (sum over the pairs)."""
    total = 0j
    for j, on, by, f in pairs:
        if j == joint:
            if on == link:
                total = total + f
            elif by == link:
                total = total - f
    return total
