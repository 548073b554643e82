"""The authored linkage: joints with drawn positions, links as sets of joints, ground, driver.

Immutable records. Everything derived (lengths, modes, solutions) is recomputed by the solver
from the drawn pose; nothing derived is stored here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import Enum

from ..errors import UnknownIdError
from .drawing import LinkageDrawing
from .drivers import LINEAR_KINDS, DriverKind, MotionLaw, input_unit
from .loads import JointFriction, LinkMass, Load

XYTuple = tuple[float, float]


class JointKind(str, Enum):
    """Lower-pair kinds: revolute (R) and prismatic (P)."""

    R = "R"
    P = "P"


@dataclass(frozen=True)
class Joint:
    """A joint in the drawn pose.

    ``at`` is the drawn position in mm. A P joint slides along the axis through ``at`` at
    ``axis_deg`` (degrees, drawn pose); the axis moves with its two links.
    """

    id: str
    kind: JointKind
    at: XYTuple
    axis_deg: float | None = None

    def moved(self, at: XYTuple) -> "Joint":
        return replace(self, at=(float(at[0]), float(at[1])))

    def to_dict(self) -> dict:
        d: dict = {"id": self.id, "kind": self.kind.value, "at": [self.at[0], self.at[1]]}
        if self.kind is JointKind.P:
            d["axis_deg"] = self.axis_deg if self.axis_deg is not None else 0.0
        return d


@dataclass(frozen=True)
class Link:
    """A rigid link: the ids of the joints it carries (two: binary; three or more: ternary...)."""

    id: str
    joints: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"id": self.id, "joints": list(self.joints)}


@dataclass(frozen=True)
class Driver:
    """The linkage's input (see :mod:`mechsketch.core.model.drivers` for the kinds and laws).

    ``kind`` crank: ``link`` turns about the frame's revolute joint ``pivot`` (input: crank angle,
    rad). ``kind`` cylinder: ``link`` is the barrel and ``pivot`` the prismatic joint between it
    and the rod (input: distance between the two end pivots, mm). ``kind`` slider: ``link`` slides
    on the frame's prismatic joint ``pivot`` (input: displacement along the guide from the drawn
    position, mm). ``speed_rpm``: cycles per minute (a crank: revolutions; positive turns it
    counter-clockwise); ``stroke`` (mm, actuators only): the input's (start, end) over a cycle;
    ``law``: how the input moves over the cycle.
    """

    link: str
    pivot: str
    speed_rpm: float = 60.0
    kind: DriverKind = DriverKind.CRANK
    stroke: tuple[float, float] | None = None
    law: MotionLaw = MotionLaw()

    def __post_init__(self) -> None:
        if not isinstance(self.kind, DriverKind):
            object.__setattr__(self, "kind", DriverKind(self.kind))

    @property
    def omega(self) -> float:
        """Crank: angular speed at constant speed in rad/s (signed, CCW positive); any driver:
        2π / cycle period, signed as ``speed_rpm``."""
        return self.speed_rpm * 2.0 * math.pi / 60.0

    @property
    def period(self) -> float:
        """Seconds per cycle (one crank revolution, one actuator stroke out and back)."""
        return 60.0 / abs(self.speed_rpm) if self.speed_rpm else math.inf

    @property
    def linear(self) -> bool:
        """An actuator (cylinder or slider): the input is a length in mm."""
        return self.kind in LINEAR_KINDS

    @property
    def unit(self) -> str:
        """Unit of the input: ``"rad"`` (crank angle) or ``"mm"`` (actuator length)."""
        return input_unit(self.kind)

    def to_dict(self) -> dict:
        d: dict = {"kind": self.kind.value, "link": self.link, "pivot": self.pivot, "speed_rpm": self.speed_rpm}
        if self.stroke is not None:
            d["stroke"] = [self.stroke[0], self.stroke[1]]
        if not self.law.is_constant:
            d["law"] = self.law.to_dict()
        return d


@dataclass(frozen=True)
class Linkage:
    """A planar linkage element of a scene (type ``"linkage"``).

    Optional, for the kinetostatics (:mod:`mechsketch.core.model.loads`, SI units): ``masses``
    (one :class:`LinkMass` per link that has one), ``gravity`` (gx, gy) m/s² or None, ``loads``
    (forces, torques, springs, dampers) and ``friction`` (friction-circle radii of revolute
    joints). A file without them loads as before; they never change the kinematics.
    ``drawing`` (optional, scene format 3): the plate sizes of its cut-ready parts
    (:class:`~.drawing.LinkageDrawing`); it never changes the kinematics either.
    """

    id: str
    joints: tuple[Joint, ...]
    links: tuple[Link, ...]
    ground: str
    driver: Driver
    samples: int = 360
    masses: tuple[LinkMass, ...] = ()
    gravity: XYTuple | None = None
    loads: tuple[Load, ...] = ()
    friction: tuple[JointFriction, ...] = ()
    drawing: LinkageDrawing | None = None
    type: str = field(default="linkage", init=False)

    # -- look-ups -------------------------------------------------------------------------
    def joint(self, joint_id: str) -> Joint:
        for j in self.joints:
            if j.id == joint_id:
                return j
        raise UnknownIdError(f"linkage {self.id!r} has no joint {joint_id!r}")

    def link(self, link_id: str) -> Link:
        for k in self.links:
            if k.id == link_id:
                return k
        raise UnknownIdError(f"linkage {self.id!r} has no link {link_id!r}")

    def links_of(self, joint_id: str) -> tuple[str, ...]:
        """Ids of the links carrying ``joint_id``, in file order."""
        return tuple(k.id for k in self.links if joint_id in k.joints)

    @property
    def joint_ids(self) -> tuple[str, ...]:
        return tuple(j.id for j in self.joints)

    @property
    def link_ids(self) -> tuple[str, ...]:
        return tuple(k.id for k in self.links)

    @property
    def has_driver(self) -> bool:
        """False for a draft whose crank is not drawn yet (saved as ``"driver": null``)."""
        return self.driver.link in self.link_ids and self.driver.link != self.ground

    @property
    def moving_links(self) -> tuple[str, ...]:
        return tuple(k.id for k in self.links if k.id != self.ground)

    # -- masses and loads -----------------------------------------------------------------
    def mass_of(self, link_id: str) -> LinkMass | None:
        """The mass properties of ``link_id`` (None: massless)."""
        return next((m for m in self.masses if m.link == link_id), None)

    def load(self, load_id: str) -> Load:
        for ld in self.loads:
            if ld.id == load_id:
                return ld
        raise UnknownIdError(f"linkage {self.id!r} has no load {load_id!r}")

    @property
    def load_ids(self) -> tuple[str, ...]:
        return tuple(ld.id for ld in self.loads)

    def friction_of(self, joint_id: str) -> float:
        """Friction-circle radius of ``joint_id``, mm (0: frictionless)."""
        return next((f.radius for f in self.friction if f.joint == joint_id), 0.0)

    @property
    def has_dynamics(self) -> bool:
        """Some link has a mass or some load is applied: the forces are not all zero."""
        return any(m.mass > 0 or (m.inertia or 0.0) > 0 for m in self.masses) or bool(self.loads)

    def with_mass(self, link_id: str, mass: LinkMass | None) -> "Linkage":
        """Set (or with None remove) the mass properties of ``link_id``."""
        self.link(link_id)
        rest = tuple(m for m in self.masses if m.link != link_id)
        if mass is None:
            return replace(self, masses=rest)
        order = self.link_ids
        return replace(self, masses=tuple(sorted(rest + (replace(mass, link=link_id),),
                                                 key=lambda m: order.index(m.link))))

    def with_load(self, load: Load) -> "Linkage":
        """Add ``load``, or replace the load with the same id (it keeps its place)."""
        for name in load.links:
            self.link(name)
        if load.id in self.load_ids:
            return replace(self, loads=tuple(load if ld.id == load.id else ld for ld in self.loads))
        return replace(self, loads=self.loads + (load,))

    def without_load(self, load_id: str) -> "Linkage":
        self.load(load_id)
        return replace(self, loads=tuple(ld for ld in self.loads if ld.id != load_id))

    def with_gravity(self, gravity: XYTuple | None) -> "Linkage":
        g = None if gravity is None else (float(gravity[0]), float(gravity[1]))
        return replace(self, gravity=g)

    def with_friction(self, joint_id: str, radius: float) -> "Linkage":
        """Set the friction-circle radius (mm) of revolute joint ``joint_id`` (0: frictionless)."""
        self.joint(joint_id)
        rest = tuple(f for f in self.friction if f.joint != joint_id)
        if radius == 0.0:
            return replace(self, friction=rest)
        order = self.joint_ids
        return replace(self, friction=tuple(sorted(rest + (JointFriction(joint_id, float(radius)),),
                                                   key=lambda f: order.index(f.joint))))

    def _pruned(self) -> "Linkage":
        """Drop masses, loads and friction that name links or joints no longer here."""
        links, joints = set(self.link_ids), set(self.joint_ids)
        masses = tuple(m for m in self.masses if m.link in links)
        loads = tuple(ld for ld in self.loads if set(ld.links) <= links)
        friction = tuple(f for f in self.friction if f.joint in joints)
        if (masses, loads, friction) == (self.masses, self.loads, self.friction):
            return self
        return replace(self, masses=masses, loads=loads, friction=friction)

    # -- derived edits (return new linkages; the document wraps them in reversible edits) --
    def with_joint_moved(self, joint_id: str, at: XYTuple) -> "Linkage":
        self.joint(joint_id)
        return replace(self, joints=tuple(j.moved(at) if j.id == joint_id else j for j in self.joints))

    def with_joints_moved(self, moves: dict[str, XYTuple]) -> "Linkage":
        for jid in moves:
            self.joint(jid)
        return replace(self, joints=tuple(j.moved(moves[j.id]) if j.id in moves else j for j in self.joints))

    def with_joint(self, joint: Joint) -> "Linkage":
        """Add ``joint``, or replace the joint with the same id."""
        if joint.id in self.joint_ids:
            return replace(self, joints=tuple(joint if j.id == joint.id else j for j in self.joints))
        return replace(self, joints=self.joints + (joint,))

    def with_link(self, link: Link) -> "Linkage":
        """Add ``link``, or replace the link with the same id."""
        if link.id in self.link_ids:
            return replace(self, links=tuple(link if k.id == link.id else k for k in self.links))
        return replace(self, links=self.links + (link,))

    def without_joint(self, joint_id: str) -> "Linkage":
        """Remove a joint, take it out of its links, and drop links left with no joint."""
        self.joint(joint_id)
        links = tuple(Link(k.id, tuple(j for j in k.joints if j != joint_id)) for k in self.links)
        links = tuple(k for k in links if k.joints or k.id == self.ground)
        return replace(self, joints=tuple(j for j in self.joints if j.id != joint_id), links=links)._pruned()

    def without_link(self, link_id: str) -> "Linkage":
        self.link(link_id)
        return replace(self, links=tuple(k for k in self.links if k.id != link_id))._pruned()

    def with_driver(self, driver: Driver) -> "Linkage":
        return replace(self, driver=driver)

    def with_samples(self, samples: int) -> "Linkage":
        return replace(self, samples=int(samples))

    def to_dict(self) -> dict:
        joints = [j.to_dict() for j in self.joints]
        for d in joints:
            radius = self.friction_of(d["id"])
            if radius:
                d["friction_radius"] = radius
        links = [k.to_dict() for k in self.links]
        for d in links:
            mass = self.mass_of(d["id"])
            if mass is not None:
                d.update(mass.fields())
        out = {
            "type": "linkage",
            "id": self.id,
            "joints": joints,
            "links": links,
            "ground": self.ground,
            "driver": self.driver.to_dict() if self.has_driver else None,
            "samples": self.samples,
        }
        if self.gravity is not None:
            out["gravity"] = [self.gravity[0], self.gravity[1]]
        if self.loads:
            out["loads"] = [ld.to_dict() for ld in self.loads]
        if self.drawing is not None and not self.drawing.is_empty:
            out["drawing"] = self.drawing.to_dict()
        return out
