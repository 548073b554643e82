"""The workspace: the scene being edited, its undoable edits, and each element's results, cached.

Above the layers (model < solver < analyses < io < workspace < cli): the CLI and the desktop app
both read results through it. See :class:`Workspace` and ARCHITECTURE.md.
"""
from __future__ import annotations

from .facade import ElementView
from .rebuild import rebuilt
from .results import (ElementResult, GearedGenevaResult, GearResult, GenevaResult, LinkageResult, RollingFrames,
                      RollingResult, solve_element)
from .workspace import Change, ElementChange, Workspace

__all__ = ["Change", "ElementChange", "ElementResult", "ElementView", "GearResult", "GearedGenevaResult",
           "GenevaResult", "LinkageResult",
           "RollingFrames", "RollingResult", "Workspace", "rebuilt", "solve_element"]
