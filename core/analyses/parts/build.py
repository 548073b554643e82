"""One entry to the parts of any element: :func:`element_parts` picks the builder by type.

The CLI's ``export`` and ``validate`` and the GUI's export dialog all call it with one
:class:`PartOptions`, so the same options give the same parts everywhere.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import GeometryError
from ...model.drawing import DEFAULT_MIN_WEB, LinkageDrawing
from ...model.gear_pair import GearPair
from ...model.geared_geneva import GearedGeneva
from ...model.geneva import Geneva
from ...model.linkage import Linkage
from ...model.rolling_lever import RollingLever
from ...solver.plan import Plan, compile_plan
from .bore_keys import key_bores
from .gears import gear_parts
from .outline import is_circle
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
    ``bore_diameter``, ``link_width``, ``frame`` ("plate" | "drill"); rolling levers: ``depth``, ``fasteners`` (the diameter of
    the frame and slider plates' fastener holes, matched where they mount) and ``base_plate``
    (a plate carrying every pivot and the frame plate's fasteners instead of a drilling pattern).
    ``bore_key`` ("keyway" | "flat"): key the shaft bores (Geneva drives, gear blanks, a linkage's driver;
    :mod:`.bore_keys`).
    ``vocabulary``: how the front end asking names these options in messages (:mod:`.keys`).
    """

    tolerance: float = DEFAULT_TOLERANCE
    min_web: float | None = None
    boss_radius: float | None = None
    bore_diameter: float | None = None
    link_width: float | None = None
    frame: str = "plate"
    depth: float | None = None
    fasteners: float | None = None
    base_plate: bool = False
    bore_key: str | None = None
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
    return LinkageStyle(**sizes, frame=options.frame, tolerance=options.tolerance, names=tuple(names),
                        fasteners=options.fasteners, base_plate=options.base_plate)


def element_parts(element, options: PartOptions = PartOptions(), plan: Plan | None = None) -> PartSet:
    """The cut-ready parts of ``element`` (a Geneva drive, a linkage or a rolling lever); ``plan``
    reuses a compiled linkage. Raises :class:`GeometryError` (or the solver's StructureError)
    naming what to change when they cannot be built."""
    ps = _unkeyed_parts(element, options, plan)
    if options.bore_key is None:
        return ps
    return key_bores(ps, _shafts(element, ps), options.bore_key, "option:bore_key")


def _shafts(element, ps: PartSet) -> dict[str, list[tuple[tuple[float, float], float]]]:
    """Per part, its shaft bores' centres (mm) and the direction (rad) its key points."""
    if isinstance(element, GearPair):
        return _blank_shafts(ps, ("input_gear", "output_gear"))
    if isinstance(element, GearedGeneva):
        return {**_shafts(element.geneva, ps), **_blank_shafts(ps, ("input_gear", "output_gear"))}
    if isinstance(element, Geneva):
        bores = {p.name: [is_circle(h)[0] for h in p.holes if h.kinds and h.kinds[0] == "bore"] for p in ps.parts}
        crank = bores.get("crank_arm") or bores.get("locking_disc")
        wheel = bores.get("wheel")
        out = {}
        if crank and wheel:
            (cx, cy), (wx, wy) = crank[0], wheel[0]
            to_wheel = math.atan2(wy - cy, wx - cx)
            out = {"crank_arm": [(crank[0], to_wheel + math.pi)], "locking_disc": [(crank[0], to_wheel + math.pi)],
                   "wheel": [(wheel[0], to_wheel + math.pi + math.pi / element.slots)]}
        return out
    pivot = element.joint(element.driver.pivot).at
    others = [element.joint(j).at for j in element.link(element.driver.link).joints if j != element.driver.pivot]
    away = math.atan2(*(np.asarray(pivot) - np.mean(others, axis=0))[::-1]) if others else 0.0
    return {element.driver.link: [(tuple(pivot), away)]}


