"""CLI handlers for Geneva drives: ``analyze`` (kinematics + contact/wear table and summary) and
``export`` (DXF of the wheel and the driver)."""
from __future__ import annotations

from ..analyses.geneva_report import COLUMNS, analysis_table, summary
from ..io.dxf_geneva import export_geneva
from ..workspace import Workspace
from . import Analysis

__all__ = ["COLUMNS", "analysis_table", "analyze", "export", "summary"]  # the table and text live in analyses


def analyze(ws: Workspace, element_id: str) -> Analysis:
    """Kinematics and contact/wear over one crank revolution (the workspace's result): the table
    and its summary. Raises the core's error when the drive cannot be analysed."""
    res = ws.result(element_id)
    if res.kinematics is None or res.contact is None:
        raise res.exception
    return Analysis(analysis_table(res.kinematics, res.contact), res.summary())


def export(ws: Workspace, element_id: str, path: str, tolerance: float) -> str:
    """Write the wheel and the driver as DXF (exact arcs: ``tolerance`` is not needed)."""
    return export_geneva(ws.element(element_id), path)
