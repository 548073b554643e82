"""The results the workspace hands out per element: linkages, Geneva drives, rolling levers.

Qt-free. :class:`~mechsketch.core.workspace.Workspace` computes each result once per element value
(and request) and caches it; the CLI and the GUI read the same objects. Every result carries its
time (``seconds``) and its error measures, and holds what the canvas animates so that nothing is
computed per animation frame:

- :class:`LinkageResult` - the compiled plan, the sweep over one driver revolution at order 2 and
  (on first access) the diagnostics, or the core's message when the linkage cannot be solved;

- :class:`GenevaResult` - kinematics and contact/wear over one crank revolution (N = the element's
  ``samples``), the exact drawable geometry (or why it cannot be built; built on first access:
  ``analyze --csv`` never needs it), and per frame the crank's and the wheel's world rotations
  (rad) read from the kinematics;
- :class:`RollingResult` - the synthesis (with the slip measures), the static curves (frame
  profile, slider profile in the slider frame, bicentrode) and :class:`RollingFrames`: one crank
  revolution from the folded dead centre when the element has a drive (``drive.frames(φ)``),
  else the stroke there and back with a cosine law (``pose(θ)``).

Failures are data: a result with ``error`` set (the core's message) and ``exception`` (the error
itself, which the CLI re-raises), never a raised exception.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Union

import numpy as np

from ..analyses.linkage_report import linkage_summary
from ..errors import MechsketchError
from ..model.drivers import input_text
from ..model.linkage import Linkage
from ..solver.diagnostics import Diagnostics, diagnose
from ..solver.plan import Plan, Solution, compile_plan
from .budget import check_request

if TYPE_CHECKING:  # pragma: no cover  (imported by the solve of their element type: issue 14)
    from ..model.geneva import Geneva
    from ..model.rolling_lever import RollingLever
    from ..analyses.geneva.contact import GenevaContact
    from ..analyses.geneva.geometry import GenevaGeometry
    from ..analyses.geneva.kinematics import GenevaKinematics
    from ..analyses.rolling.slip import SlipSamples
    from ..analyses.rolling.synthesis import RollingSynthesis

#: frames of a rolling lever's animation cycle: 2·points, at least this many
ROLLING_MIN_FRAMES = 360
#: points on the drawn frame and slider profiles (polylines of the exact curves)
PROFILE_POINTS = 400


def _message(exc: BaseException) -> str:
    return str(exc).strip() or type(exc).__name__


class _Result:
    """What every result has: the element it is of, and whether it solved (``error`` None)."""

    element: object
    error: str | None

    @property
    def element_id(self) -> str:
        return self.element.id

    @property
    def ok(self) -> bool:
        return self.error is None


# -- linkage -----------------------------------------------------------------------------------
@dataclass
class LinkageResult(_Result):
    """One linkage solved over one driver revolution of N samples at order 2.

    ``plan`` the compiled plan, ``solution`` the sweep (positions, velocities, accelerations);
    :attr:`diagnostics` (ranges, dead points, transmission angles, residual) is computed on first
    access. ``error`` is the core's message when the linkage cannot be compiled or solved (a
    linkage half drawn by the tools is normal). ``seconds``: compile and sweep time;
    ``incremental``: the sweep re-ran only the groups a drag touched.
    """

    element: Linkage
    plan: Plan | None = None
    solution: Solution | None = None
    error: str | None = None
    exception: MechsketchError | None = field(default=None, repr=False)   # what ``error`` says
    seconds: float = 0.0
    incremental: bool = False
    _diagnostics: Diagnostics | None = field(default=None, repr=False)
    _summary: str | None = field(default=None, repr=False)

    kind = "linkage"

    @property
    def n_frames(self) -> int:
        return len(self.solution) if self.solution is not None else 0

    @property
    def period(self) -> float:
        """Seconds per driver revolution (one animation cycle)."""
        rpm = self.element.driver.speed_rpm
        return 60.0 / abs(rpm) if rpm else 1.0

    @property
    def diagnostics(self) -> Diagnostics | None:
        """Reachable ranges, dead points, transmission angles and residual (computed once)."""
        if self._diagnostics is None and self.solution is not None:
            self._diagnostics = diagnose(self.solution)
        return self._diagnostics

    @property
    def diagnostics_if_computed(self) -> Diagnostics | None:
        """:attr:`diagnostics` if something asked for them already, else None (never computes:
        what a live drag shows without waiting for them)."""
        return self._diagnostics

    def frame_text(self, k: int) -> str:
        """Read-out of frame ``k``: the input (crank angle in degrees, or actuator length in mm) and time."""
        sol = self.solution
        unit = self.plan.input_unit
        value = float(sol.input[k]) if unit == "mm" else math.remainder(float(sol.input[k]), 2 * math.pi)
        return f"input {input_text(value, unit, 2)}  t {float(sol.t[k]):.3f} s"

    def summary(self) -> str:
        """What ``mechsketch analyze SCENE --element ID --summary`` prints (computed once: the
        classification's searches take seconds on a 1,000-joint linkage, which the GUI's worker
        thread pays before the result is shown)."""
        if self.solution is None:
            return f"linkage {self.element.id!r}: {self.error}"
        if self._summary is None:
            self._summary = linkage_summary(self.element, self.plan, self.diagnostics, self.solution)
        return self._summary


def solve_linkage(element: Linkage, samples: int | None = None, plan: Plan | None = None) -> LinkageResult:
    """Compile (unless ``plan`` is given) and sweep ``element`` at ``samples`` (default the
    element's) to order 2. Never raises for a linkage that cannot be solved."""
    from_plan = plan is not None
    t0 = time.perf_counter()
    res = LinkageResult(element)
    try:
        check_request(element, samples or element.samples)
        res.plan = plan if from_plan else compile_plan(element)
        res.solution = res.plan.sweep(samples=samples or element.samples, order=2)
    except MechsketchError as exc:
        res.error, res.exception = _message(exc), exc.with_traceback(None)
        res.solution = None
    res.seconds = time.perf_counter() - t0
    return res


# -- Geneva ------------------------------------------------------------------------------------
@dataclass
class GenevaResult(_Result):
    """One Geneva drive solved over one crank revolution of N samples.

    ``crank_rotation`` and ``wheel_rotation`` (N,) rad are the world rotations of the driver parts
    (about the crank centre) and of the wheel (about its centre) from their built frames, at frame
    k: direction + φ_k and direction + wheel.angle_k (the kinematics' world-frame wheel angle,
    ∓π/z held still in the dwell). ``error`` is the core's message when the drive or its drawing
    cannot be built (the kinematics may still be there for the plots).
    """

    element: Geneva
    kinematics: GenevaKinematics | None = None
    contact: GenevaContact | None = None
    crank_rotation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    wheel_rotation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    seconds: float = 0.0
    _summary: str | None = field(default=None, repr=False)
    _geometry: GenevaGeometry | None = field(default=None, repr=False)
    _geometry_pending: bool = field(default=False, repr=False)   # True: build it on first access
    _error: str | None = field(default=None, repr=False)
    _exception: MechsketchError | None = field(default=None, repr=False)

    kind = "geneva"

    def _build_geometry(self) -> None:
        """Build the drawable geometry once (about 40 ms), on the first read of ``geometry``,
        ``error``, ``exception`` or ``n_frames``; its time is added to ``seconds``."""
        if not self._geometry_pending:
            return
        from ..analyses.geneva.geometry import geometry

        self._geometry_pending = False
        t0 = time.perf_counter()
        try:
            self._geometry = geometry(self.element)
        except MechsketchError as exc:
            self._error = f"cannot draw the drive: {_message(exc)}"
            self._exception = exc.with_traceback(None)
        self.seconds += time.perf_counter() - t0

    @property
    def geometry(self) -> GenevaGeometry | None:
        """The exact drawable drive (None when it cannot be built: see ``error``)."""
        self._build_geometry()
        return self._geometry

    @property
    def error(self) -> str | None:
        """The core's message when the drive or its drawing cannot be built, else None."""
        self._build_geometry()
        return self._error

    @property
    def exception(self) -> MechsketchError | None:
        """The error ``error`` words (what the CLI re-raises)."""
        self._build_geometry()
        return self._exception

    @property
    def n_frames(self) -> int:
        """Frames of the animation cycle (0 when nothing can be animated)."""
        return len(self.crank_rotation) if self.geometry is not None else 0

    @property
    def period(self) -> float:
        """Seconds per crank revolution (one animation cycle)."""
        return 60.0 / abs(self.element.speed_rpm)

    def frame_text(self, k: int) -> str:
        """Read-out of frame ``k``: crank angle and time."""
        kin = self.kinematics
        return f"crank φ {math.degrees(kin.phi[k]):.1f}°  t {float(kin.t[k]):.3f} s"

    def phi_deg(self) -> np.ndarray:
        """Crank angle φ of every sample (°, from the line of centres, time order)."""
        return np.degrees(self.kinematics.phi) if self.kinematics is not None else np.zeros(0)

    def summary(self) -> str:
        """What ``mechsketch analyze SCENE --element ID --summary`` prints (computed once, on demand;
        it reports the relief of the drawn geometry, so it builds the geometry)."""
        if self._summary is None:
            if self.kinematics is None or self.contact is None:
                self._summary = f"geneva {self.element.id!r}: {self.error}"
            else:
                from ..analyses.geneva.report import summary as geneva_summary

                self._summary = geneva_summary(self.element, self.kinematics, self.contact, self.geometry)
        return self._summary


def solve_geneva(element: Geneva, samples: int | None = None) -> GenevaResult:
    """Kinematics and contact/wear of ``element`` at ``samples`` points (default the element's)
    and the per-frame rotations; the drawable geometry is built when first read. Never raises
    for a bad drive."""
    from ..analyses.geneva.contact import contact
    from ..analyses.geneva.kinematics import kinematics

    t0 = time.perf_counter()
    res = GenevaResult(element)
    n = int(samples or element.samples)
    try:
        check_request(element, n)
        res.kinematics = kinematics(element, n)
        res.contact = contact(element, n, element.model)
    except MechsketchError as exc:
        res._error, res._exception = _message(exc), exc.with_traceback(None)
        res.seconds = time.perf_counter() - t0
        return res
    direction = math.radians(element.wheel_direction_deg)
    res.crank_rotation = direction + res.kinematics.phi
    res.wheel_rotation = direction + res.kinematics.wheel_angle
    res._geometry_pending = True
    res.seconds = time.perf_counter() - t0
    return res


# -- rolling lever -----------------------------------------------------------------------------
@dataclass
class RollingFrames:
    """The rolling lever at each frame of its animation cycle, arrays over N frames.

    ``theta`` lever rotation (rad, 0 = drawn pose), ``alpha`` rocker angle (rad), ``F`` the pin,
    ``P`` the pair-D contact, ``P0`` the pair-E contact (N, 2) mm in the ground; ``S5`` slider
    travel (mm). With a drive: ``phi`` crank angle (rad, CCW from the folded dead centre), crank
    pivot ``A``, crank pin ``B`` and lever point ``C`` (N, 2) mm; else they are None. ``u1`` /
    ``u2`` (N,) rad: the contact angles on the lever circle and on the slider circle (lever frame,
    drawn pose), so the contact can be marked on the lever at every frame.
    """

    theta: np.ndarray
    alpha: np.ndarray
    F: np.ndarray
    P: np.ndarray
    P0: np.ndarray
    S5: np.ndarray
    phi: np.ndarray | None = None
    A: np.ndarray | None = None
    B: np.ndarray | None = None
    C: np.ndarray | None = None
    u1: np.ndarray | None = None
    u2: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.theta)


