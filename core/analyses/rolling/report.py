"""The human summary of a rolling-lever synthesis (what ``mechsketch synthesize --summary`` prints)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .geometry import pose_state

if TYPE_CHECKING:  # pragma: no cover
    from .synthesis import RollingSynthesis


def _rng(x: np.ndarray, fmt: str = ".6g") -> str:
    return f"{np.nanmin(x):{fmt}} … {np.nanmax(x):{fmt}}"


def summary(res: "RollingSynthesis") -> str:
    """Stroke, working range, S5, slip measures, time, crank and coupler (text, mm/rad/degrees)."""
    el, g = res.element, res.geom
    n = res.points
    th0, th1 = float(res.theta[0]), float(res.theta[-1])
    lines = [f"rolling lever {el.id!r}: method {res.method}, N = {n} intervals ({n + 1} points)"]
    lines.append(f"stroke: θ from {el.stroke.start:g} to {el.stroke.end:g} rad "
                 f"({math.degrees(el.stroke.span):+.4f}°); contact on the lever circle u1 from "
                 f"{math.degrees(res.u1[0]):.4f}° to {math.degrees(res.u1[-1]):.4f}°")
    wr = res.working_range
    lo, hi = sorted((el.stroke.start, el.stroke.end))
    margin = min(lo - wr.lower, wr.upper - hi)
    lines.append(f"working range from the drawn pose: {wr.describe()}; the stroke keeps {margin:.6f} rad "
                 "from its nearer end")
    if res.method == "exact":
        rate = pose_state(g, res.alpha, res.theta).rate
    else:  # the constructions only have poses: difference quotients
        rate = np.diff(res.alpha) / np.diff(res.theta)
    lines.append(f"rocker: ℓ = {g.ell:.6g} mm, α {_rng(res.alpha)} rad, dα/dθ {_rng(rate, '.4f')}")
    if res.method != "exact":
        lines.append(f"constructed poses: θ from {th0:.6f} to {th1:.6f} rad (the exact motion reaches the same "
                     f"lever arc at θ = {el.stroke.end:.6f} rad)")
    lines.append(f"pair E: k53 {_rng(res.k53, '.6g')} mm/rad; S5 {_rng(res.S5, '.6g')} mm "
                 f"(travel {float(np.nanmax(res.S5) - np.nanmin(res.S5)):.6g} mm)")
    if el.slider_law is not None:
        law = el.slider_law
        what = (f"a table of {len(law.table)} points (quintic spline)" if law.kind == "table"
                else f"{law.kind}, travel {law.travel:g} mm over the stroke")
        lines.append(f"slider law S5(θ): {what}; the lever element Π30 and the slider profile Π50 are the exact "
                     "centrodes of the lever/slider relative motion (k53 = dS5/dθ)")
        if res.law is not None:
            lines += [f"  {line}" for line in res.law.lines()]
    if res.method == "exact":
        lines.append(f"time: {res.time_s * 1e3:.2f} ms (integration in {len(res.path.theta) - 1} adaptive steps, "
                     f"{res.path.evaluations} evaluations, working range included); integration error "
                     f"bound {res.error_mm:.2e} mm (tolerance {el.tolerance:.1e} mm)")
        if res.error_mm > el.tolerance:
            lines.append(f"note: the tolerance is not met ({res.error_mm:.2e} mm): close to the working-range end "
                         f"the contact moves ~1/√(distance) faster than the lever, and rounding in α is magnified "
                         f"as much; end the stroke further from it ({margin:.2e} rad now) or raise `tolerance`")
    else:
        lines.append(f"time: {res.time_s * 1e3:.2f} ms for the construction (+ {res.time_exact_s * 1e3:.2f} ms "
                     "for the exact motion used for the stroke's lever arc, the drive and the references)")
    rep = res.slip
    if rep is not None:
        if rep.continuous is not None:
            c = rep.continuous
            lines.append("slip of the computed motion (exact method, independent of N):")
            lines.append(f"  pair D: lever material at the contact slides {c.slip_d:.2e} mm; centrode lengths "
                         f"{c.length_fixed:.9f} (frame) and {c.length_moving:.9f} mm (lever), mismatch "
                         f"{c.mismatch_d:.2e} mm")
            lines.append(f"  pair E: lever against slider at P0 slides {c.slip_e:.2e} mm; lengths "
                         f"{c.length_slider:.9f} (slider) and {c.length_lever_e:.9f} mm (lever), mismatch "
                         f"{c.mismatch_e:.2e} mm")
            lines.append(f"  worst: {c.worst:.2e} mm")
        p = rep.points
        lines.append(f"slip measures at the {n + 1} points (notes, section C):")
        lines.append(f"  arc-length mismatch of the polygon  {p.arc_mismatch:+.4e} mm (chords; N⁻² for every method)")
        lines.append(f"  kinematic slip, pair D / pair E     {p.kinematic_slip:.4e} / {p.kinematic_slip_e:.4e} mm")
        lines.append(f"  IC offset from the rocker line      {p.ic_offset:.4e} mm")
        lines.append(f"  deviation from the exact centrode   {p.deviation:.4e} mm")
        ph = rep.physical
        if math.isfinite(ph.slip):
            lines.append(f"  physical slip on a spline profile   {ph.slip:.4e} mm over θ ∈ [{ph.start:.4f}, {ph.end:.4f}] "
                         f"rad ({ph.rolled:.4g} mm rolled, {100.0 * ph.ratio:.3g} %)")
        else:
            lines.append(f"  physical slip on a spline profile   not computed: {ph.reason}")
        if rep.refined is not None:
            a, b = p.kinematic_slip, rep.refined.kinematic_slip
            if res.method == "paper":
                lines.append(f"note: the paper's construction levels off (flaw C1): its kinematic slip is {a:.4f} mm "
                             f"with N = {n} and {b:.4f} mm with N = {2 * n} (a converging method would quarter it); "
                             f"its instant centres stay {p.ic_offset:.3g} mm off the rocker line and the profile "
                             f"deviates {p.deviation:.3g} mm from the exact centrode. More points do not help: "
                             "use method 'exact'.")
            else:
                lines.append(f"note: the corrected construction converges as N⁻²: kinematic slip {a:.3e} mm with "
                             f"N = {n}, {b:.3e} mm with N = {2 * n} (ratio {a / b:.2f})")
        if rep.refined_error:
            lines.append(f"note: with N = {2 * n} points {rep.refined_error}")
        lines.append(f"  (measures computed in {rep.time_s * 1e3:.0f} ms)")
    d = res.drive
    if d is not None:
        lines.append(f"drive: crank {d.crank:.6g} mm, coupler {d.coupler:.6g} mm (|A − C| from {d.d_min:.6g} to "
                     f"{d.d_max:.6g} mm)")
        lines.append(f"  dead centres: folded at θ = {d.theta_folded:.6f} rad (crank {math.degrees(d.phi_folded):.3f}°), "
                     f"extended at θ = {d.theta_extended:.6f} rad (crank {math.degrees(d.phi_extended):.3f}°)")
        lines.append(f"  crank turning counter-clockwise: forward stroke {math.degrees(d.forward_angle):.3f}°, return "
                     f"{360.0 - math.degrees(d.forward_angle):.3f}° (time ratio {d.time_ratio:.4f})")
    return "\n".join(lines)

