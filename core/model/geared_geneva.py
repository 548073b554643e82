"""A Geneva drive whose crank is driven through a non-circular gear pair (type ``geared_geneva``):
the smooth Geneva drive of issue 25, item 4, and the first coupled elements of a scene.

Coupling: the gear pair's output shaft is the Geneva's crank shaft, so the output angle of the
gears is the crank angle of the drive, and the crank's torque goes back through the gears to the
input. It is one scene element holding both, ``{"type": "geared_geneva", "id": ..., "geneva":
{...}, "gears": {...}}``, rather than two elements pointing at each other: the workspace computes
and caches each element's result from that element's value alone (an edit of one element never
changes another's result, and undo finds what it had), which two linked elements would break.

``geneva`` holds the Geneva element's own fields (without ``type`` and ``id``): its
``speed_rpm`` is now the crank's *mean* speed, which is the input shaft's speed (opposite sense)
divided by the gears' mean ratio. ``gears`` holds ``center_distance`` (mm, input pivot to the
crank centre), ``input_direction_deg`` (from the crank centre to the input pivot), ``function``
(see :mod:`.gear_pair`: here ψ maps the input's progress angle θ to the crank's progress angle
u, θ = u = 0 at mid-indexing; with ψ(±φ0) = ±φ0 the index time and the dwell are those of the
constant-speed crank), and optionally ``bore_radius``, ``tolerance``, ``min_web``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ..errors import Problem
from . import geneva as geneva_model
from .gear_function import GearFunction
from .gear_pair import GearPair, parse_fields

SCHEMA = "geared_geneva.schema.json"


@dataclass(frozen=True)
class GearedGeneva:
    """A Geneva drive driven through a gear pair (see the module docstring). ``geneva`` is the
    drive (its id this element's), the rest the gears' authored fields (mm, degrees, rad)."""

    id: str
    geneva: geneva_model.Geneva
    center_distance: float
    function: GearFunction
    input_direction_deg: float = 180.0
    bore_radius: float | None = None
    tolerance: float = 0.01
    min_web: float = 1.0
    type: str = field(default="geared_geneva", init=False)

    @property
    def input_center(self) -> tuple[float, float]:
        d = math.radians(self.input_direction_deg)
        cc = self.geneva.crank_center
        return (cc[0] + self.center_distance * math.cos(d), cc[1] + self.center_distance * math.sin(d))

    @property
    def gear_pair(self) -> GearPair:
        """The gears as a :class:`GearPair` (input at :attr:`input_center`, output on the crank; the
        input turns opposite to the crank at its mean speed times the mean ratio)."""
        g = self.geneva
        return GearPair(self.id, self.input_center, self.center_distance, self.function,
                        self.input_direction_deg + 180.0, -g.speed_rpm / self.function.ratio, g.samples,
                        self.bore_radius, self.tolerance, self.min_web)

    def to_dict(self) -> dict[str, Any]:
        gd = self.geneva.to_dict()
        del gd["type"], gd["id"]
        gears: dict[str, Any] = {"center_distance": self.center_distance, "input_direction_deg": self.input_direction_deg,
                                 "function": self.function.to_dict(), "tolerance": self.tolerance,
                                 "min_web": self.min_web}
        if self.bore_radius is not None:
            gears["bore_radius"] = self.bore_radius
        return {"type": "geared_geneva", "id": self.id, "geneva": gd, "gears": gears}


def parse(data: dict[str, Any], path: str) -> tuple[GearedGeneva | None, list[Problem]]:
    """Check a schema-valid geared_geneva dict for meaning: the Geneva part as a Geneva element
    (every limit of the drive, paths under ``geneva``), the gears as a gear pair's fields (the
    speed ratio within its range), a mean ratio of 1 (one crank turn per input turn: the index time
    and dwell are then set by the function) and the gears' blanks fitting between the shafts."""
    eid = data["id"]
    problems: list[Problem] = []

    def bad(where: str, msg: str) -> None:
        problems.append(Problem(f"{path}.gears.{where}", msg, eid))

    el, found = geneva_model.parse({**data["geneva"], "type": "geneva", "id": eid}, f"{path}.geneva")
    problems += found
    gears = data["gears"]
    fields = parse_fields({**gears, "speed_rpm": 60.0}, path, eid, bad)
    if fields is not None and fields["function"].ratio != 1.0:
        bad("function", f"the gears must turn the crank once per input turn (mean ratio 1); got "
                        f"{fields['function'].ratio:g}")
    if problems or el is None or fields is None:
        return None, problems
    return GearedGeneva(eid, el, fields["center_distance"], fields["function"],
                        float(gears.get("input_direction_deg", 180.0)), fields["bore_radius"], fields["tolerance"],
                        fields["min_web"]), []
