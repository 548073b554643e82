"""A linkage by its dimensions: the table of every length and angle, and the undoable edit that
sets one of them and re-assembles the linkage (:mod:`.assembly`) at its drawn input.

Every link lists, in its own frame (:func:`~.assembly.frame_of`: origin its first revolute joint
r0, x axis towards its second r1):

- ``length:LINK:r0:r1`` — the distance of its first two revolute joints (a binary link's length,
  the ground's pivot distance), mm;
- for every further revolute joint rm (a ternary link's third joint, a coupler point):
  ``length:LINK:r0:rm`` and ``length:LINK:r1:rm`` (the sides of the triangle r0, r1, rm), mm, and
  ``angle:LINK:r0:r1:rm`` — the angle at r0 from r0→r1 to r0→rm, degrees (CCW positive);
- for every prismatic joint p on it: ``offset:LINK:p`` — the signed distance of r0 from the slide
  axis (positive: r0 on its left), mm — and, when the link has two revolute joints,
  ``axis:LINK:p`` — the axis's direction from r0→r1, degrees (a link with no revolute joints: from
  its first slide axis).

Setting one keeps every other dimension of the table (a length keeps the other sides of its
triangle; an angle keeps r0–rm; an offset keeps the axis's direction; an axis keeps the offset),
then :func:`~.assembly.reassemble` closes the linkage again group by group in the drawn assembly
modes — or refuses with the group and by how much it misses. :class:`SetDimension` is the core
edit (``Workspace.apply(SetDimension("fourbar", "length:crank:A:B", 50.0))``); its inverse puts
the old drawing back exactly.
"""
from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

from ..errors import EditError, GeometryError, StructureError, UnknownIdError
from ..model.edits import Edit, ReplaceElement
from ..model.limits import MAX_ANGLE_DEG, MAX_LENGTH_MM
from ..model.linkage import JointKind, Linkage
from ..model.scene import Scene
from .assembly import Shape, reassemble, shapes
from .plan import compile_plan

LENGTH, ANGLE, OFFSET, AXIS = "length", "angle", "offset", "axis"


@dataclass(frozen=True)
class Dimension:
    """One row of the dimension table: its ``key`` (see the module docstring), the ``link`` it
    belongs to, a ``label`` (``"B–C"``, ``"∠C B E"``, ``"offset of S"``, ``"axis of S"``), its
    ``value`` and ``unit`` (``"mm"`` or ``"°"``)."""

    key: str
    link: str
    label: str
    value: float
    unit: str

    @property
    def kind(self) -> str:
        return self.key.split(":", 1)[0]


def _deg(z: complex) -> float:
    return math.degrees(cmath.phase(z))


def _table(s: Shape, prismatic: list[str], ground: bool) -> list[Dimension]:
    out = []
    rs = s.revolute
    p = s.pts
    if len(rs) >= 2:
        out.append(Dimension(f"{LENGTH}:{s.link}:{rs[0]}:{rs[1]}", s.link, f"{rs[0]}–{rs[1]}", abs(p[rs[1]] - p[rs[0]]), "mm"))
    for rm in rs[2:]:
        out.append(Dimension(f"{LENGTH}:{s.link}:{rs[0]}:{rm}", s.link, f"{rs[0]}–{rm}", abs(p[rm] - p[rs[0]]), "mm"))
        out.append(Dimension(f"{LENGTH}:{s.link}:{rs[1]}:{rm}", s.link, f"{rs[1]}–{rm}", abs(p[rm] - p[rs[1]]), "mm"))
        out.append(Dimension(f"{ANGLE}:{s.link}:{rs[0]}:{rs[1]}:{rm}", s.link, f"∠{rs[1]} {rs[0]} {rm}",
                             _deg(p[rm] - p[rs[0]]), "°"))
    for k, pj in enumerate(prismatic):
        w = s.axes[pj]
        if rs:
            out.append(Dimension(f"{OFFSET}:{s.link}:{pj}", s.link, f"offset of {pj} from {rs[0]}",
                                 (w.conjugate() * (p[rs[0]] - p[pj])).imag, "mm"))
        if len(rs) >= 2:
            out.append(Dimension(f"{AXIS}:{s.link}:{pj}", s.link, f"axis of {pj} from {rs[0]}→{rs[1]}", _deg(w), "°"))
        elif ground:   # a frame with fewer than two pivots: the guide's direction in the plane
            out.append(Dimension(f"{AXIS}:{s.link}:{pj}", s.link, f"axis of {pj}", _deg(s.frame[1] * w), "°"))
        elif k > 0:
            out.append(Dimension(f"{AXIS}:{s.link}:{pj}", s.link, f"axis of {pj} from {prismatic[0]}", _deg(w), "°"))
    return out


def dimensions(linkage: Linkage) -> list[Dimension]:
    """Every dimension of ``linkage``, link by link in file order (see the module docstring)."""
    shp = shapes(linkage)
    out = []
    for lk in linkage.links:
        prismatic = [j for j in lk.joints if linkage.joint(j).kind is JointKind.P]
        out += _table(shp[lk.id], prismatic, lk.id == linkage.ground)
    return out


def _triangle(link: str, base: float, a: float, b: float, y_old: float, names: str) -> complex:
    """The point at distance a from (0, 0) and b from (base, 0), on the side of ``y_old``."""
    x = (a * a - b * b + base * base) / (2.0 * base)
    h2 = a * a - x * x
    if h2 < -1e-9 * max(a, b, base) ** 2:
        raise EditError(f"link {link}: the sides {names} ({base:.6g}, {a:.6g} and {b:.6g} mm) do not close a "
                        f"triangle (the longest exceeds the sum of the others by "
                        f"{2 * max(a, b, base) - (a + b + base):.6g} mm)")
    return complex(x, math.copysign(math.sqrt(max(h2, 0.0)), y_old if y_old != 0.0 else 1.0))


