"""``mechsketch export``: the cut-ready parts of any element as DXF or SVG; and the drawing check
that ``mechsketch validate`` runs as its manufacturability warnings (the same parts, the same
check: a scene whose validation has no warning exports; ``validate --strict`` makes them errors).

    mechsketch export SCENE [--element ID] (--dxf PATH | --svg PATH | --pdf PATH) [--layout assembled|apart]
                      [--parts P,...] [--split] [--arcs bulge|entities] [--annotate] [--kerf MM]
                      [--tolerance MM] [--min-web MM] [--boss-radius MM] [--bore-diameter MM]
                      [--link-width MM] [--frame plate|drill] [--depth MM] [--material TEXT]
                      [--thickness MM] [--fasteners MM] [--base-plate] [--bore-key keyway|flat]

``--pdf`` writes a drawing sheet per element (every element with parts unless ``--element``
is given) through a renderer the caller supplies (:data:`PDF_WRITER`: the ``mechsketch``
launcher sets Qt's; core never imports Qt).

An option that does not apply to the element (``--depth`` for a Geneva drive, ``--arcs`` for an
SVG) is refused, not ignored, and so is a size that is not a positive number.

The part builders (shapely) and the writers (ezdxf) are imported by the functions that use them:
building the parser, which every command does, imports neither.
"""
from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING, Callable

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
                ("depth", "--depth"), ("frame", "--frame"), ("kerf", "--kerf"), ("arcs_entities", "--arcs entities"),
                ("annotate", "--annotate"), ("fasteners", "--fasteners"), ("base_plate", "--base-plate"), ("bore_key", "--bore-key"))


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
    out.add_argument("--pdf", metavar="PATH", help="write a drawing sheet (A4/A3) per element: the parts to scale, "
                     "dimensioned, with a title block and the analysis summary (needs Qt: the 'mechsketch' command)")
    e.add_argument("--material", metavar="TEXT", help="PDF: the title block's material field (default blank)")
    e.add_argument("--thickness", type=float, metavar="MM", help="PDF: the title block's thickness field")
    e.add_argument("--layout", choices=LAYOUTS, default="apart",
                   help="apart: parts side by side, named (default); assembled: in the mechanism's pose")
    e.add_argument("--parts", metavar="P,...", help="only these parts (names as in the report)")
    e.add_argument("--split", action="store_true", help="one file per part: PATH_NAME.ext")
    e.add_argument("--arcs", choices=ARC_STYLES, default=None,
                   help="DXF: bulge polylines (default) or LINE/ARC entities for older CAM readers")
    e.add_argument("--annotate", action="store_true",
                   help="add part names and traced curves on NOTES_* layers (default: cut geometry only)")
    e.add_argument("--kerf", type=float, default=None, metavar="MM",
                   help="write the tool paths of a cut this wide: outlines kerf/2 outside, holes kerf/2 inside")
    e.add_argument("--tolerance", type=float, default=None, metavar="MM",
                   help=f"largest deviation of fitted curves (rolling profiles, coupler curves; default {DEFAULT_TOLERANCE:g})")
    e.add_argument("--min-web", dest="min_web", type=float, metavar="MM",
                   help="thinnest web every part must keep (default: the element's drawing.min_web or 1)")
    e.add_argument("--boss-radius", dest="boss_radius", type=float, metavar="MM", help="linkage plates")
    e.add_argument("--bore-diameter", dest="bore_diameter", type=float, metavar="MM", help="linkage bores")
    e.add_argument("--link-width", dest="link_width", type=float, metavar="MM", help="binary link bar width")
    e.add_argument("--frame", choices=("plate", "drill"), default=None,
                   help="a linkage's frame as a plate or as the drilling pattern of its pivots")
    e.add_argument("--depth", type=float, metavar="MM", help="rolling-lever frame and slider plates")
    e.add_argument("--fasteners", type=float, metavar="MM", help="rolling lever: fastener holes of this diameter in the "
                   "frame and slider plates (2 each), matched in the frame's drilling pattern or base plate")
    e.add_argument("--bore-key", dest="bore_key", choices=("keyway", "flat"), default=None,
                   help="key the shaft bores (Geneva wheel and crank, a linkage's driver): a DIN 6885 keyway or a flat")
    e.add_argument("--base-plate", dest="base_plate", action="store_const", const=True, default=None,
                   help="rolling lever: a base plate carrying every pivot (and the frame plate's fasteners) "
                        "instead of the drilling pattern")
    return e


