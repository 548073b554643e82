"""One entry to the parts of any element: :func:`element_parts` picks the builder by type.

The CLI's ``export`` and ``validate`` and the GUI's export dialog all call it with one
:class:`PartOptions`, so the same options give the same parts everywhere.
"""
from __future__ import annotations

from dataclasses import dataclass

from ...errors import GeometryError
from ...model.drawing import DEFAULT_MIN_WEB, LinkageDrawing
from ...model.gear_pair import GearPair
from ...model.geared_geneva import GearedGeneva
from ...model.geneva import Geneva
from ...model.linkage import Linkage
from ...model.rolling_lever import RollingLever
from ...solver.plan import Plan, compile_plan
from .gears import gear_parts
from .keys import API, Vocabulary, name_of
from .geneva import geneva_parts
from .linkage import LinkageStyle, linkage_parts
from .records import PartSet
from .rolling import RollingStyle, rolling_parts
from ..rolling.synthesis import synthesize

#: the curve tolerance (mm) of fitted profiles and traced coupler curves, by default
DEFAULT_TOLERANCE = 0.001


@dataclass(frozen=True)
class PartOptions:
    """What the user may set for one export (mm; None: the element's ``drawing`` block, else the
    scaled default).

    ``tolerance``: fitted curves (rolling profiles, coupler traces); ``min_web``: the thinnest web
    (None: the element's ``drawing.min_web`` or 1 mm); linkages: ``boss_radius``,
    ``bore_diameter``, ``link_width``, ``frame`` ("plate" | "drill"); rolling levers: ``depth``.
    ``vocabulary``: how the front end asking names these options in messages (:mod:`.keys`).
    """

    tolerance: float = DEFAULT_TOLERANCE
    min_web: float | None = None
    boss_radius: float | None = None
    bore_diameter: float | None = None
    link_width: float | None = None
    frame: str = "plate"
    depth: float | None = None
    vocabulary: Vocabulary = API


def min_web_of(element, options: PartOptions) -> float:
    """The minimum web in force for ``element`` (mm): the option, else the element's
    ``drawing.min_web``, else 1 mm."""
    if options.min_web is not None:
        return options.min_web
    if isinstance(element, GearedGeneva):
        return min(element.geneva.min_web, element.min_web)
    if isinstance(element, (Geneva, GearPair)):
        return element.min_web
    if isinstance(element, Linkage) and element.drawing is not None and element.drawing.min_web is not None:
        return element.drawing.min_web
    return DEFAULT_MIN_WEB


#: LinkageStyle field -> (PartOptions field, LinkageDrawing field)
_LINKAGE_SIZES = {"boss_radius": ("boss_radius", "boss_radius"), "bore_diameter": ("bore_diameter", "bore_diameter"),
                  "width": ("link_width", "link_width"), "block_length": (None, "block_length"),
                  "block_width": (None, "block_width")}


def linkage_style(element: Linkage, options: PartOptions) -> LinkageStyle:
    """The plate sizes of ``element`` for ``options``: each size from the export option, else the
    linkage's ``drawing`` block, else None (scaled); messages name where each came from."""
    drawing = element.drawing or LinkageDrawing()
    vocab = options.vocabulary
    sizes, names = {}, []
    for field, (opt, key) in _LINKAGE_SIZES.items():
        given = getattr(options, opt) if opt is not None else None
        if given is not None:
            sizes[field] = given
            names.append((field, vocab.option(opt) or opt))
        elif getattr(drawing, key) is not None:
            sizes[field] = getattr(drawing, key)
            names.append((field, f"drawing.{key}"))
        else:
            names.append((field, name_of(f"drawing.{key}", vocab)))
    return LinkageStyle(**sizes, frame=options.frame, tolerance=max(options.tolerance, 1e-4), names=tuple(names))


def element_parts(element, options: PartOptions = PartOptions(), plan: Plan | None = None) -> PartSet:
    """The cut-ready parts of ``element`` (a Geneva drive, a linkage or a rolling lever); ``plan``
    reuses a compiled linkage. Raises :class:`GeometryError` (or the solver's StructureError)
    naming what to change when they cannot be built."""
    if isinstance(element, Geneva):
        return geneva_parts(element)
    if isinstance(element, Linkage):
        return linkage_parts(element, plan if plan is not None else compile_plan(element),
                             linkage_style(element, options), min_web_of(element, options))
    if isinstance(element, RollingLever):
        depth_name = options.vocabulary.option("depth") or "the plate depth"
        return rolling_parts(synthesize(element, measures=False),
                             RollingStyle(depth=options.depth, tolerance=options.tolerance, depth_name=depth_name))
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
