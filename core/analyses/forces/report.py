"""What the kinetostatics reports: the CSV columns of ``mechsketch analyze SCENE --forces`` and the
``--summary`` text, shared by the CLI and the GUI.

Columns (SI units), after the kinematic columns of the linkage table:

- ``driver.torque`` N·m: the torque the motor applies to the driver link, counter-clockwise
  positive (``driver.force`` N, positive extending, for a linear actuator);
- per revolute joint J on two or more links, ``J.Fx`` ``J.Fy`` N: the force the earlier-listed of
  its links (file order) exerts on the later-listed one; where more links share the joint, one
  further pair per further link L, ``J[L].Fx`` ``J[L].Fy``: the force on L from the joint (the
  first link takes the balance);
- ``shaking.Fx`` ``shaking.Fy`` N and ``shaking.M`` N·m: what the mechanism exerts on the frame
  (moment about the driver's pivot; for an actuator about its joint's drawn position);
- only when some joint has friction: ``driver.torque_friction`` N·m, the driving torque with
  Coulomb friction, beside the frictionless one.
"""
from __future__ import annotations

import math

import numpy as np

from ...model.linkage import JointKind
from .kinetostatics import ForceResult, input_label
from ..table import Table


def reaction_columns(res: ForceResult) -> list[tuple[str, str, str]]:
    """(column prefix, joint, link the force acts on) for every revolute reaction, in file order."""
    out = []
    lk = res.linkage
    for j in lk.joints:
        if j.kind is not JointKind.R or j.id not in res.pins:
            continue
        for m, link in enumerate(res.pins[j.id]):
            out.append((j.id if m == 0 else f"{j.id}[{link}]", j.id, link))
    return out


def force_columns(res: ForceResult) -> dict[str, np.ndarray]:
    """The ``--forces`` columns by name, each (N,) (see the module docstring)."""
    cols: dict[str, np.ndarray] = {res.driver.column: res.driver.values}
    for prefix, joint, link in reaction_columns(res):
        f = res.pins[joint][link]
        cols[f"{prefix}.Fx"] = f[:, 0]
        cols[f"{prefix}.Fy"] = f[:, 1]
    cols["shaking.Fx"] = res.shaking_force[:, 0]
    cols["shaking.Fy"] = res.shaking_force[:, 1]
    cols["shaking.M"] = res.shaking_moment
    if res.friction is not None:
        cols[f"{res.driver.column}_friction"] = res.friction.driver.values
    return cols


def force_table(res: ForceResult, base: Table | None = None) -> Table:
    """``base`` (the kinematic table, same rows) with the force columns appended, or those alone,
    then ``forces_valid`` (1/0: the row's forces are given, where its kinematics with rates is
    valid) and, per force column C, ``C.err``: its estimated error (same unit; empty where the
    forces are not valid)."""
    cols = force_columns(res)
    errors = res.errors
    cols["forces_valid"] = res.valid.astype(float)
    for name in list(cols)[:-1]:
        cols[f"{name}.err"] = errors[name]
    if base is None:
        return Table.from_columns(cols, integer={"forces_valid"})
    extra = np.column_stack([np.asarray(v, dtype=float) for v in cols.values()])
    return Table(base.columns + list(cols), np.column_stack([base.data, extra]), set(base.integer) | {"forces_valid"})


def _at(res: ForceResult, k: int) -> str:
    return input_label(res, k)


def _peak(values: np.ndarray) -> tuple[float, int]:
    a = np.abs(values)
    if not np.isfinite(a).any():
        return math.nan, 0
    k = int(np.nanargmax(a))
    return float(values[k]), k


def _rms(values: np.ndarray) -> float:
    v = values[np.isfinite(values)]
    return float(np.sqrt(np.mean(v * v))) if v.size else math.nan


def _pm(err: np.ndarray, k: int) -> str:
    """' (± e)': the error estimate at sample ``k`` (nothing where there is none)."""
    e = float(err[k]) if err is not None and k < len(err) else math.nan
    return f" (± {e:.1e})" if math.isfinite(e) else ""


def force_summary(res: ForceResult) -> str:
    """Peak and RMS driving effort, the peak reaction of every joint, the shaking force and
    moment, each peak with its estimated error (``res.errors``), over the rows whose forces are
    valid; the worst power-balance residual, where forces blow up near dead points, and the
    result with friction (the text of ``analyze --forces --summary``)."""
    lk = res.linkage
    d = res.driver
    unit = d.unit
    err = res.errors
    lines = [f"forces of {lk.id!r} over {len(res)} samples (SI units; {res.seconds * 1e3:.2f} ms):"]
    if not lk.has_dynamics:
        lines.append("  no masses or loads: every force is zero (give links a mass or add loads)")
    peak, k = _peak(d.values)
    lines.append(f"  driving {d.kind} ({d.link}): peak {peak:.6g} {unit}{_pm(err[d.column], k)} at input "
                 f"{_at(res, k)}, RMS {_rms(d.values):.6g} {unit}")
    for prefix, joint, link in reaction_columns(res):
        mag = np.hypot(res.pins[joint][link][:, 0], res.pins[joint][link][:, 1])
        p, k = _peak(mag)
        lines.append(f"  joint {prefix} (on {link}): peak |F| {p:.6g} N{_pm(err[prefix + '.Fx'], k)} at input "
                     f"{_at(res, k)}")
    for jid, s in res.slides.items():
        p, k = _peak(s.normal)
        m, km = _peak(s.moment)
        lines.append(f"  slide {jid} (on {s.on}): peak normal force {abs(p):.6g} N{_pm(err[f'slide.{jid}.normal'], k)} "
                     f"at input {_at(res, k)}, peak moment {abs(m):.6g} N·m{_pm(err[f'slide.{jid}.moment'], km)} "
                     f"at input {_at(res, km)}")
    sf = np.hypot(res.shaking_force[:, 0], res.shaking_force[:, 1])
    p, k = _peak(sf)
    m, km = _peak(res.shaking_moment)
    lines.append(f"  shaking: peak |F| {p:.6g} N{_pm(err['shaking.Fx'], k)} at input {_at(res, k)}, peak |M| "
                 f"{abs(m):.6g} N·m{_pm(err['shaking.M'], km)} at input {_at(res, km)} (about the driver pivot "
                 f"{lk.driver.pivot}{'' if res.unit == 'rad' else ', as drawn'})")
    pw = res.power
    lines.append(f"  power balance (motor + loads − dKE/dt): worst relative residual {pw.worst:.2e}")
    invalid = int((~res.valid).sum())
    if invalid:
        lines.append(f"  {invalid} samples without forces (forces_valid 0): not assembled, or at a toggle where "
                     f"the kinematics' rates are not valid")
    for note in res.dead_point_notes():
        lines.append(f"  near a dead point: {note}")
    fr = res.friction
    if fr is not None:
        radii = ", ".join(f"{j} {r:g} mm" for j, r in fr.radii.items())
        peak_f, k = _peak(fr.driver.values)
        lines.append(f"  with joint friction (friction circles {radii}): driving {d.kind} peak {peak_f:.6g} "
                     f"{unit} at input {_at(res, k)}, RMS {_rms(fr.driver.values):.6g} {unit}; "
                     f"{fr.iterations} passes, converged at {int(fr.converged.sum())}/{len(res)} samples, "
                     f"power balance residual {fr.power.worst:.2e}")
    return "\n".join(lines)
