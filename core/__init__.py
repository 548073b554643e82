"""mechsketch core: the headless model, solver, analyses and file formats (never imports Qt).

Public API::

    from mechsketch.core import Workspace
    ws = Workspace.open("scene.json")
    sol = ws["slider_crank"].solve(samples=360, order=2)   # cached by the workspace
    sol.position("C")   # (N, 2) mm

The model records (``load_scene(...).element(id)``) hold only what the user drew; everything
derived comes from the workspace (or the solver and analyses functions it calls).
"""
from __future__ import annotations

from .errors import (EditError, ExportError, GeometryError, MechsketchError, Problem, RequestError,
                     SceneFormatError, StructureError, UnknownIdError)
from .io.scene_file import dumps_scene, load_scene, loads_scene, save_scene, validate_file
from .model.edits import AddElement, MoveJoint, MoveJoints, RemoveElement, ReplaceElement
from .model.linkage import Driver, Joint, JointKind, Link, Linkage
from .model.scene import Scene

__all__ = [
    "AddElement", "Driver", "EditError", "ElementView", "ExportError", "GeometryError", "Joint",
    "JointKind", "Link", "Linkage", "MechsketchError", "MoveJoint", "MoveJoints", "Problem", "RemoveElement",
    "ReplaceElement", "RequestError", "Scene", "SceneFormatError", "SetDimension", "StructureError",
    "UnknownIdError", "Workspace", "dumps_scene", "load_scene", "loads_scene", "save_scene", "validate_file",
]


def __getattr__(name: str):
    """``Workspace`` and ``ElementView`` load the analyses: imported on first use, so that
    ``import mechsketch.core`` stays light for code that only reads and writes scenes."""
    if name in ("Workspace", "ElementView"):
        from . import workspace

        return getattr(workspace, name)
    if name == "SetDimension":   # the dimension edit: it re-assembles through the solver
        from .solver.dimensions import SetDimension

        return SetDimension
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
