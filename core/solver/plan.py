"""Compile a linkage once into a plan of array kernels; evaluate it on many driver angles at once.

``plan = compile_plan(linkage)``; ``sol = plan.sweep(samples=3600, order=2)`` or
``plan.evaluate(angles, order=0)``. Only the groups that the requested joints depend on are run,
and only up to the requested derivative order ("model only what a scene needs").
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Callable, Iterable

import numpy as np

from ..errors import GeometryError, RequestError, UnknownIdError
from ..model.drivers import DriverKind
from ..model.linkage import JointKind, Linkage
from . import kernels as K
from .branches import find_branch_points, flip_factor
from .drive import CrankDrive, find_linear_branch_points, linear_flip, make_drive
from .motion_law import cycle
from .structure import MODAL_KINDS, Group, GroupKind, decompose, mobility
from .tolerances import RATE_REL, SINGULAR_REL, TOGGLE_COND, TOUCH_REL

__all__ = ["TOGGLE_COND", "TOUCH_REL", "Plan", "Solution", "Step", "compile_plan", "unwrap_finite"]


def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


@dataclass
class Step:
    """A compiled group: its record, the links it needs known, and its kernel call."""

    group: Group
    needs: tuple[str, str]
    run: Callable[[dict, int, "np.ndarray | None"], K.DyadOut]
    scale: float = 1.0   # length scale of the group (mm), for branch-point tolerances
    coord: float = 0.0   # largest drawn coordinate magnitude of the group and its known links, mm


@dataclass
class Plan:
    """The compiled solving order of a linkage (driver, then dyads)."""

    linkage: Linkage
    groups: list[Group]
    steps: list[Step]
    pivot: complex
    theta0: float
    reporter: dict[str, str]          # joint -> link whose frame reports its position
    angle0: dict[str, float]          # moving link -> drawn angle of its first→second joint
    solved_by: dict[str, int] = field(default_factory=dict)  # link -> step index (-1: driver/ground)
    coord_scale: float = 0.0          # largest drawn coordinate magnitude, mm
    _branches: dict[str, np.ndarray] | None = field(default=None, repr=False)
    #: how the input enters (crank, slider, cylinder: :mod:`.drive`); ``theta0`` is its drawn input
    drive: CrankDrive | None = field(default=None, repr=False)
    _local: "Plan | None" = field(default=None, repr=False)
    #: joint -> (link whose frame reports it, drawn position): the lookup of every extraction
    joint_at: dict[str, tuple[str, complex]] = field(default_factory=dict, repr=False)

    def local(self) -> "Plan":
        """This plan for the linkage moved so that its driver pivot sits at the origin (the
        plan itself if it does already): what depends on the geometry only — the branch points —
        is decided on it, so that it does not depend on where the linkage sits in the plane.
        The same groups; inputs and branch offsets mean the same on both."""
        if self.pivot == 0:
            return self
        if self._local is None:
            px, py = self.pivot.real, self.pivot.imag
            moved = replace(self.linkage, joints=tuple(j.moved((j.at[0] - px, j.at[1] - py))
                                                       for j in self.linkage.joints))
            self._local = compile_plan(moved, self.groups)
        return self._local

    @property
    def mobility(self) -> int:
        return mobility(self.linkage)

    @property
    def omega(self) -> float:
        """Driver angular speed, rad/s (signed, CCW positive)."""
        return self.linkage.driver.omega

    @property
    def direction(self) -> float:
        """+1 if the driver turns counter-clockwise, else −1."""
        return 1.0 if self.omega >= 0 else -1.0

    def _needed(self, links: Iterable[str]) -> set[int]:
        need: set[int] = set()
        stack = list(links)
        while stack:
            k = self.solved_by[stack.pop()]
            if k >= 0 and k not in need:
                need.add(k)
                stack.extend(self.steps[k].needs)
        return need

    def closure(self, k: int) -> list[int]:
        """Step ``k`` and every step it depends on, in solving order."""
        return sorted(self._needed(self.steps[k].needs) | {k})

    def steps_for(self, joints: Iterable[str] | None) -> list[int]:
        """Indices of the steps needed to know ``joints`` (all steps if None)."""
        if joints is None:
            return list(range(len(self.steps)))
        links = []
        for j in joints:
            if j not in self.reporter:
                raise UnknownIdError(f"linkage {self.linkage.id!r} has no joint {j!r}")
            links.append(self.reporter[j])
        return sorted(self._needed(links))

    def branch_points(self, steps: Iterable[int] | None = None) -> dict[str, np.ndarray]:
        """Per group, the input offsets (rad from the drawn pose, driver direction) where the
        smooth motion passes from one assembly mode to the other. Searched once per group, and
        only for the groups asked for (``steps``, closed under dependencies; default all)."""
        if self._branches is None:
            self._branches = {}
        idx = range(len(self.steps)) if steps is None else steps
        todo = [k for k in idx if self.steps[k].group.name not in self._branches]
        if todo:
            if self.drive is not None and self.drive.linear:   # inputs (mm) along the stroke
                find_linear_branch_points(self, todo, self._branches)
            else:
                find_branch_points(self, todo, self._branches)
        return self._branches

    @property
    def input_unit(self) -> str:
        """Unit of the input (``Solution.input``): ``"rad"`` (crank angle) or ``"mm"`` (actuator)."""
        return self.drive.unit if self.drive is not None else "rad"

    def run_steps(self, inputs: np.ndarray, order: int, idx: Iterable[int],
                  branches: dict[str, np.ndarray], omega: float | None = None, alpha: float = 0.0,
                  states: dict | None = None) -> dict[str, K.DyadOut]:
        """Run the kernels of steps ``idx`` at ``inputs`` (the engine under :meth:`evaluate`)."""
        w = self.omega if omega is None else omega
        drv = self.linkage.driver
        if states is None:
            states = {}
        states[self.linkage.ground] = K.ground_state()
        if self.drive is None:
            states[drv.link] = K.crank(self.pivot, self.theta0, inputs, w, alpha, order)
        else:
            self.drive.set_states(states, inputs, w, alpha, order)
        linear = self.drive is not None and self.drive.linear
        outs: dict[str, K.DyadOut] = {}
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            for k in idx:
                step = self.steps[k]
                if step.group.fixed:
                    out = _held(step.run(states, order, None), inputs.shape, order)
                else:
                    offsets = branches.get(step.group.name)
                    flip = (linear_flip(offsets, inputs, self.theta0) if linear else
                            flip_factor(offsets, inputs, self.theta0, self.direction))
                    out = step.run(states, order, flip)
                # assembled only where the solved poses are finite: the kernels' arithmetic can
                # break down although their assembly test passed (outer joints exactly
                # coincident: a 0/0 direction; lengths whose squares overflow)
                # (one pass: a sum of the coordinates is finite iff each one is, short of overflow
                # beyond 1e308, which no pose within the input limits reaches)
                probe = out.probe
                if probe is None:
                    (xi, yi), (ci, si), (xj, yj), (cj, sj) = (out.state_i.xy, out.state_i.cs,
                                                              out.state_j.xy, out.state_j.cs)
                    probe = xi + yi + ci + si + xj + yj + cj + sj
                out.ok = out.ok & np.isfinite(probe)
                states[step.group.link_i] = out.state_i
                states[step.group.link_j] = out.state_j
                outs[step.group.name] = out
        return outs

    def evaluate(self, inputs, order: int = 2, omega: float | None = None, alpha: float = 0.0,
                 joints: Iterable[str] | None = None, t=None) -> "Solution":
        """Solve at driver inputs ``inputs`` (shape (N,): crank angles, rad; actuator lengths or
        displacements, mm — see :attr:`input_unit`), with the input's rate ``omega`` (rad/s or
        mm/s) and acceleration ``alpha`` (rad/s² or mm/s²), scalars or (N,) arrays.

        ``order`` 0: positions; 1: + velocities; 2: + accelerations. ``joints``: only what these
        depend on is computed. Each group keeps its drawn assembly mode, switched only at branch
        points crossed since the drawn pose (so the motion stays on its smooth branch).
        """
        if order not in (0, 1, 2):
            raise RequestError(f"order must be 0, 1 or 2, got {order}")
        idx = self.steps_for(joints)
        branches = self.branch_points(idx)
        start = time.perf_counter()
        inputs = np.asarray(inputs, dtype=float).reshape(-1)
        w = self.omega if omega is None else _rate(omega)
        alpha = _rate(alpha)
        states: dict[str, K.LinkState] = {}
        outs = self.run_steps(inputs, order, idx, branches, w, alpha, states)
        valid = None
        for out in outs.values():
            if valid is None:
                valid = np.array(out.ok, dtype=bool)
                if valid.shape != inputs.shape:
                    valid = np.broadcast_to(valid, inputs.shape).copy()
            else:
                np.logical_and(valid, out.ok, out=valid)
        if valid is None:
            valid = np.ones(inputs.shape, dtype=bool)
        elapsed = time.perf_counter() - start
        return Solution(self, inputs, order, states, outs, valid, w, t, elapsed, alpha)

    def sweep(self, samples: int | None = None, order: int = 2, joints: Iterable[str] | None = None
              ) -> "Solution":
        """One cycle of the driver (T = 60/|rpm| s) in N samples at times t = k·T/N.

        A crank at constant speed: sample k is at input θ0 + sign(ω)·2πk/N, from the drawn pose in
        the driver's direction. Any other law (:mod:`.motion_law`): the input, its rate and its
        acceleration of the law at t_k (a crank from its drawn angle; an actuator over its stroke).
        """
        n = int(samples or self.linkage.samples)
        if n < 2:
            raise RequestError(f"samples must be at least 2, got {n}")
        drv = self.linkage.driver
        if drv.linear or not drv.law.is_constant:
            m = cycle(drv, self.theta0, n)
            return self.evaluate(m.q, order=order, omega=m.qd, alpha=m.qdd, joints=joints, t=m.t)
        k = np.arange(n)
        sgn = 1.0 if self.omega >= 0 else -1.0
        inputs = self.theta0 + sgn * (2.0 * math.pi / n) * k
        t = k * (2.0 * math.pi / abs(self.omega) / n)
        return self.evaluate(inputs, order=order, joints=joints, t=t)


def _held(out: K.DyadOut, shape: tuple[int, ...], order: int) -> K.DyadOut:
    """A fixed group (hung on the frame only: zero mobility) solved once: its links stay in the
    drawn pose (anchor at its drawn point, no rotation, rates exactly 0) at every sample; its
    assembly test, conditioning and margin (those of the drawn pose) broadcast to ``shape``."""
    def still(st: K.LinkState) -> K.LinkState:
        held = K.LinkState(st.a0, np.full(shape, st.a0, dtype=complex), np.ones(shape, dtype=complex))
        if order >= 1:
            held.vA, held.omega = np.zeros(shape, dtype=complex), np.zeros(shape)
        if order >= 2:
            held.aA, held.alpha = np.zeros(shape, dtype=complex), np.zeros(shape)
        return held

    zero = np.zeros(shape)
    slides = tuple(K.Slide(zero, zero if order >= 1 else None, zero if order >= 2 else None) for _ in out.slides)
    ok = np.broadcast_to(np.asarray(out.ok, dtype=bool), shape).copy()
    sing = None if out.singular is None else np.broadcast_to(np.asarray(out.singular, dtype=bool), shape).copy()
    return K.DyadOut(still(out.state_i), still(out.state_j), ok,
                     np.broadcast_to(np.asarray(out.cond, dtype=float), shape).copy(),
                     np.broadcast_to(np.asarray(out.gap, dtype=float), shape).copy(), out.mode, slides, sing)


def _axis(linkage: Linkage, jid: str) -> tuple[complex, complex]:
    j = linkage.joint(jid)
    a = math.radians(j.axis_deg or 0.0)
    return _c(j.at), complex(math.cos(a), math.sin(a))


def _compile_step(linkage: Linkage, g: Group) -> Step:
    at = {j.id: _c(j.at) for j in linkage.joints}
    ki, kj = g.known_i, g.known_j
    # rounding tolerance of an assembly margin (mm): scale of the group plus of the coordinates it
    # computes with (its joints and those of the links it hangs on; not the whole linkage's, so
    # that moving a joint elsewhere does not change this group's results)
    near = set(g.joints) | set(linkage.link(ki).joints) | set(linkage.link(kj).joints)
    coord = max((abs(at[j]) for j in near), default=0.0)

    def touch_tol(size: float) -> float:
        return TOUCH_REL * (size + coord)

    def near_tol(size: float) -> float:
        return SINGULAR_REL * (size + coord)

    scale = 1.0
    if g.kind is GroupKind.RRR:
        m0, h0, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
        scale = abs(l0 - m0) + abs(l0 - h0)
        tol, near = touch_tol(scale), near_tol(scale)
        run = lambda s, o, f: K.rrr(s[ki], m0, s[kj], h0, l0, o, f, tol, near)  # noqa: E731
    elif g.kind is GroupKind.RRP:
        m0, l0 = at[g.outer_i], at[g.inner]
        s0, u0 = _axis(linkage, g.outer_j)
        scale = abs(l0 - m0)
        tol = touch_tol(scale)
        run = lambda s, o, f: K.rrp(s[ki], m0, s[kj], s0, u0, l0, o, f, tol)  # noqa: E731
    elif g.kind is GroupKind.RPR:
        m0, h0 = at[g.outer_i], at[g.outer_j]
        _, u0 = _axis(linkage, g.inner)
        scale = abs(m0 - h0)
        tol, near = touch_tol(scale), near_tol(scale)
        run = lambda s, o, f: K.rpr(s[ki], m0, s[kj], h0, u0, o, f, tol, near)  # noqa: E731
    elif g.kind is GroupKind.PRP:
        s1, u1 = _axis(linkage, g.outer_i)
        s2, u2 = _axis(linkage, g.outer_j)
        l0 = at[g.inner]
        run = lambda s, o, f: K.prp(s[ki], s1, u1, s[kj], s2, u2, l0, o)  # noqa: E731
    else:  # RPP
        m0 = at[g.outer_i]
        _, ui0 = _axis(linkage, g.inner)
        s2, u2 = _axis(linkage, g.outer_j)
        run = lambda s, o, f: K.rpp(s[ki], m0, ui0, s[kj], s2, u2, o)  # noqa: E731
    return Step(g, (ki, kj), run, max(scale, 1e-300), coord)


def _check_lengths(linkage: Linkage) -> None:
    """Two revolute joints of one link at the same drawn point leave it no length to solve with."""
    for lk in linkage.links:
        pts = [(j, _c(linkage.joint(j).at)) for j in lk.joints if linkage.joint(j).kind is JointKind.R]
        span = max((abs(p - q) for _, p in pts for _, q in pts), default=0.0)
        for a in range(len(pts)):
            for b in range(a + 1, len(pts)):
                if abs(pts[a][1] - pts[b][1]) <= 1e-9 * max(span, 1.0):
                    raise GeometryError(f"link {lk.id!r}: joints {pts[a][0]!r} and {pts[b][0]!r} are at the "
                                        f"same point ({pts[a][1].real:g}, {pts[a][1].imag:g}) mm")


def compile_plan(linkage: Linkage, groups: list[Group] | None = None) -> Plan:
    """Decompose ``linkage`` (raises StructureError, or GeometryError for a link with two joints
    at one point) and compile its kernels, once. ``groups``: the decomposition of a linkage of the
    same topology (see :func:`mechsketch.core.solver.incremental.topology_key`), reused as is."""
    _check_lengths(linkage)
    if groups is None and linkage.driver.kind is DriverKind.CRANK:
        groups = decompose(linkage)   # checks the crank (and a draft without one) first
    drive = make_drive(linkage)
    groups = drive.decompose(linkage) if groups is None else list(groups)
    steps = []
    for g in groups:
        own = drive.compile_step(linkage, g)   # the group an actuator drives
        steps.append(_compile_step(linkage, g) if own is None else Step(g, (g.known_i, g.known_j), *own))
    pivot, theta0 = drive.pivot, drive.input0
    solved_by = {linkage.ground: -1, **{k: -1 for k in drive.known}}
    for k, g in enumerate(groups):
        solved_by[g.link_i] = k
        solved_by[g.link_j] = k
    for extra, base in drive.extra.items():   # a cylinder's rod: solved with its barrel
        solved_by[extra] = solved_by[base]
    order = [linkage.ground, *drive.known] + [l for g in groups for l in (g.link_i, g.link_j)]
    order += [extra for extra in drive.extra]
    file_order = linkage.link_ids
    reporter = {}
    for j in linkage.joints:
        carriers = linkage.links_of(j.id)
        if j.kind is JointKind.P:  # the later link in the file carries the reported point
            reporter[j.id] = max(carriers, key=file_order.index)
        else:  # the earliest solved link carrying it
            reporter[j.id] = min(carriers, key=order.index)
    angle0 = {}
    for lk in linkage.links:
        if lk.id == linkage.ground:
            continue
        pts = [_c(linkage.joint(j).at) for j in lk.joints[:2]]
        v = pts[1] - pts[0] if len(pts) == 2 else 0j
        angle0[lk.id] = math.atan2(v.imag, v.real) if abs(v) > 0 else 0.0
    coord = max((abs(_c(j.at)) for j in linkage.joints), default=0.0)
    joint_at = {j.id: (reporter[j.id], _c(j.at)) for j in linkage.joints}
    return Plan(linkage, groups, steps, pivot, theta0, reporter, angle0, solved_by, coord, drive=drive,
                joint_at=joint_at)


def _xy(z: np.ndarray, n: int) -> np.ndarray:
    """Complex (N,) (or scalar) -> float (N, 2) view."""
    z = np.ascontiguousarray(np.broadcast_to(z, (n,)), dtype=complex)
    return z.view(np.float64).reshape(n, 2)


def _rate(v) -> float | np.ndarray:
    """An input rate as a float, or a float array when it varies over the samples."""
    if isinstance(v, (float, int)) or np.ndim(v) == 0:
        return float(v)
    return np.asarray(v, dtype=float)


def _below(v, bound: float) -> bool:
    """|v| ≤ bound everywhere (v a scalar or an array; False for NaN)."""
    if isinstance(v, np.ndarray) and v.ndim:
        return bool(v.size == 0 or np.max(np.abs(v)) <= bound)
    return bool(abs(float(v)) <= bound)


def _xy2(p: tuple, n: int) -> np.ndarray:
    """(x, y) pair of float (N,) arrays (or scalars) -> a new float (N, 2) array."""
    out = np.empty((n, 2))
    out[:, 0] = p[0]
    out[:, 1] = p[1]
    return out


def unwrap_finite(a: np.ndarray) -> np.ndarray:
    """np.unwrap along samples, restarting after NaN gaps (each finite run unwrapped on its own)."""
    out = np.array(a, dtype=float)
    fin = np.isfinite(out)
    if fin.all():
        return np.unwrap(out)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], fin.view(np.int8), [0]))))
    for s, e in zip(edges[::2], edges[1::2]):
        out[s:e] = np.unwrap(out[s:e])
    return out


class Solution:
    """Kinematics of a linkage at N driver samples.

    Joint results are (N, 2) arrays (mm, mm/s, mm/s²); link results (N,) (rad, rad/s, rad/s²).
    Samples where some evaluated group cannot be assembled are NaN and ``valid`` is False there.
    """

    def __init__(self, plan: Plan, inputs, order, states, outs, valid, omega, t, elapsed, alpha=0.0):
        self.plan = plan
        #: (N,) the driver's input at each sample: the crank angle (rad) or the actuator's length
        #: (cylinder) or displacement along its guide (slider), mm — see ``plan.input_unit``
        self.input = inputs
        self.order = order
        self.valid = valid
        #: the input's rate (rad/s or mm/s) and acceleration (rad/s² or mm/s²): scalars or (N,)
        self.omega_driver = omega
        self.alpha_driver = alpha
        self._t = t
        self.elapsed = elapsed
        self._states = states
        self._outs = outs
        self._n = inputs.shape[0]
        self._all_valid = bool(valid.all())
        self._quiet: bool | None = None
        self._rates_valid: np.ndarray | None = None

    def __len__(self) -> int:
        return self.input.shape[0]

    @property
    def t(self) -> np.ndarray:
        """(N,) time of each sample, s (made on first use when the solve was not given one)."""
        if self._t is None:
            inputs, omega = self.input, self.omega_driver
            self._t = ((inputs - inputs[0]) / omega if np.ndim(omega) == 0 and omega
                       else np.zeros_like(inputs))
        return self._t

    @t.setter
    def t(self, value: np.ndarray) -> None:
        self._t = value

    @property
    def rates_valid(self) -> np.ndarray:
        """(N,) bool: ``valid`` samples whose velocities (and accelerations, at order 2) are given:
        every solved group's velocity system is conditioned so that the rates' estimated relative
        error, 8·eps·(1 + coordinates/size)/cond² (/cond for PRP and RPP), is below
        :data:`~.tolerances.RATE_REL` — not at a toggle or change point, where they are 0/0 or
        rounding noise — and every link's rates are finite (no overflow at extreme speed).
        All False for a solve of order 0."""
        if self.order < 1:
            return np.zeros(len(self), dtype=bool)
        if self._rates_valid is None:
            ok = self.valid.copy()
            eps = np.finfo(float).eps
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
                for step in self.plan.steps:
                    out = self._outs.get(step.group.name)
                    if out is None or step.group.fixed:
                        continue
                    c = np.broadcast_to(np.asarray(out.cond, dtype=float), ok.shape)
                    if step.group.kind in MODAL_KINDS:
                        c = c * c
                    ok &= 8.0 * eps * (1.0 + step.coord / step.scale) <= RATE_REL * c
                for st in self._states.values():
                    rates = [*st.vxy, st.omega] + ([*st.axy, st.alpha] if self.order >= 2 else [])
                    for r in rates:
                        ok &= np.broadcast_to(np.isfinite(np.asarray(r)), ok.shape)
            self._rates_valid = ok
        return self._rates_valid

    @property
    def singular(self) -> np.ndarray:
        """(N,) bool: samples where a group assembles but its pose is undetermined (its outer
        joints coincide: a rhombus or a kite where B meets D). They are not ``valid`` (NaN, not
        a guess); the diagnostics report them as singular points."""
        out = np.zeros(len(self), dtype=bool)
        for o in self._outs.values():
            if o.singular is not None:
                out |= o.singular
        return out

    # -- internals ------------------------------------------------------------------------
    def _state(self, link: str) -> K.LinkState:
        try:
            return self._states[link]
        except KeyError:
            lk = self.plan.linkage
            if link not in lk.link_ids:
                raise UnknownIdError(f"linkage {lk.id!r} has no link {link!r}") from None
            raise UnknownIdError(f"link {link!r} was not solved (not requested: ask for joints "
                                 f"on it, or for all joints)") from None

    def _mask(self, a: np.ndarray) -> np.ndarray:
        """NaN where the pose is not assembled (arithmetic on NaN/inf there raises no warnings)."""
        if self._all_valid:
            return a
        if a.ndim == 2:
            return np.where(self.valid[:, None], a, np.nan)
        return np.where(self.valid, a, np.nan)

    def _is_quiet(self) -> bool:
        """True when the rates cannot meet inf, 0/0 or overflow in the extraction's arithmetic:
        every sample assembled, every group's conditioning at least 1e-8, the input's rate at most
        1e30 and its acceleration 1e60 (per s, s²), coordinates at most 1e30 mm: the rates are
        then below ~1e130 and their squares times the arms finite. Otherwise the extraction runs
        under ``np.errstate`` (1 µs a call)."""
        q = self._quiet
        if q is None:
            q = (self._all_valid and self.plan.coord_scale <= 1e30
                 and _below(self.omega_driver, 1e30) and _below(self.alpha_driver, 1e60))
            for out in self._outs.values() if q else ():
                c = out.cond
                if isinstance(c, np.ndarray) and c.size and not c.min() >= 1e-8:
                    q = False
                    break
            self._quiet = q
        return q

    def _need(self, order: int, what: str) -> None:
        if self.order < order:
            raise RequestError(f"{what} needs a solve with order >= {order} (this one has order {self.order})")

    def _joint(self, joint: str) -> tuple[K.LinkState, complex]:
        e = self.plan.joint_at.get(joint)
        if e is None:
            raise UnknownIdError(f"linkage {self.plan.linkage.id!r} has no joint {joint!r}")
        st = self._states.get(e[0])
        return (self._state(e[0]) if st is None else st), e[1]

    def link_state(self, link: str) -> K.LinkState:
        """The kernel state of ``link`` (anchor, rotation and their rates: complex/float (N,) or
        scalars, mm and rad units; see :class:`~mechsketch.core.solver.kernels.LinkState`), for
        analyses that work on many points of a link at once (the kinetostatics). Raises
        :class:`UnknownIdError` for a link not solved here."""
        return self._state(link)

    # -- joints and points ----------------------------------------------------------------
    def position(self, joint: str) -> np.ndarray:
        """(N, 2) position of ``joint``, mm."""
        st, p0 = self._joint(joint)
        out = st.write_point(p0, np.empty((self._n, 2)))
        return out if self._all_valid else self._mask(out)

    def velocity(self, joint: str) -> np.ndarray:
        """(N, 2) velocity, mm/s."""
        if self.order < 1:
            self._need(1, "velocity")
        st, p0 = self._joint(joint)
        if self._quiet or self._is_quiet():
            return st.write_velocity(p0, np.empty((self._n, 2)))
        with np.errstate(invalid="ignore", over="ignore"):
            out = st.write_velocity(p0, np.empty((self._n, 2)))
        return out if self._all_valid else self._mask(out)

    def acceleration(self, joint: str) -> np.ndarray:
        """(N, 2) acceleration, mm/s²."""
        if self.order < 2:
            self._need(2, "acceleration")
        st, p0 = self._joint(joint)
        if self._quiet or self._is_quiet():
            return st.write_acceleration(p0, np.empty((self._n, 2)))
        with np.errstate(invalid="ignore", over="ignore"):
            out = st.write_acceleration(p0, np.empty((self._n, 2)))
        return out if self._all_valid else self._mask(out)

    def point(self, link: str, xy) -> np.ndarray:
        """(N, 2) position of the point of ``link`` drawn at ``xy`` (mm)."""
        return self._mask(_xy2(self._state(link).point_xy(_c(xy)), len(self)))

    def point_velocity(self, link: str, xy) -> np.ndarray:
        self._need(1, "velocity")
        st = self._state(link)
        with np.errstate(invalid="ignore", over="ignore"):
            return self._mask(_xy2(st.vel_xy(st.arm_xy(_c(xy))), len(self)))

    def point_acceleration(self, link: str, xy) -> np.ndarray:
        self._need(2, "acceleration")
        st = self._state(link)
        with np.errstate(invalid="ignore", over="ignore"):
            return self._mask(_xy2(st.acc_xy(st.arm_xy(_c(xy))), len(self)))

    # -- links ----------------------------------------------------------------------------
    def rotation(self, link: str) -> np.ndarray:
        """(N,) rotation of ``link`` from its drawn pose, rad, unwrapped along the samples."""
        drv = self.plan.linkage.driver
        if link == drv.link and not drv.linear:
            rho = self.input - self.plan.theta0
        elif link == self.plan.linkage.ground:
            rho = np.zeros(len(self))
        else:
            c, s = self._state(link).cs
            n = len(self)
            rho = unwrap_finite(np.arctan2(np.broadcast_to(s, (n,)), np.broadcast_to(c, (n,))))
        return self._mask(rho)

    def angle(self, link: str) -> np.ndarray:
        """(N,) angle of the vector from the link's first joint to its second (rad, unwrapped);
        where those coincide in the drawn pose, the rotation from the drawn pose."""
        return self.rotation(link) + self.plan.angle0.get(link, 0.0)

    def omega(self, link: str) -> np.ndarray:
        """(N,) angular velocity, rad/s (CCW positive)."""
        self._need(1, "omega")
        return self._mask(np.broadcast_to(np.asarray(self._state(link).omega, dtype=float), (len(self),)).copy())

    def alpha(self, link: str) -> np.ndarray:
        """(N,) angular acceleration, rad/s²."""
        self._need(2, "alpha")
        return self._mask(np.broadcast_to(np.asarray(self._state(link).alpha, dtype=float), (len(self),)).copy())

    # -- groups ---------------------------------------------------------------------------
    @property
    def groups(self) -> list[Group]:
        return [s.group for s in self.plan.steps if s.group.name in self._outs]

    def group_output(self, name: str) -> K.DyadOut:
        """The kernel output of group ``name`` (states, ``ok``, ``cond``, ``gap``, ``mode``,
        ``slides``); raises :class:`UnknownIdError` for a group not solved here."""
        try:
            return self._outs[name]
        except KeyError:
            names = [s.group.name for s in self.plan.steps]
            if name in names:
                raise UnknownIdError(f"group {name!r} was not solved (not requested)") from None
            raise UnknownIdError(f"linkage {self.plan.linkage.id!r} has no group {name!r} "
                                 f"(groups: {', '.join(names) or 'none'})") from None

    def conditioning(self, group: str) -> np.ndarray:
        """(N,) |det| of the group's velocity system normalised to [0, 1] (0: toggle)."""
        return self.group_output(group).cond

    def feasible(self, group: str) -> np.ndarray:
        return self.group_output(group).ok

    def transmission_angle(self, group: str) -> np.ndarray:
        """(N,) transmission angle μ of an RRR group, rad in [0, π]: the angle at the inner joint."""
        self.group_output(group)  # UnknownIdError for a group not solved here
        g = next(g for g in self.groups if g.name == group)
        if g.kind is not GroupKind.RRR:
            raise RequestError(f"transmission angle is defined here for RRR groups; {group} is {g.kind}")
        L = self.position(g.inner)
        a = self.position(g.outer_i) - L
        b = self.position(g.outer_j) - L
        return np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(axis=1)))

    def residual(self) -> float:
        """Max loop-closure residual, mm: each joint computed from every link carrying it agrees,
        and every link stays rigid.

        For an R joint, the distance between its positions carried by each solved link; for a P
        joint, the distance of one link's axis point from the other link's axis line; for a link,
        how far its joints move from their drawn distances to its anchor (|rotation| ≠ 1). The
        last catches a group that puts a shared joint in the same wrong place for both links.
        """
        link = self.plan.linkage
        worst = 0.0
        with np.errstate(invalid="ignore"):
            for k, st in self._states.items():
                reach = max((abs(_c(link.joint(j).at) - st.a0) for j in link.link(k).joints), default=0.0)
                r = np.abs(np.abs(np.broadcast_to(st.rot, (len(self),))) - 1.0) * reach
                worst = max(worst, float(np.nanmax(r[self.valid], initial=0.0)))
            for j in link.joints:
                carriers = [c for c in link.links_of(j.id) if c in self._states]
                if len(carriers) < 2:
                    continue
                p0 = _c(j.at)
                pts = [np.broadcast_to(self._states[c].point(p0), (len(self),)) for c in carriers]
                if j.kind is JointKind.R:
                    r = max(np.nanmax(np.abs(p - pts[0])[self.valid], initial=0.0) for p in pts[1:])
                else:
                    _, u0 = _axis(link, j.id)
                    u = np.broadcast_to(self._states[carriers[0]].rot, (len(self),)) * u0
                    r = np.nanmax(np.abs(K.cross(u, pts[1] - pts[0]))[self.valid], initial=0.0)
                worst = max(worst, float(r))
        return worst