@dataclass
class RollingResult(_Result):
    """One rolling lever synthesised, with what the canvas and the plots draw.

    ``frame_profile`` (M, 2) mm ground frame and ``slider_profile`` (M, 2) mm slider frame are
    polylines through the synthesis' profile curves; ``bicentrode`` (N+1, 2) mm the locus of P0;
    ``lever_arc`` and ``slider_arc`` (start, end) rad the contact angles u1, u2 over the stroke
    (lever frame; with a slider law ``slider_arc`` is the θ range and ``lever_profile_e`` (M, 2) mm
    the lever element Π30 in the lever frame). :attr:`slip_samples`: the slip of pairs D and E accumulated along the stroke,
    computed by the synthesis' slip report (the last values are the summary's figures).
    ``error`` holds the core's message when the synthesis failed.
    """

    element: RollingLever
    synthesis: RollingSynthesis | None = None
    frames: RollingFrames | None = None
    frame_profile: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    slider_profile: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    bicentrode: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    lever_arc: tuple[float, float] = (0.0, 0.0)
    slider_arc: tuple[float, float] = (0.0, 0.0)
    #: with a slider law: the lever element Π30 in the lever frame, (M, 2) mm (else empty)
    lever_profile_e: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    error: str | None = None
    exception: MechsketchError | None = field(default=None, repr=False)   # what ``error`` says
    seconds: float = 0.0

    kind = "rolling_lever"

    @property
    def slip_samples(self) -> SlipSamples | None:
        """Slip of pairs D and E per sample along the stroke (None without a slip report)."""
        syn = self.synthesis
        return syn.slip.samples if syn is not None and syn.slip is not None else None

    @property
    def n_frames(self) -> int:
        return len(self.frames) if self.frames is not None else 0

    #: the element has no speed: its animation cycle (the stroke there and back, or one crank
    #: turn with a drive) is shown in this many seconds at 1x
    period = 2.0

    def frame_text(self, k: int) -> str:
        """Read-out of frame ``k``: lever rotation (and crank angle with a drive)."""
        f = self.frames
        text = f"lever θ {math.degrees(f.theta[k]):.2f}°"
        return text if f.phi is None else f"crank φ {math.degrees(f.phi[k]):.1f}°  {text}"

    def summary(self) -> str:
        """What ``mechsketch synthesize SCENE --element ID --summary`` prints."""
        if self.synthesis is None:
            return f"rolling lever {self.element.id!r}: {self.error}"
        from ..analyses.rolling.report import summary as rolling_summary

        return rolling_summary(self.synthesis)


