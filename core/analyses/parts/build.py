"""One entry to the parts of any element: :func:`element_parts` picks the builder by type.

The CLI's ``export`` and ``validate`` and the GUI's export dialog all call it with one
:class:`PartOptions`, so the same options give the same parts everywhere.
"""
from __future__ import annotations

from dataclasses import dataclass

from ...errors import GeometryError
from ...model.gear_pair import GearPair
from ...model.geared_geneva import GearedGeneva
from ...model.geneva import Geneva
from ...model.linkage import Linkage
from ...model.rolling_lever import RollingLever
from ...solver.plan import Plan, compile_plan
from .check import DEFAULT_MIN_WEB
from .records import PartSet
from .gears import gear_parts
from .geneva import geneva_parts
from .linkage import LinkageStyle, linkage_parts
from .rolling import RollingStyle, rolling_parts
from ..rolling.synthesis import synthesize

#: the curve tolerance (mm) of fitted profiles and traced coupler curves, by default
DEFAULT_TOLERANCE = 0.001


@dataclass(frozen=True)
class PartOptions:
    """What the user may set (mm; None: the element's or the scaled default).

    ``tolerance``: fitted curves (rolling profiles, coupler traces); ``min_web``: the thinnest web
    (None: the element's ``drawing.min_web`` or 1 mm); linkages: ``boss_radius``,
    ``bore_diameter``, ``link_width``, ``frame`` ("plate" | "drill"); rolling levers: ``depth``.
    """

    tolerance: float = DEFAULT_TOLERANCE
    min_web: float | None = None
    boss_radius: float | None = None
    bore_diameter: float | None = None
    link_width: float | None = None
    frame: str = "plate"
    depth: float | None = None


def min_web_of(element, options: PartOptions) -> float:
    """The minimum web in force for ``element`` (mm)."""
    if options.min_web is not None:
        return options.min_web
    if isinstance(element, GearedGeneva):
        return min(element.geneva.min_web, element.min_web)
    return element.min_web if isinstance(element, (Geneva, GearPair)) else DEFAULT_MIN_WEB


def element_parts(element, options: PartOptions = PartOptions(), plan: Plan | None = None) -> PartSet:
    """The cut-ready parts of ``element`` (a Geneva drive, a linkage or a rolling lever); ``plan``
    reuses a compiled linkage. Raises :class:`GeometryError` (or the solver's StructureError)
    naming what to change when they cannot be built."""
    if isinstance(element, Geneva):
        return geneva_parts(element)
    if isinstance(element, Linkage):
        style = LinkageStyle(boss_radius=options.boss_radius, bore_diameter=options.bore_diameter,
                             width=options.link_width, frame=options.frame, tolerance=max(options.tolerance, 1e-4))
        return linkage_parts(element, plan if plan is not None else compile_plan(element), style,
                             min_web_of(element, options))
    if isinstance(element, RollingLever):
        return rolling_parts(synthesize(element, measures=False),
                             RollingStyle(depth=options.depth, tolerance=options.tolerance))
    if isinstance(element, (GearPair, GearedGeneva)):   # issue 25: pitch-curve blanks (and the drive)
        return gear_parts(element)
    raise GeometryError(f"element {getattr(element, 'id', '?')!r} of type {getattr(element, 'type', '?')!r} "
                        "has no parts to export")


def part_names(element) -> tuple[str, ...]:
    """The names of the parts ``element`` will have, without building them (for a dialog's list;
    a linkage may add a ``LINK_guide_JOINT`` plate where a block's travel passes over a pin)."""
    if isinstance(element, Geneva):
        return ("wheel", "locking_disc", "crank_arm", "roller")
    if isinstance(element, Linkage):
        return element.link_ids
    if isinstance(element, RollingLever):
        return ("frame", "frame_pivots", "lever", "slider")
    if isinstance(element, GearPair):
        return ("input_gear", "output_gear")
    if isinstance(element, GearedGeneva):
        return ("wheel", "locking_disc", "crank_arm", "roller", "input_gear", "output_gear")
    return ()