def _blank_shafts(ps: PartSet, names: tuple[str, ...]) -> dict[str, list[tuple[tuple[float, float], float]]]:
    """A gear blank's bore, keyed towards the farthest point of its outline (where the blank has
    most material: the long radius of a non-circular pitch curve)."""
    out = {}
    for p in ps.parts:
        bores = [is_circle(h)[0] for h in p.holes if h.kinds and h.kinds[0] == "bore"]
        if p.name in names and bores and p.outer is not None:
            c = np.asarray(bores[0], float)
            far = p.outer.points[int(np.argmax(np.hypot(*(p.outer.points - c).T)))]
            out[p.name] = [(bores[0], math.atan2(far[1] - c[1], far[0] - c[0]))]
    return out


def _unkeyed_parts(element, options: PartOptions, plan: Plan | None) -> PartSet:
    if isinstance(element, Geneva):
        return geneva_parts(element)
    if isinstance(element, Linkage):
        check_tolerance_option(options.tolerance, options.vocabulary)
        if options.base_plate and options.frame != "drill":
            raise GeometryError(f"{name_of('option:base_plate', options.vocabulary)} carries a linkage frame's drilling "
                                f"pattern: choose {name_of('option:frame', options.vocabulary)} drill with it (the "
                                "frame as a plate is already one)")
        ps = linkage_parts(element, plan if plan is not None else compile_plan(element),
                           linkage_style(element, options), min_web_of(element, options))
        if options.fasteners is not None and not any("option:fasteners" in p.keys for p in ps.parts):
            raise GeometryError(f"{name_of('option:fasteners', options.vocabulary)} fastens a linkage's separate guide "
                                f"plates to their links; linkage {element.id!r} has none (its guides are slots in "
                                "their links)")
        return ps
    if isinstance(element, RollingLever):
        depth_name = options.vocabulary.option("depth") or "the plate depth"
        return rolling_parts(synthesize(element, measures=False),
                             RollingStyle(depth=options.depth, tolerance=options.tolerance, depth_name=depth_name,
                                          fasteners=options.fasteners, base_plate=options.base_plate))
    if isinstance(element, (GearPair, GearedGeneva)):   # issue 25: pitch-curve blanks (and the drive)
        return gear_parts(element)
    raise GeometryError(f"element {getattr(element, 'id', '?')!r} of type {getattr(element, 'type', '?')!r} "
                        "has no parts to export")


#: part options every element takes
COMMON_OPTIONS = frozenset({"min_web"})


def applicable_options(element) -> frozenset[str]:
    """The :class:`PartOptions` fields the parts of ``element`` use; a front end refuses the
    others when the user sets them (issue 23: options that do not apply are refused, not ignored).
    ``tolerance`` applies where curves are fitted: a rolling lever's profiles, a linkage's traced
    coupler points."""
    if isinstance(element, Linkage):
        traced = any(len(element.links_of(j.id)) == 1 and element.links_of(j.id)[0] != element.ground
                     for j in element.joints)
        return COMMON_OPTIONS | {"boss_radius", "bore_diameter", "link_width", "frame", "bore_key", "fasteners",
                                 "base_plate"} | \
            ({"tolerance"} if traced else set())
    if isinstance(element, RollingLever):
        return COMMON_OPTIONS | {"depth", "tolerance", "fasteners", "base_plate"}
    if isinstance(element, (Geneva, GearPair, GearedGeneva)):
        return COMMON_OPTIONS | {"bore_key"}
    return COMMON_OPTIONS


def check_tolerance_option(tolerance: float, vocab: Vocabulary = API) -> None:
    """Refuse a curve tolerance that is not a positive number of millimetres (0 is refused, not
    clamped)."""
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise GeometryError(f"{name_of('option:tolerance', vocab)} must be a positive number of millimetres "
                            f"(the largest deviation of a fitted curve); got {tolerance:g}")


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
