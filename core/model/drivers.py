"""What drives a linkage: the kind of input and its motion law over the cycle (authored records).

A linkage has one input, :attr:`Linkage.driver <mechsketch.core.model.linkage.Linkage.driver>`
(a :class:`~mechsketch.core.model.linkage.Driver`), of one of three kinds:

- ``crank`` — a link turning about a revolute joint (``pivot``) of the frame; it may carry any
  number of joints (a crank with a traced point, a V-engine crank with two pins). The input is
  the crank angle, rad: the direction of the vector from the pivot to the link's first other joint.
- ``cylinder`` — a linear actuator between two pivots (an RPR with driven length): the barrel
  (``link``) and the rod, joined by the prismatic joint ``pivot``, each pinned at its other end.
  The input is the distance between the two end pivots, mm (the actuator length).
- ``slider`` — a link on a prismatic joint ``pivot`` of the frame, driven along that fixed guide.
  The input is its displacement along the guide from the drawn position, mm (0 when drawn).

A cycle lasts ``60 / |speed_rpm|`` s (one crank revolution; one extend-and-retract stroke of an
actuator). The :class:`MotionLaw` says how the input moves over the cycle:

- ``constant`` — a crank at constant speed (the sign of ``speed_rpm`` gives the sense); an
  actuator at constant speed from the stroke's start to its end and back.
- ``cycloidal``, ``harmonic``, ``modified_trapezoid`` — the classical cam rise laws: a crank makes
  one turn per cycle starting and ending at rest (cycloidal, modified trapezoid); an actuator
  rises from the stroke's start to its end in the first half cycle and returns in the second.
- ``table`` — points (cycle fraction τ in [0, 1), input) through which a periodic cubic spline
  (continuous to the second derivative) passes: for a crank the input is the angle from the drawn
  angle in degrees (a last point at τ = 1 may add whole turns: 360·k); for an actuator it is the
  input itself in mm (the cycle closes on the first point).

Velocities and accelerations of every law come from its closed form (see
:mod:`mechsketch.core.solver.motion_law`), never from differences.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum


class DriverKind(StrEnum):
    """Kind of a linkage's input (a ``str``: ``DriverKind.CRANK == "crank"``)."""

    CRANK = "crank"
    CYLINDER = "cylinder"
    SLIDER = "slider"


#: the driver kinds whose input is a length (mm), moved between stroke limits
LINEAR_KINDS: tuple[DriverKind, ...] = (DriverKind.CYLINDER, DriverKind.SLIDER)


class LawKind(StrEnum):
    """Motion law of the input over one cycle."""

    CONSTANT = "constant"
    CYCLOIDAL = "cycloidal"
    HARMONIC = "harmonic"
    MODIFIED_TRAPEZOID = "modified_trapezoid"
    TABLE = "table"


#: fewest points of a table law (a periodic cubic spline through them)
MIN_TABLE_POINTS = 3


@dataclass(frozen=True)
class MotionLaw:
    """How the input moves over one cycle (see the module docstring).

    ``points``: the table law's (τ, value) pairs, τ strictly increasing from 0 (a crank: degrees
    from the drawn angle; an actuator: mm); empty for the other laws.
    """

    kind: LawKind = LawKind.CONSTANT
    points: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.kind, LawKind):
            object.__setattr__(self, "kind", LawKind(self.kind))

    @property
    def is_constant(self) -> bool:
        return self.kind is LawKind.CONSTANT

    def to_dict(self) -> dict:
        d: dict = {"kind": self.kind.value}
        if self.kind is LawKind.TABLE:
            d["points"] = [[t, v] for t, v in self.points]
        return d


def input_unit(kind: DriverKind) -> str:
    """Unit of the input of a driver of ``kind``: ``"rad"`` (crank) or ``"mm"`` (actuators)."""
    return "mm" if kind in LINEAR_KINDS else "rad"


def input_text(value: float, unit: str, digits: int = 1) -> str:
    """An input as read by a person: a crank angle (``unit`` "rad") in degrees, ``"123.4°"``; an
    actuator's length or displacement (``unit`` "mm") in millimetres, ``"56.7 mm"``."""
    if unit == "mm":
        return f"{value:.{digits}f} mm"
    return f"{math.degrees(value):.{digits}f}°"


__all__ = ["DriverKind", "LINEAR_KINDS", "LawKind", "MIN_TABLE_POINTS", "MotionLaw", "input_text", "input_unit"]
