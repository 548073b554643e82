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
from .model.edits import AddElement, MoveJoint, MoveJoints, RemoveElement, ReplaceElement
from .model.linkage import Driver, Joint, JointKind, Link, Linkage
from .model.scene import Scene

__all__ = [
    "AddElement", "Driver", "EditError", "ElementView", "ExportError", "GeometryError", "Joint",
    "JointKind", "Link", "Linkage", "MechsketchError", "MoveJoint", "MoveJoints", "Problem", "RemoveElement",
    "ReplaceElement", "RequestError", "Scene", "SceneFormatError", "SetDimension", "StructureError",
    "UnknownIdError", "Workspace", "dumps_scene", "load_scene", "loads_scene", "save_scene", "validate_file",
]


#: the scene file functions: they load every element kind's model (some with numpy), which the
#: entry points must not import before they have set the process up (gui/launcher.py)
_SCENE_FILE = ("dumps_scene", "load_scene", "loads_scene", "save_scene", "validate_file")


def __getattr__(name: str):
    """``Workspace`` and ``ElementView`` load the analyses, the scene file functions every element
    kind: imported on first use, so that ``import mechsketch.core`` (which every entry point and
    every submodule import does first) stays light."""
    if name in _SCENE_FILE:
        from .io import scene_file

        return getattr(scene_file, name)
    if name in ("Workspace", "ElementView"):
        from . import workspace

        return getattr(workspace, name)
    if name == "SetDimension":   # the dimension edit: it re-assembles through the solver
        from .solver.dimensions import SetDimension

        return SetDimension
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
