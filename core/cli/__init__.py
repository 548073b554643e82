"""Headless command line: ``mechsketch analyze|validate|export|synthesize|centrodes SCENE ...``.

Every number the GUI shows can be reproduced here: both read their results from the same
:class:`~mechsketch.core.workspace.Workspace`. Element types plug in through :data:`HANDLERS`: a
module per type with the functions a command needs (see ``_handler``).
Exit status: 0 ok, 1 a problem with the scene or the request (message on stderr), 2 usage.

Start-up (issue 14): this module imports only argparse and the errors; each command imports what
it uses when it runs (the scene reader, the workspace, the CSV writer; ``export`` the part
builders, shapely and ezdxf), so ``analyze --summary`` pays for no drawing or DXF code.
"""
from __future__ import annotations

import argparse
import importlib
import os
import sys
from typing import TYPE_CHECKING, Any, Callable, Sequence

from ..errors import MechsketchError, Problem, StructureError
from ..runtime import tune_allocator
from .design_cmds import add_design_parser
from .export_cmds import add_export_parser
from .study_cmds import add_study_parser

if TYPE_CHECKING:  # pragma: no cover
    from ..workspace import Workspace

#: element type -> module implementing its commands, each taking the workspace and the element id:
#: ``analyze(ws, id) -> Analysis`` (samples: the workspace's override), ``synthesize(ws, id) ->
#: Analysis``, ``centrodes(ws, id, link, relative_to, samples) -> Table``. ``export`` works for
#: every element type (core/cli/export_cmds.py).
HANDLERS: dict[str, str] = {
    "linkage": "mechsketch.core.cli.linkage_cmds",
    "geneva": "mechsketch.core.cli.geneva_cmds",
    "rolling_lever": "mechsketch.core.cli.rolling_cmds",
    "gear_pair": "mechsketch.core.cli.gears_cmds",
    "geared_geneva": "mechsketch.core.cli.gears_cmds",
}


#: a handler function -> the command as the user types it (messages never name a function)
COMMAND_WORDS: dict[str, str] = {"analyze": "mechsketch analyze", "analyze_forces": "mechsketch analyze --forces",
                                 "synthesize": "mechsketch synthesize", "centrodes": "mechsketch centrodes",
                                 "centrodes_dxf": "mechsketch centrodes --dxf"}


class CliError(MechsketchError, ValueError):
    """A request the CLI cannot carry out (unknown element, command not for this type)."""


def _kind_words(element_type: str) -> str:
    """An element type in words (``rolling_lever`` -> ``rolling lever``)."""
    return {"geneva": "Geneva drive", "geared_geneva": "geared Geneva drive"}.get(element_type,
                                                                                   element_type.replace("_", " "))


def _commands_for(element_type: str) -> list[str]:
    """The commands that apply to an element type, as typed (``export`` applies to every type)."""
    name = HANDLERS.get(element_type)
    module = importlib.import_module(name) if name else None
    return [words for fn, words in COMMAND_WORDS.items() if hasattr(module, fn)] + ["mechsketch export"]


def _handler(element: Any, command: str):
    name = HANDLERS.get(element.type)
    module = importlib.import_module(name) if name else None
    fn = getattr(module, command, None) if module else None
    if fn is None:
        *others, last = _commands_for(element.type)
        use = f"{', '.join(others)} or {last}" if others else last
        raise CliError(f"{COMMAND_WORDS[command]} does not apply to the {_kind_words(element.type)} "
                       f"{element.id!r}; for it use {use}")
    return fn


def _pick(scene, element_id: str | None, command: str):
    if element_id is not None:
        try:
            return scene.element(element_id)
        except KeyError as exc:
            raise CliError(exc.args[0]) from None
    for e in scene.elements:
        module = importlib.import_module(HANDLERS[e.type]) if e.type in HANDLERS else None
        if module is not None and hasattr(module, command):
            if len(scene.elements) > 1:
                print(f"note: using element {e.id!r} (choose with --element ID)", file=sys.stderr)
            return e
    raise CliError(f"the scene has no element that {COMMAND_WORDS[command]} applies to")


