"""Drawing sizes an element may carry for its cut-ready parts, and the defaults they fall back to.

A part keeps at least :data:`DEFAULT_MIN_WEB` mm of material between its holes and its edges
unless the element (``drawing.min_web`` of a Geneva drive or a linkage) or the export
(``--min-web``) says otherwise.

A linkage's optional ``drawing`` block (:class:`LinkageDrawing`, scene format version 3) holds its
plate sizes, so a scene can carry the values that make it cut-ready; an export option of the same
name overrides the block for one export, and a size given nowhere is scaled to the linkage (see
``core/analyses/parts/linkage.py``). These are sizes of the parts only: they never change the
kinematics, and a block whose sizes cannot make a plate still loads (``validate`` warns,
``export`` refuses, naming the key).
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any, Callable

from .limits import MAX_LENGTH_MM, SMALLEST

#: thinnest web (mm) a part keeps by default
DEFAULT_MIN_WEB = 1.0


@dataclass(frozen=True)
class LinkageDrawing:
    """Plate sizes of a linkage's parts (mm); ``None``: the export option or the scaled default.

    ``boss_radius``: the rounded end of a plate around each revolute joint; ``bore_diameter``: the
    bore on each revolute joint (0: none drawn); ``link_width``: a binary link's bar (at most
    2 × boss; narrower gives a dog-bone); ``min_web``: the thinnest web every part keeps;
    ``block_length``, ``block_width``: a slider block along and across its guide.
    """

    boss_radius: float | None = None
    bore_diameter: float | None = None
    link_width: float | None = None
    min_web: float | None = None
    block_length: float | None = None
    block_width: float | None = None

    def to_dict(self) -> dict[str, float]:
        """The block as written to a scene file (only the sizes given)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}

    @property
    def is_empty(self) -> bool:
        return not self.to_dict()


#: keys of the block that may be 0 (the others must be positive)
MAY_BE_ZERO = ("bore_diameter",)


def parse_linkage_drawing(data: Any, bad: Callable[[str, str], None]) -> LinkageDrawing | None:
    """The block of a (schema-checked) linkage dict, or None when absent. ``bad(where, message)``
    records a problem at ``drawing.KEY``; each size must be finite, within ±1e9 mm, positive (the
    bore may be 0) and not below 1e-6 mm when nonzero."""
    if data is None:
        return None
    values: dict[str, float] = {}
    for f in fields(LinkageDrawing):
        if f.name not in data:
            continue
        v = float(data[f.name])
        lo = 0.0 if f.name in MAY_BE_ZERO else SMALLEST["mm"]
        if not (v == 0.0 and f.name in MAY_BE_ZERO) and not lo <= v <= MAX_LENGTH_MM:
            words = "0 or from" if f.name in MAY_BE_ZERO else "from"
            bad(f"drawing.{f.name}", f"must be {words} {SMALLEST['mm']:g} to {MAX_LENGTH_MM:g} mm, got {v:g}")
            continue
        if 0.0 < v < SMALLEST["mm"]:
            bad(f"drawing.{f.name}", f"must be 0 or from {SMALLEST['mm']:g} to {MAX_LENGTH_MM:g} mm, got {v:g}")
            continue
        values[f.name] = v
    return LinkageDrawing(**values)
