"""An underlay: a drawing (polylines read from a DXF or SVG file) or a picture placed under the
canvas to draw over, e.g. the outline of a machine the mechanism must fit, or a photo of a part.
It is a reference, not a part: it is not solved, exported or checked for manufacture.

Its own coordinates (``source units``: a DXF's or SVG's units, a picture's pixels with y up from
the bottom-left corner) are mapped into the scene by a :class:`Placement`: a similarity
``world = offset + scale·R(angle)·source`` (mm per source unit, degrees, mm). Placing an underlay
by two points of known distance is :meth:`Placement.scaled_about`; moving it is
:meth:`Placement.moved`. Records are immutable; every change is a new record (one undo step).
"""
from __future__ import annotations

import base64
import binascii
import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

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

    def _ab(self) -> tuple[float, float]:
        t = math.radians(self.angle_deg)
        return self.scale * math.cos(t), self.scale * math.sin(t)

    def to_world(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) source points -> (N, 2) world points, mm."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)
        a, b = self._ab()
        return np.column_stack([self.offset[0] + a * p[:, 0] - b * p[:, 1],
                                self.offset[1] + b * p[:, 0] + a * p[:, 1]])

    def to_source(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) world points (mm) -> (N, 2) source points (the inverse of :meth:`to_world`)."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2) - np.asarray(self.offset, dtype=float)
        a, b = self._ab()
        k = a * a + b * b
        return np.column_stack([(a * p[:, 0] + b * p[:, 1]) / k, (-b * p[:, 0] + a * p[:, 1]) / k])

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

    def source_corners(self) -> np.ndarray:
        """(4, 2) corners of the source extent (a picture's frame, a drawing's bounding box)."""
        if self.image is not None:
            w, h = self.image.width, self.image.height
            return np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])
        pts = self.source_points()
        if not len(pts):
            return np.zeros((4, 2))
        (x0, y0), (x1, y1) = pts.min(axis=0), pts.max(axis=0)
        return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])

    def source_points(self) -> np.ndarray:
        """(M, 2) every vertex of every path, source units."""
        if not self.paths:
            return np.zeros((0, 2))
        return np.concatenate([np.asarray(p, dtype=float) for p in self.paths])

    def world_paths(self) -> list[np.ndarray]:
        """Each path as (n, 2) world points, mm."""
        return [self.placement.to_world(np.asarray(p, dtype=float)) for p in self.paths]

    def world_points(self) -> np.ndarray:
        """(M, 2) every vertex in the world (what snaps), mm."""
        return self.placement.to_world(self.source_points())

    def world_bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of what is drawn, mm."""
        c = self.placement.to_world(self.source_corners())
        return float(c[:, 0].min()), float(c[:, 1].min()), float(c[:, 0].max()), float(c[:, 1].max())

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
