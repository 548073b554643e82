"""Kinetostatics of a linkage: joint reactions and the driving effort, group by group in closed form.

The Assur decomposition that solves the kinematics also makes the forces statically determinate
group by group: each class-II group (two links, three joints) has six equilibrium equations and
six unknown reaction components. Walking the groups from the last one back to the driver, every
load a later group puts on the links of an earlier one is known when that group is solved, and
each group's reactions come out of a few cross products (Cramer's rule on a 2×2 system whose
determinant is the group's kinematic one, so forces grow as 1/conditioning near a dead point).
Finally the driver link gives the torque the motor applies; the frame collects the shaking force
and moment. A linear actuator's effort is a force (N, positive extending): a slider driven along a
frame guide takes it along the guide beside the guide's normal force and couple; a cylinder's
barrel and rod are locked into the bar V of its group (loads summed about the barrel's pivot M),
and the rod's own balance then gives the push along the slide axis (barrel on rod) and the
slide's normal force and moment. Its power is the force times the rod's speed out of the barrel. Everything is vectorised over the samples of a :class:`~mechsketch.core.solver.plan.Solution`
of order 2; nothing loops over samples.

Loads on each link (d'Alembert): gravity m·g at the centre of mass, the inertia force −m·a_c and
moment −I·α from the accelerations the kinematics computed, constant point forces and torques,
springs (tension k·(ℓ − ℓ0)) and viscous dampers (tension c·dℓ/dt) between two link points.

Conventions and units. The model is in mm; forces are SI: N, N·m, kg, kg·m², m/s², W. Points and
vectors are complex numbers x + iy (arrays (N,)); ``cross(a, b)`` is the z component of a × b.
A revolute joint's reaction is reported as the force on each of its later-listed links (file
order) from the joint; with two links that is the force the earlier-listed link exerts on the
later-listed one; with more, the first link takes the balance. A prismatic joint is frictionless:
its reaction is a force normal to the slide plus a moment, reported as exerted by the
earlier-listed link on the later-listed one, the moment about the joint's point as the later link
carries it (the point :meth:`Solution.position` reports). The shaking force and moment are what
the mechanism exerts on the frame (through its joints, the motor's stator and the springs and
dampers anchored to it), the moment about the driver's pivot.

Checks carried with the result: the power balance per sample (:class:`PowerBalance`: motor power
plus the power of the loads minus d(kinetic energy)/dt, analytically from the velocities and
accelerations; zero up to round-off for exact reactions) and the groups' conditioning, with the
places where it falls below :data:`COND_WARN` (:meth:`ForceResult.dead_point_notes`).

Coulomb friction in revolute joints (friction-circle radius ρ: a friction moment ρ·|reaction|
against the relative rotation) makes the problem nonlinear; it is solved beside the frictionless
result by a fixed-point iteration of the same closed-form pass (:class:`FrictionResult`).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ...errors import RequestError
from ...model.drivers import input_text
from ...model.linkage import JointKind, Linkage
from ...solver.kernels import cross
from ...solver.plan import Plan, Solution
from ...solver.structure import Group
from .errors import force_errors
from .passes import MM, Kinetostatics, Pass, _neg, _pin_force

__all__ = ["COND_WARN", "DeadPointNote", "DriverEffort", "ForceResult", "FrictionResult", "MM",
           "PowerBalance", "SlideReaction", "input_label", "linkage_forces"]
#: a group whose conditioning falls below this is named in the report (forces ~ 1/conditioning)
COND_WARN = 0.1
#: friction iteration: at most this many closed-form passes, until the change is below FRICTION_TOL
FRICTION_MAX_ITER = 60
FRICTION_TOL = 1e-13


def _xy(z, n: int) -> np.ndarray:
    """Complex (N,) (or scalar) -> float (N, 2): a view of a contiguous complex array."""
    z = np.asarray(z)
    if z.shape != (n,) or z.dtype != np.complex128 or not z.flags.c_contiguous:
        z = np.ascontiguousarray(np.broadcast_to(z, (n,)), dtype=np.complex128)
    return z.view(np.float64).reshape(n, 2)


def _arr(x, n: int) -> np.ndarray:
    """A float (N,) array of ``x`` (a scalar broadcasts; an (N,) float array is returned as is)."""
    if isinstance(x, np.ndarray) and x.shape == (n,) and x.dtype == np.float64:
        return x
    return np.array(np.broadcast_to(np.asarray(x, dtype=float), (n,)))


# -- results ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class DriverEffort:
    """What the driver applies to keep the prescribed motion, (N,) per sample.

    ``kind`` "torque": N·m on the driver link, counter-clockwise positive (a crank); "force": N
    along a linear actuator, positive extending (reserved for actuator drivers). ``column`` is
    the CSV column name (``driver.torque`` / ``driver.force``).
    """

    kind: str
    link: str
    values: np.ndarray

    @property
    def unit(self) -> str:
        return "N·m" if self.kind == "torque" else "N"

    @property
    def column(self) -> str:
        return f"driver.{self.kind}"


@dataclass(frozen=True)
class SlideReaction:
    """Reaction of prismatic joint ``joint``: exerted by link ``by`` (earlier in the file) on link
    ``on``. ``force`` (N, 2) N, normal to the slide; ``normal`` (N,) N its signed size along
    n = J·u (u the slide axis as the links turn it); ``moment`` (N,) N·m about the joint's point
    carried by ``on``."""

    joint: str
    by: str
    on: str
    force: np.ndarray
    normal: np.ndarray
    moment: np.ndarray


@dataclass(frozen=True)
class PowerBalance:
    """The power balance per sample, W, arrays (N,): ``motor`` (driver effort × its speed),
    ``loads`` (applied forces, torques, gravity, springs, dampers, joint friction), ``kinetic``
    d(kinetic energy)/dt, ``residual`` = motor + loads − kinetic (zero for exact reactions) and
    ``scale`` the sum of the magnitudes of all terms."""

    motor: np.ndarray
    loads: np.ndarray
    kinetic: np.ndarray
    residual: np.ndarray
    scale: np.ndarray

    @property
    def relative(self) -> np.ndarray:
        """(N,) |residual| over the largest ``scale`` of the cycle (NaN where not assembled)."""
        top = float(np.nanmax(self.scale, initial=0.0)) if np.isfinite(self.scale).any() else 0.0
        return np.abs(self.residual) / (top if top > 0 else 1.0)

    @property
    def worst(self) -> float:
        """The largest relative residual of the cycle (0 when nothing moves)."""
        rel = self.relative
        return float(np.nanmax(rel, initial=0.0)) if np.isfinite(rel).any() else 0.0


@dataclass(frozen=True)
class FrictionResult:
    """The forces with Coulomb friction in the revolute joints (``radii`` joint -> mm).

    ``driver``, ``pins``, ``slides``, ``power`` as in :class:`ForceResult`; ``iterations``
    closed-form passes; ``converged`` (N,) bool where the last pass changed nothing above
    :data:`FRICTION_TOL` relative.
    """

    radii: dict[str, float]
    driver: DriverEffort
    pins: dict[str, dict[str, np.ndarray]]
    slides: dict[str, SlideReaction]
    power: PowerBalance
    iterations: int
    converged: np.ndarray


@dataclass
class ForceResult:
    """Kinetostatics of one linkage over the samples of a solution (arrays (N,), SI units).

    ``driver`` the driving effort; ``pins`` revolute joint -> {link: (N, 2) N, the force on that
    link from the joint} for every link after the first in file order; ``slides`` prismatic
    joint -> :class:`SlideReaction`; ``shaking_force`` (N, 2) N and ``shaking_moment`` (N,) N·m
    on the frame (moment about the driver pivot); :attr:`power` the :class:`PowerBalance`
    (computed on first access); :attr:`errors` the estimated error of every column (computed on
    first access, :mod:`.errors`); ``conditioning`` group -> (N,) in [0, 1]; ``friction`` the
    result with joint friction (None without); ``valid`` (N,) where the kinematics with its rates
    is valid (``Solution.rates_valid``: assembled, not at a toggle) and the forces finite — every
    force is NaN elsewhere; ``seconds`` the time of the force computation (not the kinematics).
    """

    linkage: Linkage
    input: np.ndarray
    t: np.ndarray
    valid: np.ndarray
    driver: DriverEffort
    pins: dict[str, dict[str, np.ndarray]]
    slides: dict[str, SlideReaction]
    shaking_force: np.ndarray
    shaking_moment: np.ndarray
    conditioning: dict[str, np.ndarray]
    friction: FrictionResult | None = None
    seconds: float = 0.0
    groups: tuple[Group, ...] = ()
    #: the input's unit: "rad" (a crank's angle) or "mm" (an actuator's length or displacement)
    unit: str = "rad"
    _notes: list | None = field(default=None, repr=False)
    _power: PowerBalance | None = field(default=None, repr=False)
    _power_args: tuple | None = field(default=None, repr=False)
    _errors: dict | None = field(default=None, repr=False)
    _error_args: tuple | None = field(default=None, repr=False)

    def __len__(self) -> int:
        return self.input.shape[0]

    @property
    def errors(self) -> dict[str, np.ndarray]:
        """Per force column (``driver.torque``, ``J.Fx``, ``shaking.M``, ...; and
        ``slide.J.normal``, ``slide.J.moment``) its estimated absolute error, (N,) N or N·m, from
        the conditioning of the group solves (:func:`~.errors.force_errors`); NaN where the
        forces are not valid. Computed on first access."""
        if self._errors is None:
            plan, sol = self._error_args
            self._errors = force_errors(self, plan, sol)
            self._error_args = None
        return self._errors

    @property
    def power(self) -> PowerBalance:
        """The power balance per sample (motor + loads − d(KE)/dt), computed on first access."""
        if self._power is None:
            ks, motor, valid = self._power_args
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
                F, M = ks.applied(keep_inertia=True)
            self._power = _balance(ks, F, M, motor, valid)
            ks.release()
            self._power_args = None
        return self._power

    def reaction(self, joint: str, link: str | None = None) -> np.ndarray:
        """(N, 2) N: the force on ``link`` (default: the second of the joint's links in the file)
        from revolute joint ``joint``; for a prismatic joint, its normal force on the later link."""
        if joint in self.slides:
            return self.slides[joint].force
        if joint not in self.pins:
            lk = self.linkage
            if joint not in lk.joint_ids:
                raise RequestError(f"linkage {lk.id!r} has no joint {joint!r}")
            raise RequestError(f"joint {joint!r} carries no reaction (it is on one link only)")
        on = self.pins[joint]
        if link is None:
            return next(iter(on.values()))
        if link not in on:
            carriers = self.linkage.links_of(joint)
            if link in carriers:   # the first link takes the balance of the others
                return -sum(on.values())
            raise RequestError(f"link {link!r} is not on joint {joint!r} (links: {', '.join(carriers)})")
        return on[link]

    def dead_point_notes(self) -> list["DeadPointNote"]:
        """Groups whose conditioning falls below :data:`COND_WARN`: where, how low, and the
        largest reaction of the group's joints there (forces grow as 1/conditioning)."""
        if self._notes is None:
            self._notes = _notes(self)
        return self._notes


@dataclass(frozen=True)
class DeadPointNote:
    """Near a dead point of group ``group``: its conditioning ``cond`` is lowest at sample
    ``index`` (input ``at``: "123.45°" for a crank, "956.00 mm" for an actuator), where the
    largest reaction of its joints is ``force`` N at joint ``joint``."""

    group: str
    index: int
    at: str
    cond: float
    joint: str
    force: float

    def __str__(self) -> str:
        return (f"{self.group}: conditioning {self.cond:.3g} at input {self.at} — forces "
                f"grow as 1/conditioning there ({self.force:.4g} N at {self.joint})")


def input_label(res: ForceResult, k: int) -> str:
    """The input at sample ``k`` as read by a person: a crank angle in degrees in (−180°, 180°]
    ("123.45°"), an actuator's length or displacement in mm ("956.00 mm")."""
    x = float(res.input[k])
    if res.unit == "rad":
        x = math.remainder(x, 2 * math.pi)
    return input_text(x, res.unit, 2)


def _notes(res: ForceResult) -> list[DeadPointNote]:
    out = []
    groups = {g.name: g for g in res.groups}
    for name, cond in res.conditioning.items():
        c = np.where(res.valid, cond, np.nan)
        if not np.isfinite(c).any():
            continue
        k = int(np.nanargmin(c))
        if c[k] >= COND_WARN:
            continue
        best, where = 0.0, ""
        for j in groups[name].joints:
            if j in res.pins:
                f = max(float(np.hypot(*v[k])) for v in res.pins[j].values())
            elif j in res.slides:
                f = float(abs(res.slides[j].normal[k]))
            else:
                continue
            if f > best or not where:
                best, where = f, j
        out.append(DeadPointNote(name, k, input_label(res, k), float(c[k]), where, best))
    return out


# -- the computation ---------------------------------------------------------------------------------
def _views(ks: Kinetostatics, p: Pass, valid: np.ndarray, all_valid: bool
           ) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, SlideReaction]]:
    """The pass's revolute and prismatic reactions in the reported form (module docstring)."""
    lk, n = ks.lk, ks.n

    def xy(z) -> np.ndarray:
        out = _xy(z, n)
        return out if all_valid else np.where(valid[:, None], out, np.nan)

    def masked(a) -> np.ndarray:
        out = _arr(a, n)
        return out if all_valid else np.where(valid, out, np.nan)

    pins: dict[str, dict[str, np.ndarray]] = {}
    slides: dict[str, SlideReaction] = {}
    single = {j: (on, f) for j, on, _by, f in p.pairs}   # the one pair of a two-link joint
    carriers_of = ks.static.carriers
    for j in lk.joints:
        carriers = carriers_of[j.id]
        if len(carriers) < 2:
            continue
        if j.kind is JointKind.R:
            if len(carriers) == 2:
                on, f = single[j.id]
                pins[j.id] = {carriers[1]: xy(f if on == carriers[1] else _neg(f))}
            else:
                pins[j.id] = {b: xy(_pin_force(p.pairs, j.id, b)) for b in carriers[1:]}
        elif j.id in p.slides:
            on, f, q, c = p.slides[j.id]
            by, later = carriers
            if on != later:
                f, c = _neg(f), _neg(c)
            moment = MM * (c + cross(q - ks.point(later, ks.at[j.id]), f))
            normal = (f * np.conjugate(ks.normal(later, j.id))).real
            slides[j.id] = SlideReaction(j.id, by, later, xy(f), masked(normal), masked(moment))
    return pins, slides