def _emit(analysis, csv_target: str | None, summary: bool) -> None:
    """Write the table and/or the summary; the summary goes to stderr when the CSV is on stdout."""
    from ..io.table import write_csv

    if csv_target is not None:
        write_csv(analysis.table, csv_target)
    if summary or csv_target is None:
        out = sys.stderr if csv_target == "-" else sys.stdout
        print(analysis.summary, file=out)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="mechsketch", description="Planar mechanism CAD. With no command: open the "
                                "desktop app on a built-in example.")
    sub = p.add_subparsers(dest="command")
    a = sub.add_parser("analyze", help="solve over one driver revolution; CSV table and/or summary")
    a.add_argument("scene")
    a.add_argument("--element", metavar="ID")
    a.add_argument("--samples", type=int, metavar="N")
    a.add_argument("--csv", metavar="PATH|-")
    a.add_argument("--summary", action="store_true")
    a.add_argument("--forces", action="store_true",
                   help="add the driving torque (a linear actuator: its force), joint reactions and "
                        "shaking force/moment (N, N·m) "
                        "to the table and the summary")
    v = sub.add_parser("validate", help="list the problems of a scene file (exit 0 when it can be analysed) "
                                        "and, as warnings, why its parts cannot be cut")
    v.add_argument("scene")
    v.add_argument("--strict", action="store_true",
                   help="manufacturability warnings are errors (exit 1): the scene must be cut-ready too")
    add_export_parser(sub)
    s = sub.add_parser("synthesize", help="synthesise rolling profiles (rolling_lever)")
    s.add_argument("scene")
    s.add_argument("--element", metavar="ID")
    s.add_argument("--csv", metavar="PATH|-")
    s.add_argument("--summary", action="store_true")
    c = sub.add_parser("centrodes", help="instant centres and centrodes of a linkage link")
    c.add_argument("scene")
    c.add_argument("--element", metavar="ID")
    c.add_argument("--link", required=True)
    c.add_argument("--relative-to", dest="relative_to", default=None, metavar="L")
    c.add_argument("--samples", type=int, metavar="N")
    out = c.add_mutually_exclusive_group(required=True)
    out.add_argument("--csv", metavar="PATH|-", help="the instant centres per sample (input, P, p, valid)")
    out.add_argument("--dxf", metavar="PATH", help="both centrodes as arc-fitted curves (the pitch curves)")
    c.add_argument("--tolerance", type=float, metavar="MM", help="DXF: largest deviation of the arcs (default 0.01)")
    add_design_parser(sub)
    add_study_parser(sub)
    o = sub.add_parser("open", help="open a scene file in the desktop app")
    o.add_argument("scene", nargs="?")
    return p


def _structure_problems(ws: Workspace) -> list[Problem]:
    """Linkages that load but cannot be solved (mobility, higher-class group, no driver yet)."""
    from ..model.linkage import Linkage

    out = []
    for k, el in enumerate(ws.scene.elements):
        if isinstance(el, Linkage):
            try:
                ws.plan(el.id)
            except StructureError as exc:
                who = ", ".join(exc.joints) if exc.joints else None
                out.append(Problem(f"$.elements[{k}]", str(exc) + (f" [joints {who}]" if who else ""), el.id))
    return out


MAX_SAMPLES = 1_000_000
#: the heading of validate's warnings
MANUFACTURABILITY = ("manufacturability warnings (the scene can be analysed; its cut-ready parts cannot be cut "
                     "with the sizes in force, and export refuses them until these are changed):")