#: export option (PartOptions field) -> its flag, for the options that only some elements take
ELEMENT_FLAGS = {"boss_radius": "--boss-radius", "bore_diameter": "--bore-diameter", "link_width": "--link-width",
                 "frame": "--frame", "depth": "--depth", "tolerance": "--tolerance", "fasteners": "--fasteners",
                 "base_plate": "--base-plate", "bore_key": "--bore-key"}


def options_of(args: argparse.Namespace) -> PartOptions:
    """The part options of parsed ``export`` arguments."""
    from ..analyses.parts.build import PartOptions

    return PartOptions(tolerance=args.tolerance if args.tolerance is not None else DEFAULT_TOLERANCE,
                       min_web=args.min_web, boss_radius=args.boss_radius, bore_diameter=args.bore_diameter,
                       link_width=args.link_width, frame=args.frame or "plate", depth=args.depth,
                       fasteners=args.fasteners, base_plate=bool(args.base_plate), bore_key=args.bore_key,
                       vocabulary=export_vocabulary())


def refuse_what_does_not_apply(el, args: argparse.Namespace) -> None:
    """:class:`RequestError` naming every option given that the element's parts or the format do
    not use, and every size that is not a positive number (none is ignored or clamped)."""
    import math

    from ..analyses.parts.build import applicable_options

    fits = applicable_options(el)
    wrong = [flag for field, flag in ELEMENT_FLAGS.items() if getattr(args, field) is not None and field not in fits]
    if wrong:
        what = f"element {el.id!r} ({el.type})"
        hint = (" (a linkage's coupler curves are fitted only where it has a joint on one moving link)"
                if "--tolerance" in wrong and el.type == "linkage" else "")
        raise RequestError(f"{', '.join(wrong)} do{'es' if len(wrong) == 1 else ''} not apply to {what}{hint}; "
                           f"it takes {', '.join(sorted(ELEMENT_FLAGS[f] for f in fits if f in ELEMENT_FLAGS)) or 'none of the plate options'}")
    if args.arcs is not None and args.dxf is None:
        raise RequestError("--arcs applies to DXF only (an SVG writes its arcs as SVG arcs)")
    if args.tolerance is not None and not args.annotate and el.type == "linkage":
        raise RequestError("--tolerance applies to the traced coupler curves, which are written only with --annotate")
    for flag, value, zero_ok in (("--tolerance", args.tolerance, False), ("--min-web", args.min_web, True),
                                 ("--kerf", args.kerf, True), ("--boss-radius", args.boss_radius, False),
                                 ("--bore-diameter", args.bore_diameter, True), ("--link-width", args.link_width, False),
                                 ("--depth", args.depth, False), ("--fasteners", args.fasteners, False)):
        if value is not None and not (math.isfinite(value) and (value >= 0 if zero_ok else value > 0)):
            raise RequestError(f"{flag} must be a {'non-negative' if zero_ok else 'positive'} number of millimetres; "
                               f"got {value:g}")


def _plan(ws: Workspace, el):
    from ..model.linkage import Linkage

    return ws.plan(el.id) if isinstance(el, Linkage) else None


#: ``write(pages, path, title)`` of a PDF renderer (``mechsketch.gui.drawing_pdf.write_pdf``), set
#: by the launcher; None: ``--pdf`` is refused with what to run instead
PDF_WRITER: Callable[..., None] | None = None