def _rolling_frames(res: RollingSynthesis, n: int) -> RollingFrames:
    """The animation cycle (see :class:`RollingFrames`)."""
    from ..analyses.rolling.geometry import pose_state

    k = np.arange(n, dtype=float)
    drive = res.drive
    if drive is not None:
        phi = drive.phi_folded + 2.0 * math.pi * k / n
        m = drive.frames(phi)
        st = pose_state(res.geom, m.alpha, m.theta)
        return RollingFrames(m.theta, m.alpha, m.F, m.P, m.P0, m.S5, phi, m.A, m.B, m.C, st.u1, st.u2)
    st = res.element.stroke
    theta = st.start + st.span * 0.5 * (1.0 - np.cos(2.0 * math.pi * k / n))
    state, s5 = res.pose(theta)
    return RollingFrames(theta, state.alpha, state.F, state.P, state.P0, s5, u1=state.u1, u2=state.u2)


def _curve(curve_range, points: int) -> np.ndarray:
    curve, t0, t1 = curve_range
    return np.asarray(curve(np.linspace(t0, t1, points)), dtype=float)


def rolling_frame_count(element: RollingLever) -> int:
    """Frames of the animation cycle: 2·points (there and back), at least :data:`ROLLING_MIN_FRAMES`."""
    return max(2 * int(element.points), ROLLING_MIN_FRAMES)


