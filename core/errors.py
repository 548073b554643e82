"""One exception root for mechsketch; every leaf also subclasses the matching builtin.

Messages name the offending id, JSON path and value, so the user knows what to fix.
"""
from __future__ import annotations


class MechsketchError(Exception):
    """Root of every error mechsketch raises on purpose."""


class SceneFormatError(MechsketchError, ValueError):
    """A scene file or scene dict is malformed; ``problems`` lists every finding.

    Each problem is a :class:`Problem` with a JSON path (``$.elements[0].joints[2].at``),
    the id involved (or ``None``) and a message.
    """

    def __init__(self, problems: list["Problem"], source: str = "scene") -> None:
        self.problems = list(problems)
        self.source = source
        head = f"{source}: {len(self.problems)} problem(s)"
        super().__init__(head + "\n" + "\n".join(f"  {p}" for p in self.problems))


class StructureError(MechsketchError, ValueError):
    """The linkage cannot be decomposed: wrong mobility, or a group we do not solve.

    ``joints`` names the joints involved, ``links`` the links.
    """

    def __init__(self, message: str, joints: tuple[str, ...] = (), links: tuple[str, ...] = ()) -> None:
        self.joints = tuple(joints)
        self.links = tuple(links)
        super().__init__(message)


class GeometryError(MechsketchError, ValueError):
    """A geometry that cannot be built (impossible sizes, a stroke beyond its range, ...)."""


class ExportError(MechsketchError, OSError):
    """Writing a file failed (unwritable path, disk full); the message names the path."""


class UnknownIdError(MechsketchError, KeyError):
    """An id (element, joint, link, group) that the document or the solution does not hold.

    Also a :class:`KeyError`, but printed as its message (``KeyError`` would quote it).
    """

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else "unknown id"


class EditError(MechsketchError, ValueError):
    """An edit that cannot be applied to the document (a duplicate id, a changed topology...)."""


class RequestError(MechsketchError, ValueError):
    """A request the solver or an analysis cannot serve as asked (derivative order, samples,
    a quantity not computed by this solve); the message says what to ask instead."""


class Problem:
    """One finding of validation: where, which id, what is wrong."""

    __slots__ = ("path", "id", "message")

    def __init__(self, path: str, message: str, id: str | None = None) -> None:
        self.path = path
        self.id = id
        self.message = message

    def __str__(self) -> str:
        who = f" [{self.id}]" if self.id else ""
        return f"{self.path}{who}: {self.message}"

    def __repr__(self) -> str:
        return f"Problem({self.path!r}, {self.message!r}, id={self.id!r})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Problem) and (self.path, self.id, self.message) == (
            other.path, other.id, other.message)

    def __hash__(self) -> int:
        return hash((self.path, self.id, self.message))
