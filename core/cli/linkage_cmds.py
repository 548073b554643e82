"""CLI handlers for linkage elements: ``analyze`` (CSV table + summary), ``analyze --forces``
(the same table with the force columns, and the forces summary) and ``centrodes``."""
from __future__ import annotations

import numpy as np

from ..analyses.centrodes import linkage_centrodes
from ..analyses.forces_report import force_summary, force_table
from ..analyses.table import Table
from ..model.linkage import Linkage
from ..workspace import Workspace
from . import Analysis


def analysis_table(linkage: Linkage, sol) -> Table:
    """Columns: t, input, per joint J.x J.y J.vx J.vy J.ax J.ay, per moving link K.angle K.omega
    K.alpha, valid (mm, mm/s, mm/s², rad, rad/s, rad/s²; 1/0)."""
    cols: dict[str, np.ndarray] = {"t": sol.t, "input": sol.input}
    for j in linkage.joint_ids:
        p, v, a = sol.position(j), sol.velocity(j), sol.acceleration(j)
        for name, arr in (("x", p[:, 0]), ("y", p[:, 1]), ("vx", v[:, 0]), ("vy", v[:, 1]),
                          ("ax", a[:, 0]), ("ay", a[:, 1])):
            cols[f"{j}.{name}"] = arr
    for k in linkage.moving_links:
        cols[f"{k}.angle"] = sol.angle(k)
        cols[f"{k}.omega"] = sol.omega(k)
        cols[f"{k}.alpha"] = sol.alpha(k)
    cols["valid"] = sol.valid.astype(float)
    return Table.from_columns(cols, integer={"valid"})


def analyze(ws: Workspace, element_id: str) -> Analysis:
    """The workspace's solve of one revolution at order 2 (N: the workspace's sample override,
    else the element's); the table per sample and the diagnostics summary. Raises the core's
    error when the linkage cannot be solved."""
    ws.plan(element_id)   # StructureError / GeometryError with the joints at fault
    res = ws.result(element_id)
    if res.solution is None:
        raise res.exception
    return Analysis(analysis_table(res.element, res.solution), res.summary())


def analyze_forces(ws: Workspace, element_id: str) -> Analysis:
    """:func:`analyze` plus the kinetostatics: the table gains ``driver.torque``, ``J.Fx J.Fy``
    per revolute joint and ``shaking.Fx shaking.Fy shaking.M`` (N, N·m; see
    :mod:`mechsketch.core.analyses.forces_report`); the summary gains the forces summary."""
    base = analyze(ws, element_id)
    res = ws.forces(element_id)
    return Analysis(force_table(res, base.table), base.summary + "\n" + force_summary(res))


def centrodes(ws: Workspace, element_id: str, link: str, relative_to: str | None, samples: int | None
              ) -> Table:
    """Instant centres of ``link`` (relative to the frame or ``relative_to``) as a CSV table."""
    sol = ws.solve(element_id, samples=samples, order=1)
    return linkage_centrodes(sol, ws.element(element_id), link, relative_to).table()
