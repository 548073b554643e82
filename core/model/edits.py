"""Small reversible edits of a scene.

``new_scene, inverse = edit.apply_to(scene)``: an edit returns the edit that undoes it. The
workspace (:class:`mechsketch.core.workspace.Workspace`) applies them and tells its listeners;
the GUI's undo commands only wrap them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..errors import EditError
from .linkage import Linkage, XYTuple
from .scene import Scene


class Edit:
    """Base of reversible edits: ``apply_to(scene) -> (new_scene, inverse)``."""

    label = "edit"

    def apply_to(self, scene: Scene) -> tuple[Scene, "Edit"]:  # pragma: no cover - abstract
        raise NotImplementedError


@dataclass(frozen=True)
class ReplaceElement(Edit):
    """Put ``element`` in place of the element with the same id (the universal edit)."""

    element: Any
    label: str = "edit element"

    def apply_to(self, scene: Scene) -> tuple[Scene, Edit]:
        old = scene.element(self.element.id)
        return scene.with_element(self.element), ReplaceElement(old, self.label)


@dataclass(frozen=True)
class AddElement(Edit):
    element: Any
    index: int | None = None
    label: str = "add element"

    def apply_to(self, scene: Scene) -> tuple[Scene, Edit]:
        if self.element.id in scene.ids:
            raise EditError(f"an element with id {self.element.id!r} exists already")
        return scene.with_element(self.element, self.index), RemoveElement(self.element.id, self.label)


@dataclass(frozen=True)
class RemoveElement(Edit):
    element_id: str
    label: str = "remove element"

    def apply_to(self, scene: Scene) -> tuple[Scene, Edit]:
        index = scene.index_of(self.element_id)
        old = scene.element(self.element_id)
        return scene.without_element(self.element_id), AddElement(old, index, self.label)


@dataclass(frozen=True)
class MoveJoints(Edit):
    """Move joints of one linkage to new drawn positions (mm)."""

    element_id: str
    moves: tuple[tuple[str, XYTuple], ...]
    label: str = "move joint"

    def apply_to(self, scene: Scene) -> tuple[Scene, Edit]:
        link: Linkage = scene.element(self.element_id)
        old = tuple((jid, link.joint(jid).at) for jid, _ in self.moves)
        new = link.with_joints_moved(dict(self.moves))
        return scene.with_element(new), MoveJoints(self.element_id, old, self.label)


def MoveJoint(element_id: str, joint_id: str, at: XYTuple) -> MoveJoints:
    """Move one joint (a convenience constructor of :class:`MoveJoints`)."""
    return MoveJoints(element_id, ((joint_id, (float(at[0]), float(at[1]))),))
