"""What a designer asks a linkage to do — a path, rigid-body poses or an input–output function —
read from arrays and checked before any synthesis runs.

Each ``*_target`` function takes plain arrays (what a CSV, the canvas or a script gives) and
returns a frozen record, or raises :class:`DesignError` naming what is wrong and what to change
(too few points, NaN, repeated or degenerate poses, a function that is not one). Units: mm for
positions, degrees in the inputs (records hold radians where a name says ``_rad``).

Also here: :class:`Progress`, the callback protocol of every long synthesis (fraction done and a
message; return True to cancel), and :class:`Cancelled`, raised when it asks to stop.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from ..errors import MechsketchError, RequestError

#: fewest points of a closed path, an open path (untimed) and a timed path
MIN_CLOSED, MIN_OPEN, MIN_TIMED = 6, 4, 3
#: fewest and most poses (motion) and precision pairs (function)
MIN_POSES, MIN_PAIRS = 3, 3
#: two points closer than this fraction of the target's size are the same point
SAME_REL = 1e-9


class DesignError(RequestError):
    """A design request that cannot be met as asked (too few or repeated points, a degenerate
    problem, nothing reachable): the message says what to add, remove or relax."""


class Cancelled(MechsketchError):
    """The caller's progress callback asked to stop; nothing was returned."""


#: ``progress(fraction, message) -> stop``: fraction in [0, 1]; return True to cancel (the
#: synthesis then raises :class:`Cancelled` at its next check). Called from the thread doing the
#: work (a GUI marshals it to its own thread).
Progress = Callable[[float, str], "bool | None"]


def report(progress: Progress | None, fraction: float, message: str) -> None:
    """Tell ``progress`` how far the work is; raise :class:`Cancelled` if it asks to stop."""
    if progress is not None and progress(min(max(fraction, 0.0), 1.0), message):
        raise Cancelled(f"cancelled at {fraction:.0%}: {message}")


def _finite_rows(a: np.ndarray, what: str, columns: str) -> None:
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if bad.size:
        rows = ", ".join(str(int(k) + 1) for k in bad[:5]) + (" ..." if bad.size > 5 else "")
        raise DesignError(f"{what}: row(s) {rows} are not numbers ({columns} must all be finite); "
                          "fix or remove them")


def _array(values, ncol: int, what: str, columns: str) -> np.ndarray:
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise DesignError(f"{what}: expected rows of {ncol} numbers ({columns})") from None
    if a.ndim != 2 or a.shape[1] != ncol:
        raise DesignError(f"{what}: expected rows of {ncol} numbers ({columns}), got an array of shape {a.shape}")
    _finite_rows(a, what, columns)
    return a


def size_of(points: np.ndarray) -> float:
    """The size of a point set: the diagonal of its bounding box, mm (points (M, 2))."""
    return float(np.hypot(*(points.max(axis=0) - points.min(axis=0)))) if len(points) else 0.0


@dataclass(frozen=True)
class PathTarget:
    """Ordered points a coupler point must pass through.

    ``points`` (M, 2) mm, in order; ``closed``: the path is a loop traced once per crank turn
    (else an open arc traced within one turn); ``inputs_rad``: None (untimed: only the shape
    counts) or (M,) the crank angle at each point from the first, rad (timed: prescribed)."""

    points: np.ndarray
    closed: bool = True
    inputs_rad: np.ndarray | None = None

    @property
    def size(self) -> float:
        """Bounding-box diagonal, mm: deviations are reported relative to it."""
        return size_of(self.points)

    @property
    def timed(self) -> bool:
        return self.inputs_rad is not None


