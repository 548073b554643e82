"""Masses and loads of a linkage: what its kinetostatics (:mod:`mechsketch.core.analyses.forces.kinetostatics`)
needs besides the kinematics. Immutable records, all optional in a scene file.

Units: drawn positions and lengths in mm (the model's unit); masses kg, moments of inertia kg·m²,
forces N, torques N·m (counter-clockwise positive), spring stiffness N/mm, damping N·s/mm,
gravity m/s², friction-circle radii mm.

- :class:`LinkMass` — a link's mass, the drawn position of its centre of mass (default the
  centroid of its joints) and its moment of inertia about that centre (default the slender-bar
  estimate m·L²/12, L the link's longest joint-to-joint span: :func:`default_inertia`);
- :class:`PointForce` — a constant world-frame force at a point of a link (given by its drawn
  position; it moves with the link);
- :class:`Torque` — a constant torque on a link;
- :class:`Spring` — a linear spring between two points of two links (tension positive);
- :class:`Damper` — a linear viscous damper between two points of two links;
- :class:`JointFriction` — the friction-circle radius of a revolute joint (Coulomb friction,
  solved beside the frictionless result).

Every load has a stable string ``id`` (``"F1"``, ``"spring"``...) so that the GUI selects and
edits it by id, never by position in the list.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Union

XYTuple = tuple[float, float]


def _xy(p) -> list[float]:
    return [float(p[0]), float(p[1])]


@dataclass(frozen=True)
class LinkMass:
    """Mass properties of one link: ``mass`` kg, ``com`` drawn centre of mass (mm; None: the
    centroid of the link's joints), ``inertia`` kg·m² about the centre of mass (None: estimated)."""

    link: str
    mass: float
    com: XYTuple | None = None
    inertia: float | None = None

    def fields(self) -> dict:
        """The link-dict fields of a scene file (``mass``, ``com``, ``inertia``)."""
        d: dict = {"mass": self.mass}
        if self.com is not None:
            d["com"] = _xy(self.com)
        if self.inertia is not None:
            d["inertia"] = self.inertia
        return d


@dataclass(frozen=True)
class End:
    """One end of a spring or damper: a point of ``link`` drawn at ``at`` (mm)."""

    link: str
    at: XYTuple

    def to_dict(self) -> dict:
        return {"link": self.link, "at": _xy(self.at)}


@dataclass(frozen=True)
class PointForce:
    """A constant force ``force`` (N, world frame) at the point of ``link`` drawn at ``at`` (mm)."""

    id: str
    link: str
    at: XYTuple
    force: XYTuple
    kind: ClassVar[str] = "force"

    @property
    def links(self) -> tuple[str, ...]:
        return (self.link,)

    def to_dict(self) -> dict:
        return {"id": self.id, "link": self.link, "at": _xy(self.at), "force": _xy(self.force)}


@dataclass(frozen=True)
class Torque:
    """A constant torque ``torque`` (N·m, counter-clockwise positive) on ``link``."""

    id: str
    link: str
    torque: float
    kind: ClassVar[str] = "torque"

    @property
    def links(self) -> tuple[str, ...]:
        return (self.link,)

    def to_dict(self) -> dict:
        return {"id": self.id, "link": self.link, "torque": self.torque}


@dataclass(frozen=True)
class Spring:
    """A linear spring between two link points: tension k·(ℓ − ℓ0) N pulls the ends together
    (ℓ current length mm; ``stiffness`` k N/mm; ``free_length`` ℓ0 mm, None: the drawn length)."""

    id: str
    ends: tuple[End, End]
    stiffness: float
    free_length: float | None = None
    kind: ClassVar[str] = "spring"

    @property
    def links(self) -> tuple[str, ...]:
        return (self.ends[0].link, self.ends[1].link)

    @property
    def drawn_length(self) -> float:
        (ax, ay), (bx, by) = self.ends[0].at, self.ends[1].at
        return math.hypot(bx - ax, by - ay)

    @property
    def rest_length(self) -> float:
        """ℓ0, mm: ``free_length``, else the drawn length."""
        return self.drawn_length if self.free_length is None else self.free_length

    def to_dict(self) -> dict:
        d = {"id": self.id, "ends": [e.to_dict() for e in self.ends], "stiffness": self.stiffness}
        if self.free_length is not None:
            d["free_length"] = self.free_length
        return d


@dataclass(frozen=True)
class Damper:
    """A linear viscous damper between two link points: tension c·dℓ/dt N (``damping`` c N·s/mm)."""

    id: str
    ends: tuple[End, End]
    damping: float
    kind: ClassVar[str] = "damper"

    @property
    def links(self) -> tuple[str, ...]:
        return (self.ends[0].link, self.ends[1].link)

    def to_dict(self) -> dict:
        return {"id": self.id, "ends": [e.to_dict() for e in self.ends], "damping": self.damping}


@dataclass(frozen=True)
class JointFriction:
    """Coulomb friction in revolute joint ``joint``: friction-circle ``radius`` (mm), i.e. the
    friction moment is radius·|reaction| against the relative rotation."""

    joint: str
    radius: float


Load = Union[PointForce, Torque, Spring, Damper]
LOAD_KINDS: tuple[str, ...] = ("force", "torque", "spring", "damper")
#: the file key that tells each kind of load apart
KIND_KEYS: dict[str, str] = {"force": "force", "torque": "torque", "stiffness": "spring", "damping": "damper"}
#: id prefixes of new loads of each kind (F1, T1, K1, C1...)
ID_PREFIX: dict[str, str] = {"force": "F", "torque": "T", "spring": "K", "damper": "C"}


def next_load_id(kind: str, taken) -> str:
    """The first free id ``F1``, ``F2``... (``T``, ``K``, ``C`` for torques, springs, dampers)."""
    prefix = ID_PREFIX[kind]
    taken = set(taken)
    k = 1
    while f"{prefix}{k}" in taken:
        k += 1
    return f"{prefix}{k}"


def default_inertia(mass: float, span_mm: float) -> float:
    """The stated estimate of a link's moment of inertia about its centre of mass when none is
    given: a slender bar, m·L²/12 (kg·m²) with L (mm → m) the link's longest joint-to-joint span;
    0 for a block whose joints coincide."""
    length = span_mm * 1e-3
    return mass * length * length / 12.0
