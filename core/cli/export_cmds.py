"""``mechsketch export``: the cut-ready parts of any element as DXF or SVG; and the drawing check
that ``mechsketch validate`` runs as its manufacturability warnings (the same parts, the same
check: a scene whose validation has no warning exports; ``validate --strict`` makes them errors).

    mechsketch export SCENE [--element ID] (--dxf PATH | --svg PATH) [--layout assembled|apart]
                      [--parts P,...] [--split] [--arcs bulge|entities] [--tolerance MM]
                      [--min-web MM] [--boss-radius MM] [--bore-diameter MM] [--link-width MM]
                      [--frame plate|drill] [--depth MM]

The part builders (shapely) and the writers (ezdxf) are imported by the functions that use them:
building the parser, which every command does, imports neither.
"""
from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from ..errors import MechsketchError, Problem, RequestError, StructureError

if TYPE_CHECKING:  # pragma: no cover
    from ..analyses.parts.build import PartOptions
    from ..analyses.parts.keys import Vocabulary
    from ..workspace import Workspace

#: the option choices and default of ``export`` as analyses.parts (LAYOUTS), io.dxf_parts
#: (ARC_STYLES) and analyses.parts.build (DEFAULT_TOLERANCE, mm) define them, repeated so that
#: the parser imports none of those modules (tests/core/test_cli_imports.py checks they agree)
LAYOUTS = ("assembled", "apart")
ARC_STYLES = ("bulge", "entities")
DEFAULT_TOLERANCE = 0.001
#: export option (PartOptions field) -> its flag here: how messages of ``export`` name them
EXPORT_FLAGS = (("boss_radius", "--boss-radius"), ("bore_diameter", "--bore-diameter"),
                ("link_width", "--link-width"), ("min_web", "--min-web"), ("tolerance", "--tolerance"),
                ("depth", "--depth"), ("frame", "--frame"))


def export_vocabulary() -> Vocabulary:
    """How ``mechsketch export`` names what to change: its flags, and the scene's keys."""
    from ..analyses.parts.keys import Vocabulary

    return Vocabulary(EXPORT_FLAGS, "mechsketch export")


def validate_vocabulary() -> Vocabulary:
    """How ``mechsketch validate`` names what to change: the scene's keys only (it has no part
    options); export options in words."""
    from ..analyses.parts.keys import Vocabulary

    return Vocabulary((), "mechsketch validate")


def add_export_parser(sub) -> argparse.ArgumentParser:
    """The ``export`` sub-command and its options."""
    e = sub.add_parser("export", help="write the cut-ready parts of an element as DXF or SVG (mm), checked first")
    e.add_argument("scene")
    e.add_argument("--element", metavar="ID")
    out = e.add_mutually_exclusive_group(required=True)
    out.add_argument("--dxf", metavar="PATH", help="write DXF R2010 in millimetres")
    out.add_argument("--svg", metavar="PATH", help="write SVG in millimetres")
    e.add_argument("--layout", choices=LAYOUTS, default="apart",
                   help="apart: parts side by side, named (default); assembled: in the mechanism's pose")
    e.add_argument("--parts", metavar="P,...", help="only these parts (names as in the report)")
    e.add_argument("--split", action="store_true", help="one file per part: PATH_NAME.ext")
    e.add_argument("--arcs", choices=ARC_STYLES, default="bulge",
                   help="DXF: bulge polylines (default) or LINE/ARC entities for older readers")
    e.add_argument("--tolerance", type=float, default=DEFAULT_TOLERANCE, metavar="MM",
                   help="largest deviation of fitted curves (rolling profiles, coupler curves)")
    e.add_argument("--min-web", dest="min_web", type=float, metavar="MM",
                   help="thinnest web every part must keep (default: the element's drawing.min_web or 1)")
    e.add_argument("--boss-radius", dest="boss_radius", type=float, metavar="MM", help="linkage plates")
    e.add_argument("--bore-diameter", dest="bore_diameter", type=float, metavar="MM", help="linkage bores")
    e.add_argument("--link-width", dest="link_width", type=float, metavar="MM", help="binary link bar width")
    e.add_argument("--frame", choices=("plate", "drill"), default="plate",
                   help="a linkage's frame as a plate or as the drilling pattern of its pivots")
    e.add_argument("--depth", type=float, metavar="MM", help="rolling-lever frame and slider plates")
    return e


def options_of(args: argparse.Namespace) -> PartOptions:
    """The part options of parsed ``export`` arguments."""
    from ..analyses.parts.build import PartOptions

    return PartOptions(tolerance=args.tolerance, min_web=args.min_web, boss_radius=args.boss_radius,
                       bore_diameter=args.bore_diameter, link_width=args.link_width, frame=args.frame,
                       depth=args.depth, vocabulary=export_vocabulary())


def _plan(ws: Workspace, el):
    from ..model.linkage import Linkage

    return ws.plan(el.id) if isinstance(el, Linkage) else None


def run_export(ws: Workspace, args: argparse.Namespace) -> str:
    """Build, check and write the parts; returns the report."""
    from ..analyses.parts.build import element_parts, min_web_of
    from ..io.export_parts import export_parts

    scene = ws.scene
    if args.element is not None:
        el = scene.element(args.element)
    elif scene.elements:
        el = scene.elements[0]
        if len(scene.elements) > 1:
            print(f"note: using element {el.id!r} (choose with --element ID)", file=sys.stderr)
    else:
        raise RequestError("the scene has no element to export")
    opts = options_of(args)
    names = [n.strip() for n in args.parts.split(",") if n.strip()] if args.parts else None
    ps = element_parts(el, opts, _plan(ws, el))
    fmt, path = ("dxf", args.dxf) if args.dxf is not None else ("svg", args.svg)
    return export_parts(ps, path, fmt, args.layout, names, args.split, args.arcs, min_web_of(el, opts),
                        opts.vocabulary).report


def drawing_warnings(ws: Workspace) -> list[Problem]:
    """Manufacturability: for each element that can be analysed, every reason its parts cannot be
    cut with the sizes in force (the drawing block, else the defaults), one per failing part,
    named in the scene's keys. ``validate`` lists them as warnings (``--strict``: errors); the
    export refuses the same parts."""
    from ..analyses.parts import check_parts, failures
    from ..analyses.parts.build import PartOptions, element_parts, min_web_of
    from ..model.kinds import element_kind

    out = []
    opts = PartOptions(vocabulary=validate_vocabulary())
    for k, el in enumerate(ws.scene.elements):
        kind = element_kind(el.type)
        if kind is not None and not kind.parts:
            continue   # an underlay: a reference, nothing is cut from it
        try:
            ps = element_parts(el, opts, _plan(ws, el))
            min_web = min_web_of(el, opts)
            lines = failures(ps, check_parts(ps.parts, min_web), opts.vocabulary)
        except StructureError:
            continue  # reported by the structure check
        except MechsketchError as exc:
            lines = [f"its parts cannot be built: {exc}"]
        out += [Problem(f"$.elements[{k}]", line, el.id) for line in lines]
    return out
