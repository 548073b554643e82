"""CLI handlers for gear pairs and Geneva drives driven through gears: ``analyze`` (the per-sample
table and the summary); ``export`` (core/cli/export_cmds.py) writes their parts (the pitch-curve
blanks; for a geared Geneva the drive's four parts and both blanks)."""
from __future__ import annotations

from ..analyses.gears.report import gear_table
from ..analyses.geneva.driven_report import geared_table
from ..workspace import GearedGenevaResult, Workspace
from .analysis import Analysis


def analyze(ws: Workspace, element_id: str) -> Analysis:
    """A gear pair: the gear table; a geared Geneva: the drive's table with the gears' input angle,
    ratio and the input torque. Raises the core's error when the element cannot be analysed."""
    res = ws.result(element_id)
    if isinstance(res, GearedGenevaResult):
        if res.kinematics is None or res.contact is None or res.gears is None:
            raise res.exception
        return Analysis(geared_table(res.kinematics, res.contact, res.gears.kinematics, res.input_torque), res.summary)
    if res.kinematics is None:
        raise res.exception
    return Analysis(gear_table(res.kinematics), res.summary)


#: the geared Geneva's table already holds the driving torque (on the gears' input)
analyze_forces = analyze