def _balance(ks: Kinetostatics, F: dict, M: dict, motor: np.ndarray, valid: np.ndarray) -> PowerBalance:
    """The power balance of a pass: motor power ``motor`` (W) with the loads ``F``/``M``."""
    with np.errstate(invalid="ignore", over="ignore"):
        loads, kinetic, scale = ks.power_terms(F, M)
        nan = np.where(valid, 0.0, np.nan)
        return PowerBalance(motor + nan, loads + nan, kinetic + nan, motor + loads - kinetic + nan,
                            scale + np.abs(motor) + nan)


def linkage_forces(plan: Plan, sol: Solution) -> ForceResult:
    """Driving effort, joint reactions, shaking force and moment of ``plan``'s linkage over the
    samples of ``sol`` (a full solve of order 2), with the groups' conditioning, the power
    balance (computed on first access of ``power``) and, when joints have friction, the result
    with friction beside. Arrays (N,) or (N, 2), SI units (see :class:`ForceResult`). Raises
    :class:`RequestError` for a solution without accelerations or of only some groups.
    """
    if sol.order < 2:
        raise RequestError(f"forces need a solve with order 2 (accelerations); this one has order {sol.order}")
    if len(sol.groups) != len(plan.steps):
        raise RequestError("forces need every group solved: solve without a joints filter")
    start = time.perf_counter()
    ks = Kinetostatics(plan, sol)
    n = ks.n
    drv = ks.lk.driver.link
    ekind = "torque" if ks.kind == "crank" else "force"
    unit = MM if ekind == "torque" else 1.0     # the pass's effort: N·mm (crank) or N (actuator)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        w = ks.motor_speed()      # rad/s (crank) or m/s (actuator): motor power = effort × w
        if ks.lk.friction:   # the friction's power balance is eager: it needs the inertia loads
            F, M = ks.applied(keep_inertia=True)
            p = ks.run(F, M)
        else:                # the loads are dropped group by group as the pass goes
            p = ks.run(*ks.applied(), consume=True)
        effort = _arr(unit * p.effort, n)
        # every reaction a group finds is passed on to its known links and so, group by group,
        # to the frame (and the driver): a NaN or inf anywhere reaches these sums
        # and only where the kinematics' rates are (a force grows as 1/conditioning; at a toggle
        # the accelerations are 0/0 or rounding noise, and so would every force be)
        valid = sol.rates_valid & np.isfinite(effort + p.frame_moment) & np.isfinite(p.frame_force)
        all_valid = bool(valid.all())
        if not all_valid:
            effort = np.where(valid, effort, np.nan)
        pins, slides = _views(ks, p, valid, all_valid)
        frame_f = _xy(p.frame_force, n)
        frame_m = _arr(MM * p.frame_moment, n)
        if not all_valid:
            frame_f = np.where(valid[:, None], frame_f, np.nan)
            frame_m = np.where(valid, frame_m, np.nan)
        friction = None
        if ks.friction_pairs():
            fp, F2, M2, its, conv = ks.with_friction(F, M, p, FRICTION_TOL, FRICTION_MAX_ITER)
            feff = np.where(valid, _arr(unit * fp.effort, n), np.nan)
            fpins, fslides = _views(ks, fp, valid, all_valid)
            friction = FrictionResult({fr.joint: fr.radius for fr in ks.lk.friction},
                                      DriverEffort(ekind, drv, feff), fpins, fslides,
                                      _balance(ks, F2, M2, feff * w, valid), its, conv & valid)
    res = ForceResult(ks.lk, sol.input, sol.t, valid, DriverEffort(ekind, drv, effort), pins, slides,
                      frame_f, frame_m, {s.group.name: _arr(sol.group_output(s.group.name).cond, n)
                                         for s in plan.steps},
                      friction, groups=tuple(s.group for s in plan.steps), unit=plan.input_unit)
    ks.release()
    res._power_args = (ks, effort * w, valid)
    res._error_args = (plan, sol)
    res.seconds = time.perf_counter() - start
    return res
