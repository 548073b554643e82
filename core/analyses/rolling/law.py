"""A prescribed slider law S5(θ) for pair E, and the checks of the profiles it gives (issue 25, item 2).

With a slider law the lever's pair-E element is not chosen (a circle) but derived: the instant
centre of the lever relative to the slider is P0 = P − k53·n with k53 = dS5/dθ (P the pair-D
contact, the lever's instant centre; n = J d_s): the lever's velocity field ω·J(X − P) equals the
slider's k53·ω·d_s at X = P0. The lever element Π30 is the locus of P0 in the lever frame, the
slider profile Π50 its locus in the slider frame Q = P0 − S5·d_s: the exact centrodes of the
relative motion, which roll on each other without slip. The exact method integrates S5 from
k53 = S5'(θ) beside α (:mod:`.exact`), so the integrated S5 against the law is the check that
S5 is reproduced.

:class:`~.slider_law.LawCurve` evaluates the law: a table through a quintic spline (C⁴: the profiles' curvature
is continuous; cubic below 6 points), a rise law (:func:`~mechsketch.core.solver.motion_law.profile`)
S5 = travel·h((θ − θ_from)/(θ_to − θ_from)). :func:`law_checks` measures, on the synthesis' exact
continuous motion, what the issue asks of the result: pure rolling (arc lengths of Π30 and Π50,
equal), no cusp or reversal of either profile, the contact on the working side, S5 reproduced, and
the pressure angle (contact normal against the slider's motion).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .geometry import pose_state, rot

#: Gauss–Legendre nodes per interval between synthesis samples for the arc lengths
_NODES = 8
#: a profile whose speed |dC/dθ| falls below this fraction of its mean has a cusp
CUSP_FRACTION = 1e-3


@dataclass(frozen=True)
class LawChecks:
    """What a synthesis with a slider law is checked for (mm, rad, degrees where named).

    ``length_lever`` ∫|dΠ30/dθ| (lever frame) and ``length_slider`` ∫|dΠ50/dθ| (slider frame) over
    the stroke and ``rolling_mismatch`` their difference (pure rolling: 0 up to the integration);
    ``min_speed_lever`` / ``min_speed_slider`` the smallest |dC/dθ| (mm/rad) against their means
    (a cusp where it vanishes) and ``reversal`` whether a tangent turns back (the dot product of
    neighbouring tangents negative); ``folds_lever`` / ``folds_slider`` whether a profile crosses
    itself (it folds back: no plate can carry it); ``side_margin`` the smallest side·(P0 − P)·n over the stroke (mm;
    ≥ 0: the contact stays on the working side) and ``side_at`` its θ; ``s5_error`` the largest
    |S5 integrated − (law(θ) − law(0))| (mm); ``pressure_angle_deg`` the largest angle between the
    contact normal and the slider's motion; ``cusp``: True if either profile has one.
    """

    length_lever: float
    length_slider: float
    rolling_mismatch: float
    min_speed_lever: float
    mean_speed_lever: float
    min_speed_slider: float
    mean_speed_slider: float
    reversal: bool
    side_margin: float
    side_at: float
    s5_error: float
    pressure_angle_deg: float
    folds_lever: bool = False
    folds_slider: bool = False

    @property
    def cusp(self) -> bool:
        return (self.min_speed_lever < CUSP_FRACTION * self.mean_speed_lever
                or self.min_speed_slider < CUSP_FRACTION * self.mean_speed_slider)

    @property
    def folds(self) -> bool:
        return self.folds_lever or self.folds_slider

    @property
    def ok(self) -> bool:
        return not self.cusp and not self.reversal and not self.folds and self.side_margin >= 0.0

    def lines(self) -> list[str]:
        """The checks in words (the synthesis summary and the design report)."""
        return [
            f"pure rolling: Π30 (lever) {self.length_lever:.9f} mm and Π50 (slider) {self.length_slider:.9f} mm "
            f"long, mismatch {self.rolling_mismatch:.2e} mm",
            f"profiles: smallest speed |dC/dθ| {self.min_speed_lever:.4g} (lever, mean {self.mean_speed_lever:.4g}) "
            f"and {self.min_speed_slider:.4g} mm/rad (slider, mean {self.mean_speed_slider:.4g}): "
            + ("a cusp" if self.cusp else "no cusp") + ("; a tangent reverses" if self.reversal else ", no reversal")
            + ("; the lever element folds back across itself" if self.folds_lever else "")
            + ("; the slider profile folds back across itself" if self.folds_slider else "")
            + ("" if self.folds else ", neither crosses itself"),
            f"contact on the working side: side·(P0 − P)·n ≥ {self.side_margin:.4g} mm (at θ = {self.side_at:.6f} rad)"
            + ("" if self.side_margin >= 0 else " — ON THE WRONG SIDE"),
            f"S5 reproduced to {self.s5_error:.2e} mm; largest pressure angle {self.pressure_angle_deg:.3f}°",
        ]


def law_checks(res: Any, lengths: tuple[float, float] | None = None) -> LawChecks:
    """:class:`LawChecks` of an exact synthesis with a slider law (a
    :class:`~.synthesis.RollingSynthesis`: its geometry, exact path, samples θ and S5), on its
    continuous motion:
    Gauss–Legendre (``_NODES`` per interval of the synthesis grid) of the profile speeds, which
    come in closed form from the motion: with P moving at dP/dθ (fourth-order differences of the
    dense output) and k53 from the law, dP0/dθ = dP/dθ − k53'·n; in the lever frame
    dΠ30/dθ = Rot(−θ)(dP0/dθ − v_lever(P0)) with the lever's velocity field J(X − P) per unit θ
    (its instant centre is P); in the slider frame dΠ50/dθ = dP0/dθ − k53·d_s. These two are
    equal in length by construction (J(P0 − P) = k53·d_s), so the arc lengths compared for pure
    rolling are ``lengths`` = (lever, slider) when given: the slip report's, measured on each
    curve's own points (:func:`~.slip.continuous_slip`)."""
    geom, path, law = res.geom, res.path, res.geom.law
    th = res.theta
    x, w = np.polynomial.legendre.leggauss(_NODES)
    lo, hi = th[:-1], th[1:]
    mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    q = (mid[:, None] + half[:, None] * x[None, :]).ravel()
    wq = np.abs((half[:, None] * w[None, :]).ravel())
    eta = np.minimum(1e-4, 0.25 * np.abs(np.repeat(half, _NODES)))
    # the stencil (±2 steps) stays inside the stroke: beyond its ends the working range may be over
    eta = np.minimum(eta, 0.45 * np.minimum(q - min(th[0], th[-1]), max(th[0], th[-1]) - q))
    base = path.base_index(q)

    def p_of(t):
        a, _ = path.at(t, base=base)
        return pose_state(geom, a, t).P

    dP = (p_of(q - 2 * eta) - 8 * p_of(q - eta) + 8 * p_of(q + eta) - p_of(q + 2 * eta)) / (12 * eta[:, None])
    a, s5 = path.at(q, base=base)
    st = pose_state(geom, a, q)
    _, k53, k53p = law.values(q)
    n, ds = np.asarray(geom.n), np.asarray(geom.ds)
    dP0 = dP - k53p[:, None] * n
    r = st.P0 - st.P
    v_field = np.stack([-r[:, 1], r[:, 0]], axis=-1)          # J(P0 − P): the lever's velocity per unit θ
    d_lever = rot(-q, dP0 - v_field)
    d_slider = dP0 - k53[:, None] * ds
    sl, ss = np.linalg.norm(d_lever, axis=1), np.linalg.norm(d_slider, axis=1)
    span = float(np.sum(wq))
    mean_l, mean_s = float(wq @ sl) / span, float(wq @ ss) / span
    length_l, length_s = lengths if lengths is not None else (mean_l * span, mean_s * span)

    def reversal(d: np.ndarray) -> bool:
        return bool(np.any(np.einsum("ij,ij->i", d[1:], d[:-1]) < 0.0))

    side = geom.side * ((st.P0 - st.P) @ n)
    ks = int(np.argmin(side))
    s_law = law.values(np.array([0.0, *th]))[0]
    s5_err = float(np.max(np.abs(res.S5 - (s_law[1:] - s_law[0]))))
    tangent = d_slider / np.maximum(ss, 1e-300)[:, None]        # common tangent of the centrodes at P0
    normal_dot_ds = np.abs(tangent[:, 0] * -ds[1] + tangent[:, 1] * ds[0])   # |normal · d_s|
    pressure = float(np.degrees(np.max(np.arccos(np.clip(normal_dot_ds, 0.0, 1.0)))))
    import shapely   # heavy; only for the measures

    lever_pts = rot(-q, st.P0 - st.F) + np.asarray(geom.f)
    q_pts = st.P0 - s5[:, None] * ds
    return LawChecks(length_l, length_s, length_l - length_s, float(sl.min()), mean_l,
                     float(ss.min()), mean_s, reversal(d_lever) or reversal(d_slider),
                     float(side[ks]), float(q[ks]), s5_err, pressure,
                     not shapely.LineString(lever_pts).is_simple, not shapely.LineString(q_pts).is_simple)
