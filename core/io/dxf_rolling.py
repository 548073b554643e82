"""DXF export of a rolling lever: the frame profile, the lever outline and the slider profile.

Millimetres ($INSUNITS = 4), one layer per part, each part in its own frame:

- ``FRAME_PROFILE`` (ground frame): the fixed centrode (pair D) as an arc-fitted LWPOLYLINE
  (biarcs, bulges), and the frame's pivot holes: the rocker pivot G and, with a drive, the crank
  pivot A (circles of ``pin_diameter``);
- ``LEVER`` (lever frame = drawn pose): the two working arcs as true ARCs, the lever circle over the
  contact angles u1 of the stroke and the slider circle over u2, the pin hole at f and, with a
  drive, the coupler pin hole at C;
- ``SLIDER_PROFILE`` (slider frame, equal to the ground at S5 = 0): the slider's conjugate profile
  Q as an arc-fitted LWPOLYLINE.

Freeform profiles are fitted by biarcs (:mod:`mechsketch.core.analyses.biarc`) against the exact
curve of the synthesis (the integrated centrode for the exact method, the spline through the
constructed points for the paper's and the corrected constructions); the maximum deviation is
measured, reported and kept below the tolerance.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from ..analyses.biarc import BiarcFit, fit_biarcs
from ..errors import GeometryError
from .dxf import new_document, save_document

LAYERS = {"FRAME_PROFILE": 1, "LEVER": 5, "SLIDER_PROFILE": 3}
#: tolerances below this are refused (mm): the biarc count grows like tolerance^(-1/3)
MIN_TOLERANCE = 1e-6


@dataclass
class RollingExport:
    """What was written: the biarc fits of both profiles and the drawn arcs (mm, degrees)."""

    path: str
    tolerance: float
    frame: BiarcFit
    slider: BiarcFit
    lever_arc_deg: tuple[float, float]
    slider_arc_deg: tuple[float, float]
    method: str
    construction_deviation: float  # constructions only: their profile's distance from the exact centrode

    def report(self) -> str:
        """A few lines for the CLI: layers, arc counts, deviations against the tolerance."""
        src = ("the exact curve (integrated centrode)" if self.method == "exact" else
               "the constructed profile (natural cubic spline through the points)")
        lines = [f"wrote {self.path} (DXF R2010, millimetres), deviations measured against {src}:",
                 f"  FRAME_PROFILE: fixed centrode as {len(self.frame.arcs)} arcs ({self.frame.spans} biarcs), "
                 f"max deviation {self.frame.max_deviation:.3e} mm (tolerance {self.tolerance:g} mm)",
                 f"  SLIDER_PROFILE: slider profile as {len(self.slider.arcs)} arcs ({self.slider.spans} biarcs), "
                 f"max deviation {self.slider.max_deviation:.3e} mm",
                 f"  LEVER: lever arc {self.lever_arc_deg[0]:.4f}° … {self.lever_arc_deg[1]:.4f}°, slider arc "
                 f"{self.slider_arc_deg[0]:.4f}° … {self.slider_arc_deg[1]:.4f}° (true arcs), pin hole(s)"]
        if self.method != "exact":
            lines.append(f"  note: the {self.method} construction itself deviates {self.construction_deviation:.4g} mm "
                         "from the exact centrode")
        return "\n".join(lines)


def _polyline(msp, fit: BiarcFit, layer: str) -> None:
    msp.add_lwpolyline(fit.vertices_and_bulges(), format="xyb", dxfattribs={"layer": layer})


def _arc_range(u: np.ndarray) -> tuple[float, float]:
    """Start and end angles (degrees, CCW) covering the angles u (rad, unwrapped)."""
    lo, hi = math.degrees(float(np.min(u))), math.degrees(float(np.max(u)))
    return lo, hi


def export_rolling(res, path: str | os.PathLike, tolerance: float = 0.001) -> RollingExport:
    """Write the DXF of a :class:`~mechsketch.core.analyses.rolling_synthesis.RollingSynthesis`.

    Raises :class:`GeometryError` for a tolerance that is not finite or below :data:`MIN_TOLERANCE`
    (or below ten times the integration error), :class:`~mechsketch.core.errors.ExportError` if the
    file cannot be written.
    """
    if not (math.isfinite(tolerance) and tolerance > 0.0):
        raise GeometryError(f"the DXF tolerance must be a positive number of millimetres, got {tolerance}")
    floor = max(MIN_TOLERANCE, 10.0 * (res.error_mm if math.isfinite(res.error_mm) else 0.0))
    if tolerance < floor:
        raise GeometryError(f"a DXF tolerance of {tolerance:g} mm is below what is exported faithfully "
                            f"({floor:g} mm)")
    el = res.element
    frame = _fit(res.frame_profile(), tolerance, "frame profile")
    slider = _fit(res.slider_profile(), tolerance, "slider profile")
    doc = new_document(LAYERS)
    msp = doc.modelspace()
    _polyline(msp, frame, "FRAME_PROFILE")
    _polyline(msp, slider, "SLIDER_PROFILE")
    r_pin = 0.5 * el.pin_diameter
    msp.add_circle(el.rocker_pivot, r_pin, dxfattribs={"layer": "FRAME_PROFILE"})
    lev = _arc_range(res.u1)
    sld = _arc_range(res.u2)
    msp.add_arc(el.lever_circle.center, el.lever_circle.radius, lev[0], lev[1], dxfattribs={"layer": "LEVER"})
    msp.add_arc(el.slider_circle.center, el.slider_circle.radius, sld[0], sld[1], dxfattribs={"layer": "LEVER"})
    msp.add_circle(el.pin, r_pin, dxfattribs={"layer": "LEVER"})
    if el.drive is not None:
        msp.add_circle(el.drive.crank_pivot, r_pin, dxfattribs={"layer": "FRAME_PROFILE"})
        msp.add_circle(el.drive.coupler_point, r_pin, dxfattribs={"layer": "LEVER"})
    save_document(doc, path)
    dev = math.nan
    if res.method != "exact":
        dev = float(np.max(res.reference().distance(res.P)))
    return RollingExport(str(path), tolerance, frame, slider, lev, sld, res.method, dev)


def _fit(curve_range, tolerance: float, what: str) -> BiarcFit:
    curve, t0, t1 = curve_range
    try:
        return fit_biarcs(curve, t0, t1, tolerance)
    except ValueError as exc:
        raise GeometryError(f"cannot fit the {what} within {tolerance:g} mm: {exc}") from None
