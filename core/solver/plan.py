"""Compile a linkage once into a plan of array kernels; evaluate it on many driver angles at once.

``plan = compile_plan(linkage)``; ``sol = plan.sweep(samples=3600, order=2)`` or
``plan.evaluate(angles, order=0)``. Only the groups that the requested joints depend on are run,
and only up to the requested derivative order ("model only what a scene needs").
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Iterable

import numpy as np

from ..errors import GeometryError, RequestError, UnknownIdError
from ..model.drivers import DriverKind
from ..model.linkage import JointKind, Linkage
from . import fpquiet as _fp
from . import kernels as K
from .branches import find_branch_points, flip_factor
from .grid import SweepGrid
from .drive import CrankDrive, find_linear_branch_points, linear_flip, make_drive
from .memory import reserve as _reserve
from .motion_law import cycle
from .solution import Solution, _axis, _c, unwrap_finite
from .steps import Step
from .structure import Group, GroupKind, decompose, mobility
from .tolerances import SINGULAR_REL, TOGGLE_COND, TOUCH_REL

__all__ = ["TOGGLE_COND", "TOUCH_REL", "Plan", "Solution", "Step", "compile_plan", "unwrap_finite"]

#: sweeps of up to this many samples need no reserve (:mod:`.memory`)
_reserved_for = 255
#: a plan keeps the input grids of sweeps of this many sample counts (:meth:`Plan._make_grid`)
_GRIDS = 4


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
    #: (every step's index, the branch points) once every group's branch points are known
    _every: tuple | None = field(default=None, repr=False)
    #: per sample count, the input grid of the constant-speed sweeps (:mod:`.grid`), read-only
    _grid: dict | None = field(default=None, repr=False)
    #: the frame's points and their rates at its joints' drawn positions (scalars, the same at
    #: every solve; :meth:`_frame_template`): each solve's frame state starts from copies of them
    _ground: tuple | None = field(default=None, repr=False)
    #: per step (the step, fixed, group name, link i, link j): what a solve reads of its group
    _flat: list | None = field(default=None, repr=False)

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

    def needed(self, links: Iterable[str]) -> set[int]:
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
        return sorted(self.needed(self.steps[k].needs) | {k})

    def steps_for(self, joints: Iterable[str] | None) -> list[int]:
        """Indices of the steps needed to know ``joints`` (all steps if None)."""
        if joints is None:
            return list(range(len(self.steps)))
        links = []
        for j in joints:
            if j not in self.reporter:
                raise UnknownIdError(f"linkage {self.linkage.id!r} has no joint {j!r}")
            links.append(self.reporter[j])
        return sorted(self.needed(links))

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
                  states: dict | None = None, crank: "SweepGrid | None" = None) -> dict[str, K.DyadOut]:
        """Run the kernels of steps ``idx`` at ``inputs`` (the engine under :meth:`evaluate`).
        ``crank``: for a sweep's inputs at the plan's constant speed, their :class:`~.grid.SweepGrid`
        (the crank's cos/sin, and its points' motion once kept)."""
        w = self.omega if omega is None else omega
        drv = self.linkage.driver
        if states is None:
            states = {}
        frame = self._ground
        if frame is None:
            frame = self._ground = self._frame_template()
        ground = K.ground_state()
        ground.share_points(*frame)
        states[self.linkage.ground] = ground
        if crank is not None:
            st = states[drv.link] = K.crank(self.pivot, self.theta0, inputs, w, alpha, order, crank.cs)
            crank.share(st)
        elif self.drive is None:
            states[drv.link] = K.crank(self.pivot, self.theta0, inputs, w, alpha, order)
        else:
            self.drive.set_states(states, inputs, w, alpha, order)
        linear = self.drive is not None and self.drive.linear
        outs: dict[str, K.DyadOut] = {}
        token = _fp.enter()
        try:
            flat = self._flat
            if flat is None or len(flat) != len(self.steps):
                flat = self._flat = [(s, s.group.fixed, s.group.name, s.group.link_i, s.group.link_j)
                                     for s in self.steps]
            for k in idx:
                step, fixed, name, link_i, link_j = flat[k]
                if fixed:
                    out = _held(step.run(states, order, None), inputs.shape, order)
                else:
                    offsets = branches.get(name)
                    flip = (None if offsets is None or not offsets.size else   # no branch point: both give None
                            linear_flip(offsets, inputs, self.theta0) if linear else
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
                if not (type(probe) is float and math.isfinite(probe)):   # finite float: proved finite
                    out.ok, out.every = out.ok & np.isfinite(probe), False
                states[link_i] = out.state_i
                states[link_j] = out.state_j
                outs[name] = out
        finally:
            _fp.leave(token)
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
        return self._solve(inputs, order, omega, alpha, joints, t)

    def _solve(self, inputs, order: int, omega, alpha, joints, t, crank: "SweepGrid | None" = None) -> "Solution":
        """:meth:`evaluate`; ``crank``: the crank's motion kept with a sweep's grid (:meth:`run_steps`)."""
        every = self._every
        if joints is None and every is not None and every[1] is self._branches:   # every step's known
            idx, branches = every
        else:
            idx = self.steps_for(joints)
            branches = self.branch_points(idx)
            if joints is None:
                self._every = (idx, branches)
        start = time.perf_counter()
        if not (inputs.__class__ is np.ndarray and inputs.dtype == np.float64 and inputs.ndim == 1):
            inputs = np.asarray(inputs, dtype=float).reshape(-1)
        if inputs.shape[0] > _reserved_for:
            _reserve(inputs.shape[0])
        w = self.omega if omega is None else omega if omega.__class__ is float else _rate(omega)
        if alpha.__class__ is not float:
            alpha = _rate(alpha)
        states: dict[str, K.LinkState] = {}
        outs = self.run_steps(inputs, order, idx, branches, w, alpha, states, crank)
        valid = None
        every = True        # every group found every sample assembled: valid is all True
        for out in outs.values():
            if valid is None:
                valid = np.array(out.ok, dtype=bool)
                if valid.shape != inputs.shape:
                    valid = np.broadcast_to(valid, inputs.shape).copy()
            elif not (every and out.every):
                np.logical_and(valid, out.ok, out=valid)
            every = every and out.every
        if valid is None:
            valid = np.ones(inputs.shape, dtype=bool)
        elapsed = time.perf_counter() - start
        return Solution(self, inputs, order, states, outs, valid, w, t, elapsed, alpha,
                        all_valid=True if every else None)

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
        if order not in (0, 1, 2):
            raise RequestError(f"order must be 0, 1 or 2, got {order}")
        w = self.omega
        grid = None if self._grid is None else self._grid.get(n)
        if grid is None:
            grid = self._make_grid(n)
        k = grid.k
        dt = 2.0 * math.pi / abs(w) / n
        # the inputs: a copy of the grid's (a solution's own); the times made only if read
        # (Solution.t calls this); the crank's motion shared, read-only
        sol = self._solve(grid.inputs.copy(), order, w, 0.0, joints, lambda: k * dt,
                          grid if grid.cs is not None else None)
        if grid.points is None and grid.cs is not None:
            grid.harvest(sol._states.get(self.linkage.driver.link), order)
        return sol

    def _frame_template(self) -> tuple:
        """(points, rates) caches of the frame's state at its joints' drawn positions, complete
        ([arm, point] and [velocity, acceleration], scalars), for
        :meth:`~.link_state.LinkState.share_points` (each solve gets its own copies of the dicts:
        complete entries are never written, so solves in several threads do not race on them)."""
        st = K.ground_state()
        for j in self.linkage.link(self.linkage.ground).joints:
            p0 = self.joint_at[j][1]
            arm = st.arm_xy(p0)
            st.point_xy(p0)
            st.vel_at(p0, arm)
            st.acc_at(p0, arm)
        return st._points or {}, st._rates or {}

    def _make_grid(self, n: int) -> SweepGrid:
        """A new :class:`~.grid.SweepGrid` for sweeps of ``n`` samples, kept (the last few sizes)."""
        crank = self.drive is None or self.drive.__class__ is CrankDrive
        drawn = [self.joint_at[j][1] for j in self.linkage.link(self.linkage.driver.link).joints] if crank else None
        grid = SweepGrid(n, self.omega, self.theta0, drawn)
        if self._grid is None or len(self._grid) >= _GRIDS:
            self._grid = {}
        self._grid[n] = grid
        return grid


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
        c = K._rrr_const(m0, h0, l0)
        run = lambda s, o, f: K.rrr(s[ki], m0, s[kj], h0, l0, o, f, tol, near, c)  # noqa: E731
    elif g.kind is GroupKind.RRP:
        m0, l0 = at[g.outer_i], at[g.inner]
        s0, u0 = _axis(linkage, g.outer_j)
        scale = abs(l0 - m0)
        tol = touch_tol(scale)
        c = K._rrp_const(m0, u0, l0)
        run = lambda s, o, f: K.rrp(s[ki], m0, s[kj], s0, u0, l0, o, f, tol, c)  # noqa: E731
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


def _rate(v) -> float | np.ndarray:
    """An input rate as a float, or a float array when it varies over the samples."""
    if isinstance(v, (float, int)) or np.ndim(v) == 0:
        return float(v)
    return np.asarray(v, dtype=float)
