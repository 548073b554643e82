"""CLI handlers for linkage elements: ``analyze`` (CSV table + summary) and ``centrodes``."""
from __future__ import annotations

import numpy as np

from ..analyses.linkage_report import linkage_summary
from ..analyses.table import Table
from ..model.linkage import Linkage
from ..solver.diagnostics import diagnose
from ..solver.plan import compile_plan
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


def analyze(linkage: Linkage, samples: int | None) -> Analysis:
    """Solve one revolution at order 2; table per sample and the diagnostics summary."""
    plan = compile_plan(linkage)
    sol = plan.sweep(samples=samples or linkage.samples, order=2)
    return Analysis(analysis_table(linkage, sol), linkage_summary(linkage, plan, diagnose(sol)))


def centrodes(linkage: Linkage, link: str, relative_to: str | None, samples: int | None) -> Table:
    """Instant centres of ``link`` (relative to the frame or ``relative_to``) as a CSV table."""
    from ..analyses.centrodes import linkage_centrodes

    sol = compile_plan(linkage).sweep(samples=samples or linkage.samples, order=1)
    return linkage_centrodes(sol, linkage, link, relative_to).table()