def solve_rolling(element: RollingLever, measures: bool = True) -> RollingResult:
    """Synthesise ``element`` (with the slip measures unless ``measures`` is False: a drag preview
    re-synthesises in about 5 ms, the measures take some 50 ms more) and precompute its frames
    and curves."""
    from ..analyses.rolling.synthesis import synthesize

    t0 = time.perf_counter()
    out = RollingResult(element)
    try:
        res = synthesize(element, measures=measures)
        out.frames = _rolling_frames(res, rolling_frame_count(element))
        out.frame_profile = _curve(res.frame_profile(), PROFILE_POINTS)
        out.slider_profile = _curve(res.slider_profile(), PROFILE_POINTS)
        if element.slider_law is not None:
            out.lever_profile_e = _curve(res.lever_profile_e(), PROFILE_POINTS)
    except MechsketchError as exc:
        out.error, out.exception = _message(exc), exc.with_traceback(None)
        out.frames = None
        out.seconds = time.perf_counter() - t0
        return out
    out.synthesis = res
    out.bicentrode = np.asarray(res.P0, dtype=float)
    out.lever_arc = (float(np.min(res.u1)), float(np.max(res.u1)))
    out.slider_arc = (float(np.min(res.u2)), float(np.max(res.u2)))
    out.seconds = time.perf_counter() - t0
    return out


