"""``mechsketch design KIND ...``: a mechanism from what the designer needs.

Each kind of design problem is a module of this package registered in :data:`DESIGN_KINDS`,
defining ``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int`` (the exit
status; problems with the request raise a :class:`~mechsketch.core.errors.MechsketchError`, which
the CLI prints as ``error: ...`` with exit 1). A kind's module imports what it computes with
inside ``run``, so that building the parser, which every command does, stays cheap.
"""
from __future__ import annotations

import argparse
import importlib

#: design kind -> the module implementing it (``mechsketch design KIND --help`` lists its options)
DESIGN_KINDS: dict[str, str] = {
    # linkage synthesis (issue 22): a path, poses, or an input-output function
    "path": "mechsketch.core.cli.design_path",
    "motion": "mechsketch.core.cli.design_motion",
    "function": "mechsketch.core.cli.design_function",
    # from requirements (issue 25): Geneva drives, rolling levers with a slider law, gear pitch curves
    "geneva": "mechsketch.core.cli.design_geneva",
    "rolling": "mechsketch.core.cli.design_rolling",
    "gears": "mechsketch.core.cli.design_gears",
}


def add_design_parser(sub) -> argparse.ArgumentParser:
    """The ``design`` sub-command with one sub-command per registered kind."""
    d = sub.add_parser("design", help="synthesise a mechanism from requirements: "
                       + (", ".join(DESIGN_KINDS) or "no kinds in this build"))
    kinds = d.add_subparsers(dest="design_kind", metavar="KIND")
    kinds.required = True
    for kind, name in DESIGN_KINDS.items():
        module = importlib.import_module(name)
        p = kinds.add_parser(kind, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
    return d


def run_design(args: argparse.Namespace) -> int:
    """Run ``mechsketch design KIND ...`` (parsed); returns the exit status."""
    return importlib.import_module(DESIGN_KINDS[args.design_kind]).run(args)
