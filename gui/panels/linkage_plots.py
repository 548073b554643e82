"""What the plots panel shows for a linkage: the selected joint's or link's kinematics, the
transmission angles, and the force rows (pure: reads the controller, never writes).

The panel (:mod:`.plots`) draws the :class:`~.plot_series.PlotData` these functions return; a
Geneva drive or rolling lever brings its own (:mod:`.element_plots`).
"""
from __future__ import annotations

import numpy as np

from mechsketch.core import MechsketchError
from mechsketch.core.model.linkage import Linkage

from ..controller import SceneController
from .element_plots import element_plot_data
from .force_plots import add_force_series
from .plot_series import PlotData, Series


def _target(controller: SceneController) -> tuple[Linkage, str, str] | None:
    """(linkage, "joint"|"link", id) to plot: the selection, else the last group's inner joint."""
    for eid, kind, ident in controller.selection:
        if eid not in controller.scene.ids:
            continue
        el = controller.scene.element(eid)
        if isinstance(el, Linkage) and ident in (el.joint_ids if kind == "joint" else el.link_ids):
            return el, kind, ident
    for lk in controller.linkages():
        res = controller.result(lk.id)
        if res is not None and res.plan is not None and res.plan.steps:
            return lk, "joint", res.plan.steps[-1].group.inner
        if lk.joints:
            return lk, "joint", lk.joint_ids[-1]
    return None


def plot_data(controller: SceneController) -> PlotData:
    """What to plot for the controller's current selection (pure: reads, never writes)."""
    element = element_plot_data(controller)
    if element is not None:
        return element
    target = _target(controller)
    if target is None:
        return PlotData("nothing to plot: the scene has no linkage")
    lk, kind, ident = target
    res = controller.result(lk.id)
    if res is None or res.solution is None:
        return PlotData(f"{lk.id} is not solved: {res.error if res else 'no result'}")
    sol = res.solution
    if sol.plan.input_unit == "mm":   # an actuator: its length (cylinder) or displacement (slider)
        what = "cylinder length" if str(lk.driver.kind) == "cylinder" else "slider displacement"
        data = PlotData(f"{kind} {ident} of {lk.id}", np.asarray(sol.input, dtype=float),
                        np.asarray(sol.valid, dtype=bool), x_label=f"input: {what} (mm)", x_unit="mm")
    else:
        data = PlotData(f"{kind} {ident} of {lk.id}", np.degrees(sol.input), np.asarray(sol.valid, dtype=bool))
    S = data.series
    try:
        if kind == "joint":
            p, v, a = sol.position(ident), sol.velocity(ident), sol.acceleration(ident)
            S += [Series("position", f"{ident}.x", "mm", p[:, 0]), Series("position", f"{ident}.y", "mm", p[:, 1]),
                  Series("velocity", f"{ident}.vx", "mm/s", v[:, 0]),
                  Series("velocity", f"{ident}.vy", "mm/s", v[:, 1]),
                  Series("velocity", f"|v {ident}|", "mm/s", np.hypot(v[:, 0], v[:, 1])),
                  Series("acceleration", f"{ident}.ax", "mm/s²", a[:, 0]),
                  Series("acceleration", f"{ident}.ay", "mm/s²", a[:, 1]),
                  Series("acceleration", f"|a {ident}|", "mm/s²", np.hypot(a[:, 0], a[:, 1]))]
            data.labels.update(position="position (mm)", velocity="velocity (mm/s)",
                               acceleration="acceleration (mm/s²)")
        elif ident == lk.ground:
            data.title += " (the frame does not move)"
        else:
            S += [Series("position", f"{ident}.angle", "°", np.degrees(sol.angle(ident))),
                  Series("velocity", f"{ident}.ω", "rad/s", sol.omega(ident)),
                  Series("acceleration", f"{ident}.ε", "rad/s²", sol.alpha(ident))]
            data.labels.update(position="angle (°)", velocity="ω (rad/s)", acceleration="ε (rad/s²)")
    except MechsketchError as exc:
        data.title += f" — {exc}"
    for g in sol.groups:
        if g.kind == "RRR":
            S.append(Series("transmission", f"μ {g.name}", "°", np.degrees(sol.transmission_angle(g.name))))
    data.labels["transmission"] = "μ (°)"
    add_force_series(controller, data, lk, kind, ident)
    return data


def robust_range(arrays: list[np.ndarray], tail: float = 0.5) -> tuple[float, float] | None:
    """A y range showing the curves without letting a spike near a toggle (ω, ε → ∞) flatten
    everything else: the full range, or the central 100 − 2·``tail`` percent of the values
    widened by half its span when a few extreme values lie beyond that. None: no finite value."""
    if not arrays:
        return None
    values = np.concatenate([np.asarray(a, dtype=float).ravel() for a in arrays])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return None
    lo, hi = float(values.min()), float(values.max())
    plo, phi = (float(v) for v in np.percentile(values, [tail, 100.0 - tail]))
    span = phi - plo
    if span > 0 and (hi - lo) > 4.0 * span:
        return plo - 0.5 * span, phi + 0.5 * span
    return lo, hi if hi > lo else lo + 1.0
