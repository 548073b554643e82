"""What a Geneva drive reports: the per-sample analysis table and the human summary.

``mechsketch analyze SCENE --element ID`` prints them (CSV / ``--summary``); the GUI's plots panel
exports the same table and its diagnostics panel shows the same summary.
"""
from __future__ import annotations

import math

import numpy as np

from ...errors import GeometryError
from ...model.geneva import Geneva
from .contact import GenevaContact
from .geometry import GenevaGeometry, geometry
from .kinematics import GenevaKinematics
from ..table import Table

#: the analysis table's columns and their units (rad, rad/s, rad/s², rad/s³; N; N·m; mm; mm/s;
#: N·min/m; MPa); contact columns are empty outside the engagement, and ``contact_valid`` 0 flags
#: an engaged row outside the contact model's validity range (its strip, widths, deformation,
#: slip speed and pressure empty; the slip path empty from the first such row on)
COLUMNS = ("t", "input", "wheel.angle", "wheel.omega", "wheel.alpha", "wheel.jerk", "engaged",
           "contact_valid", "Rn",
           "Rn_paper", "moment", "strip_width", "hertz_half_width", "deformation", "rolling_ratio",
           "slip_speed", "slip_path", "wear_invariant", "contact_pressure")


def analysis_table(kin: GenevaKinematics, con: GenevaContact) -> Table:
    """The per-sample table (see :data:`COLUMNS`); ``Rn`` is the normal force of the model in force."""
    cols: dict[str, np.ndarray] = {
        "t": kin.t, "input": kin.phi, "wheel.angle": kin.wheel_angle, "wheel.omega": kin.omega,
        "wheel.alpha": kin.alpha, "wheel.jerk": kin.jerk, "engaged": kin.engaged.astype(float),
        "contact_valid": con.contact_valid.astype(float),
        "Rn": con.Rn, "Rn_paper": con.Rn_paper, "moment": con.moment, "strip_width": con.strip_width,
        "hertz_half_width": con.hertz_half_width, "deformation": con.deformation,
        "rolling_ratio": con.rolling_ratio, "slip_speed": con.slip_speed, "slip_path": con.slip_path,
        "wear_invariant": con.wear_invariant, "contact_pressure": con.contact_pressure,
    }
    return Table.from_columns({k: cols[k] for k in COLUMNS}, integer={"engaged", "contact_valid"})


def _deg(x: float) -> str:
    return f"{math.degrees(x):.4g}°"


