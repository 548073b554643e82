"""Edit an element by its file fields: the new values go through the same schema and parser as a
scene file, so what a property panel accepts is exactly what ``validate`` accepts."""
from __future__ import annotations

import copy
from typing import Any

from ..io.scene_file import scene_from_dict
from ..model.scene import FORMAT, SCHEMA_VERSION


def rebuilt(element: Any, changes: dict[str, Any]) -> tuple[Any, str | None]:
    """``element`` with ``changes`` applied to its dict (dotted keys: ``{"clearance.slot": 0.1}``),
    built as a scene file is read: the element's JSON schema, then its module's ``parse``.

    Returns (new element, None), or (None, the core's messages) when the values are refused.
    """
    data = copy.deepcopy(element.to_dict())
    for key, value in changes.items():
        node = data
        *parents, leaf = key.split(".")
        for part in parents:
            node = node.setdefault(part, {})
        node[leaf] = value
    doc = {"format": FORMAT, "schema_version": SCHEMA_VERSION, "units": "mm", "elements": [data]}
    scene, problems = scene_from_dict(doc, source=f"element {element.id}")
    if problems or scene is None:
        def text(p) -> str:
            tail = p.path.removeprefix("$.elements[0]").lstrip(".")
            return p.message if not tail or tail in changes else f"{tail}: {p.message}"
        return None, "; ".join(text(p) for p in problems) or "refused"
    return scene.elements[0], None
