"""The result of a solve: kinematics of a linkage at N driver samples, read joint by joint.

:class:`Solution` holds the link states the kernels computed (:class:`~.link_state.LinkState`)
and the groups' outputs, and extracts from them each joint's (N, 2) position, velocity and
acceleration (mm, mm/s, mm/s²) and each link's rotation and rates, on request. A joint is read
from the link that reports it (:attr:`Plan.joint_at`); the link keeps the points it computed, so
that a joint's position is computed once per solve however often it is read.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import RequestError, UnknownIdError
from ..model.linkage import JointKind, Linkage
from . import kernels as K
from .steps import StepPlan
from .structure import MODAL_KINDS, Group, GroupKind
from .tolerances import RATE_EPS, RATE_REL


__all__ = ["Solution", "unwrap_finite"]


def _c(xy) -> complex:
    """An (x, y) pair as x + iy."""
    return complex(float(xy[0]), float(xy[1]))


def _axis(linkage: Linkage, jid: str) -> tuple[complex, complex]:
    """A P joint's drawn point and unit axis direction."""
    j = linkage.joint(jid)
    a = math.radians(j.axis_deg or 0.0)
    return _c(j.at), complex(math.cos(a), math.sin(a))


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


#: rows of the residual's work buffer at a time (N = 3,600: 0.9 MB, held in cache)
_BLOCK = 16


def _residual_layout(plan: StepPlan) -> tuple[dict, dict, list]:
    """What :meth:`Solution.residual` reads of the linkage, made once per plan: the joints'
    drawn points (complex, mm), each link's joints, and for every joint carried by two links or
    more (id, is an R joint, unit axis of a P joint, the links carrying it)."""
    lay = getattr(plan, "_residual_layout", None)
    if lay is None:
        lk = plan.linkage
        drawn = {j.id: _c(j.at) for j in lk.joints}
        link_joints = {k.id: k.joints for k in lk.links}
        shared = []
        for j in lk.joints:
            links = lk.links_of(j.id)
            if len(links) >= 2:
                is_r = j.kind is JointKind.R
                shared.append((j.id, is_r, None if is_r else _axis(lk, j.id)[1], links))
        lay = (drawn, link_joints, shared)
        if hasattr(plan, "__dict__"):
            plan._residual_layout = lay
    return lay