# -- gear pairs and the Geneva they drive ---------------------------------------------------------
@dataclass
class GearResult(_Result):
    """A non-circular gear pair over one input turn of N samples (equal times).

    ``kinematics`` (:class:`~..analyses.gears.pitch.GearKinematics`), ``checks``
    (:class:`~..analyses.gears.pitch.PitchChecks`), ``input_curve`` / ``output_curve`` (M, 2) mm the
    pitch curves in their body frames (closed polylines), ``input_center`` / ``output_center`` mm,
    ``input_rotation`` / ``output_rotation`` (N,) rad the world rotations of the bodies per frame
    (line of centres included). ``error`` is the core's message when the pair cannot be built.
    """

    element: object
    kinematics: object = None
    checks: object = None
    input_curve: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    output_curve: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    input_center: tuple[float, float] = (0.0, 0.0)
    output_center: tuple[float, float] = (0.0, 0.0)
    input_rotation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    output_rotation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    error: str | None = None
    exception: MechsketchError | None = field(default=None, repr=False)
    seconds: float = 0.0

    kind = "gear_pair"

    @property
    def n_frames(self) -> int:
        return len(self.input_rotation)

    @property
    def period(self) -> float:
        return self.kinematics.period if self.kinematics is not None else 1.0

    def frame_text(self, k: int) -> str:
        kin = self.kinematics
        return f"input {math.degrees(kin.input_rotation[k]):.1f}°  ratio {kin.ratio[k]:.3f}  t {float(kin.t[k]):.3f} s"

    def summary(self) -> str:
        if self.kinematics is None:
            return f"gear pair {self.element.id!r}: {self.error}"
        from ..analyses.gears.report import gear_summary

        el = self.element
        return gear_summary(el.id, el.function, el.center_distance, self.kinematics, self.checks)


def solve_gear_pair(element, samples: int | None = None) -> GearResult:
    """The pitch curves, checks and kinematics of a ``gear_pair`` element (never raises)."""
    from ..analyses.gears.pitch import checks, curves, kinematics

    t0 = time.perf_counter()
    out = GearResult(element)
    try:
        n = int(samples or element.samples)
        kin = kinematics(element.function, element.center_distance, element.speed_rpm, n)
        out.kinematics, out.checks = kin, checks(element.function, element.center_distance, kin.sense)
        out.input_curve, out.output_curve = curves(element.function, element.center_distance, kin.sense, PROFILE_POINTS)
    except MechsketchError as exc:
        out.error, out.exception = _message(exc), exc.with_traceback(None)
        out.kinematics = None
        return out
    d = math.radians(element.direction_deg)
    out.input_center, out.output_center = element.input_center, element.output_center
    out.input_rotation = d + kin.input_rotation
    out.output_rotation = d + kin.output_rotation
    out.seconds = time.perf_counter() - t0
    return out


