"""What a gear pair reports: the per-sample table and the summary (``mechsketch analyze`` and the
app's diagnostics and plots)."""
from __future__ import annotations

import math

from ...model.gear_function import GearFunction
from ..table import Table
from .pitch import GearKinematics, PitchChecks

#: the table's columns: time s, input angle rad, output angle rad, speed ratio, output rates
#: (rad/s, rad/s², rad/s³, CCW), pitch radii mm
COLUMNS = ("t", "input", "output.angle", "ratio", "output.omega", "output.alpha", "output.jerk", "r1", "r2")


def gear_table(kin: GearKinematics) -> Table:
    """The per-sample table (:data:`COLUMNS`)."""
    cols = {"t": kin.t, "input": kin.input_rotation, "output.angle": kin.output_rotation, "ratio": kin.ratio,
            "output.omega": kin.omega_out, "output.alpha": kin.alpha_out, "output.jerk": kin.jerk_out,
            "r1": kin.r1, "r2": kin.r2}
    return Table.from_columns({k: cols[k] for k in COLUMNS})


def describe(fn: GearFunction) -> str:
    """The transmission function in words."""
    if fn.kind == "elliptic":
        return f"elliptic, eccentricity {fn.eccentricity:g} (equal ellipses turning about their foci)"
    if fn.kind == "fourier":
        return (f"ψ = {fn.ratio:g}·φ + Fourier terms (sin {', '.join(f'{v:.6g}' for v in fn.sin) or '—'}; "
                f"cos {', '.join(f'{v:.6g}' for v in fn.cos) or '—'})")
    return f"a table of {len(fn.table)} points, mean ratio {fn.ratio:g} (periodic quintic spline)"


def gear_summary(name: str, fn: GearFunction, a: float, kin: GearKinematics, ch: PitchChecks) -> str:
    """The summary of a gear pair (mm, rad, degrees)."""
    lines = [f"gear pair {name!r}: non-circular external gears, centre distance a = {a:g} mm, function {describe(fn)}; "
             f"input {abs(kin.omega) * 30 / math.pi:g} rpm {'CCW' if kin.sense > 0 else 'CW'}, the output the other "
             f"way; {len(kin.t)} samples per input turn",
             "pitch curves: the exact centrodes of the relative motion, r1 = a·ψ'/(1 + ψ'), r2 = a/(1 + ψ') on the "
             "line of centres"]
    lines += [f"  {x}" for x in ch.lines()]
    lines.append(f"  output: speed up to {max(abs(kin.omega_out.max()), abs(kin.omega_out.min())):.6g} rad/s, "
                 f"acceleration up to {max(abs(kin.alpha_out.max()), abs(kin.alpha_out.min())):.6g} rad/s², jerk up "
                 f"to {max(abs(kin.jerk_out.max()), abs(kin.jerk_out.min())):.6g} rad/s³")
    return "\n".join(lines)
