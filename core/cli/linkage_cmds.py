"""CLI handlers for linkage elements: ``analyze`` (CSV table + summary), ``analyze --forces``
(the same table with the force columns, and the forces summary), ``centrodes``, and the
kinematic warnings ``validate`` prints (:func:`kinematic_warnings`)."""
from __future__ import annotations

import math
import sys
from typing import TYPE_CHECKING

import numpy as np

from ..analyses.table import Table
from .analysis import Analysis

if TYPE_CHECKING:  # pragma: no cover
    from ..model.linkage import Linkage
    from ..workspace import Workspace


RATE_COLUMNS = ("vx", "vy", "ax", "ay", "omega", "alpha")


def analysis_table(linkage: Linkage, sol) -> Table:
    """Columns: t, input, per joint J.x J.y J.vx J.vy J.ax J.ay, per moving link K.angle K.omega
    K.alpha, valid, rates_valid (mm, mm/s, mm/s², rad, rad/s, rad/s²; 1/0).

    ``input`` is the driver's input (``Solution.input``): a crank's angle (rad, unwrapped), a
    cylinder's length between its pivots or a slider's displacement along its guide from the
    drawn position (mm); ``t`` the time (s) in the cycle of the driver's motion law.

    ``valid``: the pose is known (every position and angle of the row is a finite number);
    ``rates_valid``: so are its velocities and accelerations (0 at an exact toggle or change point,
    where they are singular, or where they overflow). Fields not covered by the flags are empty."""
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
    rate_names = [c for c in cols if c.rsplit(".", 1)[-1] in RATE_COLUMNS and "." in c]
    pose_names = [c for c in cols if c not in rate_names and c not in ("t", "input")]
    valid = sol.valid.copy()
    for c in pose_names:
        valid &= np.isfinite(cols[c])
    rates = valid & sol.rates_valid
    for c in rate_names:
        rates &= np.isfinite(cols[c])
    for c in pose_names:
        cols[c] = np.where(valid, cols[c], np.nan)
    for c in rate_names:
        cols[c] = np.where(rates, cols[c], np.nan)
    cols["valid"] = valid.astype(float)
    cols["rates_valid"] = rates.astype(float)
    return Table.from_columns(cols, integer={"valid", "rates_valid"})


def analyze(ws: Workspace, element_id: str) -> Analysis:
    """The workspace's solve of one revolution at order 2 (N: the workspace's sample override,
    else the element's); the table per sample and the diagnostics summary. Raises the core's
    error when the linkage cannot be solved."""
    ws.plan(element_id)   # StructureError / GeometryError with the joints at fault
    res = ws.result(element_id)
    if res.solution is None:
        raise res.exception
    return Analysis(analysis_table(res.element, res.solution), res.summary)


def analyze_forces(ws: Workspace, element_id: str) -> Analysis:
    """:func:`analyze` plus the kinetostatics: the table gains ``driver.torque``, ``J.Fx J.Fy``
    per revolute joint and ``shaking.Fx shaking.Fy shaking.M`` (N, N·m; see
    :mod:`mechsketch.core.analyses.forces.report`); the summary gains the forces summary."""
    from ..analyses.forces.report import force_summary, force_table

    base = analyze(ws, element_id)
    res = ws.forces(element_id)
    return Analysis(force_table(res, base.table), lambda: base.summary + "\n" + force_summary(res))


def centrodes(ws: Workspace, element_id: str, link: str, relative_to: str | None, samples: int | None
              ) -> Table:
    """Instant centres of ``link`` (relative to the frame or ``relative_to``) as a CSV table."""
    from ..analyses.centrodes import linkage_centrodes

    from ..io.dxf_centrodes import default_limit

    sol = ws.solve(element_id, samples=samples, order=1)
    el = ws.element(element_id)
    c = linkage_centrodes(sol, el, link, relative_to)
    at = c.point(default_limit(el) / 20.0)
    if at is not None:
        print(f"note: {c.point_message(at)}", file=sys.stderr)
    return c.table()


def centrodes_dxf(ws: Workspace, element_id: str, link: str, relative_to: str | None, samples: int | None,
                  path: str, tolerance: float | None) -> str:
    """Write both centrodes of ``link`` as arc-fitted DXF curves (``tolerance`` mm, default
    0.01; ``samples`` locate the translations, default 720); returns the export's report."""
    from ..io.dxf_centrodes import export_centrodes

    return export_centrodes(ws.plan(element_id), link, relative_to, path,
                            0.01 if tolerance is None else tolerance, samples or 720).report()


def kinematic_warnings(ws: Workspace) -> list[str]:
    """What ``validate`` says of the linkages' motion (warnings: every analysis can still run):
    a PRP or RPP group whose guides turn parallel during the cycle — its blocks run off to
    infinity as the input approaches those poses, so the driver cannot pass them — with the
    inputs (refined between the samples), the reachable ranges and the joints to change."""
    from ..model.drivers import input_text
    from ..model.linkage import Linkage
    from ..solver.diagnostics import PARALLEL_NOTE, DeadPointKind

    out = []
    for el in ws.scene.elements:
        if not isinstance(el, Linkage):
            continue
        res = ws.result(el.id)
        if res is None or res.solution is None:
            continue
        diag = res.diagnostics
        where: dict[str, list[str]] = {}
        for p in diag.dead_points:
            if p.kind is DeadPointKind.LIMIT and p.note == PARALLEL_NOTE:
                x = math.remainder(p.input, 2 * math.pi) if p.unit == "rad" else p.input
                text = input_text(x, p.unit, 2)
                if text not in where.setdefault(p.group, []):
                    where[p.group].append(text)
        for name, inputs in where.items():
            g = next(s.group for s in res.plan.steps if s.group.name == name)
            guides = [j for j in g.joints if el.joint(j).kind.value == "P"]
            ranges = "; ".join(f"{input_text(a, diag.unit, 2)} to {input_text(b, diag.unit, 2)}"
                               for a, b in diag.reachable) or "none"
            out.append(f"warning: linkage {el.id!r}: the guides of {name} turn parallel at input "
                       f"{' and '.join(inputs)}: its blocks run off to infinity there, so the driver "
                       f"cannot pass those inputs (reachable: {ranges}); turn a guide (axis_deg of "
                       f"{' or '.join(guides)}) or change the links that carry them so that the guides "
                       f"stay apart over the cycle")
    return out
