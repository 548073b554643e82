"""``mechsketch design gears REQ.json --out OUT.json [--id ID]``: a non-circular gear pair whose
pitch curves (the exact centrodes) realise a required transmission function at a centre distance
(:mod:`mechsketch.core.design.gears`); the report gives the centre distance and ratio achieved,
closure, pure rolling, curvature, pressure swing and the blanks' web, each with its margin.
"""
from __future__ import annotations

import argparse

from .design_io import add_common, read_requirements, write_result

HELP = "non-circular gear pitch curves from a required transmission function ψ(φ) and centre distance"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p, "gears")


def run(args: argparse.Namespace) -> int:
    from ..design.gears import design_gears

    res = design_gears(read_requirements(args.requirements), args.id)
    return write_result((res.element,), args.out, res.report.text())
