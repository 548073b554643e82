"""Rolling-lever synthesis: pair D (frame profile), pair E (slider profile), drive, slip report.

:func:`synthesize` runs the element's method (``exact``: the ODE of :mod:`.exact`;
``paper``: the literal compass construction; ``corrected``: the construction with flaw C1 fixed,
:mod:`.paper`) over the stroke with ``points`` intervals, and returns a
:class:`RollingSynthesis` holding the sampled profiles, the working range, the crank synthesis and
the residual-slip measures of :mod:`.slip`. :func:`error_table` tabulates error and time
against N for several methods.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ...errors import GeometryError
from ...model.rolling_lever import METHODS, RollingLever
from .drive import DriveSynthesis, synthesize_drive
from .exact import ExactPath, WorkingRange, exact_path, march_limit
from .geometry import LeverGeometry, PoseState, pose_state, rot, slider_point
from .law import LawChecks, law_checks
from .paper import construct
from .slip import (ContinuousMeasures, ExactReference, NaturalSpline, PhysicalSlip, PointMeasures,
                           SlipSamples, continuous_slip, physical_slip, point_measures, point_slip_samples,
                           reference_for)
from ..table import Table

COLUMNS = ("theta", "alpha", "F.x", "F.y", "P.x", "P.y", "u1", "P0.x", "P0.y", "u2", "k53", "S5", "Q.x", "Q.y")


@dataclass
class SlipReport:
    """Every residual-slip figure of one synthesis (mm); ``continuous`` only for the exact method.

    ``refined`` holds the point measures of the same method with 2N intervals (for the paper's
    method this shows the plateau: the kinematic slip does not fall); ``refined_error`` says why
    it is missing when the construction with 2N intervals failed.

    ``samples`` (:class:`~.slip.SlipSamples`): the slip of pairs D and E accumulated along
    the stroke at every sample - of the computed motion for the exact method (ending at
    ``continuous.slip_d``/``slip_e``), of the construction points otherwise (ending at
    ``points.kinematic_slip``/``kinematic_slip_e``). The slip plots draw these arrays.
    """

    points: PointMeasures
    physical: PhysicalSlip
    continuous: ContinuousMeasures | None
    refined: PointMeasures | None
    time_s: float
    refined_error: str | None = None
    samples: SlipSamples | None = None


@dataclass
class RollingSynthesis:
    """Sampled result of a synthesis over k = 0…N (θ_k rad; positions mm in the ground frame, Q in the
    slider frame; u1/u2 contact angles on the lever circles in the lever frame, rad; k53 mm/rad; S5 mm).

    ``path`` is the exact motion over the stroke (for every method: the reference, the drive and
    the DXF curve of the exact method). ``time_s`` is the synthesis time of the method (s; for the
    exact method including the working-range search), ``time_exact_s`` that of the exact motion
    and working range, ``error_mm`` the exact method's bound on the integration error of P and Q
    (mm; see :func:`~.exact.integrate`; NaN for the constructions).
    """

    element: RollingLever
    method: str
    geom: LeverGeometry
    theta: np.ndarray
    alpha: np.ndarray
    F: np.ndarray
    P: np.ndarray
    u1: np.ndarray
    P0: np.ndarray
    u2: np.ndarray
    k53: np.ndarray
    S5: np.ndarray
    Q: np.ndarray
    path: ExactPath
    working_range: WorkingRange
    time_s: float
    error_mm: float
    time_exact_s: float = math.nan
    drive: DriveSynthesis | None = None
    slip: SlipReport | None = None
    #: with a slider law: pure rolling, cusps, working side, S5 reproduced (:mod:`.law`), with the measures
    law: LawChecks | None = None
    _ref: ExactReference | None = field(default=None, repr=False)

    @property
    def points(self) -> int:
        return len(self.theta) - 1

    def table(self) -> Table:
        """The CSV table: columns :data:`COLUMNS` (mm, rad; Q in the slider frame)."""
        cols = dict(zip(COLUMNS, (self.theta, self.alpha, self.F[:, 0], self.F[:, 1], self.P[:, 0], self.P[:, 1],
                                  self.u1, self.P0[:, 0], self.P0[:, 1], self.u2, self.k53, self.S5,
                                  self.Q[:, 0], self.Q[:, 1])))
        return Table.from_columns(cols)

    def pose(self, theta: np.ndarray) -> tuple[PoseState, np.ndarray]:
        """The exact motion at lever rotations θ (M,) rad inside the stroke: the pose state (pin F,
        contacts P and P0, circle centres, contact angles; mm, rad) and S5 (M,) mm (for animation
        without a crank; with one, see ``drive.frames``)."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        a, s5 = self.path.at(theta)
        return pose_state(self.geom, a, theta), s5

    # -- curves for drawing and export --------------------------------------------------------
    def frame_profile(self) -> tuple[Callable[[np.ndarray], np.ndarray], float, float]:
        """(curve, t0, t1): the frame profile (fixed centrode, ground frame) as a curve t -> (M, 2) mm.

        Exact method: t is θ and the curve is the integrated centrode (dense output). Constructions:
        t is the chord-length parameter of the natural cubic spline through P_k.
        """
        if self.method == "exact":
            def curve(t):
                a, _ = self.path.at(t)
                return pose_state(self.geom, a, t).P
            return curve, float(self.theta[0]), float(self.theta[-1])
        sp = NaturalSpline(self.P)
        return sp.eval, 0.0, sp.length_param

    def slider_profile(self) -> tuple[Callable[[np.ndarray], np.ndarray], float, float]:
        """(curve, t0, t1): the slider profile Q in the slider frame; see :meth:`frame_profile`."""
        if self.method == "exact":
            def curve(t):
                a, s5 = self.path.at(t)
                return slider_point(self.geom, pose_state(self.geom, a, t).P0, s5)
            return curve, float(self.theta[0]), float(self.theta[-1])
        sp = NaturalSpline(self.Q)
        return sp.eval, 0.0, sp.length_param

    @property
    def lever_e_points(self) -> np.ndarray:
        """The pair-E contacts P0 at the samples in the lever frame (N+1, 2) mm: points of the slider
        circle, or with a slider law of the lever element Π30."""
        return rot(-np.asarray(self.theta, dtype=float), self.P0 - self.F) + np.asarray(self.geom.f)

    def lever_profile_e(self) -> tuple[Callable[[np.ndarray], np.ndarray], float, float]:
        """(curve, θ0, θ1): with a slider law, the lever element Π30 - the pair-E contact P0 in the
        lever frame (the drawn pose) - as a curve θ -> (M, 2) mm over the stroke (exact method)."""
        def curve(t):
            a, _ = self.path.at(t)
            st = pose_state(self.geom, a, t)
            return rot(-np.asarray(t, dtype=float), st.P0 - st.F) + np.asarray(self.geom.f)
        return curve, float(self.theta[0]), float(self.theta[-1])

    def reference(self) -> ExactReference:
        """A tight exact reference centrode covering the stroke (built once, on demand)."""
        if self._ref is None:
            stroke = self.element.stroke
            self._ref = reference_for(self.geom, stroke.start, stroke.end, self.working_range)
        return self._ref


