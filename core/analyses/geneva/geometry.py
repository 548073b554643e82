"""Drawable Geneva drive: the wheel, locking disc, crank arm and roller as exact lines and arcs.

Frames (mm): the wheel is built about its centre O2 with slot k's axis at angle π + 2πk/z, so slot 0
points at the crank centre when the wheel rotation is 0 (mid-engagement, φ = 0); the driver parts
are built about the crank centre O1 with the crank arm along +x (the roller at (r, 0)).
:meth:`GenevaGeometry.placed` puts them in the world at any crank angle.

The wheel (seeds/NOTES.md, section B): z stadium slots (walls at ±w, w = r_p + c_s, from the
corner line x_c = A·cos(π/z) in to the bottom semicircle of radius w centred at x_b = A − r − c_b),
horn lands on the outer circle R_o = √(x_c² + w²), concave locking arcs of radius R_arc centred on
the bisectors at distance A, and the hub bore. The locking disc has radius R_L = R_arc − c_l and a
circular relief cut centred at distance A along the crank arm.

The relief. The classical radius R_o is slightly too small (notes). Here it is the smallest radius,
about that centre, whose circle contains every point of the disc that comes within c_l of the wheel
during the engagement: the wheel outline is offset by c_l (exact lines and arcs), moved into the
crank frame at each crank angle, and the farthest point from the relief centre among (a) offset
vertices inside the disc, (b) the farthest points of offset arcs inside the disc and (c) the
crossings of the offset outline with the disc circle is found in closed form per angle, then
maximised over the angle (grid, then zoom; relief.py). At the engagement ends the offset locking arc lies on
the disc circle; the limit of its crossing there (angle ±φ0 on the disc) is added in closed form.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ...errors import GeometryError
from ...model.geneva import WheelDimensions, require_valid
from ..contour import Contour, Part
from .kinematics import wheel_angle
from .relief import INSIDE_TOL, RELIEF_GRID, RELIEF_ZOOM, maximise, relief_values  # noqa: F401 (re-exported)

if TYPE_CHECKING:
    from ...model.geneva import Geneva

#: the relief radius drawn is the exact one rounded up to this step (mm)
RELIEF_ROUND = 1e-3
#: the default crank bore is this fraction of the locking disc's radius (capped by the relief)
CRANK_BORE_FRACTION = 0.25
#: sizes chosen by default keep their webs this far over the minimum web (issue 23: a part made at
#: exactly its minimum is read below it by other tools' rounding; the z = 8 locking disc was 1.0000 mm)
DEFAULT_WEB_MARGIN = 1.1


def wheel_outline(d: WheelDimensions) -> Contour:
    """The wheel's outer contour (CCW, wheel frame, slot 0 along −x), 6 vertices per slot.

    Per slot, from its lower corner: wall, bottom semicircle, wall, horn land (outer circle),
    locking arc (concave), horn land of the next slot.
    """
    z = d.slots
    land_b = math.tan(d.land_angle / 4.0)
    lock_b = -math.tan(d.lock_half_angle / 2.0)  # included angle 2·β_L, clockwise
    local = np.array([
        [d.x_c, -d.w], [d.x_b, -d.w], [d.x_b, d.w], [d.x_c, d.w],
        [d.outer_radius * math.cos(math.pi / z - d.gamma), d.outer_radius * math.sin(math.pi / z - d.gamma)],
        [d.outer_radius * math.cos(math.pi / z + d.gamma), d.outer_radius * math.sin(math.pi / z + d.gamma)],
    ])
    bul = np.array([0.0, -1.0, 0.0, land_b, lock_b, land_b])
    kinds = ("wall", "bottom", "wall", "land", "lock", "land")
    pts, bs, ks = [], [], []
    for k in range(z):
        a = math.pi + 2.0 * math.pi * k / z
        c, s = math.cos(a), math.sin(a)
        pts.append(local @ np.array([[c, s], [-s, c]]))
        bs.append(bul)
        ks.extend(kinds)
    return Contour(np.vstack(pts), np.concatenate(bs), tuple(ks))


def wheel_area_closed_form(d: WheelDimensions, bore: float) -> float:
    """The notes' closed-form wheel area (mm²): π R_o² − z[slot] − z·lens(R_o, R_arc, A) − π bore²."""
    ro, w, xc, xb, ra, a = d.outer_radius, d.w, d.x_c, d.x_b, d.lock_arc_radius, d.center_distance
    slot = 2 * w * (xc - xb) + math.pi * w * w / 2 + (ro * ro * math.acos(xc / ro) - xc * w)
    lens = (ro * ro * math.acos((a * a + ro * ro - ra * ra) / (2 * a * ro))
            + ra * ra * math.acos((a * a + ra * ra - ro * ro) / (2 * a * ra))
            - 0.5 * math.sqrt((-a + ro + ra) * (a + ro - ra) * (a - ro + ra) * (a + ro + ra)))
    return math.pi * ro * ro - d.slots * slot - d.slots * lens - math.pi * bore * bore