def run_export(ws: Workspace, args: argparse.Namespace, handler: Callable | None = None) -> str:
    """Build, check and write the parts; returns the report. ``handler(element, command)``: the
    CLI's command lookup (``--pdf`` takes the analysis summary from ``analyze``)."""
    from ..analyses.parts.build import element_parts, min_web_of
    from ..io.export_parts import export_parts

    if getattr(args, "pdf", None) is not None:
        return run_drawing(ws, args, handler)
    for flag, value in (("--material", getattr(args, "material", None)), ("--thickness", getattr(args, "thickness", None))):
        if value is not None:
            raise RequestError(f"{flag} applies to --pdf only (a cut file has no title block)")
    scene = ws.scene
    if args.element is not None:
        el = scene.element(args.element)
    elif scene.elements:
        el = scene.elements[0]
        if len(scene.elements) > 1:
            print(f"note: using element {el.id!r} (choose with --element ID)", file=sys.stderr)
    else:
        raise RequestError("the scene has no element to export")
    refuse_what_does_not_apply(el, args)
    opts = options_of(args)
    names = [n.strip() for n in args.parts.split(",") if n.strip()] if args.parts else None
    ps = element_parts(el, opts, _plan(ws, el))
    fmt, path = ("dxf", args.dxf) if args.dxf is not None else ("svg", args.svg)
    return export_parts(ps, path, fmt, args.layout, names, args.split, args.arcs or "bulge", min_web_of(el, opts),
                        opts.vocabulary, annotate=args.annotate, kerf=args.kerf or 0.0).report


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


def analysis_summary(ws: Workspace, el, handler: Callable | None) -> list[str]:
    """The lines of the element's analysis summary (``analyze``, with the forces of a loaded
    linkage; ``synthesize`` for a rolling lever), or one line saying why there is none."""
    from ..errors import MechsketchError

    if handler is None:
        return []
    commands = ["analyze_forces", "analyze", "synthesize"] if getattr(el, "loads", ()) else ["analyze", "synthesize"]
    for command in commands:
        try:
            return handler(el, command)(ws, el.id).summary.splitlines()
        except MechsketchError as exc:
            last = str(exc)
    return [f"no analysis: {last}"]


def run_drawing(ws: Workspace, args: argparse.Namespace, handler: Callable | None = None) -> str:
    """``export --pdf``: a drawing sheet per element (see the module docstring); the report."""
    from pathlib import Path

    from ..analyses.parts import require_checked
    from ..analyses.parts.build import element_parts, min_web_of
    from ..errors import GeometryError
    from ..io.drawing_sheet import drawing_page

    if PDF_WRITER is None:
        raise RequestError("--pdf needs Qt's PDF writer: run it with the 'mechsketch' command (mechsketch export "
                           "SCENE --pdf PATH), which has the desktop app's libraries")
    refuse = [f for f, v in (("--arcs", args.arcs), ("--kerf", args.kerf), ("--split", args.split or None),
                             ("--annotate", args.annotate or None), ("--parts", args.parts)) if v is not None]
    if refuse or args.layout != "apart":
        raise RequestError(f"{', '.join(refuse) or '--layout assembled'} do not apply to --pdf (the sheet draws "
                           "every part flat, dimensioned)")
    if args.thickness is not None and not (math.isfinite(args.thickness) and args.thickness > 0):
        raise RequestError(f"--thickness must be a positive number of millimetres; got {args.thickness:g}")
    els = [ws.scene.element(args.element)] if args.element is not None else \
        [e for e in ws.scene.elements if e.type != "underlay"]
    if not els:
        raise RequestError("the scene has no element to draw")
    sets, skipped = [], []
    for el in els:
        if args.element is not None:
            refuse_what_does_not_apply(el, args)
        opts = options_of(args)
        try:
            ps = element_parts(el, opts, _plan(ws, el))
        except GeometryError as exc:
            if args.element is not None or "no parts" not in str(exc):
                raise
            skipped.append(f"  {el.id}: no sheet ({exc})")
            continue
        require_checked(ps, min_web_of(el, opts), opts.vocabulary)
        sets.append((el, ps))
    if not sets:
        raise RequestError("no element of the scene has parts to draw")
    pages = [drawing_page(ps, Path(args.scene).name, analysis_summary(ws, el, handler), args.material or "",
                          f"{args.thickness:g}" if args.thickness else "", sheet=(k + 1, len(sets)))
             for k, (el, ps) in enumerate(sets)]
    PDF_WRITER(pages, args.pdf, f"{Path(args.scene).name}: drawing")
    lines = [f"wrote {args.pdf}: {len(pages)} drawing sheet(s), landscape, millimetres"]
    for page, (el, ps) in zip(pages, sets):
        lines.append(f"  {el.id}: {page.paper} at {page.scale_text}, {len(ps.parts)} part(s), "
                     f"{len(page.dimensions)} dimension(s)")
    return "\n".join(lines + skipped)
