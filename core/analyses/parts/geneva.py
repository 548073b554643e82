"""Cut-ready parts of a Geneva drive: the wheel, the locking disc, the crank arm and the roller.

Built from the drive's exact geometry (:func:`~..geneva.geometry.geometry`: true lines and arcs,
so every edge is exact and the deviation is 0), placed in the scene at a crank angle (default
φ = 0, mid-engagement). Each part names the scene keys that size it, so a failed check tells the
user what to change. The crank arm's end boss is kept off the roller's radius and the bores the
parts share are drawn once in the assembled layout (see :func:`~.parts.lay_out`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..geneva.geometry import GenevaGeometry, geometry
from .outline import ccw
from .records import Part, PartSet

if TYPE_CHECKING:
    from ...model.geneva import Geneva

#: part name -> scene keys that size it
KEYS = {
    "wheel": ("slots", "center_distance", "roller_radius", "clearance.slot", "clearance.bottom",
              "drawing.locking_arc_radius", "drawing.wheel_bore_radius"),
    "locking_disc": ("drawing.crank_bore_radius", "clearance.lock", "drawing.locking_arc_radius"),
    "crank_arm": ("drawing.crank_bore_radius", "drawing.pin_radius"),
    "roller": ("roller_radius", "drawing.pin_radius"),
}


def geneva_parts(element: "Geneva", phi: float = 0.0, geo: GenevaGeometry | None = None) -> PartSet:
    """The four parts of ``element`` in the scene at crank angle ``phi`` (rad); ``geo`` reuses a
    built geometry. Raises :class:`~mechsketch.core.errors.GeometryError` naming the key to change
    when the drive cannot be drawn."""
    geo = geo if geo is not None else geometry(element)
    placed = geo.placed(phi)
    parts = tuple(Part(name, ccw(p.outer), tuple(p.holes), group=name, keys=KEYS[name])
                  for name, p in placed.items())
    d, rel = geo.dims, geo.relief
    notes = (
        f"wheel: z = {d.slots}, R_o = {d.outer_radius:.4f} mm, slot width {2 * d.w:.4f} mm, slot depth "
        f"{d.slot_depth:.4f} mm, hub bore {geo.wheel_bore:.4f} mm (hub limit {d.hub_max:.4f} mm), locking arcs "
        f"R_arc = {d.lock_arc_radius:.4f} mm",
        f"locking disc: R_L = {d.lock_disc_radius:.4f} mm, relief radius {rel.drawn:.3f} mm at {d.center_distance:g} mm "
        f"(clears by c_l; classical R_o {rel.classical:.5f} would interfere), crank bore {geo.crank_bore:.4f} mm",
        f"crank arm: crank radius {d.crank_radius:.4f} mm, pin {geo.pin_radius:.4f} mm; drawn at crank angle "
        f"{math.degrees(phi):g}° (mid-engagement when 0); minimum web {element.min_web:g} mm (drawing.min_web)",
    )
    return PartSet(element.id, parts, (), notes, web_key="drawing.min_web")