def locking_disc_outline(radius: float, relief_radius: float, a: float) -> tuple[Contour, float]:
    """The locking disc (CCW, crank frame) with the relief circle (centre (A, 0)) cut away, and the
    relief half-angle ψ_r on the disc (rad)."""
    xi = (a * a + radius * radius - relief_radius * relief_radius) / (2.0 * a)
    if not -radius < xi < radius:
        raise GeometryError(f"the relief circle (radius {relief_radius:.6g} mm at {a:.6g} mm) does not cut "
                            f"the locking disc (radius {radius:.6g} mm)")
    yi = math.sqrt(radius * radius - xi * xi)
    psi = math.atan2(yi, xi)
    kappa = math.atan2(yi, a - xi)
    pts = np.array([[xi, yi], [xi, -yi]])
    bul = np.array([math.tan((2 * math.pi - 2 * psi) / 4.0), -math.tan(kappa / 2.0)])
    return Contour(pts, bul, ("disc", "relief")), psi


def belt_outline(r1: float, r2: float, length: float) -> Contour:
    """The hull of circle (0, 0; r1) and circle (length, 0; r2): a crank arm (CCW, crank frame)."""
    t = math.acos((r1 - r2) / length)  # normal of the outer tangents: n·(C2 − C1) = r1 − r2
    c, s = math.cos(t), math.sin(t)
    pts = np.array([[r1 * c, -r1 * s], [length + r2 * c, -r2 * s], [length + r2 * c, r2 * s], [r1 * c, r1 * s]])
    bul = np.array([0.0, math.tan(2 * t / 4.0), 0.0, math.tan((2 * math.pi - 2 * t) / 4.0)])
    return Contour(pts, bul, ("line", "boss", "line", "hub"))


# -- the relief (the search: relief.py) ------------------------------------------------
@dataclass(frozen=True)
class Relief:
    """Relief radii about the point at distance A on the crank arm (mm): ``exact`` clears the wheel
    by c_l (worst at crank angle ``phi_exact``, rad); ``touch`` only avoids contact (c_l = 0, the
    notes' value); ``classical`` = R_o; ``limit_end`` the closed-form requirement at the engagement
    ends, √(R_L² + A² − 2·A·R_L·cos φ0); ``drawn`` = ``exact`` rounded up to 0.001 mm."""

    exact: float
    phi_exact: float
    touch: float
    classical: float
    limit_end: float
    drawn: float