def _working_range(geom: LeverGeometry, path: ExactPath) -> WorkingRange:
    """Both ends of the working range, marching outward from the stroke's integrated ends."""
    th = path.theta
    i_lo, i_hi = int(np.argmin(th)), int(np.argmax(th))
    lo_start = (float(th[i_lo]), float(path.alpha[i_lo]), float(path.S5[i_lo]))
    hi_start = (float(th[i_hi]), float(path.alpha[i_hi]), float(path.S5[i_hi]))
    if th[i_lo] > 0.0:  # the stroke lies above the drawn pose: march down from θ = 0
        lo_start = (0.0, geom.alpha0, 0.0)
    if th[i_hi] < 0.0:
        hi_start = (0.0, geom.alpha0, 0.0)
    lo, lo_why = march_limit(geom, *lo_start, -1.0)
    hi, hi_why = march_limit(geom, *hi_start, 1.0)
    return WorkingRange(lo, hi, lo_why, hi_why)


def synthesize(element: RollingLever, method: str | None = None, points: int | None = None,
               measures: bool = True, physical_range: tuple[float, float] | None = None) -> RollingSynthesis:
    """Synthesise the rolling lever's profiles.

    Parameters
    ----------
    element : the rolling-lever element (drawn pose in mm, stroke in rad).
    method : ``"exact"`` | ``"paper"`` | ``"corrected"``; default the element's.
    points : N, the stroke is sampled at N + 1 points; default the element's.
    measures : compute the slip report (tens of milliseconds; off for fast previews).
    physical_range : θ range (rad) of the physical-slip run; default the whole constructed range.

    Raises :class:`GeometryError` when the stroke leaves the working range (the message gives the
    reachable range), when the slider circle cannot be reached, or when the drive cannot be built.
    """
    method = element.method if method is None else method
    if method not in METHODS:
        raise GeometryError(f"unknown synthesis method {method!r} (methods: {', '.join(METHODS)})")
    if element.slider_law is not None and method != "exact":
        raise GeometryError(f"rolling lever {element.id!r} has a slider law: only the exact method synthesises "
                            f"it (the {method} construction needs a slider circle)")
    n = element.points if points is None else int(points)
    if n < 2:
        raise GeometryError(f"points must be at least 2, got {n}")
    geom = LeverGeometry.from_element(element)
    start, end = element.stroke.start, element.stroke.end
    t0 = time.perf_counter()
    path = exact_path(geom, start, end, element.tolerance)
    wr = _working_range(geom, path)
    grid = np.linspace(start, end, n + 1)
    al, s5 = path.at(grid)
    al[0], s5[0] = path.alpha[0], path.S5[0]
    if grid[-1] == path.theta[-1]:   # the stroke's end is a node: its value, not a dense step to it
        al[-1], s5[-1] = path.alpha[-1], path.S5[-1]
    t_exact = time.perf_counter() - t0
    if method == "exact":
        th = grid
        st = pose_state(geom, al, th)
        P, P0, F = st.P, st.P0, st.F
        u1, u2, k53 = np.unwrap(st.u1), np.unwrap(st.u2), st.k53
        Q = slider_point(geom, P0, s5)
        elapsed = time.perf_counter() - t0
        error = path.error_mm
    else:
        ends = pose_state(geom, al[[0, -1]], grid[[0, -1]])
        u_ends = np.unwrap(ends.u1)
        t1 = time.perf_counter()
        c = construct(geom, method, (start, float(al[0])), float(s5[0]), float(u_ends[0]), float(u_ends[1]), n)
        elapsed = time.perf_counter() - t1
        th, al, F, P, u1, P0, u2, k53, s5, Q = c.theta, c.alpha, c.F, c.P, c.u1, c.P0, c.u2, c.k53, c.S5, c.Q
        error = math.nan
    bad = ~np.isfinite(al) | ~np.isfinite(s5) | ~np.isfinite(k53) | ~np.all(np.isfinite(P), axis=1) \
        | ~np.all(np.isfinite(Q), axis=1)
    if np.any(bad):  # never hand back NaN: the sampled motion left the working range somewhere
        k = int(np.argmax(bad))
        raise GeometryError(f"the {method} synthesis cannot evaluate the motion at point {k} of {n} "
                            f"(θ = {th[k]:.6f} rad): the pose is outside the working range {wr.describe()}")
    result = RollingSynthesis(element, method, geom, th, al, F, P, u1, P0, u2, k53, s5, Q, path, wr,
                              elapsed, error, t_exact)
    if element.drive is not None:
        result.drive = synthesize_drive(path, geom, start, end, element.drive.crank_pivot,
                                        element.drive.coupler_point)
    if measures:
        result.slip = slip_report(result, physical_range)
        if geom.law is not None:
            c = result.slip.continuous
            result.law = law_checks(result, (c.length_lever_e, c.length_slider) if c is not None else None)
    return result


