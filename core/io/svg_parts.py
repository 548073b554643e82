"""SVG writer of a laid-out sheet of parts (laser cutters, browsers): the same parts as the DXF.

Millimetres: ``width``/``height`` in mm and a viewBox in mm, so one user unit is 1 mm. SVG's y
axis points down, so y is written as ``ymax − y`` (and each arc's sweep flag follows). One
``<g id="part-NAME">`` per part holding one ``<path>`` (outline and holes, ``fill-rule:
evenodd``); arcs are SVG elliptical-arc commands with equal radii (true arcs, no chords), each
at most 90° (:mod:`.cut_paths`: the centre an SVG reader finds again from the end points is then
well conditioned). Only cut geometry by default; with ``annotate``, traced curves in ``<g
id="notes-trace-NAME">`` and part names as ``<text>`` in ``<g id="notes-labels">`` (every
group that is not cut has an id starting with ``notes-`` and the class ``notes``).
"""
from __future__ import annotations

import os
from xml.sax.saxutils import escape, quoteattr

import numpy as np

from ..analyses.contour import Contour
from ..analyses.parts import Sheet
from .atomic import atomic_write_text
from .cut_paths import SVG_MAX_SWEEP, min_segment, split_arcs

STROKE = "#d00000"
HAIRLINE = 0.1  # mm


def _f(v: float) -> str:
    return f"{v:.10g}"


def _path_data(c: Contour, ymax: float, shortest: float, what: str, closed: bool = True) -> str:
    c = split_arcs(c, SVG_MAX_SWEEP, shortest, what, closed)
    sg = c.segments()
    n = len(c) if closed else len(c) - 1
    x, y = sg.p0[0]
    out = [f"M {_f(x)} {_f(ymax - y)}"]
    for k in range(n):
        px, py = sg.p1[k]
        if not sg.is_arc[k]:
            out.append(f"L {_f(px)} {_f(ymax - py)}")
            continue
        sweep = 0 if sg.theta[k] > 0 else 1   # y flipped: CCW in the drawing is clockwise on screen
        out.append(f"A {_f(sg.radius[k])} {_f(sg.radius[k])} 0 0 {sweep} {_f(px)} {_f(ymax - py)}")
    if closed:
        out.append("Z")
    return " ".join(out)


def sheet_svg(sheet: Sheet, annotate: bool = False) -> str:
    """The SVG text of ``sheet`` (see the module docstring)."""
    x0, y0, x1, y1 = sheet.bounds
    shortest = min_segment(max(x1 - x0, y1 - y0))
    m = 0.02 * max(x1 - x0, y1 - y0, 1.0)
    x0, y0, x1, y1 = x0 - m, y0 - m, x1 + m, y1 + m
    w, h = x1 - x0, y1 - y0
    ymax = y1
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<svg xmlns="http://www.w3.org/2000/svg" width="{_f(w)}mm" height="{_f(h)}mm" '
             f'viewBox="{_f(x0)} {_f(ymax - y1)} {_f(w)} {_f(h)}">',
             f"<title>{escape(sheet.element_id)}: {escape(sheet.layout)} parts, millimetres</title>"]
    style = f'fill="none" stroke="{STROKE}" stroke-width="{HAIRLINE}" fill-rule="evenodd"'
    for p in sheet.parts:
        d = " ".join(_path_data(c, ymax, shortest, f"part {p.name!r}, " + ("its outline" if p.outer is not None and k == 0
                                                                           else "a hole"))
                     for k, c in enumerate(p.contours))
        lines.append(f'<g id={quoteattr("part-" + p.name)}><path {style} d="{d}"/></g>')
    if annotate:
        for cv in sheet.curves:
            d = _path_data(Contour(cv.points, np.asarray(cv.bulges, float)), ymax, shortest,
                           f"the curve {cv.name!r}", cv.closed)
            lines.append(f'<g id={quoteattr("notes-trace-" + cv.name)} class="notes"><path fill="none" '
                         f'stroke="#0050d0" stroke-width="{HAIRLINE}" stroke-dasharray="1 1" d="{d}"/></g>')
        if sheet.labels:
            lines.append('<g id="notes-labels" class="notes" font-family="sans-serif" fill="#000000">')
            for lb in sheet.labels:
                lines.append(f'<text x="{_f(lb.at[0])}" y="{_f(ymax - lb.at[1])}" font-size="{_f(lb.height)}">'
                             f"{escape(lb.text)}</text>")
            lines.append("</g>")
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def write_svg(sheet: Sheet, path: str | os.PathLike, annotate: bool = False) -> None:
    """Write ``sheet`` as SVG to ``path`` atomically; :class:`ExportError` names the path."""
    atomic_write_text(path, sheet_svg(sheet, annotate))