def _validate(args: argparse.Namespace) -> int:
    """``validate``: problems that stop an analysis are errors (exit 1); reasons the parts cannot
    be cut are warnings in a section of their own (exit 0), errors with ``--strict``."""
    from ..io.scene_file import load_scene, validate_file
    from ..workspace import Workspace
    from .export_cmds import drawing_warnings

    problems, warnings, motion = validate_file(args.scene), [], []
    if not problems:
        ws = Workspace(load_scene(args.scene))
        problems = _structure_problems(ws)
        warnings = drawing_warnings(ws)
        if not problems:
            from .linkage_cmds import kinematic_warnings   # the solver's findings: every analysis still runs

            motion = kinematic_warnings(ws)
    if args.strict:
        problems, warnings = problems + warnings, []
    for prob in problems:
        print(prob)
    if not problems:
        print(f"{args.scene}: ok")
        for warning in motion:
            print(warning)
    if warnings:
        print(MANUFACTURABILITY)
        for w in warnings:
            print(f"  {w}")
    return 0 if not problems else 1



def single_blas_thread() -> bool:
    """Ask OpenBLAS for one thread (``OPENBLAS_NUM_THREADS=1``) unless the user set it, before
    numpy is loaded (True if set here). mechsketch's arrays are worked on elementwise and its linear
    solves are small, so BLAS threads never help it; but OpenBLAS starts one per core when numpy
    is imported and they spin meanwhile: on a 2-core machine that cost ``analyze --summary`` 0.06 s
    of its 0.21 s (benchmarks/bench_cli.py, issue 14). Called first by the entry points."""
    if "numpy" in sys.modules or "OPENBLAS_NUM_THREADS" in os.environ:
        return False
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    return True


def run(args: argparse.Namespace) -> int:
    """Run a parsed headless command; returns the exit status."""
    from ..io.scene_file import load_scene, validate_file
    from ..workspace import Workspace

    if args.command == "study":
        from .study_cmds import run as run_study

        return run_study(args)
    if args.command == "design":
        from .design_cmds import run_design

        return run_design(args)
    if args.command == "validate":
        return _validate(args)
    samples = getattr(args, "samples", None)   # analyze, centrodes: one check for both
    if samples is not None and not 2 <= samples <= MAX_SAMPLES:
        raise CliError(f"--samples must be from 2 to {MAX_SAMPLES:,}, got {samples:,}")
    ws = Workspace(load_scene(args.scene))
    scene = ws.scene
    if args.command == "analyze":
        command = "analyze_forces" if args.forces else "analyze"
        el = _pick(scene, args.element, command)
        ws.samples = args.samples
        _emit(_handler(el, command)(ws, el.id), args.csv, args.summary)
    elif args.command == "export":
        from .export_cmds import run_export

        print(run_export(ws, args, _handler))
    elif args.command == "synthesize":
        el = _pick(scene, args.element, "synthesize")
        _emit(_handler(el, "synthesize")(ws, el.id), args.csv, args.summary)
    elif args.command == "centrodes":
        from ..io.table import write_csv

        el = _pick(scene, args.element, "centrodes")
        if args.dxf is not None:
            print(_handler(el, "centrodes_dxf")(ws, el.id, args.link, args.relative_to, args.samples, args.dxf,
                                                args.tolerance))
        else:
            if args.tolerance is not None:
                raise CliError("--tolerance applies to --dxf only (the CSV lists the exact centres)")
            write_csv(_handler(el, "centrodes")(ws, el.id, args.link, args.relative_to, args.samples), args.csv)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the headless commands (``mechsketch.gui.launcher`` adds the app)."""
    single_blas_thread()   # before numpy is imported
    tune_allocator()   # before any array is allocated (core/runtime.py); once per process
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command in (None, "open"):
        parser.error("the desktop app is started by the 'mechsketch' launcher, not by the headless CLI")
    try:
        return run(args)
    except MechsketchError as exc:  # SceneFormatError, StructureError, GeometryError, ExportError...
        print(f"error: {exc}", file=sys.stderr)
        return 1
    except BrokenPipeError:  # e.g. `mechsketch analyze ... --csv - | head`
        return 0

