"""CLI handlers for Geneva drives: ``analyze`` (kinematics + contact/wear table and summary) and
``export`` (DXF of the wheel and the driver)."""
from __future__ import annotations

from ..analyses.geneva_contact import contact
from ..analyses.geneva_kinematics import kinematics
from ..analyses.geneva_report import COLUMNS, analysis_table, summary
from ..model.geneva import Geneva
from . import Analysis

__all__ = ["COLUMNS", "analysis_table", "analyze", "export", "summary"]  # the table and text live in analyses


def analyze(element: Geneva, samples: int | None) -> Analysis:
    """Kinematics and contact/wear over one crank revolution: the table and its summary."""
    n = samples or element.samples
    kin = kinematics(element, n)
    con = contact(element, n, element.model)
    return Analysis(analysis_table(kin, con), summary(element, kin, con))


def export(element: Geneva, path: str, tolerance: float) -> str:
    """Write the wheel and the driver as DXF (exact arcs: ``tolerance`` is not needed)."""
    from ..io.dxf_geneva import export_geneva

    return export_geneva(element, path)
