"""The batch engine: one linkage's compiled plan run for D designs × N samples at once.

:class:`BatchPlan` holds what all designs share — the groups in solving order, the drive and its
inputs over the cycle — and for a chunk of designs (a :class:`~.geometry.Geometry`) makes the
groups' drawn constants as arrays (D, 1) (:meth:`BatchPlan.constants`), runs the kernels of
:mod:`.bkernels` on them (:meth:`BatchPlan.run`) and keeps each group on its smooth branch:

**Assembly-mode continuity per design.** A group switches assembly mode only where it passes
through a toggle (a branch point, see :mod:`mechsketch.core.solver.branches`): its assembly margin
touches zero. Such designs are rare (a Grashof equality, a parallelogram), so each design is first
screened (:meth:`BatchPlan.screen`): local minima of every group's margin over a turn (or the
stroke) that come within 2 % of the group's size are refined by a golden-section search over all
candidates at once; only a design whose margin then touches zero, or is zero at the drawn input,
is handed to the one-design branch search (``Plan.branch_points`` of that design), and its
samples get the same mode flips as the one-design path.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import RequestError
from ..model.linkage import Linkage
from ..solver.branches import CANDIDATE, GOLDEN_STEPS, flip_factor
from ..solver.drive import linear_flip, linear_range
from ..solver.motion_law import cycle
from ..solver.plan import Plan, compile_plan
from ..solver.structure import MODAL_KINDS, GroupKind
from ..solver.tolerances import BRANCH_REL, SINGULAR_REL, TOUCH_REL
from . import bkernels as BK
from . import vec as V
from .bcylinder import cyl_rrp, cyl_rrr
from .geometry import Geometry, design_linkage

#: a refined margin within this many times the one-design branch threshold sends the design to
#: the one-design branch search (generous: a false alarm costs a few ms, a miss a wrong branch)
SUSPECT = 1e3
#: screening grid over one turn or the stroke when the sweep's own samples cannot serve
SCREEN_SAMPLES = 180


class Inputs:
    """The driver's input over the N samples of one cycle, shared by every design: ``q`` (N,)
    (rad or mm), its rate ``qd`` and acceleration ``qdd`` (scalars or (N,)), times ``t`` (s);
    ``turn``: the samples are a uniform turn of a crank from its drawn angle."""

    def __init__(self, q, qd, qdd, t, turn: bool) -> None:
        self.q, self.qd, self.qdd, self.t, self.turn = q, qd, qdd, t, turn

    def row(self, x):
        """An input array as a row (1, N) (scalars stay scalars)."""
        return x.reshape(1, -1) if isinstance(x, np.ndarray) and x.ndim == 1 else x


class Constants:
    """The drawn constants of a chunk of D designs: per step a dict of arrays (D, 1); the drawn
    joints ``at`` and slide axes ``axis``; each moving link's drawn angle ``angle0``."""

    def __init__(self, n: int, at: dict, axis: dict, steps: dict, angle0: dict) -> None:
        self.n, self.at, self.axis, self.steps, self.angle0 = n, at, axis, steps, angle0

    def take(self, idx) -> "Constants":
        """The constants of designs ``idx`` (an index array)."""
        def pick(v):
            if isinstance(v, tuple):
                return tuple(pick(x) for x in v)
            if isinstance(v, dict):
                return {k: pick(x) for k, x in v.items()}
            if isinstance(v, np.ndarray) and v.ndim == 2:
                return v[idx]
            return v
        return Constants(len(idx), pick(self.at), pick(self.axis), pick(self.steps), pick(self.angle0))


class Run:
    """The link states and group outputs of one run of the kernels over a chunk."""

    def __init__(self, states: dict, outs: dict, shape: tuple) -> None:
        self.states, self.outs, self.shape = states, outs, shape
        valid = None
        for out in outs.values():
            ok = np.broadcast_to(out.ok, shape)
            valid = ok.copy() if valid is None else valid & ok
        self.valid = np.ones(shape, dtype=bool) if valid is None else valid


def _col(p, dtype=float):
    """A pair of (D,) arrays as a pair of (D, 1) arrays."""
    return p[0].reshape(-1, 1), p[1].reshape(-1, 1)


def _abs(p):
    """|p| per design: hypot (as Python's abs of a complex) for reals, √ for a complex step."""
    if np.iscomplexobj(p[0]) or np.iscomplexobj(p[1]):
        return V.norm(p)
    return np.hypot(p[0], p[1])


def _sign(x):
    return np.where(V.re(x) >= 0.0, 1.0, -1.0)


