"""DXF writer of a laid-out sheet of parts (:class:`~mechsketch.core.analyses.parts.Sheet`).

It only serialises: the parts were built and checked before. R2010, millimetres ($INSUNITS = 4,
$MEASUREMENT = 1), header extents ($EXTMIN/$EXTMAX) set to the drawing's exact bounds, one layer
per part (its name), one per drawn curve (``trace_<name>``) and ``LABELS`` for the part names.

Two entity styles (``arcs``):

- ``"bulge"``: each contour one closed LWPOLYLINE whose arcs are bulges (true arcs, no chords);
- ``"entities"``: LINE and ARC entities (for older readers that drop bulges: dxf2gcode, dime);
  an ARC is always counter-clockwise in DXF, so a clockwise arc is written from its end.

Full circles (bores) are CIRCLE entities in both styles.
"""
from __future__ import annotations

import math
import os
import re

import numpy as np

from ..analyses.contour import Contour
from ..analyses.parts import Sheet, is_circle
from ..errors import ExportError
from .dxf import new_document, save_document

ARC_STYLES = ("bulge", "entities")
LABEL_LAYER = "LABELS"
_BAD = re.compile(r"[<>/\\\":;?*|=`,\s]")


def layer_name(name: str) -> str:
    """A DXF-safe layer name for a part or curve name."""
    return _BAD.sub("_", name) or "part"


def _write_contour(msp, c: Contour, layer: str, arcs: str, closed: bool = True) -> None:
    attribs = {"layer": layer}
    circ = is_circle(c) if closed else None
    if circ is not None:
        msp.add_circle(circ[0], circ[1], dxfattribs=attribs)
        return
    pts = np.asarray(c.points, float)
    bul = np.asarray(c.bulges, float)
    if arcs == "bulge":
        verts = [(float(x), float(y), float(b)) for (x, y), b in zip(pts, bul)]
        if not closed:
            verts[-1] = (verts[-1][0], verts[-1][1], 0.0)
        msp.add_lwpolyline(verts, format="xyb", close=closed, dxfattribs=attribs)
        return
    sg = c.segments()
    n = len(bul) if closed else len(bul) - 1
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


def sheet_document(sheet: Sheet, arcs: str = "bulge"):
    """An ezdxf document of ``sheet`` (see the module docstring)."""
    if arcs not in ARC_STYLES:
        raise ExportError(f"--arcs must be one of {', '.join(ARC_STYLES)}; got {arcs!r}")
    layers = {}
    for k, p in enumerate(sheet.parts):
        layers.setdefault(layer_name(p.name), 1 + k % 6)
    for c in sheet.curves:
        layers.setdefault(layer_name(f"trace_{c.name}"), 8)
    if sheet.labels:
        layers[LABEL_LAYER] = 7
    doc = new_document(layers)
    msp = doc.modelspace()
    for p in sheet.parts:
        for c in p.contours:
            _write_contour(msp, c, layer_name(p.name), arcs)
    for cv in sheet.curves:
        _write_contour(msp, Contour(cv.points, cv.bulges), layer_name(f"trace_{cv.name}"), arcs, cv.closed)
    for lb in sheet.labels:
        msp.add_text(lb.text, height=lb.height, dxfattribs={"layer": LABEL_LAYER, "insert": (lb.at[0], lb.at[1])})
    x0, y0, x1, y1 = sheet.bounds
    # ezdxf copies the modelspace's extents and limits into the header when it saves
    msp.dxf.extmin, msp.dxf.extmax = (x0, y0, 0.0), (x1, y1, 0.0)
    msp.dxf.limmin, msp.dxf.limmax = (x0, y0), (x1, y1)
    doc.header["$EXTMIN"], doc.header["$EXTMAX"] = (x0, y0, 0.0), (x1, y1, 0.0)
    return doc


def write_dxf(sheet: Sheet, path: str | os.PathLike, arcs: str = "bulge") -> None:
    """Write ``sheet`` to ``path`` atomically (an overwritten file keeps its mode);
    :class:`ExportError` names the path when it cannot be written."""
    save_document(sheet_document(sheet, arcs), path)
