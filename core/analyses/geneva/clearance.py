"""Independent check of a drawn Geneva drive with shapely: no overlap over a full revolution.

The wheel, the roller and the relieved locking disc are turned into polygons (chord sagitta ≤
``tol``), the roller and the disc are moved into the wheel's frame at every crank angle of a full
revolution (plus the exact engagement ends ±φ0), and shapely measures the distances, vectorised over
the angles. Polygons inscribed in arcs move each outline by at most ``tol``, so each distance is
exact to within 2·``tol``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from .geometry import GenevaGeometry, locking_disc_outline
from .kinematics import wheel_angle


@dataclass(frozen=True)
class ClearanceReport:
    """Smallest gaps over the revolution (mm) and where they occur (crank angle, rad).

    ``roller`` wheel–roller gap (the slot clearance c_s when the slot is drawn right);
    ``disc`` wheel–locking-disc gap (≥ c_l with a clearing relief); ``overlap_roller`` and
    ``overlap_disc``: any overlap at all; ``phi`` the angles checked (rad, shape (N,));
    ``roller_gap`` and ``disc_gap`` the gaps at each angle (mm, shape (N,)); ``tol`` the polygon
    chord tolerance (mm); the distances are exact to within 2·tol.
    """

    roller: float
    phi_roller: float
    disc: float
    phi_disc: float
    overlap_roller: bool
    overlap_disc: bool
    phi: np.ndarray
    roller_gap: np.ndarray
    disc_gap: np.ndarray
    tol: float


def _moved_polys(coords: np.ndarray, angle: np.ndarray, tx: np.ndarray, ty: np.ndarray) -> np.ndarray:
    """Polygons of ring ``coords`` (M, 2) rotated by ``angle`` (N,) then shifted: (N,) geometries."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    x = c * coords[:, 0] - s * coords[:, 1] + tx[:, None]
    y = s * coords[:, 0] + c * coords[:, 1] + ty[:, None]
    ring = np.stack([x, y], axis=2)
    return shapely.polygons(np.concatenate([ring, ring[:, :1]], axis=1))


def _overlaps(wheel: shapely.Geometry, others: np.ndarray, gap: np.ndarray) -> np.ndarray:
    """Whether each of ``others`` shares area with ``wheel`` (only the touching ones are intersected)."""
    out = np.zeros(gap.shape, bool)
    touch = np.nonzero(gap <= 0.0)[0]
    if touch.size:
        out[touch] = shapely.area(shapely.intersection(wheel, others[touch])) > 0
    return out


def check_clearances(geo: GenevaGeometry, samples: int = 720, tol: float = 5e-4,
                     relief_radius: float | None = None) -> ClearanceReport:
    """Sweep a full crank revolution and measure the wheel–roller and wheel–disc gaps with shapely.

    ``relief_radius`` replaces the drawn relief (mm), e.g. the classical R_o, to show that it does
    not clear. Works in the wheel's frame: one wheel polygon, N roller and N disc polygons.
    """
    d = geo.dims
    a = d.center_distance
    phi = -math.pi + 2 * math.pi * np.arange(samples) / samples
    phi = np.unique(np.concatenate([phi, [-d.phi0, d.phi0]]))
    eng = np.abs(phi) <= d.phi0
    theta = np.where(eng, wheel_angle(np.where(eng, phi, 0.0), d.lam), np.sign(phi) * math.pi / d.slots)
    # crank frame -> wheel frame: q_w = R(θ)·(R(φ)·q_c − (A, 0))
    rot = theta + phi
    tx, ty = -a * np.cos(theta), -a * np.sin(theta)
    # only the part of the wheel the driver can reach: within (driver reach + the crank centre's
    # travel in the wheel frame) of the crank centre's mid position (−A, 0)
    reach = max(d.crank_radius + geo.roller.outer.segments().radius[0], d.lock_disc_radius)
    reach += 2 * a * math.sin(math.pi / (2 * d.slots)) + 1.0
    wheel = shapely.intersection(shapely.Polygon(geo.wheel.outer.polyline(tol)),
                                 shapely.Point(-a, 0.0).buffer(reach, quad_segs=64))
    shapely.prepare(wheel)
    rollers = _moved_polys(geo.roller.outer.polyline(tol), rot, tx, ty)
    if relief_radius is None:
        disc_outline = geo.locking_disc.outer
    else:
        disc_outline, _ = locking_disc_outline(d.lock_disc_radius, relief_radius, a)
    # likewise only the part of the disc that can reach the wheel (NaN distance: nothing left)
    ring = shapely.Point(0.0, 0.0).buffer(d.outer_radius + 1.0, quad_segs=64)
    discs = shapely.intersection(_moved_polys(disc_outline.polyline(tol), rot, tx, ty), ring)
    gap_r = shapely.distance(wheel, rollers)
    gap_d = shapely.distance(wheel, discs)
    gap_d = np.where(np.isnan(gap_d), np.inf, gap_d)
    over_r, over_d = _overlaps(wheel, rollers, gap_r), _overlaps(wheel, discs, gap_d)
    kr, kd = int(np.argmin(gap_r)), int(np.argmin(gap_d))
    return ClearanceReport(
        roller=float(gap_r[kr]), phi_roller=float(phi[kr]), disc=float(gap_d[kd]), phi_disc=float(phi[kd]),
        overlap_roller=bool(over_r.any()), overlap_disc=bool(over_d.any()), phi=phi, roller_gap=gap_r,
        disc_gap=gap_d, tol=tol)
