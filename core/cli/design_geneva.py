"""``mechsketch design geneva REQ.json --out OUT.json [--id ID]``: the smallest Geneva drive
meeting the requirements (:mod:`mechsketch.core.design.geneva`), written as a scene, with a report
of each requirement's value and margin and the binding one; an infeasible set exits 1 naming the
requirement to relax and by how much. With ``"smooth": {...}`` in REQ the drive is driven through
a synthesised non-circular gear pair (:mod:`mechsketch.core.design.smooth_geneva`).
"""
from __future__ import annotations

import argparse

from .design_io import add_common, read_requirements, write_result

HELP = ("size the smallest Geneva drive meeting requirements (slots or dwell, speed, load, contact "
        "stress, wear life, size, web)")


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_common(p, "geneva")


def run(args: argparse.Namespace) -> int:
    from ..design.geneva import design_geneva

    req = read_requirements(args.requirements)
    if isinstance(req, dict) and req.get("smooth") is not None:
        from ..design.smooth_geneva import design_smooth_geneva

        res = design_smooth_geneva(req, args.id)
    else:
        res = design_geneva(req, args.id)
    return write_result((res.element,), args.out, res.report.text())
