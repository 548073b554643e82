"""``mechsketch design rolling REQ.json --out OUT.json [--id ID]``: a rolling lever whose slider
follows a prescribed law S5(θ) (:mod:`mechsketch.core.design.rolling`): the lever element and the
slider profile are the exact centrodes of the relative motion; the report states pure rolling,
S5 reproduced, no cusp or fold, the working side and the parts' web, each with its margin.
"""
from __future__ import annotations

import argparse

from .design_io import add_common, read_requirements, write_result

HELP = "a rolling lever whose slider follows a prescribed law S5(θ) (exact centrodes of pair E)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p, "lever")


def run(args: argparse.Namespace) -> int:
    from ..design.rolling import design_rolling

    res = design_rolling(read_requirements(args.requirements), args.id)
    return write_result((res.element,), args.out, res.report.text())