def summary(el: Geneva, kin: GenevaKinematics, con: GenevaContact, geo: GenevaGeometry | None = None) -> str:
    """A human summary of the kinematics, the drawable geometry limits and the contact/wear model
    (``geo``: the drive's geometry when the caller has it built, else it is built here)."""
    d = el.dimensions()
    w1 = el.omega1
    sense = "CCW" if w1 > 0 else "CW"
    lines = [
        f"geneva {el.id!r}: external radial-entry Geneva, z = {el.slots}, A = {el.center_distance:g} mm, "
        f"crank r = A·sin(π/z) = {el.crank_radius:.6g} mm (λ = {el.lam:.6g}), roller r_p = {el.roller_radius:g} mm "
        f"× l = {el.roller_length:g} mm; crank {el.speed_rpm:g} rpm {sense} (ω1 = {w1:.6g} rad/s), wheel turns "
        f"{'CW' if w1 > 0 else 'CCW'}; {len(kin.phi)} samples, φ from the line of centres, CCW",
        "kinematics (closed form; columns wheel.*: world frame, CCW positive, rad, rad/s, rad/s², rad/s³):",
        f"  indexing over 2φ0 = {_deg(2 * kin.phi0)} of crank (entry φ = {_deg(-math.copysign(kin.phi0, w1))}), "
        f"motion fraction {kin.motion_fraction:.4f}, dwell fraction {kin.dwell_fraction:.4f}, period {kin.period:.6g} s",
        f"  i_max = ω2/ω1 = λ/(1 − λ) = {kin.i_max:.6g} at φ = 0; peak |α2| = ε̃_max·ω1² = {kin.accel_peak:.6g} rad/s² "
        f"(ε̃_max = {kin.accel_peak_ratio:.6g}) at φ = {_deg(-math.copysign(kin.phi_peak, w1))} (speeding up) and "
        f"{_deg(math.copysign(kin.phi_peak, w1))} (slowing down); sampled peak "
        f"{abs(kin.sampled_peak[1]):.6g} rad/s² at {_deg(kin.sampled_peak[0])}",
        f"  acceleration jump at entry and exit: tan(π/z)·ω1² = {kin.jump:.6g} rad/s² (a step between dwell and "
        "indexing rows, never interpolated; infinite jerk there, the jerk column is the finite part); "
        f"jerk at mid-indexing j̃(0)·|ω1|³ = {kin.jerk_centre:.6g} rad/s³",
        "wheel geometry (closed form, mm): "
        f"slot width {2 * d.w:.4f}, slot depth {d.slot_depth:.4f}, outer radius R_o {d.outer_radius:.4f}, "
        f"maximum hub radius {d.hub_max:.4f}, land angle {_deg(d.land_angle)} each side of a slot, "
        f"locking arc R_arc {d.lock_arc_radius:.4f} (admissible ({d.lock_arc_range[0]:.4f}, {d.lock_arc_range[1]:.4f}]), "
        f"locking disc R_L {d.lock_disc_radius:.4f}",
    ]
    try:
        geo = geo if geo is not None else geometry(el)
        rel = geo.relief
        lines.append(f"  relief of the locking disc (centre at A on the crank): {rel.drawn:.3f} mm drawn, "
                     f"{rel.exact:.5f} exact to clear by c_l = {el.clearance.lock:g}, {rel.touch:.5f} to avoid contact; "
                     f"the classical R_o = {rel.classical:.5f} is {rel.touch - rel.classical:.4f} mm too small; "
                     f"locking margin φ0 + β_L − ψ_r = {_deg(geo.locking_margin)}")
    except GeometryError as exc:
        lines.append(f"  drawing: {exc}")
    lines += _contact_lines(el, con)
    lines += [
        "assumptions:",
    ]
    lines += [f"  - {a}" for a in con.assumptions]
    return "\n".join(lines)