def path_target(points: Sequence[Sequence[float]], closed: bool = True,
                inputs_deg: Sequence[float] | None = None) -> PathTarget:
    """A checked path target from (M, 2) points (mm) and, for a timed path, (M,) crank angles (°)
    from the first point (strictly monotonic, within one turn). A closed path whose last point
    repeats the first drops it; points repeated one after the other are refused."""
    pts = _array(points, 2, "path", "x, y")
    timed = inputs_deg is not None
    t = None
    if timed:
        t = np.asarray(inputs_deg, dtype=float).reshape(-1)
        if t.shape[0] != pts.shape[0]:
            raise DesignError(f"path: {pts.shape[0]} points but {t.shape[0]} input angles; give one per point")
        _finite_rows(t[:, None], "path", "input_deg")
    size = size_of(pts)
    if closed and len(pts) > 1 and np.hypot(*(pts[-1] - pts[0])) <= SAME_REL * max(size, 1e-300):
        pts, t = pts[:-1], (t[:-1] if t is not None else None)
    need = MIN_TIMED if timed else (MIN_CLOSED if closed else MIN_OPEN)
    kind = "a timed path" if timed else ("a closed path" if closed else "an open path")
    if len(pts) < need:
        raise DesignError(f"{kind} needs at least {need} points to define it; got {len(pts)}: add points")
    if not size > 0.0:
        raise DesignError("path: every point is at the same place; give points that trace a path")
    step = np.hypot(*np.diff(pts, axis=0).T)
    same = np.flatnonzero(step <= SAME_REL * size)
    if same.size:
        k = int(same[0])
        raise DesignError(f"path: points {k + 1} and {k + 2} are the same point ({pts[k, 0]:g}, {pts[k, 1]:g}); "
                          "remove the repeat")
    if t is not None:
        t = t - t[0]
        d = np.diff(t)
        if not (np.all(d > 0) or np.all(d < 0)):
            raise DesignError("path: the input angles must increase (or decrease) from point to point")
        if abs(t[-1]) >= 360.0:
            raise DesignError(f"path: the input angles span {abs(t[-1]):g}°, more than one turn; "
                              "a coupler point passes each point once per turn")
        t = np.radians(t)
    return PathTarget(pts, bool(closed), t)


@dataclass(frozen=True)
class PoseTarget:
    """Rigid-body positions of the coupler: ``points`` (n, 2) mm of its reference point and
    ``angles_rad`` (n,) its orientation, in the order the coupler must pass them."""

    points: np.ndarray
    angles_rad: np.ndarray

    @property
    def size(self) -> float:
        """The bounding-box diagonal of the pose points, mm (at least the turn's chord scale)."""
        return size_of(self.points)

    @property
    def complex_points(self) -> np.ndarray:
        return self.points[:, 0] + 1j * self.points[:, 1]


def pose_target(poses: Sequence[Sequence[float]]) -> PoseTarget:
    """A checked pose target from (n, 3) rows x, y (mm), angle (°). Refused: fewer than 3 poses,
    two equal poses, every pose at one point (the coupler only turns about it: no finite pivots),
    and poses that are pure translations along one line (no circle passes through three
    collinear positions: only a slider could guide them)."""
    a = _array(poses, 3, "poses", "x, y, angle_deg")
    n = len(a)
    if n < MIN_POSES:
        raise DesignError(f"motion synthesis needs at least {MIN_POSES} poses; got {n}: add poses")
    pts, ang = a[:, :2], np.radians(a[:, 2])
    size = size_of(pts)
    for i in range(n):
        for j in range(i + 1, n):
            far = math.hypot(*(pts[j] - pts[i])) > SAME_REL * max(size, 1.0)
            turn = abs(math.remainder(ang[j] - ang[i], 2 * math.pi)) > 1e-9
            if not far and not turn:
                raise DesignError(f"poses {i + 1} and {j + 1} are the same pose ({pts[i, 0]:g}, {pts[i, 1]:g}, "
                                  f"{a[i, 2]:g}°); remove one or move it")
    if not size > 0.0:
        raise DesignError("poses: every pose has its point at the same place, so the coupler only turns about "
                          "that point and every pivot of a four-bar would sit on it; move the poses apart")
    turns = np.abs(np.remainder(ang - ang[0] + math.pi, 2 * math.pi) - math.pi)
    z = pts[:, 0] + 1j * pts[:, 1]
    if np.all(turns[1:] > 1e-9):   # each pose is pose 1 turned about its pole: one pole for all?
        rot = np.exp(1j * (ang[1:] - ang[0]))
        poles = (z[1:] - rot * z[0]) / (1.0 - rot)
        if np.all(np.abs(poles - poles[0]) <= 1e-9 * size):
            raise DesignError(f"poses: every pose is the first turned about one point ({poles[0].real:g}, "
                              f"{poles[0].imag:g}): a single pivot there guides the body and every dyad's centre "
                              "lies on it, so no four-bar does; move a pose off that rotation")
    if np.all(turns <= 1e-9):
        d = (pts - pts[0]) / size
        u = d[np.argmax(np.hypot(d[:, 0], d[:, 1]))]
        off = np.abs(d[:, 0] * u[1] - d[:, 1] * u[0]) / np.hypot(*u)
        if np.all(off <= 1e-9):
            raise DesignError("poses: the coupler does not turn and its point moves along one line (pure "
                              "translation along a line): no circle passes through the collinear positions of "
                              "any coupler point, so no four-bar guides it; turn the poses or move one off the line")
    return PoseTarget(pts, ang)


