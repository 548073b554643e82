"""What a Geneva drive driven through gears reports (``mechsketch analyze`` on a ``geared_geneva``):
the drive's kinematics against the constant-speed crank, its wheel geometry and contact lines
(as :mod:`.report`), the gears' summary, and the torque passed back to the input."""
from __future__ import annotations

import numpy as np

from ..table import Table
from .contact import GenevaContact
from .driven import Smoothness
from .geometry import GenevaGeometry
from .kinematics import GenevaKinematics
from .report import COLUMNS as GENEVA_COLUMNS, _contact_lines, analysis_table

#: the table: the Geneva's columns, then the gears' input angle (rad) and the input torque (N·m)
COLUMNS = GENEVA_COLUMNS + ("gears.input", "gears.ratio", "driver.torque")


def geared_table(kin: GenevaKinematics, con: GenevaContact, gears_kin, input_torque: np.ndarray) -> Table:
    """The Geneva table (rows at equal times, φ the crank angle) with the gears' input angle and
    speed ratio and the torque on the input shaft (N·m, CCW)."""
    base = analysis_table(kin, con)
    cols = {name: base.column(name) for name in base.columns}
    cols.update({"gears.input": gears_kin.input_rotation, "gears.ratio": gears_kin.ratio,
                 "driver.torque": input_torque})
    return Table.from_columns(cols, integer={"engaged", "contact_valid"})


def geared_summary(el, kin: GenevaKinematics, con: GenevaContact, sm: Smoothness, gears_text: str,
                   input_torque: np.ndarray, geo: GenevaGeometry | None) -> str:
    """The summary (mm, rad/s², rad/s³, N, N·m)."""
    g = el.geneva
    d = g.dimensions()
    lines = [f"geared Geneva {el.id!r}: z = {g.slots}, A = {g.center_distance:g} mm, crank r = {g.crank_radius:.6g} mm, "
             f"roller r_p = {g.roller_radius:g} mm; the crank is the output of non-circular gears (centre distance "
             f"{el.center_distance:g} mm) whose input turns at {abs(g.speed_rpm) / el.function.ratio:g} rpm, so the "
             f"crank's mean speed is {abs(g.speed_rpm):g} rpm; {len(kin.phi)} samples at equal times",
             "kinematics of the wheel (closed form of the crank angle through the gears' ψ, world frame):"]
    lines += [f"  {x}" for x in sm.lines()]
    lines.append(f"  jerk at mid-indexing {kin.jerk_centre:.6g} rad/s³ (indexing sense)")
    lines.append("wheel geometry (closed form, mm): "
                 f"slot width {2 * d.w:.4f}, slot depth {d.slot_depth:.4f}, outer radius R_o {d.outer_radius:.4f}, "
                 f"maximum hub radius {d.hub_max:.4f}, locking disc R_L {d.lock_disc_radius:.4f}")
    if geo is None:
        lines.append("  drawing: the drive cannot be drawn (see the error)")
    lines += _contact_lines(g, con)
    peak = float(np.max(np.abs(input_torque))) if len(input_torque) else 0.0
    lines.append(f"torque on the gears' input (the crank's torque passed back through frictionless gears, "
                 f"T_in = −T_c·ψ'): peak {peak:.6g} N·m")
    lines += gears_text.splitlines()
    lines.append("assumptions:")
    lines += [f"  - {a}" for a in con.assumptions]
    return "\n".join(lines)
