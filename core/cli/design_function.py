"""``mechsketch design function PAIRS.csv --out OUT.json``: a four-bar whose rocker angle
(columns ``input_deg,output_deg``) or a slider-crank whose slider position (``input_deg,
output_mm``) follows the pairs, both measured from the first row; exact for 3 pairs
(Freudenstein), least squares for more. Each candidate's output link is ``output``."""
from __future__ import annotations

import argparse

HELP = "a four-bar (input_deg,output_deg) or slider-crank (input_deg,output_mm) following input-output pairs"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from .design_args import add_common

    p.add_argument("pairs", metavar="PAIRS.csv", help="columns input_deg,output_deg or input_deg,output_mm")
    p.add_argument("--topology", choices=("fourbar", "slider_crank"), default=None,
                   help="default: fourbar for output_deg, slider_crank for output_mm")
    p.add_argument("--size", type=float, default=None, metavar="MM", help="a four-bar's ground length (default 100)")
    add_common(p)


def run(args: argparse.Namespace) -> int:
    from ..design.function import synthesize_function
    from ..design.targets import DesignError, function_target
    from .design_linkage import check_writable, options_from, read_columns, stderr_progress, write_result

    options = options_from(args)
    check_writable(args.out)
    try:
        cols = read_columns(args.pairs, ("input_deg", "output_deg"))
        unit = "deg"
    except DesignError as first:
        try:
            cols = read_columns(args.pairs, ("input_deg", "output_mm"))
        except DesignError:
            raise first from None
        unit = "mm"
    topology = args.topology or ("fourbar" if unit == "deg" else "slider_crank")
    target = function_target(list(zip(cols["input_deg"], cols[f"output_{unit}"])), unit)
    result = synthesize_function(target, options, topology, args.size, stderr_progress())
    return write_result(result, args.out)
