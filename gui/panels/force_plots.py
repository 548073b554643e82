"""Force rows of the plots panel for a linkage with masses or loads (pure: reads the controller).

Two rows below the kinematic ones, against the same input angle:

- ``torque`` — the driving torque (N·m, counter-clockwise positive: what the motor applies to the
  driver; for a cylinder or a slider driven along its guide the driving force, N, positive
  extending, labelled so) and, when joints have friction, the driving effort with friction beside it;
- ``reaction`` — the selected joint's reaction (N): Fx, Fy and |F| of the force on each of its
  later-listed links (a prismatic joint: its normal force); for a selected link, |F| at each of
  its joints on that link.

The forces come from ``Workspace.forces`` (computed the first time they are plotted, then cached
by element value); NaN where the pose cannot be assembled breaks the lines like the kinematics.
"""
from __future__ import annotations

import numpy as np

from mechsketch.core import MechsketchError
from mechsketch.core.model.linkage import Linkage

from .plot_series import PLOTS, PlotData, Series

FORCE_ROWS = (("torque", "driving torque (N·m)"), ("reaction", "joint force (N)"))


def add_force_series(controller, data: PlotData, lk: Linkage, kind: str, ident: str) -> None:
    """Append the force rows and curves of ``lk`` to ``data`` (selection ``kind``/``ident``)."""
    if not lk.has_dynamics:
        return
    try:
        res = controller.workspace.forces(lk.id)
    except MechsketchError as exc:
        data.title += f" — forces: {exc}"
        return
    if len(res) != len(data.x):
        return
    data.rows = PLOTS + FORCE_ROWS
    S = data.series
    d = res.driver
    S.append(Series("torque", f"{d.column} ({d.link})", d.unit, d.values))
    if res.friction is not None:
        S.append(Series("torque", f"{d.column} with friction", d.unit, res.friction.driver.values))
    data.labels["torque"] = f"driving {d.kind} ({d.unit})"
    if kind == "joint":
        if ident in res.pins:
            for link, f in res.pins[ident].items():
                tag = ident if len(res.pins[ident]) == 1 else f"{ident}[{link}]"
                S += [Series("reaction", f"{tag}.Fx", "N", f[:, 0]), Series("reaction", f"{tag}.Fy", "N", f[:, 1]),
                      Series("reaction", f"|F {tag}|", "N", np.hypot(f[:, 0], f[:, 1]))]
        elif ident in res.slides:
            s = res.slides[ident]
            S.append(Series("reaction", f"{ident} normal force", "N", s.normal))
        data.labels["reaction"] = f"force at {ident} (N)"
    else:
        for j in lk.link(ident).joints:
            if j in res.pins or j in res.slides:
                f = res.reaction(j, ident) if j in res.pins else res.slides[j].force
                S.append(Series("reaction", f"|F {j} on {ident}|", "N", np.hypot(f[:, 0], f[:, 1])))
        data.labels["reaction"] = f"forces on {ident} (N)"