@dataclass
class GearedGenevaResult(GenevaResult):
    """A Geneva drive driven through gears (``geared_geneva``): a :class:`GenevaResult` of its drive
    (``element`` the inner Geneva, with the composite's id) whose ``kinematics`` and ``contact`` are
    those of the geared crank and whose ``crank_rotation`` follows the gears' output; ``gears`` the
    pair's :class:`GearResult` on the same frames, ``smoothness`` against the constant crank,
    ``input_torque`` (N,) N·m the crank's torque passed back through the gears, ``composite`` the
    scene element."""

    gears: GearResult | None = None
    smoothness: object = None
    input_torque: np.ndarray = field(default_factory=lambda: np.zeros(0))
    composite: object = None

    kind = "geared_geneva"

    def summary(self) -> str:
        if self._summary is None:
            if self.kinematics is None or self.contact is None or self.gears is None:
                self._summary = f"geared Geneva {self.element.id!r}: {self.error}"
            else:
                from ..analyses.geneva.driven_report import geared_summary

                self._summary = geared_summary(self.composite, self.kinematics, self.contact, self.smoothness,
                                               self.gears.summary(), self.input_torque, self.geometry)
        return self._summary


def solve_geared_geneva(element, samples: int | None = None) -> GearedGenevaResult:
    """The driven Geneva and its gears over one input turn (never raises)."""
    from ..analyses.geneva.contact import contact
    from ..analyses.geneva.driven import GearCrank, driven_kinematics, smoothness
    from ..analyses.geneva.torque import crank_torque

    t0 = time.perf_counter()
    g = element.geneva
    res = GearedGenevaResult(g, composite=element)
    n = int(samples or g.samples)
    try:
        check_request(g, n)
        kin, theta = driven_kinematics(g.slots, g.omega1, element.function, n)
        crank = GearCrank(element.function, g.omega1)
        u = (1.0 if g.omega1 > 0 else -1.0) * kin.phi
        res.kinematics = kin
        res.contact = contact(g, n, g.model, u=u, crank=crank)
        res.smoothness = smoothness(element.function, g.slots, g.omega1)
        res.gears = solve_gear_pair(element.gear_pair, n)
        ratio = crank.ev.derivatives(theta)[1]
        res.input_torque = -crank_torque(g, res.contact).torque * ratio
    except MechsketchError as exc:
        res._error, res._exception = _message(exc), exc.with_traceback(None)
        res.seconds = time.perf_counter() - t0
        return res
    direction = math.radians(g.wheel_direction_deg)
    res.crank_rotation = direction + kin.phi
    res.wheel_rotation = direction + kin.wheel_angle
    res._geometry_pending = True
    res.seconds = time.perf_counter() - t0
    return res


ElementResult = Union[LinkageResult, GenevaResult, RollingResult, GearResult]


def solve_element(element, samples: int | None = None, measures: bool = True) -> ElementResult | None:
    """The result of any element (``samples`` overrides a linkage's or a Geneva drive's own
    sample count; ``measures`` False skips a rolling lever's slip report, for drag previews);
    None for an element type this version does not solve."""
    if isinstance(element, Linkage):
        return solve_linkage(element, samples)
    kind = getattr(element, "type", None)   # the other models are imported for their own elements only
    if kind == "geneva":
        from ..model.geneva import Geneva

        return solve_geneva(element, samples) if isinstance(element, Geneva) else None
    if kind == "rolling_lever":
        from ..model.rolling_lever import RollingLever

        return solve_rolling(element, measures) if isinstance(element, RollingLever) else None
    if kind == "gear_pair":
        return solve_gear_pair(element, samples)
    if kind == "geared_geneva":
        return solve_geared_geneva(element, samples)
    return None
