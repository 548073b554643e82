"""The variables of a design study: which numbers of a linkage a study may change, and their keys.

A *design* is the linkage with some of these values changed. The keys:

- every key of the dimension table (:func:`~mechsketch.core.solver.dimensions.dimensions`):
  ``length:LINK:A:B`` (mm), ``angle:LINK:A:B:C`` (°), ``offset:LINK:P`` (mm), ``axis:LINK:P`` (°);
  setting one keeps every other dimension, as :class:`~mechsketch.core.solver.dimensions.SetDimension`;
- ``x:J`` and ``y:J`` (mm): the drawn position of a joint of the frame (a pivot or a guide's
  point); every moving link keeps its dimensions and the crank its drawn angle;
- ``point:LINK:J:x`` and ``point:LINK:J:y`` (mm): a further revolute joint of a link (a coupler
  point, a ternary link's third joint) in the link's own frame (origin its first revolute joint,
  x axis towards its second);
- ``mass:LINK`` (kg), ``inertia:LINK`` (kg·m², about the centre of mass), ``com:LINK:x`` and
  ``com:LINK:y`` (mm, drawn centre of mass);
- ``load:ID:fx`` / ``load:ID:fy`` (N, a point force), ``load:ID:torque`` (N·m), and of a spring or
  damper ``load:ID:stiffness`` (N/mm), ``load:ID:free_length`` (mm), ``load:ID:damping`` (N·s/mm).

The first three kinds change the geometry (they are applied in the order given, then the linkage
is re-assembled once at its drawn input, :mod:`.geometry`); the others only the kinetostatics.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import RequestError
from ..model.linkage import JointKind, Linkage
from ..model.loads import Damper, PointForce, Spring, Torque, default_inertia
from ..solver.dimensions import dimensions

#: kinds of variables that change the drawn geometry (and so the kinematics)
GEOMETRIC = ("dimension", "pivot", "point")


@dataclass(frozen=True)
class Variable:
    """One variable of a linkage: its ``key``, ``kind`` (``dimension``, ``pivot``, ``point``,
    ``mass``, ``inertia``, ``com``, ``load``), ``unit`` and its drawn (nominal) value."""

    key: str
    kind: str
    unit: str
    nominal: float

    @property
    def geometric(self) -> bool:
        return self.kind in GEOMETRIC


def _centroid(linkage: Linkage, link: str) -> tuple[float, float]:
    pts = [linkage.joint(j).at for j in linkage.link(link).joints]
    return (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))


def variables(linkage: Linkage) -> dict[str, Variable]:
    """Every variable of ``linkage`` by key, with its nominal value (see the module docstring)."""
    out: dict[str, Variable] = {}
    for d in dimensions(linkage):
        out[d.key] = Variable(d.key, "dimension", d.unit, d.value)
    for j in linkage.link(linkage.ground).joints:
        at = linkage.joint(j).at
        out[f"x:{j}"] = Variable(f"x:{j}", "pivot", "mm", float(at[0]))
        out[f"y:{j}"] = Variable(f"y:{j}", "pivot", "mm", float(at[1]))
    for lk in linkage.links:
        rs = [j for j in lk.joints if linkage.joint(j).kind is JointKind.R]
        if len(rs) >= 2 and lk.id != linkage.ground:
            o, e = complex(*linkage.joint(rs[0]).at), complex(*linkage.joint(rs[1]).at)
            u = (e - o) / abs(e - o) if e != o else 1 + 0j
            for rm in rs[2:]:
                p = (complex(*linkage.joint(rm).at) - o) / u
                out[f"point:{lk.id}:{rm}:x"] = Variable(f"point:{lk.id}:{rm}:x", "point", "mm", p.real)
                out[f"point:{lk.id}:{rm}:y"] = Variable(f"point:{lk.id}:{rm}:y", "point", "mm", p.imag)
        if lk.id == linkage.ground:
            continue
        m = linkage.mass_of(lk.id)
        mass = m.mass if m is not None else 0.0
        span = max((math.dist(linkage.joint(a).at, linkage.joint(b).at) for a in lk.joints for b in lk.joints),
                   default=0.0)
        inertia = m.inertia if m is not None and m.inertia is not None else default_inertia(mass, span)
        com = m.com if m is not None and m.com is not None else _centroid(linkage, lk.id)
        out[f"mass:{lk.id}"] = Variable(f"mass:{lk.id}", "mass", "kg", float(mass))
        out[f"inertia:{lk.id}"] = Variable(f"inertia:{lk.id}", "inertia", "kg·m²", float(inertia))
        out[f"com:{lk.id}:x"] = Variable(f"com:{lk.id}:x", "com", "mm", float(com[0]))
        out[f"com:{lk.id}:y"] = Variable(f"com:{lk.id}:y", "com", "mm", float(com[1]))
    for ld in linkage.loads:
        fields: list[tuple[str, str, float]] = []
        if isinstance(ld, PointForce):
            fields = [("fx", "N", ld.force[0]), ("fy", "N", ld.force[1])]
        elif isinstance(ld, Torque):
            fields = [("torque", "N·m", ld.torque)]
        elif isinstance(ld, Spring):
            free = ld.free_length if ld.free_length is not None else ld.drawn_length
            fields = [("stiffness", "N/mm", ld.stiffness), ("free_length", "mm", free)]
        elif isinstance(ld, Damper):
            fields = [("damping", "N·s/mm", ld.damping)]
        for name, unit, value in fields:
            key = f"load:{ld.id}:{name}"
            out[key] = Variable(key, "load", unit, float(value))
    return out


def check_keys(linkage: Linkage, keys, what: str = "variable") -> dict[str, Variable]:
    """The :class:`Variable` of each key of ``keys`` (in order); RequestError naming every key
    ``linkage`` does not have, with the keys it has of the same kind."""
    known = variables(linkage)
    bad = [k for k in keys if k not in known]
    if bad:
        lines = []
        for k in bad:
            head = str(k).split(":", 1)[0]
            same = [v for v in known if v.split(":", 1)[0] == head]
            hint = (f"; its {head} keys: {', '.join(same[:12])}{' …' if len(same) > 12 else ''}" if same else
                    f"; key kinds: length, angle, offset, axis, x, y, point, mass, inertia, com, load")
            lines.append(f"{what} {k!r}: linkage {linkage.id!r} has no such key{hint}")
        raise RequestError("\n".join(lines))
    return {k: known[k] for k in keys}


def design_values(linkage: Linkage, values: dict) -> tuple[dict[str, np.ndarray], int]:
    """``values`` (key -> scalar or array (D,)) checked and broadcast to float arrays (D,);
    returns them and D. RequestError for an unknown key, arrays of different lengths, or a value
    that is not a finite number (naming the key and the design index)."""
    if not isinstance(values, dict):
        raise RequestError("variants must be given as a dict {key: values}")
    check_keys(linkage, list(values))
    arrays = {}
    n = None
    for k, v in values.items():
        a = np.asarray(v)
        if a.dtype.kind not in "fiu" or a.ndim > 1:
            raise RequestError(f"variable {k!r}: give a number or a 1-D array of numbers, got {a.dtype} "
                               f"of shape {a.shape}")
        a = a.astype(float).reshape(-1)
        if a.size != 1:
            if n is not None and a.size != n:
                raise RequestError(f"variable {k!r} has {a.size} values, the others {n}: give every variable "
                                   "the same number of designs (or one value)")
            n = a.size
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise RequestError(f"variable {k!r}: design {int(bad[0])} has the value {a[bad[0]]!r}, not a finite number")
        arrays[k] = a
    n = 1 if n is None else n
    return {k: (np.full(n, a[0]) if a.size == 1 else a) for k, a in arrays.items()}, n


__all__ = ["GEOMETRIC", "Variable", "check_keys", "design_values", "variables"]
