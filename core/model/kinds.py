"""The registry of element kinds: for each ``"type"`` of a scene file, its schema, parser and writer.

Follow a scene file into the code from here: an element ``{"type": "geneva", ...}`` is checked
against ``resources/schema/geneva.schema.json``, then read by :func:`.geneva.parse` into a
:class:`~.geneva.Geneva` record, whose ``to_dict`` writes it back. A new element kind is one
entry of :data:`ELEMENT_KINDS`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from ..errors import Problem
from . import gear_pair, geared_geneva, geneva, linkage_parse, rolling_lever, underlay
from .linkage import Linkage


@dataclass(frozen=True)
class ElementKind:
    """One element type: ``schema`` a file in ``mechsketch.resources.schema``; ``parse(data, path)``
    returns (the record or None, [Problem]) with ``path`` the element's JSON path in messages;
    ``dump(record)`` the element's JSON object; ``parts`` False for a kind that is no part of the
    machine (an underlay: nothing is cut from it, ``validate`` builds no parts of it)."""

    type: str
    schema: str
    parse: Callable[[dict[str, Any], str], tuple[Any, list[Problem]]]
    dump: Callable[[Any], dict[str, Any]]
    parts: bool = True


#: element type -> its kind, in the order the README lists them
ELEMENT_KINDS: dict[str, ElementKind] = {
    "linkage": ElementKind("linkage", linkage_parse.SCHEMA, linkage_parse.parse, Linkage.to_dict),
    "geneva": ElementKind("geneva", geneva.SCHEMA, geneva.parse, geneva.Geneva.to_dict),
    "rolling_lever": ElementKind("rolling_lever", rolling_lever.SCHEMA, rolling_lever.parse,
                                 rolling_lever.RollingLever.to_dict),
    # schema_version 3: a drawing or picture under the canvas (issue 22 item 6)
    "underlay": ElementKind("underlay", underlay.SCHEMA, underlay.parse, underlay.Underlay.to_dict, parts=False),
    # schema_version 3: non-circular gears and a Geneva driven through them (issue 25 items 3-4)
    "gear_pair": ElementKind("gear_pair", gear_pair.SCHEMA, gear_pair.parse, gear_pair.GearPair.to_dict),
    "geared_geneva": ElementKind("geared_geneva", geared_geneva.SCHEMA, geared_geneva.parse,
                                 geared_geneva.GearedGeneva.to_dict),
}


def element_kind(type_name: str) -> ElementKind | None:
    """The kind of an element type, or None if this version does not know it."""
    return ELEMENT_KINDS.get(type_name)
