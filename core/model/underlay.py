"""An underlay: a drawing (polylines read from a DXF or SVG file) or a picture placed under the
canvas to draw over, e.g. the outline of a machine the mechanism must fit, or a photo of a part.
It is a reference, not a part: it is not solved, exported or checked for manufacture.

Its own coordinates (``source units``: a DXF's or SVG's units, a picture's pixels with y up from
the bottom-left corner) are mapped into the scene by a :class:`Placement`: a similarity
``world = offset + scale·R(angle)·source`` (mm per source unit, degrees, mm). Placing an underlay
by two points of known distance is :meth:`Placement.scaled_about`; moving it is
:meth:`Placement.moved`. Records are immutable; every change is a new record (one undo step).
Pure Python (no numpy): the scene reader loads this module at every start of the CLI; array
versions of the mapping are where the arrays are (the canvas, the readers).
"""
from __future__ import annotations

import base64
import binascii
import math
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Iterable, Sequence

from ..errors import Problem

SCHEMA = "underlay.schema.json"
#: vertices over all paths of one drawing (a file holding more is simplified when read)
MAX_POINTS = 200_000
IMAGE_FORMATS = {"png": b"\x89PNG\r\n\x1a\n", "jpeg": b"\xff\xd8\xff"}
#: the base64 text of a picture (the scene file itself is limited to 10 MB)
MAX_IMAGE_CHARS = 6_000_000

XY = tuple[float, float]


@dataclass(frozen=True)
class Placement:
    """``world = offset + scale·R(angle_deg)·source``: ``scale`` mm per source unit (> 0)."""

    scale: float = 1.0
    angle_deg: float = 0.0
    offset: XY = (0.0, 0.0)

    def linear(self) -> tuple[float, float]:
        """(a, b): the placement's linear part is [[a, -b], [b, a]] (a = scale·cos, b = scale·sin)."""
        t = math.radians(self.angle_deg)
        return self.scale * math.cos(t), self.scale * math.sin(t)

    def to_world(self, points: Iterable[Sequence[float]]) -> list[XY]:
        """Source points (x, y) -> world points, mm."""
        a, b = self.linear()
        ox, oy = self.offset
        return [(ox + a * x - b * y, oy + b * x + a * y) for x, y in points]

    def to_source(self, points: Iterable[Sequence[float]]) -> list[XY]:
        """World points (mm) -> source points (the inverse of :meth:`to_world`)."""
        a, b = self.linear()
        ox, oy = self.offset
        k = a * a + b * b
        return [((a * (x - ox) + b * (y - oy)) / k, (-b * (x - ox) + a * (y - oy)) / k) for x, y in points]

    def moved(self, dx: float, dy: float) -> "Placement":
        """The same placement shifted by (dx, dy) mm."""
        return replace(self, offset=(self.offset[0] + dx, self.offset[1] + dy))

    def scaled_about(self, fixed: XY, factor: float) -> "Placement":
        """Scaled by ``factor`` about the world point ``fixed`` (which stays where it is)."""
        if not (factor > 0 and math.isfinite(factor)):
            raise ValueError(f"a scale factor must be a positive number, got {factor}")
        ox = fixed[0] + factor * (self.offset[0] - fixed[0])
        oy = fixed[1] + factor * (self.offset[1] - fixed[1])
        return Placement(self.scale * factor, self.angle_deg, (ox, oy))

    def to_dict(self) -> dict[str, Any]:
        return {"scale": self.scale, "angle_deg": self.angle_deg, "offset": [self.offset[0], self.offset[1]]}


@dataclass(frozen=True)
class UnderlayImage:
    """A picture: ``format`` "png" or "jpeg", ``data`` its bytes in base64, ``width`` and
    ``height`` in pixels (its source units)."""

    format: str
    data: str
    width: int
    height: int

    def raw(self) -> bytes:
        return base64.b64decode(self.data)

    def to_dict(self) -> dict[str, Any]:
        return {"format": self.format, "data": self.data, "width": self.width, "height": self.height}


