"""The command-line options every ``mechsketch design path|motion|function`` takes (argparse
only: building the parser, which every command does, stays cheap; what they mean is in
:class:`~mechsketch.core.design.options.LinkageOptions`)."""
from __future__ import annotations

import argparse


def add_common(p: argparse.ArgumentParser) -> None:
    """The options every linkage synthesis takes."""
    p.add_argument("--out", required=True, metavar="OUT.json", help="the scene of the candidates, best first")
    p.add_argument("--candidates", type=int, default=5, metavar="K", help="how many candidates (default 5)")
    p.add_argument("--min-transmission", type=float, default=30.0, metavar="DEG",
                   help="least transmission angle over the target span, degrees (default 30)")
    p.add_argument("--full-turn", action="store_true", help="the crank must turn fully")
    p.add_argument("--grashof", choices=("crank-rocker", "double crank"), default=None,
                   help="the four-bar type asked for")
    p.add_argument("--pivot-region", metavar="XMIN,YMIN,XMAX,YMAX", default=None,
                   help="the fixed pivots must lie in this rectangle (mm)")
    p.add_argument("--max-size", type=float, default=5.0, metavar="F",
                   help="fixed pivots within F target sizes of the target, links no longer (default 5)")
    p.add_argument("--max-deviation", type=float, default=None, metavar="E",
                   help="refuse candidates deviating more than E from the target (mm; for a function the "
                        "output's unit); default: the best that can be had")
    p.add_argument("--rpm", type=float, default=60.0, help="the candidates' crank speed (default 60)")


__all__ = ["add_common"]
