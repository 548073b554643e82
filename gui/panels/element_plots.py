"""Plot data of a Geneva drive or a rolling lever for the plots panel (pure: reads the controller).

- Geneva drive, against the crank angle φ (°, from the line of centres, time order): the wheel
  angle, ω, α - drawn from :meth:`GenevaKinematics.alpha_with_jumps`, so the step at entry and
  exit is a vertical jump and the dwell is an explicit zero - the (finite) jerk, the normal force
  R_n (the model in force and the paper's eq. 3), the cumulative slip path and the peak Hertz
  pressure. Contact values are NaN outside the engagement, so the lines have gaps there. The CSV
  export is the same table as ``mechsketch analyze SCENE --csv``.
- Rolling lever, against the lever rotation θ (°): the rocker angle α, k53 = dS5/dθ, the slider
  travel S5, and the slip of pairs D and E accumulated along the stroke, read from the core's
  per-sample arrays (``SlipReport.samples``: the computed motion's slip for the exact method, the
  construction points' kinematic slip otherwise; the last values are the summary's figures - the
  GUI computes no slip itself). The CSV export is the table of ``mechsketch synthesize SCENE
  --csv`` with the two slip columns added.

The cursor follows the animation frame through ``frame_x`` (the x of every frame).
"""
from __future__ import annotations

import numpy as np

from mechsketch.core.analyses.geneva.report import analysis_table
from mechsketch.core.analyses.geneva.torque import crank_torque
from mechsketch.core.analyses.table import Table
from mechsketch.core.workspace import GenevaResult, RollingResult

from ..frames import map_frame
from ..controller import SceneController
from ..selection import element_target
from .plot_series import PlotData, Series

GENEVA_ROWS = (("angle", "wheel angle (°)"), ("omega", "ω (rad/s)"), ("alpha", "α (rad/s²)"),
               ("jerk", "jerk (rad/s³)"), ("force", "Rn (N)"), ("slip", "slip path (µm)"),
               ("pressure", "p_max (MPa)"), ("torque", "crank torque (N·m)"))
ROLLING_ROWS = (("alpha", "rocker α (°)"), ("k53", "k53 (mm/rad)"), ("S5", "S5 (mm)"),
                ("slip", "slip (mm)"))


def _frame_x(controller: SceneController, x: np.ndarray) -> np.ndarray:
    """x (one value per element sample) at every global animation frame (cycle phase)."""
    total = controller.sample_count()
    n = len(x)
    if total == 0 or n == 0:
        return np.zeros(0)
    idx = [map_frame(f, total, n) for f in range(total)]
    return np.asarray(x)[idx]


def geneva_plot_data(controller: SceneController, res: GenevaResult) -> PlotData:
    """Kinematics and contact of one Geneva drive against the crank angle (see the module docstring)."""
    el = res.element
    kin, con = res.kinematics, res.contact
    if kin is None or con is None:
        return PlotData(f"geneva {el.id}: {res.error}", rows=GENEVA_ROWS, x_label="crank angle φ (°)", kind="geneva")
    x = np.degrees(kin.phi)
    phi_j, alpha_j = kin.alpha_with_jumps()
    data = PlotData(f"Geneva {el.id}", x, np.ones(len(x), dtype=bool),
                    rows=GENEVA_ROWS, x_label="crank angle φ (°, from the line of centres)", kind="geneva")
    data.series += [
        Series("angle", "wheel.angle", "°", np.degrees(kin.wheel_angle)),
        Series("omega", "wheel.ω", "rad/s", kin.omega),
        Series("alpha", "wheel.α", "rad/s²", alpha_j, np.degrees(phi_j)),   # steps by kin.jump at ±φ0
        Series("jerk", "wheel.jerk", "rad/s³", kin.jerk),
        Series("force", f"Rn ({con.model.normal_force})", "N", con.Rn),
        Series("force", "Rn (paper eq. 3)", "N", con.Rn_paper),
        Series("slip", "slip path", "µm", con.slip_path * 1e3),
        Series("pressure", "p_max", "MPa", con.contact_pressure),
        Series("torque", "driver.torque", "N·m", crank_torque(el, con).torque),   # from the contact model
    ]
    data.frame_x = _frame_x(controller, x)

    def table() -> Table:
        return analysis_table(kin, con)

    data.make_table = table
    return data


def rolling_plot_data(controller: SceneController, res: RollingResult) -> PlotData:
    """The synthesis of one rolling lever against the lever rotation θ (see the module docstring)."""
    el = res.element
    syn = res.synthesis
    if syn is None or res.frames is None:
        return PlotData(f"rolling lever {el.id}: {res.error}", rows=ROLLING_ROWS, x_label="lever rotation θ (°)", kind="rolling_lever")
    x = np.degrees(syn.theta)
    data = PlotData(f"lever {el.id} ({syn.method})", x,
                    np.ones(len(x), dtype=bool), rows=ROLLING_ROWS, x_label="lever rotation θ (°)", kind="rolling_lever")
    data.series += [
        Series("alpha", "α", "°", np.degrees(syn.alpha)),
        Series("k53", "k53", "mm/rad", syn.k53),
        Series("S5", "S5", "mm", syn.S5),
    ]
    slip = res.slip_samples
    if slip is not None:
        data.series += [Series("slip", "slip pair D", "mm", slip.slip_d, np.degrees(slip.theta)),
                        Series("slip", "slip pair E", "mm", slip.slip_e, np.degrees(slip.theta))]
        data.labels["slip"] = ("slip of the motion (mm)" if slip.source == "continuous"
                               else "kinematic slip, points (mm)")
    data.frame_x = _frame_x(controller, np.degrees(res.frames.theta))

    def table() -> Table:
        base = syn.table()
        cols = {name: base.column(name) for name in base.columns}
        if slip is not None:
            cols.update({"slip_D": slip.slip_d, "slip_E": slip.slip_e})
        return Table.from_columns(cols)

    data.make_table = table
    return data


def element_plot_data(controller: SceneController) -> PlotData | None:
    """Plot data of the Geneva drive or rolling lever the panels show, or None (plot a linkage)."""
    eid = element_target(controller)
    if eid is None:
        return None
    res = controller.element_result(eid)
    if isinstance(res, GenevaResult):
        return geneva_plot_data(controller, res)
    if isinstance(res, RollingResult):
        return rolling_plot_data(controller, res)
    return None
