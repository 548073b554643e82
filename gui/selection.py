"""What can be selected on the canvas, and which Geneva drive or rolling lever the panels show.

A selection entry is ``(element id, SelectionKind, id)``: a joint or a link of a linkage, or a
whole Geneva drive / rolling lever (then the id is the element id). The kinds are a str enum, so
they compare equal to (and print as) ``"joint"``, ``"link"``, ``"element"``.
"""
from __future__ import annotations

from enum import Enum


class SelectionKind(str, Enum):
    JOINT = "joint"
    LINK = "link"
    ELEMENT = "element"

    def __str__(self) -> str:
        return self.value


#: the selection kind of a whole Geneva drive or rolling lever: ``(element id, ELEMENT, element id)``
ELEMENT = SelectionKind.ELEMENT


def element_target(controller) -> str | None:
    """The Geneva drive or rolling lever the panels show: the first one selected, else - when
    nothing is selected and the scene has no linkage - the scene's first one (None if neither)."""
    results = controller.element_results()
    for eid, kind, _ident in controller.selection:
        if kind == ELEMENT and eid in results:
            return eid
    if not controller.selection and not controller.linkages():
        return next(iter(results), None)
    return None
