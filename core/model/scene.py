"""A scene: the user's document, an ordered tuple of elements with unique ids.

Element types (``linkage``, ``geneva``, ``rolling_lever``, ``underlay``) are immutable records with an ``id``,
a ``type`` and ``to_dict()``. Each type's schema, parser and writer are registered in
:data:`~.kinds.ELEMENT_KINDS`.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Protocol

from ..errors import UnknownIdError

FORMAT = "mechsketch.scene"
#: 2: a linkage's driver states its ``kind`` (crank, cylinder, slider) and may carry a stroke and
#: a motion law; version 1 files are migrated on reading (core/io/scene_file.py).
#: 3: a linkage may carry an optional ``drawing`` block (plate sizes for its cut-ready parts), and
#: new element kinds (underlays; gear pairs and geared Geneva drives, issue 25) and optional blocks
#: (a rolling lever's slider law); every version 2 file is a version 3 file (the migration only
#: changes the number)
SCHEMA_VERSION = 3


class Element(Protocol):
    id: str
    type: str

    def to_dict(self) -> dict[str, Any]: ...


@dataclass(frozen=True)
class Scene:
    """The authored document: elements in file order, units millimetres."""

    elements: tuple[Any, ...] = ()

    def element(self, element_id: str) -> Any:
        """The element with id ``element_id``; :class:`UnknownIdError` (a KeyError) names the known ids."""
        for e in self.elements:
            if e.id == element_id:
                return e
        raise self._unknown(element_id)

    def _unknown(self, element_id: str) -> UnknownIdError:
        known = ", ".join(repr(e.id) for e in self.elements) or "none"
        return UnknownIdError(f"scene has no element {element_id!r} (elements: {known})")

    @property
    def ids(self) -> tuple[str, ...]:
        return tuple(e.id for e in self.elements)

    def with_element(self, element: Any, index: int | None = None) -> "Scene":
        """Replace the element with the same id, or insert it (at ``index``, default last)."""
        if element.id in self.ids:
            return replace(self, elements=tuple(element if e.id == element.id else e for e in self.elements))
        els = list(self.elements)
        els.insert(len(els) if index is None else index, element)
        return replace(self, elements=tuple(els))

    def without_element(self, element_id: str) -> "Scene":
        self.element(element_id)
        return replace(self, elements=tuple(e for e in self.elements if e.id != element_id))

    def index_of(self, element_id: str) -> int:
        ids = self.ids
        if element_id not in ids:
            raise self._unknown(element_id)
        return ids.index(element_id)

    def to_dict(self) -> dict[str, Any]:
        return {"format": FORMAT, "schema_version": SCHEMA_VERSION, "units": "mm",
                "elements": [e.to_dict() for e in self.elements]}
