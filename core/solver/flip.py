"""Flip the assembly mode of one Assur group: a pure function over the authored linkage (Qt-free).

The drawn pose decides each group's assembly mode, so flipping a mode means redrawing the pose:

- RRR: the inner joint L goes to its mirror image across the line through the outer joints M, H;
  link i turns about M and link j about H (all their points go along rigidly), lengths unchanged.
- RRP: the slider pin L goes to the other root on its line along the guide; the rod turns about
  M, the slider translates along the guide.
- RPR: the other root of the slide; both links turn together, each about its own pin.

Groups solved later are then re-assembled on the new pose with their lengths and modes kept, by
running the linkage's own compiled steps once at the drawn driver angle. PRP and RPP groups have no
assembly mode.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..errors import EditError, GeometryError
from ..model.edits import ReplaceElement
from ..model.linkage import JointKind, Linkage
from . import kernels as K
from .assembly import reassemble
from .plan import Plan, compile_plan
from .structure import MODAL_KINDS, GroupKind

#: kinds whose assembly mode can be flipped
FLIPPABLE = MODAL_KINDS


def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


def _one(z) -> complex:
    """The single sample of a (1,) array or a scalar."""
    return complex(np.asarray(z).reshape(-1)[0])


def _flipped_states(plan: Plan, states: dict[str, K.LinkState], index: int) -> None:
    """Put the flipped states of step ``index``'s two links into ``states`` (one sample)."""
    g = plan.steps[index].group
    link = plan.linkage
    at = {j.id: _c(j.at) for j in link.joints}
    mi, ki = states[g.known_i], states[g.known_j]
    if g.kind is GroupKind.RRR:
        m0, h0, l0 = at[g.outer_i], at[g.outer_j], at[g.inner]
        M, H, L = _one(mi.point(m0)), _one(ki.point(h0)), _one(states[g.link_i].point(l0))
        if abs(H - M) == 0.0:
            raise GeometryError(f"group {g.name}: outer joints {g.outer_i} and {g.outer_j} coincide")
        d = (H - M) / abs(H - M)
        L2 = M + ((L - M) / d).conjugate() * d
        states[g.link_i] = K.LinkState(m0, np.array([M]), np.array([(L2 - M) / (L - M)]))
        states[g.link_j] = K.LinkState(h0, np.array([H]), np.array([(L2 - H) / (L - H)]))
    elif g.kind is GroupKind.RRP:
        m0, l0 = at[g.outer_i], at[g.inner]
        axis = link.joint(g.outer_j)
        u = _one(ki.rot) * complex(math.cos(math.radians(axis.axis_deg or 0.0)),
                                   math.sin(math.radians(axis.axis_deg or 0.0)))
        M, L = _one(mi.point(m0)), _one(states[g.link_i].point(l0))
        L2 = L - 2.0 * K.dot(np.asarray(u), np.asarray(L - M)).item() * u
        states[g.link_i] = K.LinkState(m0, np.array([M]), np.array([(L2 - M) / (L - M)]))
        states[g.link_j] = K.LinkState(l0, np.array([L2]), np.array([_one(ki.rot)]))
    elif g.kind is GroupKind.RPR:
        m0, h0 = at[g.outer_i], at[g.outer_j]
        axis = link.joint(g.inner)
        u0 = complex(math.cos(math.radians(axis.axis_deg or 0.0)), math.sin(math.radians(axis.axis_deg or 0.0)))
        c = K.cross(np.asarray(u0), np.asarray(m0 - h0)).item()
        M, H = _one(mi.point(m0)), _one(ki.point(h0))
        d = M - H
        u = _one(states[g.link_i].rot) * u0
        sigma = K.dot(np.asarray(u), np.asarray(d)).item()
        r = (d / (-sigma + 1j * c)) / u
        rot = _one(states[g.link_i].rot) * r
        states[g.link_i] = K.LinkState(m0, np.array([M]), np.array([rot]))
        states[g.link_j] = K.LinkState(h0, np.array([H]), np.array([rot]))
    else:
        raise GeometryError(f"group {g.name} ({g.kind}) has no assembly mode to flip")


