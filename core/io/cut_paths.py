"""What the part writers emit, segment by segment: arcs no wider than a reader reads exactly, and
no segment a reader cannot take (issue 23, items 1 and 2).

- GDAL (3.6) misreads LWPOLYLINE bulges of more than 180° for some chord directions: the DXF
  writer cuts such arcs in two (:data:`DXF_MAX_SWEEP`).
- An SVG elliptical arc is given by its end points and radius; its centre is found again from
  them, which is ill-conditioned near 180° (the chord nearly a diameter: an arc of 179.997° was
  read 6.9e-4 mm off). The SVG writer cuts arcs to at most 90° (:data:`SVG_MAX_SWEEP`), where the
  centre follows the end points to within √2 of their rounding.
- A line or arc shorter than :func:`min_segment` (FreeCAD's confusion distance 1e-7 mm, or 1e-9
  of the drawing's size) makes FreeCAD refuse the whole file and CAM importers fail; no writer
  emits one: :func:`split_arcs` raises :class:`ExportError` naming the part and the place.
"""
from __future__ import annotations

import math

import numpy as np

from ..analyses.contour import Contour
from ..errors import ExportError

#: the widest arc (rad) written as one LWPOLYLINE bulge (bulge ≤ 1)
DXF_MAX_SWEEP = math.pi
#: the widest arc (rad) written as one SVG arc command
SVG_MAX_SWEEP = math.pi / 2
#: the shortest segment (mm) any reader takes: FreeCAD's Precision::Confusion()
CONFUSION = 1e-7


def min_segment(size: float) -> float:
    """The shortest line or arc (mm) a writer emits on a drawing of ``size`` mm."""
    return max(CONFUSION, 1e-9 * size)


def split_arcs(c: Contour, max_sweep: float, shortest: float, what: str, closed: bool = True) -> Contour:
    """``c`` with every arc of more than ``max_sweep`` rad cut into equal arcs (the same circle;
    bulges tan(θ/4n)); :class:`ExportError` if a segment (or an open curve's last segment, when
    ``closed`` is False, is left out) is shorter than ``shortest`` mm."""
    sg = c.segments()
    n_seg = len(c) if closed else len(c) - 1
    chord = np.hypot(*(sg.p1 - sg.p0).T)
    length = np.where(sg.is_arc, sg.length, chord)
    short = np.nonzero(length[:n_seg] < shortest)[0]
    if len(short):
        k = int(short[0])
        x, y = sg.p0[k]
        raise ExportError(f"{what} has a segment {length[k]:.3g} mm long at ({x:.6g}, {y:.6g}) mm, shorter than "
                          f"{shortest:.3g} mm: CAD and CAM readers refuse it (nothing was written)")
    pieces = np.where(sg.is_arc, np.ceil(np.abs(sg.theta) / max_sweep - 1e-12), 1).astype(int)
    pieces = np.maximum(pieces, 1)
    if not closed:
        pieces[-1] = 1   # an open curve's last bulge closes nothing
    if (pieces == 1).all():
        return c
    pts, bul, kinds = [], [], []
    for k in range(len(c)):
        m = int(pieces[k])
        kind = c.kinds[k] if c.kinds else ""
        if m == 1:
            pts.append(sg.p0[k])
            bul.append(float(c.bulges[k]))
            kinds.append(kind)
            continue
        step = sg.theta[k] / m
        for q in range(m):
            ang = sg.a0[k] + q * step
            pts.append(sg.p0[k] if q == 0 else sg.centre[k] + sg.radius[k] * np.array([math.cos(ang), math.sin(ang)]))
            bul.append(math.tan(step / 4.0))
            kinds.append(kind)
    return Contour(np.array(pts), np.array(bul), tuple(kinds) if c.kinds else ())
