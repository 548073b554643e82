"""Error estimates of the kinetostatics: for every force column, per sample, how far it may be
from the exact forces of the drawn mechanism (N, N·m), from the conditioning of the group solves.

Each class-II group's reactions solve a 2×2 system whose determinant is the group's kinematic one
(conditioning c, |sin μ| for an RRR), so a group multiplies the errors of the loads it receives
by ~1/c and adds its own rounding. Walking the groups as the pass does, last first, per sample:

- the group's kinematics (the accelerations of its inertia loads, the arms of every load) carry
  the relative error the kinematics estimates for its rates (``Solution.rate_error``:
  8·eps·(1 + coordinates/size)/c², /c for PRP and RPP), plus what the links it hangs on carry,
  amplified by 1/c: ``k_g = rate_error_g + max(k of its known links)/c``;
- its reactions R_g (the sum of the magnitudes of the forces at its joints, N) then have the
  error ``E_g = (K·eps/c + k_g)·R_g + (errors of the reactions later groups passed onto its
  links)/c``, and E_g is passed on to the links it hangs on (K = 16 bounds the rounding of the
  few products and sums of one solve);
- the driver's effort takes the errors passed onto the driver link (times the largest arm about
  the pivot for a crank's torque), the frame's shaking force and moment those passed onto the
  frame and the driver link.

It is an estimate, not a bound proved for every input, but a conservative one: the tests compare
it with the error against the 50-digit equilibrium of the whole mechanism, well-conditioned and
near a dead point (a fixed group, which does not move, adds only its rounding).
"""
from __future__ import annotations

import numpy as np

from ...model.linkage import JointKind
from ...solver.plan import Plan, Solution
from .static import MM

#: the rounding of one group's solve, in units of eps·R/c
K_SOLVE = 16.0


def _abs(v) -> np.ndarray:
    """|v| of an (N, 2) force array, NaN kept."""
    return np.hypot(v[:, 0], v[:, 1])


def _chain(plan: Plan, sol: Solution, n: int) -> dict[str, np.ndarray]:
    """Per link, the relative error estimate of its kinematics (its group's and, amplified, its
    known links'), (N,)."""
    lk = plan.linkage
    kin: dict[str, np.ndarray] = {lk.ground: np.zeros(n)}
    drive = plan.drive
    for k in getattr(drive, "known", (lk.driver.link,)):
        kin[k] = np.zeros(n)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for step in plan.steps:
            g = step.group
            c = np.broadcast_to(np.asarray(sol.group_output(g.name).cond, dtype=float), (n,))
            up = np.maximum(kin.get(g.known_i, 0.0), kin.get(g.known_j, 0.0))
            own = sol.rate_error(g.name)
            kin[g.link_i] = kin[g.link_j] = own + (up / c if not g.fixed else up)
    for extra, base in getattr(drive, "extra", {}).items():   # a cylinder's rod follows its barrel
        kin[extra] = kin[base]
    return kin


def _reaction_size(res, joints) -> np.ndarray:
    """Σ over ``joints`` of the largest force any of their reported pairs or slides carries, N."""
    total = np.zeros(len(res))
    for j in joints:
        if j in res.pins:
            total = total + np.max([_abs(v) for v in res.pins[j].values()], axis=0)
        elif j in res.slides:
            total = total + np.abs(res.slides[j].normal)
    return total


def _reach(lk, link: str, about: complex) -> float:
    """The largest drawn distance (mm) from ``about`` to a joint of ``link``."""
    return max((abs(complex(*lk.joint(j).at) - about) for j in lk.link(link).joints), default=0.0)


def force_errors(res, plan: Plan, sol: Solution) -> dict[str, np.ndarray]:
    """Estimated absolute error (N or N·m, (N,)) of every force column of ``res`` (named as
    :func:`~.report.force_columns` names them; ``J.Fx`` and ``J.Fy`` share the estimate of the
    force's size), and of every slide's ``normal`` and ``moment`` (``slide.J.normal``,
    ``slide.J.moment``). NaN where the forces are not valid. See the module docstring."""
    lk = plan.linkage
    n = len(res)
    eps = np.finfo(float).eps
    kin = _chain(plan, sol, n)
    passed = {k: np.zeros(n) for k in lk.link_ids}        # errors of reactions passed onto a link, N
    joint_err: dict[str, np.ndarray] = {}
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for step in reversed(plan.steps):
            g = step.group
            c = np.broadcast_to(np.asarray(sol.group_output(g.name).cond, dtype=float), (n,))
            size = _reaction_size(res, g.joints)
            k_g = np.maximum(kin[g.link_i], kin[g.link_j])
            inc = passed[g.link_i] + passed[g.link_j]
            for extra, base in getattr(plan.drive, "extra", {}).items():
                if base in (g.link_i, g.link_j):
                    inc = inc + passed[extra]
            e = (K_SOLVE * eps / c + k_g) * size + inc / c
            for j in g.joints:
                joint_err[j] = np.maximum(joint_err.get(j, 0.0), e)
            passed[g.known_i] = passed[g.known_i] + e
            if g.known_j != g.known_i:
                passed[g.known_j] = passed[g.known_j] + e
        drv = lk.driver
        pivot = complex(*lk.joint(drv.pivot).at)
        d_err = passed[drv.link]
        effort = np.abs(res.driver.values)
        if res.driver.kind == "torque":
            e_drv = MM * d_err * _reach(lk, drv.link, pivot) + K_SOLVE * eps * effort
        else:
            e_drv = d_err + K_SOLVE * eps * effort
        joint_err[drv.pivot] = np.maximum(joint_err.get(drv.pivot, 0.0), d_err)
        shake_f = passed[lk.ground] + d_err
        shake_m = MM * (passed[lk.ground] * _reach(lk, lk.ground, pivot) + d_err * _reach(lk, drv.link, pivot)) + e_drv
    out: dict[str, np.ndarray] = {res.driver.column: e_drv}
    for j in lk.joints:
        if j.kind is JointKind.R and j.id in res.pins:
            e = joint_err.get(j.id, np.zeros(n))
            for m, link in enumerate(res.pins[j.id]):
                prefix = j.id if m == 0 else f"{j.id}[{link}]"
                out[f"{prefix}.Fx"] = out[f"{prefix}.Fy"] = e
    out["shaking.Fx"] = out["shaking.Fy"] = shake_f
    out["shaking.M"] = shake_m
    if res.friction is not None:
        top = np.nanmax(np.abs(res.friction.driver.values), initial=0.0)
        out[f"{res.driver.column}_friction"] = e_drv + 1e-13 * top     # the iteration's tolerance
    for jid, s in res.slides.items():
        e = joint_err.get(jid, np.zeros(n))
        out[f"slide.{jid}.normal"] = e
        out[f"slide.{jid}.moment"] = MM * e * max(_reach(lk, s.on, complex(*lk.joint(jid).at)), 1.0)
    valid = res.valid
    return {k: np.where(valid, v, np.nan) for k, v in out.items()}


__all__ = ["K_SOLVE", "force_errors"]