@dataclass(frozen=True)
class FunctionTarget:
    """Input–output pairs from the first row: ``inputs_rad`` (n,) the crank angle turned, rad,
    and ``outputs`` (n,) the output's change, rad (``unit`` "deg": a rocker's angle) or mm
    (``unit`` "mm": a slider's displacement), both 0 at the first row."""

    inputs_rad: np.ndarray
    outputs: np.ndarray
    unit: str = "deg"

    @property
    def angular(self) -> bool:
        return self.unit == "deg"

    @property
    def output_span(self) -> float:
        """The output's range (rad or mm)."""
        return float(np.ptp(self.outputs))


def function_target(pairs: Sequence[Sequence[float]], unit: str = "deg") -> FunctionTarget:
    """A checked function target from (n, 2) rows input (°), output (° or mm) (``unit``), taken
    relative to the first row. Refused: fewer than 3 rows, inputs that repeat or do not move in
    one direction, a span over one turn, an output that does not change."""
    if unit not in ("deg", "mm"):
        raise DesignError(f"function output unit must be 'deg' or 'mm', got {unit!r}")
    cols = f"input_deg, output_{unit}"
    a = _array(pairs, 2, "function", cols)
    if len(a) < MIN_PAIRS:
        raise DesignError(f"function synthesis needs at least {MIN_PAIRS} input-output pairs; got {len(a)}: add rows")
    x = a[:, 0] - a[0, 0]
    y = a[:, 1] - a[0, 1]
    d = np.diff(x)
    rep = np.flatnonzero(np.abs(d) <= 1e-9)
    if rep.size:
        k = int(rep[0])
        raise DesignError(f"function: rows {k + 1} and {k + 2} have the same input ({a[k, 0]:g}°); a crank angle has "
                          "one output: remove or merge them")
    if not (np.all(d > 0) or np.all(d < 0)):
        raise DesignError("function: the input angles must increase (or decrease) from row to row")
    if abs(x[-1]) >= 360.0:
        raise DesignError(f"function: the inputs span {abs(x[-1]):g}°, more than one turn of the crank")
    if np.ptp(y) <= 1e-12 * max(1.0, float(np.max(np.abs(y)))):
        raise DesignError("function: the output never changes; a linkage whose output stands still needs no "
                          "synthesis")
    out = np.radians(y) if unit == "deg" else y
    return FunctionTarget(np.radians(x), out, unit)


__all__ = ["Cancelled", "DesignError", "FunctionTarget", "PathTarget", "PoseTarget", "Progress",
           "function_target", "path_target", "pose_target", "report", "size_of"]