def slip_report(res: RollingSynthesis, physical_range: tuple[float, float] | None = None,
                refine: bool = True) -> SlipReport:
    """All residual-slip measures of a synthesis (see :mod:`.slip`)."""
    t0 = time.perf_counter()
    geom = res.geom
    ref = res.reference()
    pm = point_measures(geom, res.theta, res.alpha, res.F, res.P, res.u1, res.u2, res.S5, ref, res.P0)
    lo, hi = (None, None) if physical_range is None else physical_range
    ph = physical_slip(geom, res.P, res.theta, res.alpha, lo, hi)
    stroke = res.element.stroke
    if res.method == "exact":
        cont, samples = continuous_slip(res.path, stroke.start, stroke.end, grid=res.theta)
    else:
        cont, samples = None, point_slip_samples(geom, res.theta, res.F, res.u1, res.u2, res.S5, res.P0)
    refined = None
    refined_error = None
    if refine and res.method != "exact":
        try:
            twice = synthesize(res.element, res.method, 2 * res.points, measures=False)
        except GeometryError as exc:  # the construction itself may fail with more points near the range end
            refined_error = str(exc)
        else:
            refined = point_measures(geom, twice.theta, twice.alpha, twice.F, twice.P, twice.u1, twice.u2,
                                     twice.S5, ref)
    return SlipReport(pm, ph, cont, refined, time.perf_counter() - t0, refined_error, samples)


@dataclass(frozen=True)
class ErrorRow:
    """One row of the error-against-N table (mm, s)."""

    method: str
    n: int
    time_s: float
    arc_mismatch: float
    kinematic_slip: float
    ic_offset: float
    deviation: float
    physical_slip: float
    continuous_slip: float  # exact method only (NaN otherwise)


def error_table(element: RollingLever, ns: tuple[int, ...] = (4, 8, 16, 32, 64, 128, 256, 512),
                methods: tuple[str, ...] = ("paper", "corrected", "exact"),
                physical_range: tuple[float, float] | None = None, repeat: int = 3) -> list[ErrorRow]:
    """Error and time against N for each method; the synthesis time is the best of ``repeat`` runs."""
    rows = []
    for m in methods:
        for n in ns:
            best = math.inf
            for _ in range(max(1, repeat)):
                res = synthesize(element, m, n, measures=False)
                best = min(best, res.time_s)
            rep = slip_report(res, physical_range, refine=False)
            rows.append(ErrorRow(m, n, best, rep.points.arc_mismatch, rep.points.kinematic_slip,
                                 rep.points.ic_offset, rep.points.deviation, rep.physical.slip,
                                 rep.continuous.worst if rep.continuous else math.nan))
    return rows
