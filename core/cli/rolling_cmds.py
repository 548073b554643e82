"""CLI handlers for rolling-lever elements: ``synthesize`` (CSV table + summary); ``export`` (core/cli/export_cmds.py) writes its plates.

``synthesize`` columns: theta alpha F.x F.y P.x P.y u1 P0.x P0.y u2 k53 S5 Q.x Q.y (mm, rad, mm/rad
for k53; Q in the slider frame), one row per stroke sample k = 0…N of the element's method.
"""
from __future__ import annotations

from ..workspace import Workspace
from .analysis import Analysis


def synthesize(ws: Workspace, element_id: str) -> Analysis:
    """The element's profiles synthesised with its method and N (the workspace's result, with the
    slip measures): table and summary. Raises the core's error when the synthesis fails."""
    res = ws.result(element_id)
    if res.synthesis is None:
        raise res.exception
    return Analysis(res.synthesis.table(), res.summary)