def _contact_lines(el: Geneva, con: GenevaContact) -> list[str]:
    """The summary's contact and wear lines (the validity range first; totals only inside it)."""
    m, life, eng, v = con.model, con.life, con.engaged, con.validity
    loaded = con.Rn_max > 0.0
    where_rn = f"at φ = {_deg(con.phi_Rn_max)} (most loaded place)" if loaded else \
        "(no load: J2 = 0 and no external moment, so the roller transmits no force anywhere)"
    ratios = (f"Δ/r_p up to {v.max_deformation_ratio:.3g}, b/r_p up to {v.max_half_width_radius_ratio:.3g}, "
              f"b/l up to {v.max_half_width_length_ratio:.3g}")
    limits = (f"Δ ≤ {v.deformation_limit:g}·r_p, b ≤ {v.half_width_limit:g}·r_p and ≤ {v.half_width_limit:g}·l, "
              f"i.e. R_n ≤ {v.rn_limit:.4g} N")
    lines = ["contact and wear (Stetsiv, corrected; columns: N, N·m, mm, mm/s, N·min/m, MPa; empty outside the "
             "engagement):"]
    if v.ok:
        lines.append(f"  validity range of the contact model ({limits}): within it at every engaged row ({ratios}; "
                     f"peak R_n {v.rn_peak:.4g} N)")
    else:
        runs = ", ".join(f"{_deg(a)} to {_deg(b)}" for a, b in v.invalid_runs) or "between samples only"
        lines.append(f"  outside the contact model's validity range ({limits}) at {v.invalid_rows} of "
                     f"{v.engaged_rows} engaged rows (φ {runs}; peak R_n {v.rn_peak:.4g} N, {v.rn_peak / v.rn_limit:.3g}× the limit; the model would give "
                     f"{ratios}): those rows are flagged contact_valid 0 with their strip, widths, deformation, slip "
                     "and pressure left empty; L_s, T_i, the peak pressure and the life are not computed. Use a "
                     "stiffer roller or wheel (E), a longer roller_length or roller_radius, or a lighter load")
    lines += [
        f"  Rn = {m.normal_force} form: max {con.Rn_max:.6g} N {where_rn}; "
        f"paper's eq. (3) max {np.nanmax(con.Rn_paper[eng]) if eng.any() else 0.0:.6g} N; derived max "
        f"{np.nanmax(con.Rn_derived[eng]) if eng.any() else 0.0:.6g} N",
        f"  strip width a_paper up to {_mx(con.strip_width) * 1e3:.4g} µm, Hertz half-width b up to "
        f"{_mx(con.hertz_half_width) * 1e3:.4g} µm, roller deformation Δ up to {_mx(con.deformation) * 1e3:.4g} µm, "
        f"|ω_pi| up to {_mx(np.abs(con.rolling_ratio)):.4g} (r/r_p at entry)"
        + ("" if v.ok else " (valid rows only)"),
    ]
    if not v.ok:
        lines += ["  slip path per engagement L_s: not computed (outside the validity range); slip speed up to "
                  f"{_mx(con.slip_speed):.4g} mm/s at the valid rows",
                  "  paper's wear invariant T_i: not computed (it needs L_s)",
                  "  peak contact pressure p_max: not computed (the peak lies outside the validity range)",
                  f"  Archard (k = {el.wear.specific_wear_rate:g} mm³/(N·m), [h] = {el.wear.allowed_wear:g} mm): "
                  "wear and life not computed (outside the validity range)"]
        return lines
    t_i = (f"up to {con.wear_invariant_max:.4g} N·min/m" if math.isfinite(con.wear_invariant_max) else
           "undefined: with no load R_n = 0 and L_s = 0 (0/0), so its column is empty")
    where_p = f"at φ = {_deg(con.phi_pressure_max)}" if loaded else "(no load)"
    lines += [
        f"  slip path per engagement L_s = {con.slip_path_total * 1e3:.6g} µm (Gauss–Legendre on each smooth piece, "
        f"breaks at progress angles {', '.join(_deg(b) for b in con.breaks)}; the slip_path column, Gauss–Legendre "
        f"on every interval between samples and breaks, ends there; the trapezoid rule on the same points would "
        f"give {con.slip_path_total_trapezoid * 1e3:.6g} µm, relative difference "
        f"{_rel(con.slip_path_total_trapezoid, con.slip_path_total):.2g}); slip speed up to "
        f"{_mx(con.slip_speed):.4g} mm/s (invariant v_s/(ω1·r_p) up to {_mx(con.slip_speed_invariant):.4g})",
        f"  paper's wear invariant T_i = π·R_n·z/(30·ω1·L_s) {t_i}",
        f"  peak contact pressure p_max = 2R_n/(π·b·l) = {con.pressure_max:.4g} MPa {where_p}",
        f"  Archard (k = {el.wear.specific_wear_rate:g} mm³/(N·m), [h] = {el.wear.allowed_wear:g} mm): wear per "
        f"engagement {life.depth_drive:.3g} mm (driving flank), {life.depth_brake:.3g} mm (braking flank); " + (
            f"slot life {life.slot_cycles:.3g} crank turns, roller {life.roller_cycles:.3g}; limiting: "
            f"{life.limiting}, {life.cycles:.3g} turns = {life.hours:.3g} h at {abs(el.speed_rpm):g} rpm"
            if math.isfinite(life.cycles) else "no wear, so no limit to the life of slot or roller"),
    ]
    return lines


def _mx(arr: np.ndarray) -> float:
    fin = arr[np.isfinite(arr)]
    return float(fin.max()) if fin.size else 0.0


def _rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b) if b else 0.0