def reshaped(linkage: Linkage, key: str, value: float) -> dict[str, Shape]:
    """The link shapes of ``linkage`` with the dimension ``key`` set to ``value`` (mm or degrees),
    every other dimension of the table kept (see the module docstring)."""
    if not math.isfinite(value):
        raise EditError(f"dimension {key}: the value must be a finite number, got {value}")
    parts = key.split(":")
    limit, unit = (MAX_ANGLE_DEG, "°") if parts[0] in (ANGLE, AXIS) else (MAX_LENGTH_MM, "mm")
    if abs(value) > limit:
        raise EditError(f"dimension {key}: {value:g} {unit} is beyond ±{limit:g} {unit}")
    if len(parts) < 3 or parts[0] not in (LENGTH, ANGLE, OFFSET, AXIS):
        raise EditError(f"{key!r} is not a dimension key (length:LINK:A:B, angle:LINK:A:B:C, offset:LINK:P or "
                        "axis:LINK:P)")
    kind, link = parts[0], parts[1]
    known = {d.key for d in dimensions(linkage)}
    if key not in known:
        linkage.link(link)   # UnknownIdError naming the link
        raise UnknownIdError(f"link {link!r} of {linkage.id!r} has no dimension {key!r} (its dimensions: "
                             f"{', '.join(k for k in sorted(known) if k.split(':')[1] == link) or 'none'})")
    shp = shapes(linkage)
    s = shp[link].copy()
    shp[link] = s
    p, rs = s.pts, s.revolute
    if kind == LENGTH:
        if not value > 0.0:
            raise EditError(f"dimension {key}: a length must be positive, got {value:g} mm")
        a, b = parts[2], parts[3]
        base = abs(p[rs[1]])
        if (a, b) == (rs[0], rs[1]):
            for rm in rs[2:]:
                p[rm] = _triangle(link, value, abs(p[rm]), abs(p[rm] - p[rs[1]]), p[rm].imag,
                                  f"{rs[0]}–{rs[1]}, {rs[0]}–{rm}, {rs[1]}–{rm}")
            p[rs[1]] = complex(value, 0.0)
        elif a == rs[0]:
            p[b] = _triangle(link, base, value, abs(p[b] - p[rs[1]]), p[b].imag, f"{rs[0]}–{rs[1]}, {a}–{b}, {rs[1]}–{b}")
        else:
            p[b] = _triangle(link, base, abs(p[b]), value, p[b].imag, f"{rs[0]}–{rs[1]}, {rs[0]}–{b}, {a}–{b}")
    elif kind == ANGLE:
        rm = parts[4]
        p[rm] = abs(p[rm]) * cmath.exp(1j * math.radians(value))
    elif kind == OFFSET:
        pj = parts[2]
        w = s.axes[pj]
        old = (w.conjugate() * (p[rs[0]] - p[pj])).imag
        p[pj] = p[pj] - (value - old) * 1j * w
    else:   # AXIS: turn the axis about the foot of the perpendicular from r0 (keeping the offset)
        pj = parts[2]
        w = s.axes[pj]
        new = cmath.exp(1j * math.radians(value))
        if len(rs) < 2 and link == linkage.ground:   # the guide's direction in the plane
            new = new / s.frame[1]
        if rs:
            origin = p[rs[0]]
            offset = (w.conjugate() * (origin - p[pj])).imag
            along = (w.conjugate() * (p[pj] - origin)).real
            p[pj] = origin - offset * 1j * new + along * new
        s.axes[pj] = new
    return shp


def set_dimension(linkage: Linkage, key: str, value: float) -> Linkage:
    """``linkage`` with dimension ``key`` set to ``value`` (mm or degrees) and re-assembled at its
    drawn input in its drawn assembly modes; raises :class:`EditError` saying which group cannot
    close and by how much (the linkage is not changed), UnknownIdError for an unknown key."""
    shp = reshaped(linkage, key, float(value))
    try:
        plan = compile_plan(linkage)
    except (StructureError, GeometryError) as exc:   # a draft: no mechanism to re-assemble yet
        raise EditError(f"dimension {key} = {value:g}: linkage {linkage.id!r} cannot be re-assembled until "
                        f"it solves: {exc}") from None
    new = reassemble(linkage, shp, plan=plan)
    try:
        compile_plan(new)   # e.g. two joints of a link brought onto one point
    except GeometryError as exc:
        raise EditError(f"dimension {key} = {value:g}: {exc}") from None
    return new


@dataclass(frozen=True)
class SetDimension(Edit):
    """Set one dimension of linkage ``element_id`` (see :func:`set_dimension`); the inverse puts
    the old drawing back."""

    element_id: str
    key: str
    value: float
    label: str = "set dimension"

    def apply_to(self, scene: Scene) -> tuple[Scene, Edit]:
        old = scene.element(self.element_id)
        if not isinstance(old, Linkage):
            raise EditError(f"element {self.element_id!r} is a {old.type}; dimensions are a linkage's")
        new = set_dimension(old, self.key, self.value)
        return scene.with_element(new), ReplaceElement(old, self.label)


__all__ = ["Dimension", "SetDimension", "dimensions", "reshaped", "set_dimension"]