def relief(d: WheelDimensions, clearance_lock: float) -> Relief:
    """The relief radii of the locking disc (see :class:`Relief`)."""
    outline = wheel_outline(d)
    a, rl = d.center_distance, d.lock_disc_radius
    lim = math.sqrt(rl * rl + a * a - 2 * a * rl * math.cos(d.phi0))
    off = outline.offset(clearance_lock) if clearance_lock > 0 else outline
    (v_c, x_c), (v_t, _) = maximise([off, outline], d)
    exact = max(v_c, lim)
    return Relief(exact=exact, phi_exact=x_c if v_c >= lim else d.phi0, touch=v_t,
                  classical=d.outer_radius, limit_end=lim,
                  drawn=math.ceil(exact / RELIEF_ROUND - 1e-9) * RELIEF_ROUND)


def arm_radii(crank_bore: float, pin: float, roller: float, min_web: float) -> tuple[float, float]:
    """The crank arm's hub and boss radii (mm): the bore and the pin each with a web of at least
    110 % of ``min_web`` (:data:`DEFAULT_WEB_MARGIN`) and half their own radius; the boss kept off the roller's radius so that the
    arm's end arc never lies on the roller's outline."""
    web = DEFAULT_WEB_MARGIN * min_web
    hub = crank_bore + max(web, 0.5 * crank_bore, 0.5 * pin)
    boss = pin + max(web, 0.5 * pin)
    if abs(boss - roller) <= 0.05 * roller:
        boss = pin + max(web, 0.5 * pin) + 0.1 * roller
    return hub, boss


# -- the assembled geometry --------------------------------------------------------------------
@dataclass(frozen=True)
class GenevaGeometry:
    """The drawable drive. Parts in their own frames (see the module docstring): ``wheel``,
    ``locking_disc``, ``crank_arm`` (its own plane, above the wheel), ``roller``.

    Sizes (mm): ``dims`` (closed-form limits: hub_max, land_angle, slot_depth, ...), ``relief``,
    ``wheel_bore``, ``crank_bore``, ``pin_radius``; angles (rad): ``relief_half_angle`` ψ_r on the
    disc, ``locking_margin`` = φ0 + β_L − ψ_r (> 0: the disc locks the wheel as soon as the roller
    leaves). ``wheel_area`` exact (mm²) and ``wheel_area_closed_form`` (the notes' formula).
    """

    element_id: str
    dims: WheelDimensions
    relief: Relief
    wheel_bore: float
    crank_bore: float
    pin_radius: float
    relief_half_angle: float
    locking_margin: float
    wheel: Part
    locking_disc: Part
    crank_arm: Part
    roller: Part
    crank_center: tuple[float, float]
    wheel_center: tuple[float, float]
    direction: float

    @property
    def wheel_area(self) -> float:
        return self.wheel.area

    @property
    def wheel_area_closed_form(self) -> float:
        return wheel_area_closed_form(self.dims, self.wheel_bore)

    def wheel_rotation(self, phi: float) -> float:
        """The wheel's world rotation from its built frame at crank angle ``phi`` (rad)."""
        d = self.dims
        if abs(phi) <= d.phi0:
            return self.direction - float(wheel_angle(phi, d.lam))
        return self.direction - math.copysign(math.pi / d.slots, phi)

    def placed(self, phi: float = 0.0) -> dict[str, Part]:
        """Every part in world coordinates (mm) at crank angle ``phi`` (rad, from the line of
        centres, in (−π, π]): ``wheel``, ``locking_disc``, ``crank_arm``, ``roller``."""
        crank = self.direction + phi
        return {"wheel": self.wheel.moved(self.wheel_rotation(phi), self.wheel_center),
                "locking_disc": self.locking_disc.moved(crank, self.crank_center),
                "crank_arm": self.crank_arm.moved(crank, self.crank_center),
                "roller": self.roller.moved(crank, self.crank_center)}


