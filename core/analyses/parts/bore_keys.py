"""Keyways and flats on shaft bores (issue 23, item 5): the bore that a shaft drives a part
through gets a hub keyway (DIN 6885-1 key width b and hub depth t2 by the shaft diameter) or a
flat (a D-bore, the flat a tenth of the diameter in), so the part does not turn on its shaft.

Which bores are shaft bores: a Geneva drive's wheel bore and its crank bores (the crank arm and
the locking disc, keyed alike on one shaft); a linkage's driver link at its pivot. The key points
where the part has most material: a Geneva crank's away from the wheel (the locking disc's relief
faces the wheel), the wheel's between two slots, a driver link's away from its other joints; parts
on one shaft key alike. The bore stays
a contour of lines and true arcs; the part is checked again like any part.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import GeometryError
from ..contour import Contour
from .outline import is_circle
from .records import PartSet

KEYS = ("keyway", "flat")
#: DIN 6885-1 (parallel keys): shaft diameter above (mm) -> (key width b, hub keyway depth t2) mm
DIN_6885 = ((6.0, 2.0, 1.0), (8.0, 3.0, 1.4), (10.0, 4.0, 1.8), (12.0, 5.0, 2.3), (17.0, 6.0, 2.8),
            (22.0, 8.0, 3.3), (30.0, 10.0, 3.3), (38.0, 12.0, 3.3), (44.0, 14.0, 3.8), (50.0, 16.0, 4.3),
            (58.0, 18.0, 4.4), (65.0, 20.0, 4.9), (75.0, 22.0, 5.4), (85.0, 25.0, 5.4), (95.0, 28.0, 6.4))
#: the flat of a D-bore lies this fraction of the radius from the centre
FLAT_AT = 0.8


def key_size(diameter: float) -> tuple[float, float]:
    """(b, t2) mm of DIN 6885-1 for a shaft of ``diameter`` mm; :class:`GeometryError` outside
    6…110 mm (a smaller shaft takes a flat)."""
    if not 6.0 < diameter <= 110.0:
        raise GeometryError(f"a keyway needs a shaft of 6 to 110 mm (DIN 6885-1); the bore is Ø{diameter:.4g} mm: "
                            "use a flat instead")
    b, t2 = next((b, t2) for lo, b, t2 in reversed(DIN_6885) if diameter > lo)
    return b, t2


def keyed_bore(centre, radius: float, key: str, angle: float = 0.0) -> Contour:
    """A bore of ``radius`` mm at ``centre`` with a ``key`` ("keyway" | "flat") towards ``angle``
    rad, CCW."""
    c = np.asarray(centre, float)
    rot = np.array([[math.cos(angle), math.sin(angle)], [-math.sin(angle), math.cos(angle)]])
    if key == "flat":
        h = FLAT_AT * radius
        s = math.sqrt(radius * radius - h * h)
        pts = np.array([[h, -s], [h, s]])
        sweep = 2 * math.pi - 2 * math.acos(FLAT_AT)
        return Contour(pts @ rot + c, np.array([0.0, math.tan(sweep / 4)]), ("flat", "bore"))
    b, t2 = key_size(2 * radius)
    x = math.sqrt(radius * radius - 0.25 * b * b)
    pts = np.array([[x, -b / 2], [radius + t2, -b / 2], [radius + t2, b / 2], [x, b / 2]])
    sweep = 2 * math.pi - 2 * math.asin(0.5 * b / radius)
    return Contour(pts @ rot + c, np.array([0.0, 0.0, 0.0, math.tan(sweep / 4)]), ("keyway",) * 3 + ("bore",))


def key_bores(ps: PartSet, shafts: dict[str, list[tuple[tuple[float, float], float]]], key: str,
              option: str) -> PartSet:
    """``ps`` with the round holes centred at ``shafts[part]`` ((centre mm, to 1e-9; the key's
    direction rad) pairs) keyed by ``key``; ``option`` (the option's key) is added to the keys of
    the parts changed."""
    if key not in KEYS:
        raise GeometryError(f"a bore key must be one of {', '.join(KEYS)}; got {key!r}")
    parts, found = [], 0
    for p in ps.parts:
        centres = shafts.get(p.name, [])
        holes = []
        for h in p.holes:
            circ = is_circle(h)
            hit = [a for q, a in centres if circ is not None and math.dist(circ[0], q) <= 1e-9 * (1 + abs(q[0]) + abs(q[1]))]
            holes.append(keyed_bore(circ[0], circ[1], key, hit[0]) if hit else h)
            found += bool(hit)
        parts.append(replace(p, holes=tuple(holes), keys=p.keys + (option,)) if centres else p)
    if not found:
        raise GeometryError(f"element {ps.element_id!r} has no shaft bore to key")
    names = ", ".join(sorted(n for n in shafts if any(p.name == n for p in ps.parts)))
    what = "DIN 6885-1 hub keyway" if key == "keyway" else f"flat {FLAT_AT:g} r from the centre"
    return replace(ps, parts=tuple(parts), notes=ps.notes + (f"bore keys: {what} on the shaft bores of {names}, "
                                                              "where each part has most material",))
