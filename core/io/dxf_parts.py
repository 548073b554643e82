"""DXF writer of a laid-out sheet of parts (:class:`~mechsketch.core.analyses.parts.Sheet`).

It only serialises: the parts were built and checked before. R2010, millimetres ($INSUNITS = 4,
$MEASUREMENT = 1), header extents ($EXTMIN/$EXTMAX) set to the drawing's exact bounds, one layer
per part (its name). Only cut geometry by default: part outlines and holes. With ``annotate``,
the part names (TEXT) and the drawn curves (traced coupler curves) are added on layers whose
names start with ``NOTES_`` (``NOTES_LABELS``, ``NOTES_TRACE_<name>``), which a CAM program that
cuts every layer is told to leave out by their name.

Two entity styles (``arcs``):

- ``"bulge"``: each contour one closed LWPOLYLINE whose arcs are bulges (true arcs, no chords);
  an arc of more than 180° is written as two (GDAL misreads such bulges: see
  :mod:`.cut_paths`);
- ``"entities"``: LINE and ARC entities (for older readers that drop or misread bulges:
  dxf2gcode, dime, some plasma and laser importers); an ARC is always counter-clockwise in DXF,
  so a clockwise arc is written from its end.

Full circles (bores) are CIRCLE entities in both styles. No segment shorter than
:func:`~.cut_paths.min_segment` is ever written: the writer refuses the sheet instead.
"""
from __future__ import annotations

import math
import os
import re

import numpy as np

from ..analyses.contour import Contour
from ..analyses.parts import Sheet, is_circle
from ..errors import ExportError
from .cut_paths import DXF_MAX_SWEEP, min_segment, split_arcs
from .dxf import new_document, save_document

ARC_STYLES = ("bulge", "entities")
#: layers that are not cut start with this
NOTES = "NOTES_"
LABEL_LAYER = NOTES + "LABELS"
_BAD = re.compile(r"[<>/\\\":;?*|=`,\s]")


def layer_name(name: str) -> str:
    """A DXF-safe layer name for a part or curve name."""
    return _BAD.sub("_", name) or "part"


def trace_layer(name: str) -> str:
    """The notes layer of a drawn curve (a traced coupler curve)."""
    return layer_name(f"{NOTES}TRACE_{name}")


def _write_contour(msp, c: Contour, layer: str, arcs: str, shortest: float, what: str, closed: bool = True) -> None:
    attribs = {"layer": layer}
    circ = is_circle(c) if closed else None
    if circ is not None:
        if not 2 * math.pi * circ[1] >= shortest:
            raise ExportError(f"{what} is a circle of radius {circ[1]:.3g} mm: too small to cut (nothing was written)")
        msp.add_circle(circ[0], circ[1], dxfattribs=attribs)
        return
    if arcs == "bulge":
        c = split_arcs(c, DXF_MAX_SWEEP, shortest, what, closed)
        verts = [(float(x), float(y), float(b)) for (x, y), b in zip(np.asarray(c.points, float), c.bulges)]
        if not closed:
            verts[-1] = (verts[-1][0], verts[-1][1], 0.0)
        msp.add_lwpolyline(verts, format="xyb", close=closed, dxfattribs=attribs)
        return
    c = split_arcs(c, 2 * math.pi, shortest, what, closed)   # only checks the lengths
    sg = c.segments()
    n = len(c) if closed else len(c) - 1
    for k in range(n):
        p0, p1 = sg.p0[k], sg.p1[k]
        if not sg.is_arc[k]:
            msp.add_line((float(p0[0]), float(p0[1])), (float(p1[0]), float(p1[1])), dxfattribs=attribs)
            continue
        a0 = math.degrees(sg.a0[k])
        a1 = a0 + math.degrees(sg.theta[k])
        start, end = (a0, a1) if sg.theta[k] > 0 else (a1, a0)
        msp.add_arc((float(sg.centre[k, 0]), float(sg.centre[k, 1])), float(sg.radius[k]),
                    start % 360.0, end % 360.0, dxfattribs=attribs)


def sheet_document(sheet: Sheet, arcs: str = "bulge", annotate: bool = False):
    """An ezdxf document of ``sheet`` (see the module docstring)."""
    if arcs not in ARC_STYLES:
        raise ExportError(f"--arcs must be one of {', '.join(ARC_STYLES)}; got {arcs!r}")
    layers = {}
    for k, p in enumerate(sheet.parts):
        layers.setdefault(layer_name(p.name), 1 + k % 6)
    if annotate:
        for c in sheet.curves:
            layers.setdefault(trace_layer(c.name), 8)
        if sheet.labels:
            layers[LABEL_LAYER] = 7
    doc = new_document(layers)
    msp = doc.modelspace()
    x0, y0, x1, y1 = sheet.bounds
    shortest = min_segment(max(x1 - x0, y1 - y0))
    for p in sheet.parts:
        for k, c in enumerate(p.contours):
            what = f"part {p.name!r}, " + ("its outline" if p.outer is not None and k == 0 else "a hole")
            _write_contour(msp, c, layer_name(p.name), arcs, shortest, what)
    if annotate:
        for cv in sheet.curves:
            _write_contour(msp, Contour(cv.points, cv.bulges), trace_layer(cv.name), arcs, shortest,
                           f"the curve {cv.name!r}", cv.closed)
        for lb in sheet.labels:
            msp.add_text(lb.text, height=lb.height, dxfattribs={"layer": LABEL_LAYER, "insert": (lb.at[0], lb.at[1])})
    # ezdxf copies the modelspace's extents and limits into the header when it saves
    msp.dxf.extmin, msp.dxf.extmax = (x0, y0, 0.0), (x1, y1, 0.0)
    msp.dxf.limmin, msp.dxf.limmax = (x0, y0), (x1, y1)
    doc.header["$EXTMIN"], doc.header["$EXTMAX"] = (x0, y0, 0.0), (x1, y1, 0.0)
    return doc


def write_dxf(sheet: Sheet, path: str | os.PathLike, arcs: str = "bulge", annotate: bool = False) -> None:
    """Write ``sheet`` to ``path`` atomically (an overwritten file keeps its mode);
    :class:`ExportError` names the path when it cannot be written."""
    save_document(sheet_document(sheet, arcs, annotate), path)
