"""Whole-element transforms for placing one scene inside another (Examples -> Insert).

Pure functions on the immutable element records: :func:`translated` moves every drawn point of an
element by (dx, dy) mm (derived results move with it: nothing derived is stored), :func:`renamed`
gives it a new id, :func:`extent` is the box of its drawn points, and :func:`placed` does all of
it for a whole scene - new ids only where they collide with ids already taken.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Iterable

from ..errors import EditError
from .geneva import Geneva
from .linkage import Linkage
from .rolling_lever import Circle, Drive, RollingLever
from .gear_pair import GearPair
from .geared_geneva import GearedGeneva
from .underlay import Underlay

XY = tuple[float, float]


def _add(p: XY, dx: float, dy: float) -> XY:
    return (float(p[0]) + dx, float(p[1]) + dy)


def translated(element: Any, dx: float, dy: float) -> Any:
    """``element`` with every drawn point moved by (dx, dy) mm (linkage, Geneva drive, rolling
    lever, underlay, gear pair, geared Geneva); :class:`EditError` for a type this version cannot move."""
    if isinstance(element, Linkage):
        return replace(element, joints=tuple(j.moved(_add(j.at, dx, dy)) for j in element.joints))
    if isinstance(element, Geneva):
        return replace(element, crank_center=_add(element.crank_center, dx, dy))
    if isinstance(element, RollingLever):
        drive = element.drive
        if drive is not None:
            drive = Drive(_add(drive.crank_pivot, dx, dy), _add(drive.coupler_point, dx, dy))
        return replace(element,
                       lever_circle=Circle(_add(element.lever_circle.center, dx, dy), element.lever_circle.radius),
                       slider_circle=None if element.slider_circle is None else
                       Circle(_add(element.slider_circle.center, dx, dy), element.slider_circle.radius),
                       pin=_add(element.pin, dx, dy), rocker_pivot=_add(element.rocker_pivot, dx, dy), drive=drive)
    if isinstance(element, Underlay):
        return element.with_placement(element.placement.moved(dx, dy))
    if isinstance(element, GearPair):
        return replace(element, input_center=_add(element.input_center, dx, dy))
    if isinstance(element, GearedGeneva):   # the gears hang on the crank centre
        return replace(element, geneva=translated(element.geneva, dx, dy))
    raise EditError(f"cannot move element {getattr(element, 'id', '?')!r} of type "
                    f"{getattr(element, 'type', type(element).__name__)!r}")


def renamed(element: Any, new_id: str) -> Any:
    """``element`` under the id ``new_id`` (everything else as it was)."""
    return replace(element, id=new_id)


def extent(element: Any) -> tuple[float, float, float, float]:
    """(xmin, ymin, xmax, ymax) mm of the element's drawn points (circles by their boxes)."""
    pts: list[XY] = []
    if isinstance(element, Linkage):
        pts = [j.at for j in element.joints]
    elif isinstance(element, Geneva):
        cc, wc = element.crank_center, element.wheel_center
        r = element.center_distance
        pts = [(cc[0] - 0.6 * r, cc[1] - 0.6 * r), (wc[0] + r, wc[1] + r), (wc[0] - r, wc[1] - r)]
    elif isinstance(element, RollingLever):
        for c in (element.lever_circle, element.slider_circle):
            if c is None:
                continue
            pts += [(c.center[0] - c.radius, c.center[1] - c.radius), (c.center[0] + c.radius, c.center[1] + c.radius)]
        pts += [element.pin, element.rocker_pivot]
        if element.drive is not None:
            pts += [element.drive.crank_pivot, element.drive.coupler_point]
    elif isinstance(element, Underlay):
        x0, y0, x1, y1 = element.world_bounds()
        pts = [(x0, y0), (x1, y1)]
    elif isinstance(element, GearPair):
        a = element.center_distance
        for c in (element.input_center, element.output_center):
            pts += [(c[0] - a, c[1] - a), (c[0] + a, c[1] + a)]
    elif isinstance(element, GearedGeneva):
        box = extent(element.geneva)
        c, a = element.input_center, element.center_distance
        pts = [(box[0], box[1]), (box[2], box[3]), (c[0] - a, c[1] - a), (c[0] + a, c[1] + a)]
    if not pts:
        return (0.0, 0.0, 0.0, 0.0)
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return (min(xs), min(ys), max(xs), max(ys))


def fresh_id(stem: str, taken: Iterable[str]) -> str:
    """``stem`` if free, else ``stem2``, ``stem3``, ... (the first free one)."""
    used = set(taken)
    if stem not in used:
        return stem
    n = 2
    while f"{stem}{n}" in used:
        n += 1
    return f"{stem}{n}"


def placed(elements: Iterable[Any], at: XY, taken: Iterable[str], anchor: XY | None = None) -> list[Any]:
    """The ``elements`` moved so that ``anchor`` (default: the centre of their joint extent) lands
    on ``at`` (mm), each renamed where its id is in ``taken`` or used by an earlier one of them."""
    elements = list(elements)
    if anchor is None:
        boxes = [extent(e) for e in elements]
        if boxes:
            anchor = ((min(b[0] for b in boxes) + max(b[2] for b in boxes)) / 2,
                      (min(b[1] for b in boxes) + max(b[3] for b in boxes)) / 2)
        else:
            anchor = (0.0, 0.0)
    dx, dy = float(at[0]) - anchor[0], float(at[1]) - anchor[1]
    used = set(taken)
    out = []
    for el in elements:
        new_id = fresh_id(el.id, used)
        used.add(new_id)
        moved = translated(el, dx, dy)
        out.append(moved if new_id == el.id else renamed(moved, new_id))
    return out