def _masked_max(r: np.ndarray, valid: np.ndarray | None) -> float:
    """The greatest non-NaN value of ``r`` (rows, N) in the columns where ``valid`` (N,) (every
    column when None), 0.0 when there is none."""
    return float(np.nanmax(r if valid is None else r[:, valid], initial=0.0))


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

    def __init__(self, plan: StepPlan, inputs, order, states, outs, valid, omega, t, elapsed, alpha=0.0,
                 all_valid: bool | None = None):
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
        self._all_valid = bool(valid.all()) if all_valid is None else all_valid   # known: no reduction
        self._quiet: bool | None = None
        self._rates_valid: np.ndarray | None = None
        self._residual: float | None = None   # residual(), computed on first use
        self._joint_at = plan.joint_at   # joint -> (link reporting it, drawn point)
        frame = states.get(plan.linkage.ground)
        #: the frame's state if it is at rest as run_steps makes it (scalar zero rates): its
        #: points' rates are +0.0 arrays, made without the general path
        self._frame = frame if frame is not None and frame.still() else None

    def __len__(self) -> int:
        return self.input.shape[0]

    @property
    def t(self) -> np.ndarray:
        """(N,) time of each sample, s (made on first use when the solve was not given one)."""
        t = self._t
        if t is None:
            inputs, omega = self.input, self.omega_driver
            t = self._t = ((inputs - inputs[0]) / omega if np.ndim(omega) == 0 and omega
                           else np.zeros_like(inputs))
        elif t.__class__ is not np.ndarray and callable(t):   # made on first use (a sweep's)
            t = self._t = t()
        return t

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
        if self._rates_valid is None and self._rates_bounded():
            self._rates_valid = self.valid.copy()   # known without a pass over the samples
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
                    ok &= RATE_EPS * eps * (1.0 + step.coord / step.scale) <= RATE_REL * c
                for st in self._states.values():
                    rates = [*st.vxy, st.omega] + ([*st.axy, st.alpha] if self.order >= 2 else [])
                    for r in rates:
                        ok &= np.broadcast_to(np.isfinite(np.asarray(r)), ok.shape)
            self._rates_valid = ok
        return self._rates_valid

    def _rates_bounded(self) -> bool:
        """The rates are finite (:meth:`_is_quiet`) and every group's conditioning is known, from
        its kernel's lower bound (``DyadOut.cond_floor``), to keep the rates' estimated error below
        RATE_REL at every sample: then :attr:`rates_valid` is ``valid``, with no pass over them."""
        if not self._is_quiet():
            return False
        eps = np.finfo(float).eps
        for step in self.plan.steps:
            out = self._outs.get(step.group.name)
            if out is None or step.group.fixed:
                continue
            f = out.cond_floor
            if step.group.kind in MODAL_KINDS:
                f = f * f
            if not RATE_EPS * eps * (1.0 + step.coord / step.scale) <= RATE_REL * f:
                return False
        return True

    def rate_error(self, group: str) -> np.ndarray:
        """(N,) the estimated relative error of the rates ``group`` computes (its own part, not
        what it inherits): 8·eps·(1 + coordinates/size)/cond² (/cond for PRP and RPP), the
        estimate :attr:`rates_valid` compares with RATE_REL; 0 for a fixed group, inf where the
        group is not assembled."""
        out = self.group_output(group)
        step = next(s for s in self.plan.steps if s.group.name == group)
        if step.group.fixed:
            return np.zeros(len(self))
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            c = np.broadcast_to(np.asarray(out.cond, dtype=float), (len(self),))
            if step.group.kind in MODAL_KINDS:
                c = c * c
            e = RATE_EPS * np.finfo(float).eps * (1.0 + step.coord / step.scale) / c
        return np.where(np.asarray(out.ok) & np.isfinite(e), e, np.inf)

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
        every sample assembled, every group's conditioning at least 1e-8 (known without a
        reduction over the samples where its kernel's lower bound from the assembly margins,
        :attr:`~.kernels.DyadOut.cond_floor`, is at least 1e-6), the input's rate at most 1e30
        and its acceleration 1e60 (per s, s²), coordinates at most 1e30 mm: the rates are then
        below ~1e130 and their squares times the arms finite. Otherwise the extraction runs
        under ``np.errstate`` (1 µs a call)."""
        q = self._quiet
        if q is None:
            q = (self._all_valid and self.plan.coord_scale <= 1e30
                 and _below(self.omega_driver, 1e30) and _below(self.alpha_driver, 1e60))
            for out in self._outs.values() if q else ():
                if out.cond_floor >= 1e-6:     # the margins bound it far above: not even made
                    continue
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
        """(state of the link reporting ``joint``, its drawn point); UnknownIdError for a joint
        not in the linkage or on a link not solved here."""
        e = self.plan.joint_at.get(joint)
        if e is None:
            raise UnknownIdError(f"linkage {self.plan.linkage.id!r} has no joint {joint!r}")
        return self._state(e[0]), e[1]

    def link_state(self, link: str) -> K.LinkState:
        """The kernel state of ``link`` (anchor, rotation and their rates: complex/float (N,) or
        scalars, mm and rad units; see :class:`~mechsketch.core.solver.kernels.LinkState`), for
        analyses that work on many points of a link at once (the kinetostatics). Raises
        :class:`UnknownIdError` for a link not solved here."""
        return self._state(link)

    # -- joints and points ----------------------------------------------------------------
    def position(self, joint: str) -> np.ndarray:
        """(N, 2) position of ``joint``, mm."""
        e = self._joint_at.get(joint)
        st = None if e is None else self._states.get(e[0])
        st, p0 = self._joint(joint) if st is None else (st, e[1])
        out = np.empty((self._n, 2))
        pts = st._points
        got = None if pts is None else pts.get(p0)
        if got is not None and len(got) > 1 and got[1][0].__class__ is np.ndarray:   # computed: copy it
            x, y = got[1]
            o = out.T
            o[0] = x
            o[1] = y
        else:
            out = st.write_point(p0, out)
        return out if self._all_valid else self._mask(out)

    def velocity(self, joint: str) -> np.ndarray:
        """(N, 2) velocity, mm/s."""
        if self.order < 1:
            self._need(1, "velocity")
        e = self._joint_at.get(joint)
        st = None if e is None else self._states.get(e[0])
        st, p0 = self._joint(joint) if st is None else (st, e[1])
        if st is self._frame and self._all_valid:   # what write_velocity gives the frame: +0.0
            return np.zeros((self._n, 2))
        if self._quiet or self._is_quiet():
            return st.write_velocity(p0, np.empty((self._n, 2)))
        with np.errstate(invalid="ignore", over="ignore"):
            out = st.write_velocity(p0, np.empty((self._n, 2)))
        return out if self._all_valid else self._mask(out)

    def acceleration(self, joint: str) -> np.ndarray:
        """(N, 2) acceleration, mm/s²."""
        if self.order < 2:
            self._need(2, "acceleration")
        e = self._joint_at.get(joint)
        st = None if e is None else self._states.get(e[0])
        st, p0 = self._joint(joint) if st is None else (st, e[1])
        if st is self._frame and self._all_valid:   # what write_acceleration gives the frame: +0.0
            return np.zeros((self._n, 2))
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
        if self._residual is None:
            self._residual = self._residual_now()
        return self._residual

    def _residual_now(self) -> float:
        """:meth:`residual`, computed: the links' rotations and the gaps between a shared joint's
        positions as its carriers computed them, written a block of rows at a time into one
        (rows, N) complex buffer and reduced once per block (a max of the same elementwise
        values: bit for bit a pass per link and per joint)."""
        drawn, link_joints, shared = _residual_layout(self.plan)
        n, states = len(self), self._states
        valid = None if self._all_valid else self.valid
        gaps: list[tuple] = []     # R joints: ((x, y) by the first carrier, (x, y) by another)
        worst = 0.0
        with np.errstate(invalid="ignore"):
            for jid, is_r, u0, links in shared:
                carriers = [c for c in links if c in states]
                if len(carriers) < 2:
                    continue
                p0 = drawn[jid]
                if is_r:
                    a = states[carriers[0]].point_xy(p0)
                    gaps += [(a, states[c].point_xy(p0)) for c in carriers[1:]]
                else:   # a P joint: one carrier's axis point from the other's axis line
                    u = np.broadcast_to(states[carriers[0]].rot, (n,)) * u0
                    d = states[carriers[1]].point(p0) - states[carriers[0]].point(p0)
                    worst = max(worst, _masked_max(np.abs(K.cross(u, np.broadcast_to(d, (n,))))[None], valid))
            rots = list(states.items())
            reach = np.array([max((abs(drawn[j] - st.a0) for j in link_joints[k]), default=0.0) for k, st in rots])
            buf = np.empty((min(_BLOCK, max(len(rots), len(gaps), 1)), n), dtype=complex)
            for s in range(0, len(rots), _BLOCK):
                blk = buf[:len(rots[s:s + _BLOCK])]
                for row, (_, st) in zip(blk, rots[s:s + _BLOCK]):
                    row.real, row.imag = st.cs         # the parts of st.rot, without making it
                r = np.abs(np.abs(blk) - 1.0) * reach[s:s + _BLOCK, None]
                worst = max(worst, _masked_max(r, valid))
            for s in range(0, len(gaps), _BLOCK):
                blk = buf[:len(gaps[s:s + _BLOCK])]
                for row, ((xa, ya), (xb, yb)) in zip(blk, gaps[s:s + _BLOCK]):
                    np.subtract(xb, xa, out=row.real)   # complex subtraction is per part
                    np.subtract(yb, ya, out=row.imag)
                worst = max(worst, _masked_max(np.abs(blk), valid))
        return worst
