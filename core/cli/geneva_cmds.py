"""CLI handlers for Geneva drives: ``analyze`` (kinematics + contact/wear table and summary) and
its parts are written by ``export`` (core/cli/export_cmds.py)."""
from __future__ import annotations

import numpy as np

from ..analyses.geneva.report import COLUMNS, analysis_table, summary
from ..analyses.geneva.torque import crank_torque
from ..analyses.table import Table
from ..workspace import Workspace
from .analysis import Analysis

__all__ = ["COLUMNS", "analysis_table", "analyze", "analyze_forces", "summary"]  # the table and text live in analyses


def analyze(ws: Workspace, element_id: str) -> Analysis:
    """Kinematics and contact/wear over one crank revolution (the workspace's result): the table
    and its summary. Raises the core's error when the drive cannot be analysed."""
    res = ws.result(element_id)
    if res.kinematics is None or res.contact is None:
        raise res.exception
    return Analysis(analysis_table(res.kinematics, res.contact), res.summary)


def analyze_forces(ws: Workspace, element_id: str) -> Analysis:
    """:func:`analyze` plus the crank torque from the contact model (``driver.torque``, N·m,
    counter-clockwise positive; see :mod:`mechsketch.core.analyses.geneva.torque`)."""
    base = analyze(ws, element_id)
    res = ws.result(element_id)
    tq = crank_torque(res.element, res.contact)
    table = Table(base.table.columns + ["driver.torque"],
                  np.column_stack([base.table.data, tq.torque]), set(base.table.integer))
    text = (f"crank torque (contact model, N·m, CCW +): peak {tq.peak:.6g} at φ "
            f"{np.degrees(tq.phi_peak):.2f}°, RMS {tq.rms:.6g}")
    return Analysis(table, lambda: base.summary + "\n" + text)


