"""mechsketch core: the headless model, solver, analyses and file formats (never imports Qt).

Public API::

    from mechsketch.core import load_scene
    scene = load_scene("scene.json")
    sol = scene.element("slider_crank").solve(samples=360, order=2)
    sol.position("C")   # (N, 2) mm
"""
from __future__ import annotations

from .errors import (EditError, ExportError, GeometryError, MechsketchError, Problem, RequestError,
                     SceneFormatError, StructureError, UnknownIdError)
from .io.scene_file import dumps_scene, load_scene, loads_scene, save_scene, validate_file
from .model.edits import AddElement, Document, MoveJoint, MoveJoints, RemoveElement, ReplaceElement
from .model.linkage import Driver, Joint, JointKind, Link, Linkage
from .model.scene import Scene

__all__ = [
    "AddElement", "Document", "Driver", "EditError", "ExportError", "GeometryError", "Joint", "JointKind",
    "Link", "Linkage", "MechsketchError", "MoveJoint", "MoveJoints", "Problem", "RemoveElement",
    "ReplaceElement", "RequestError", "UnknownIdError", "Scene", "SceneFormatError", "StructureError", "dumps_scene", "load_scene",
    "loads_scene", "save_scene", "validate_file",
]