@dataclass(frozen=True)
class Underlay:
    """A drawing (``paths``: polylines in source units) or a picture (``image``), ``name`` the
    file it came from, shown at ``placement``; ``visible`` False hides it (and its points do
    not snap); ``opacity`` 0..1."""

    id: str
    name: str
    paths: tuple[tuple[XY, ...], ...] = ()
    image: UnderlayImage | None = None
    placement: Placement = Placement()
    visible: bool = True
    opacity: float = 0.6
    type: str = field(default="underlay", init=False)

    @property
    def kind(self) -> str:
        """"image" or "drawing"."""
        return "image" if self.image is not None else "drawing"

    @cached_property
    def source_box(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) in source units: a picture's frame, a drawing's bounding box."""
        if self.image is not None:
            return 0.0, 0.0, float(self.image.width), float(self.image.height)
        xs = [x for p in self.paths for x, _ in p]
        ys = [y for p in self.paths for _, y in p]
        return (min(xs), min(ys), max(xs), max(ys)) if xs else (0.0, 0.0, 0.0, 0.0)

    def source_corners(self) -> list[XY]:
        """The four corners of :attr:`source_box`."""
        x0, y0, x1, y1 = self.source_box
        return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]

    def world_paths(self) -> list[list[XY]]:
        """Each path in world points, mm."""
        return [self.placement.to_world(p) for p in self.paths]

    def world_points(self) -> list[XY]:
        """Every vertex in the world (what snaps), mm."""
        return [q for p in self.world_paths() for q in p]

    def world_bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of what is drawn, mm."""
        c = self.placement.to_world(self.source_corners())
        xs, ys = [x for x, _ in c], [y for _, y in c]
        return min(xs), min(ys), max(xs), max(ys)

    def with_placement(self, placement: Placement) -> "Underlay":
        return replace(self, placement=placement)

    def with_visible(self, visible: bool) -> "Underlay":
        return replace(self, visible=bool(visible))

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"type": "underlay", "id": self.id, "name": self.name}
        if self.image is not None:
            d["image"] = self.image.to_dict()
        else:
            d["paths"] = [[[x, y] for x, y in p] for p in self.paths]
        d["placement"] = self.placement.to_dict()
        d["visible"] = self.visible
        d["opacity"] = self.opacity
        return d


def _image_problems(img: dict[str, Any], path: str, eid: str) -> list[Problem]:
    out = []
    try:
        raw = base64.b64decode(img["data"], validate=True)
    except (binascii.Error, ValueError):
        return [Problem(f"{path}.image.data", "is not base64 text (the picture's bytes)", eid)]
    magic = IMAGE_FORMATS[img["format"]]
    if not raw.startswith(magic):
        out.append(Problem(f"{path}.image.data", f"does not hold a {img['format'].upper()} picture "
                                                 "(its first bytes say otherwise)", eid))
    return out


def parse(data: dict[str, Any], path: str) -> tuple[Underlay | None, list[Problem]]:
    """Check a schema-valid underlay dict for meaning; return the element (or None) and problems."""
    eid = data["id"]
    problems: list[Problem] = []
    has_paths, has_image = "paths" in data, "image" in data
    if has_paths == has_image:
        problems.append(Problem(path, "an underlay holds either 'paths' (a drawing) or 'image' (a picture)", eid))
        return None, problems
    image = None
    paths: tuple[tuple[XY, ...], ...] = ()
    if has_image:
        problems += _image_problems(data["image"], path, eid)
        im = data["image"]
        image = UnderlayImage(im["format"], im["data"], int(im["width"]), int(im["height"]))
    else:
        paths = tuple(tuple((float(x), float(y)) for x, y in p) for p in data["paths"])
        total = sum(len(p) for p in paths)
        if total > MAX_POINTS:
            problems.append(Problem(f"{path}.paths", f"{total:,} points; an underlay holds at most {MAX_POINTS:,}",
                                    eid))
    pl = data["placement"]
    placement = Placement(float(pl["scale"]), float(pl.get("angle_deg", 0.0)),
                          (float(pl["offset"][0]), float(pl["offset"][1])))
    if problems:
        return None, problems
    return Underlay(eid, data["name"], paths, image, placement, bool(data.get("visible", True)),
                    float(data.get("opacity", 0.6))), []
