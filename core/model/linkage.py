"""The authored linkage: joints with drawn positions, links as sets of joints, ground, driver.

Immutable records. Everything derived (lengths, modes, solutions) is recomputed by the solver
from the drawn pose; nothing derived is stored here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import Enum

from ..errors import UnknownIdError

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
    """The input crank: a binary link turning about a ground pivot.

    Positive ``speed_rpm`` turns it counter-clockwise.
    """

    link: str
    pivot: str
    speed_rpm: float = 60.0

    @property
    def omega(self) -> float:
        """Angular speed in rad/s (signed, CCW positive)."""
        return self.speed_rpm * 2.0 * math.pi / 60.0

    def to_dict(self) -> dict:
        return {"link": self.link, "pivot": self.pivot, "speed_rpm": self.speed_rpm}


@dataclass(frozen=True)
class Linkage:
    """A planar linkage element of a scene (type ``"linkage"``)."""

    id: str
    joints: tuple[Joint, ...]
    links: tuple[Link, ...]
    ground: str
    driver: Driver
    samples: int = 360
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
        return replace(self, joints=tuple(j for j in self.joints if j.id != joint_id), links=links)

    def without_link(self, link_id: str) -> "Linkage":
        self.link(link_id)
        return replace(self, links=tuple(k for k in self.links if k.id != link_id))

    def with_driver(self, driver: Driver) -> "Linkage":
        return replace(self, driver=driver)

    def with_samples(self, samples: int) -> "Linkage":
        return replace(self, samples=int(samples))

    def to_dict(self) -> dict:
        return {
            "type": "linkage",
            "id": self.id,
            "joints": [j.to_dict() for j in self.joints],
            "links": [k.to_dict() for k in self.links],
            "ground": self.ground,
            "driver": self.driver.to_dict() if self.has_driver else None,
            "samples": self.samples,
        }
