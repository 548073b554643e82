"""DXF export of the centrodes of one link of a linkage: the pitch curves of the non-circular gears
that can replace the linkage's motion of that link.

Millimetres ($INSUNITS = 4), one layer per body, each curve in its own body's frame (drawn pose):

- ``FIXED_CENTRODE``: the fixed centrode, in the frame (or in the reference link's frame when the
  centrodes are taken relative to another link), with the joints of that body as 1 mm circles;
- ``MOVING_CENTRODE``: the moving centrode in the link's frame, with the link's joints.

Each curve is fitted by biarcs (:func:`~mechsketch.core.analyses.biarc.fit_biarcs`) against the
exact centrode - the plan is solved at whatever input the fit asks for - and the largest deviation
is measured and kept below the tolerance. Where the relative motion passes through a translation
(the centre at infinity) the curve breaks: each stretch between breaks is its own polyline, cut
where the centre leaves ``limit`` mm around the link.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np

from ..analyses.biarc import BiarcFit, fit_biarcs
from ..analyses.centrodes import Centrodes, linkage_centrodes, runs
from ..errors import GeometryError
from ..model.linkage import Linkage
from ..solver.plan import Plan
from .dxf import new_document, save_document

LAYERS = {"FIXED_CENTRODE": 1, "MOVING_CENTRODE": 5}
#: the fit refuses tolerances below this (mm)
MIN_TOLERANCE = 1e-6
#: joint marks (circles) radius, mm
MARK_RADIUS = 1.0
#: a stretch shorter than this many samples is not exported (a blip near a translation)
MIN_RUN = 3


def default_limit(linkage: Linkage) -> float:
    """How far (mm) a centre may go before the curve is cut: 20 times the linkage's drawn size."""
    pts = np.asarray([j.at for j in linkage.joints], dtype=float)
    size = float(np.max(np.ptp(pts, axis=0))) if len(pts) > 1 else 100.0
    return 20.0 * max(size, 1.0)


@dataclass
class CentrodeExport:
    """What was written: per stretch the fits of both centrodes (mm), and the input ranges (rad)."""

    path: str
    link: str
    relative_to: str | None
    tolerance: float
    fixed: list[BiarcFit] = field(default_factory=list)
    moving: list[BiarcFit] = field(default_factory=list)
    ranges: list[tuple[float, float]] = field(default_factory=list)
    breaks: int = 0

    @property
    def max_deviation(self) -> float:
        """The largest measured deviation of any exported arc from the exact centrode (mm)."""
        return max((f.max_deviation for f in self.fixed + self.moving), default=0.0)

    def report(self) -> str:
        """A few lines: layers, arcs, deviations against the tolerance, breaks."""
        rel = "the frame" if self.relative_to is None else f"link {self.relative_to!r}"
        lines = [f"wrote {self.path} (DXF R2010, millimetres): centrodes of link {self.link!r} relative to {rel}, "
                 f"{len(self.ranges)} stretch(es), max deviation {self.max_deviation:.3e} mm "
                 f"(tolerance {self.tolerance:g} mm)",
                 f"  FIXED_CENTRODE: {sum(len(f.arcs) for f in self.fixed)} arcs",
                 f"  MOVING_CENTRODE: {sum(len(f.arcs) for f in self.moving)} arcs"]
        if self.breaks:
            lines.append(f"  the curves break {self.breaks} time(s) where the relative motion is a translation "
                         "(centre at infinity)")
        return "\n".join(lines)


def _stretches(c: Centrodes, limit: float, direction: float) -> list[tuple[float, float]]:
    """Input ranges (t0, t1) rad of the drawable stretches, in the sweep's direction."""
    n = len(c.input)
    step = direction * 2.0 * math.pi / n
    out = []
    for idx in runs(c.drawable(limit)):
        if len(idx) < MIN_RUN:
            continue
        t0 = float(c.input[idx[0]])
        t1 = t0 + step * (len(idx) if len(idx) == n else len(idx) - 1)   # a whole turn closes the loop
        out.append((t0, t1))
    return out


def export_centrodes(plan: Plan, link: str, relative_to: str | None, path: str | os.PathLike,
                     tolerance: float = 0.01, samples: int = 720, limit: float | None = None) -> CentrodeExport:
    """Write the centrodes of ``link`` of ``plan``'s linkage (relative to the frame or to
    ``relative_to``) to ``path`` as arc-fitted LWPOLYLINEs (see the module docstring).

    ``samples`` locate the stretches between translations; ``limit`` (mm, default
    :func:`default_limit`) cuts a curve running off towards a centre at infinity. Raises
    :class:`GeometryError` for a bad tolerance, an unknown link, centrodes that exist nowhere
    (the link only translates) or that are one point ("the centrode is a point at (x, y)": the
    link turns about a pivot it shares with the reference body), :class:`~mechsketch.core.errors.ExportError` if the file cannot
    be written.
    """
    if not (math.isfinite(tolerance) and tolerance >= MIN_TOLERANCE):
        raise GeometryError(f"the DXF tolerance must be at least {MIN_TOLERANCE:g} mm, got {tolerance}")
    linkage = plan.linkage
    sol = plan.sweep(samples=samples, order=1)
    c = linkage_centrodes(sol, linkage, link, relative_to)
    limit = default_limit(linkage) if limit is None else float(limit)
    direction = 1.0 if plan.omega >= 0 else -1.0
    stretches = _stretches(c, limit, direction)
    at = c.point(limit / 20.0)
    if at is not None:
        raise GeometryError(c.point_message(at))
    if not stretches:
        raise GeometryError(f"link {link!r} has no centrode to export: its motion relative to "
                            f"{relative_to or 'the frame'} is a translation (or it cannot be assembled) "
                            "at every sample")

    def curve(which: str):
        def at(t: np.ndarray) -> np.ndarray:
            sub = plan.evaluate(np.asarray(t, dtype=float), order=1)
            out = getattr(linkage_centrodes(sub, linkage, link, relative_to), which)
            if not np.all(np.isfinite(out)):
                raise GeometryError(f"the centrode of {link!r} cannot be evaluated between the samples "
                                    "(a translation or an assembly limit lies inside a stretch); use more samples")
            return out
        return at

    whole = len(stretches) == 1 and abs(stretches[0][1] - stretches[0][0]) >= 2 * math.pi * (1 - 1e-12)
    report = CentrodeExport(str(path), link, relative_to, tolerance, ranges=stretches,
                            breaks=0 if whole else len(stretches))
    doc = new_document(LAYERS)
    msp = doc.modelspace()
    for t0, t1 in stretches:
        for which, layer, fits in (("P", "FIXED_CENTRODE", report.fixed), ("p", "MOVING_CENTRODE", report.moving)):
            try:
                fit = fit_biarcs(curve(which), t0, t1, tolerance)
            except ValueError as exc:
                raise GeometryError(f"cannot fit the {layer.lower().replace('_', ' ')} of {link!r} within "
                                    f"{tolerance:g} mm: {exc}") from None
            fits.append(fit)
            msp.add_lwpolyline(fit.vertices_and_bulges(), format="xyb", dxfattribs={"layer": layer})
    fixed_body = linkage.ground if relative_to in (None, linkage.ground) else relative_to
    for body, layer in ((fixed_body, "FIXED_CENTRODE"), (link, "MOVING_CENTRODE")):
        for jid in linkage.link(body).joints:
            msp.add_circle(linkage.joint(jid).at, MARK_RADIUS, dxfattribs={"layer": layer})
    save_document(doc, path)
    return report