class BatchPlan:
    """One linkage compiled for batches of its designs (see the module docstring)."""

    def __init__(self, linkage: Linkage, plan: Plan | None = None) -> None:
        self.linkage = linkage
        self.plan = plan if plan is not None else compile_plan(linkage)
        self.drive = self.plan.drive
        self.kind = str(self.drive.kind) if self.drive is not None else "crank"
        self.ground = linkage.ground
        self.cyl_step = -1
        if self.kind == "cylinder":
            self.cyl_step = next(k for k, s in enumerate(self.plan.steps)
                                 if self.drive.link in (s.group.link_i, s.group.link_j))

    # -- the inputs ------------------------------------------------------------------------
    def inputs(self, samples: int) -> Inputs:
        """One cycle in ``samples`` samples, exactly as ``Plan.sweep`` samples it."""
        n = int(samples)
        if n < 2:
            raise RequestError(f"samples must be at least 2, got {n}")
        drv = self.linkage.driver
        m = cycle(drv, self.plan.theta0, n)
        turn = not drv.linear and drv.law.is_constant
        if turn:   # θ0 + sgn·(2π/N)·k as the sweep adds it
            k = np.arange(n, dtype=float)
            sgn = 1.0 if drv.omega >= 0 else -1.0
            q = sgn * (2.0 * math.pi / n) * k
            q += self.plan.theta0
            return Inputs(q, self.plan.omega, 0.0, k * (2.0 * math.pi / abs(drv.omega) / n), True)
        return Inputs(m.q, m.qd, m.qdd, m.t, False)

    # -- the drawn constants ---------------------------------------------------------------
    def constants(self, geo: Geometry) -> Constants:
        lk = self.linkage
        at = {j: _col(p) for j, p in geo.at.items()}
        axis = {j: _col(p) for j, p in geo.axis.items()}
        steps = {}
        for k, step in enumerate(self.plan.steps):
            g = step.group
            near = set(g.joints) | set(lk.link(g.known_i).joints) | set(lk.link(g.known_j).joints)
            coord = None
            for j in near:
                if j in at:
                    a = np.real(_abs(at[j]))
                    coord = a if coord is None else np.maximum(coord, a)
            c = {"coord": coord}
            if g.kind is GroupKind.RRR:
                m0, h0, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
                c["li"], c["lj"] = _abs(V.sub(l0, m0)), _abs(V.sub(l0, h0))
                c["mode"] = _sign(V.cross(V.sub(h0, m0), V.sub(l0, m0)))
                scale = np.real(c["li"] + c["lj"])
            elif g.kind is GroupKind.RRP:
                m0, l0 = at[g.outer_i], at[g.inner]
                c["li"] = _abs(V.sub(l0, m0))
                c["mode"] = _sign(V.dot(axis[g.outer_j], V.sub(l0, m0)))
                scale = np.real(c["li"])
            elif g.kind is GroupKind.RPR:
                m0, h0 = at[g.outer_i], at[g.outer_j]
                c["mode"] = _sign(V.dot(axis[g.inner], V.sub(m0, h0)))
                scale = np.real(_abs(V.sub(m0, h0)))
            else:
                scale = np.ones_like(coord)
            if k == self.cyl_step:
                scale = self._cylinder_constants(c, g, at, axis, coord)
            c["scale"] = np.maximum(scale, 1e-300)
            c["tol"] = TOUCH_REL * (scale + coord)
            c["near"] = SINGULAR_REL * (scale + coord)
            steps[g.name] = c
        angle0 = {}
        for link in lk.links:
            if link.id == lk.ground:
                continue
            js = link.joints[:2]
            if len(js) == 2:
                d = V.sub(at[js[1]], at[js[0]])
                a = np.arctan2(np.real(d[1]), np.real(d[0]))
                angle0[link.id] = np.where((np.real(d[0]) == 0) & (np.real(d[1]) == 0), 0.0, a)
            else:
                angle0[link.id] = np.zeros((geo.n, 1))
        return Constants(geo.n, at, axis, steps, angle0)

    def _cylinder_constants(self, c: dict, g, at: dict, axis: dict, coord) -> np.ndarray:
        d = self.drive
        m0, h0 = at[d.m], at[d.h]
        u0 = axis[d.slide]
        cyl = {"m": d.m, "h": d.h, "m0": m0, "h0": h0, "u0": u0, "c": V.cross(u0, V.sub(h0, m0)),
               "a0": V.dot(u0, V.sub(h0, m0))}
        cyl["mode"] = _sign(cyl["a0"])
        c["cyl"] = cyl
        if g.kind is GroupKind.RRR:
            m0g, h0g, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
            c["li"], c["lj"] = _abs(V.sub(l0, m0g)), _abs(V.sub(l0, h0g))
            c["mode"] = _sign(V.cross(V.sub(h0g, m0g), V.sub(l0, m0g)))
            scale = np.real(c["li"] + c["lj"])
        else:
            m0g, l0 = at[g.outer_i], at[g.inner]
            c["mode"] = _sign(V.dot(axis[g.outer_j], V.sub(l0, m0g)))
            scale = np.real(_abs(V.sub(l0, m0g)))
        cyl["tol"] = TOUCH_REL * (scale + coord)
        return scale

    # -- running the kernels ---------------------------------------------------------------
    def run(self, K: Constants, q, qd, qdd, order: int, flips: dict | None = None, idx=None,
            play: dict | None = None) -> Run:
        """The kernels of steps ``idx`` (default all, in solving order) at inputs ``q`` (a row
        (1, N) shared by the designs, or a column (D, 1): one input per design) with rates
        ``qd``, ``qdd``; ``flips`` group -> (D, N) ±1 past branch points (None: drawn modes);
        ``play`` revolute joint -> (x, y) displacement of the joint on its later links from its
        place on the first one solved (pin clearances; positions only, ``order`` 0)."""
        lk, at, axis = self.linkage, K.at, K.axis
        drv = lk.driver
        pl = play or {}
        if pl and order:
            raise RequestError("pin play is modelled on positions only (order 0)")
        states = {self.ground: BK.ground()}
        stroke = None
        if self.kind == "crank":
            pivot = at[drv.pivot] if drv.pivot not in pl else V.add(at[drv.pivot], pl[drv.pivot])
            states[drv.link] = BK.crank(pivot, self.plan.theta0, q, qd, qdd, order)
        elif self.kind == "slider":
            states[drv.link] = BK.slider(states[self.ground], at[drv.pivot], axis[drv.pivot], drv.pivot,
                                         q, qd, qdd, order)
        else:
            stroke = (q, qd, qdd)
        shape = np.broadcast_shapes((K.n, 1), np.shape(q))
        outs = {}
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            for k in (range(len(self.plan.steps)) if idx is None else idx):
                g = self.plan.steps[k].group
                c = K.steps[g.name]
                flip = None if flips is None else flips.get(g.name)
                si, sj = states[g.known_i], states[g.known_j]
                if k == self.cyl_step:
                    if g.kind is GroupKind.RRR:
                        out, rod = cyl_rrr(si, g.outer_i, at[g.outer_i], sj, g.outer_j, at[g.outer_j], g.inner,
                                           at[g.inner], c, c["cyl"], stroke, g.link_i == self.drive.link, order, flip)
                    else:
                        out, rod = cyl_rrp(si, g.outer_i, at[g.outer_i], sj, g.outer_j, at[g.outer_j],
                                           axis[g.outer_j], g.inner, at[g.inner], c, c["cyl"], stroke, order, flip)
                    states[self.drive.rod] = rod
                elif g.kind is GroupKind.RRR:
                    out = BK.rrr(si, g.outer_i, at[g.outer_i], sj, g.outer_j, at[g.outer_j], g.inner, at[g.inner],
                                 c, order, flip, (pl.get(g.outer_i), pl.get(g.outer_j), pl.get(g.inner)))
                elif g.kind is GroupKind.RRP:
                    out = BK.rrp(si, g.outer_i, at[g.outer_i], sj, g.outer_j, at[g.outer_j], axis[g.outer_j],
                                 g.inner, at[g.inner], c, order, flip, (pl.get(g.outer_i), pl.get(g.inner)))
                elif g.kind is GroupKind.RPR:
                    out = BK.rpr(si, g.outer_i, at[g.outer_i], sj, g.outer_j, at[g.outer_j], axis[g.inner], c,
                                 order, flip, (pl.get(g.outer_i), pl.get(g.outer_j)))
                elif g.kind is GroupKind.PRP:
                    out = BK.prp(si, g.outer_i, at[g.outer_i], axis[g.outer_i], sj, g.outer_j, at[g.outer_j],
                                 axis[g.outer_j], at[g.inner], order, pl.get(g.inner))
                else:
                    out = BK.rpp(si, g.outer_i, at[g.outer_i], axis[g.inner], sj, g.outer_j, at[g.outer_j],
                                 axis[g.outer_j], order, pl.get(g.outer_i))
                if g.fixed:
                    out = BK.held(out, out.si.a0, out.sj.a0, shape, order)
                states[g.link_i], states[g.link_j] = out.si, out.sj
                outs[g.name] = out
        return Run(states, outs, shape)

    # -- assembly-mode continuity ----------------------------------------------------------
    def screen_inputs(self, inp: Inputs) -> tuple[np.ndarray, bool, float]:
        """The inputs a screening run uses (N,), whether they close a ring (a turn), and the
        drawn input."""
        if self.linkage.driver.linear:
            lo, hi = linear_range(self.drive)
            return np.linspace(lo, hi, SCREEN_SAMPLES), False, self.drive.input0
        if inp.turn and inp.q.size >= SCREEN_SAMPLES // 2:
            return inp.q, True, self.plan.theta0
        sgn = self.plan.direction
        return self.plan.theta0 + sgn * (2.0 * math.pi / SCREEN_SAMPLES) * np.arange(SCREEN_SAMPLES), True, \
            self.plan.theta0

    def screen(self, K: Constants, run: Run | None, x: np.ndarray, ring: bool, x0: float) -> np.ndarray:
        """(D,) bool: designs some group of which may pass through a toggle (see the module
        docstring). ``run``: a run at the inputs ``x`` (N,) in the drawn modes (None: made here)."""
        if run is None:
            run = self.run(K, x.reshape(1, -1), 0.0, 0.0, 0)
        suspect = np.zeros(K.n, dtype=bool)
        for k, step in enumerate(self.plan.steps):
            g = step.group
            if g.kind not in MODAL_KINDS or g.fixed:
                continue
            out = run.outs[g.name]
            c = K.steps[g.name]
            ok = np.broadcast_to(out.ok if out.singular is None else out.ok | out.singular, run.shape)
            gap = np.where(ok, np.broadcast_to(V.re(out.gap), run.shape), -np.inf)
            if ring:
                prev, nxt = np.roll(gap, 1, axis=1), np.roll(gap, -1, axis=1)
                okp, okn = np.roll(ok, 1, axis=1), np.roll(ok, -1, axis=1)
            else:
                prev = np.concatenate([np.full((K.n, 1), -np.inf), gap[:, :-1]], axis=1)
                nxt = np.concatenate([gap[:, 1:], np.full((K.n, 1), -np.inf)], axis=1)
                okp, okn = np.isfinite(prev), np.isfinite(nxt)
            cand = ok & okp & okn & (gap <= prev) & (gap <= nxt) & (gap < CANDIDATE * c["scale"])
            thr = SUSPECT * BRANCH_REL * (c["scale"] + c["coord"])
            d_idx, s_idx = np.nonzero(cand)
            if d_idx.size:
                h = (x[1] - x[0]) if x.size > 1 else 1.0
                best = self._golden(K, k, d_idx, x[s_idx] - h, x[s_idx] + h)
                suspect[d_idx[np.abs(best) <= thr[d_idx, 0]]] = True
            at0 = self._margin(K, k, np.arange(K.n), np.full(K.n, x0))
            suspect |= (np.abs(at0) <= 4.0 * thr[:, 0])
        return suspect

    def _margin(self, K: Constants, k: int, designs: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Group ``k``'s signed assembly margin for designs ``designs`` at one input each."""
        sub = K.take(designs)
        r = self.run(sub, x.reshape(-1, 1), 0.0, 0.0, 0, idx=self.plan.closure(k))
        gap = np.broadcast_to(V.re(r.outs[self.plan.steps[k].group.name].gap), (len(designs), 1))[:, 0]
        return np.where(np.isfinite(gap), gap, np.inf)

    def _golden(self, K: Constants, k: int, designs: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """The smallest margin of group ``k`` on [a, b] per candidate (golden-section search on
        all candidates at once, as ``solver.branches.golden_min``)."""
        gr = (math.sqrt(5.0) - 1.0) / 2.0
        a, b = a.astype(float).copy(), b.astype(float).copy()
        c, d = b - gr * (b - a), a + gr * (b - a)
        fc, fd = self._margin(K, k, designs, c), self._margin(K, k, designs, d)
        for _ in range(GOLDEN_STEPS):
            left = fc < fd
            b = np.where(left, d, b)
            a = np.where(left, a, c)
            c_new = np.where(left, b - gr * (b - a), d)
            d_new = np.where(left, c, a + gr * (b - a))
            f_new = self._margin(K, k, designs, np.where(left, c_new, d_new))
            fd, fc = np.where(left, fc, f_new), np.where(left, f_new, fd)
            c, d = c_new, d_new
        return self._margin(K, k, designs, 0.5 * (a + b))

    def reference_flips(self, geo: Geometry, designs, q: np.ndarray) -> dict:
        """Mode flips (group -> (D, N) ±1) of ``designs`` from the one-design branch search,
        empty if none of them has a branch point."""
        flips: dict[str, np.ndarray] = {}
        for d in designs:
            if not geo.ok[d]:
                continue
            pd = compile_plan(design_linkage(geo, int(d)))
            for name, offsets in pd.branch_points().items():
                if offsets.size == 0:
                    continue
                f = (linear_flip(offsets, q, pd.drive.input0) if self.linkage.driver.linear else
                     flip_factor(offsets, q, pd.theta0, pd.direction))
                if name not in flips:
                    flips[name] = np.ones((geo.n, q.size))
                flips[name][d] = f
        return flips


__all__ = ["BatchPlan", "Constants", "Inputs", "Run", "SCREEN_SAMPLES", "SUSPECT"]