def geometry(element: "Geneva") -> GenevaGeometry:
    """Build the drawable drive of ``element``; :class:`GeometryError` names what cannot be built."""
    d = require_valid(element)
    rel = relief(d, element.clearance.lock)
    dr = element.drawing
    a = d.center_distance
    m = element.min_web
    wheel_bore = element.load.journal_radius if dr is None or dr.wheel_bore_radius is None else dr.wheel_bore_radius
    room = a - rel.drawn
    if dr is None or dr.crank_bore_radius is None:
        crank_bore = min(CRANK_BORE_FRACTION * d.lock_disc_radius, room - DEFAULT_WEB_MARGIN * m)
        if not crank_bore > 0:
            raise GeometryError(f"geneva {element.id!r}: no room for a crank bore: the locking disc's relief "
                                f"(radius {rel.drawn:.6g} mm at {a:.6g} mm) comes within A − relief = {room:.6g} mm "
                                f"of the crank centre, not more than 110 % of the minimum web {m:.6g} mm "
                                "(drawing.min_web; default sizes keep 10 % over it); change slots (fewer), "
                                "center_distance (larger) or roller_radius (smaller), or give drawing.crank_bore_radius")
    else:
        crank_bore = dr.crank_bore_radius
        if not crank_bore < room - m:
            raise GeometryError(f"geneva {element.id!r}: drawing.crank_bore_radius = {crank_bore:.6g} mm must be "
                                f"below A − relief radius − min_web = {room - m:.6g} mm, so that the locking disc "
                                f"keeps its thinnest section (over by {crank_bore - room + m:.6g} mm)")
    if not d.lock_disc_radius - crank_bore >= m:
        raise GeometryError(f"geneva {element.id!r}: the locking disc (radius {d.lock_disc_radius:.6g} mm) keeps "
                            f"{d.lock_disc_radius - crank_bore:.6g} mm around the crank bore, less than the minimum "
                            f"web {m:.6g} mm; change drawing.crank_bore_radius or drawing.locking_arc_radius")
    rp = element.roller_radius
    pin = min(0.5 * rp, rp - DEFAULT_WEB_MARGIN * m) if dr is None or dr.pin_radius is None else dr.pin_radius
    disc, psi = locking_disc_outline(d.lock_disc_radius, rel.drawn, a)
    margin = d.phi0 + d.lock_half_angle - psi
    if not margin > 0:
        raise GeometryError(f"geneva {element.id!r}: the relief (half-angle {math.degrees(psi):.4g}°) leaves no "
                            f"locking at the end of indexing: φ0 + β_L − ψ_r = {math.degrees(margin):.4g}° "
                            "must be > 0°")
    holes = (Contour.circle((0.0, 0.0), wheel_bore, "bore"),) if wheel_bore > 0 else ()
    wheel = Part("wheel", wheel_outline(d), holes)
    crank_holes = (Contour.circle((0.0, 0.0), crank_bore, "bore"),) if crank_bore > 0 else ()
    locking = Part("locking_disc", disc, crank_holes)
    r = d.crank_radius
    hub, boss = arm_radii(crank_bore, pin, rp, m)
    if not r - crank_bore - pin >= m:
        raise GeometryError(f"geneva {element.id!r}: the crank arm keeps {r - crank_bore - pin:.6g} mm between the "
                            f"crank bore and the roller pin, less than the minimum web {m:.6g} mm; change "
                            "drawing.crank_bore_radius or drawing.pin_radius")
    arm = Part("crank_arm", belt_outline(hub, boss, r),
               crank_holes + (Contour.circle((r, 0.0), pin, "pin"),))
    roller = Part("roller", Contour.circle((r, 0.0), rp, "roller"), (Contour.circle((r, 0.0), pin, "pin"),))
    return GenevaGeometry(
        element_id=element.id, dims=d, relief=rel, wheel_bore=wheel_bore, crank_bore=crank_bore,
        pin_radius=pin, relief_half_angle=psi, locking_margin=margin, wheel=wheel, locking_disc=locking,
        crank_arm=arm, roller=roller, crank_center=element.crank_center, wheel_center=element.wheel_center,
        direction=math.radians(element.wheel_direction_deg))
