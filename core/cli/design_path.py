"""``mechsketch design path TARGET.csv --out OUT.json``: linkages whose coupler point ``P``
traces a path (columns ``x,y`` in mm, optionally ``input_deg`` for a timed path: the crank angle
at each point from the first). Closed by default (``--open`` for an arc). Candidates come from
the atlas of each topology asked for (built on first use, kept in the user cache folder),
aligned, refined by least squares and checked by the solver."""
from __future__ import annotations

import argparse

HELP = "linkages whose coupler point traces a path (x, y; optional input_deg)"
TOPOLOGIES = ("fourbar", "slider_crank", "inverted_slider_crank", "sixbar", "any")


def add_arguments(p: argparse.ArgumentParser) -> None:
    from .design_args import add_common

    p.add_argument("target", metavar="TARGET.csv", help="columns x,y (mm) [,input_deg]")
    p.add_argument("--topology", choices=TOPOLOGIES, default="fourbar",
                   help="default: fourbar (sixbar: the six six-bar atlases; any: all nine, each built on first use)")
    p.add_argument("--open", action="store_true", help="the path is an open arc (default: a closed loop)")
    p.add_argument("--atlas-designs", type=int, default=None, metavar="N",
                   help="atlas size per topology (default 1,000,000; built on first use)")
    add_common(p)


def run(args: argparse.Namespace) -> int:
    from ..design.linkage_path import synthesize_path
    from ..design.targets import DesignError, path_target
    from .design_linkage import check_writable, options_from, read_columns, stderr_progress, write_result

    options = options_from(args)
    if args.atlas_designs is not None and not 1_000 <= args.atlas_designs <= 100_000_000:
        raise DesignError(f"--atlas-designs must be from 1,000 to 100,000,000, got {args.atlas_designs:,}")
    check_writable(args.out)
    cols = read_columns(args.target, ("x", "y"), ("input_deg",))
    target = path_target(list(zip(cols["x"], cols["y"])), closed=not args.open, inputs_deg=cols.get("input_deg"))
    result = synthesize_path(target, options, args.topology, stderr_progress(), args.atlas_designs)
    return write_result(result, args.out)