def flip_group(linkage: Linkage, group: str) -> Linkage:
    """The linkage redrawn with group ``group``'s assembly mode flipped (see the module doc).

    Raises :class:`GeometryError` if the group has no mode, or if a later group cannot be
    assembled on the flipped pose; :class:`StructureError` if the linkage does not decompose.
    """
    plan = compile_plan(linkage)
    names = [s.group.name for s in plan.steps]
    if group not in names:
        raise GeometryError(f"linkage {linkage.id!r} has no group {group!r} (groups: {', '.join(names)})")
    index = names.index(group)
    if plan.drive is not None and plan.drive.linear:   # an actuator's groups: closed again in order
        if plan.steps[index].group.kind not in FLIPPABLE:
            raise GeometryError(f"group {group} ({plan.steps[index].group.kind}) has no assembly mode to flip")
        try:
            return reassemble(linkage, flip=group, plan=plan)
        except EditError as exc:
            raise GeometryError(f"flipping {group}: {exc}; the drawing is unchanged") from None
    inputs = np.array([plan.theta0])
    states: dict[str, K.LinkState] = {
        linkage.ground: K.ground_state(),
        linkage.driver.link: K.crank(plan.pivot, plan.theta0, inputs, 0.0, 0.0, 0),
    }
    moved: set[str] = set()   # links whose pose the flip changes
    with np.errstate(invalid="ignore", divide="ignore"):
        for k, step in enumerate(plan.steps):
            out = step.run(states, 0, None)  # the drawn pose: no branch point crossed
            g = step.group
            states[g.link_i], states[g.link_j] = out.state_i, out.state_j
            if k == index:
                _flipped_states(plan, states, k)
                moved.update((g.link_i, g.link_j))
            elif moved.intersection(step.needs):
                moved.update((g.link_i, g.link_j))
                if not bool(np.all(out.ok)):
                    raise GeometryError(f"flipping {group} leaves group {step.group.name} unassemblable "
                                    f"at the drawn driver angle; the drawing is unchanged")
    joints = []
    for j in linkage.joints:
        if plan.reporter[j.id] not in moved:
            joints.append(j)
            continue
        st = states[plan.reporter[j.id]]
        p = _one(st.point(_c(j.at)))
        if not (math.isfinite(p.real) and math.isfinite(p.imag)):
            raise GeometryError(f"flipping {group} gives no position for joint {j.id}; the drawing is unchanged")
        new = j.moved((p.real, p.imag))
        if j.kind is JointKind.P:
            turn = math.degrees(np.angle(_one(st.rot)))
            new = replace(new, axis_deg=_wrap_deg((j.axis_deg or 0.0) + turn))
        joints.append(new)
    return replace(linkage, joints=tuple(joints))


def _wrap_deg(a: float) -> float:
    """An angle in degrees brought into (-180, 180], rounded off at 1e-9°."""
    a = math.remainder(a, 360.0)
    a = 180.0 if a == -180.0 else a
    return round(a, 9) + 0.0


def flip_edit(linkage: Linkage, group: str) -> ReplaceElement:
    """The reversible edit flipping ``group``'s mode (for ``controller.push``)."""
    return ReplaceElement(flip_group(linkage, group), f"flip {group}")


def group_modes(linkage: Linkage) -> dict[str, int | None]:
    """Assembly mode (+1 / −1, None: no mode) of each group, from the drawn pose."""
    plan = compile_plan(linkage)
    sol = plan.evaluate(np.array([plan.theta0]), order=0)
    return {g.name: sol.group_output(g.name).mode for g in sol.groups}


__all__ = ["FLIPPABLE", "flip_edit", "flip_group", "group_modes"]
