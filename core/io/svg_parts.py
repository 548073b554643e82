"""SVG writer of a laid-out sheet of parts (laser cutters, browsers): the same parts as the DXF.

Millimetres: ``width``/``height`` in mm and a viewBox in mm, so one user unit is 1 mm. SVG's y
axis points down, so y is written as ``ymax − y`` (and each arc's sweep flag follows). One
``<g id="part-NAME">`` per part holding one ``<path>`` (outline and holes, ``fill-rule:
evenodd``); arcs are SVG elliptical-arc commands with equal radii (true arcs, no chords);
traced curves in ``<g id="trace-NAME">``; part names as ``<text>`` in ``<g id="labels">``.
"""
from __future__ import annotations

import math
import os
from xml.sax.saxutils import escape, quoteattr

import numpy as np

from ..analyses.contour import Contour
from ..analyses.parts import Sheet
from .atomic import atomic_write_text

STROKE = "#d00000"
HAIRLINE = 0.1  # mm


def _f(v: float) -> str:
    return f"{v:.9g}"


def _path_data(c: Contour, ymax: float, closed: bool = True) -> str:
    sg = c.segments()
    n = len(c) if closed else len(c) - 1
    x, y = sg.p0[0]
    out = [f"M {_f(x)} {_f(ymax - y)}"]
    for k in range(n):
        px, py = sg.p1[k]
        if not sg.is_arc[k]:
            out.append(f"L {_f(px)} {_f(ymax - py)}")
            continue
        r = sg.radius[k]
        th = sg.theta[k]
        large = 1 if abs(th) > math.pi else 0
        if abs(abs(th) - math.pi) <= 1e-12:  # a half circle: split so the arc is unambiguous
            mid_a = sg.a0[k] + th / 2
            mx, my = sg.centre[k, 0] + r * math.cos(mid_a), sg.centre[k, 1] + r * math.sin(mid_a)
            sweep = 0 if th > 0 else 1  # y flipped: CCW in the drawing is clockwise on screen
            out.append(f"A {_f(r)} {_f(r)} 0 0 {sweep} {_f(mx)} {_f(ymax - my)}")
            out.append(f"A {_f(r)} {_f(r)} 0 0 {sweep} {_f(px)} {_f(ymax - py)}")
            continue
        sweep = 0 if th > 0 else 1
        out.append(f"A {_f(r)} {_f(r)} 0 {large} {sweep} {_f(px)} {_f(ymax - py)}")
    if closed:
        out.append("Z")
    return " ".join(out)


def sheet_svg(sheet: Sheet) -> str:
    """The SVG text of ``sheet`` (see the module docstring)."""
    x0, y0, x1, y1 = sheet.bounds
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
        d = " ".join(_path_data(c, ymax) for c in p.contours)
        lines.append(f'<g id={quoteattr("part-" + p.name)}><path {style} d="{d}"/></g>')
    for cv in sheet.curves:
        d = _path_data(Contour(cv.points, np.asarray(cv.bulges, float)), ymax, cv.closed)
        lines.append(f'<g id={quoteattr("trace-" + cv.name)}><path fill="none" stroke="#0050d0" '
                     f'stroke-width="{HAIRLINE}" stroke-dasharray="1 1" d="{d}"/></g>')
    if sheet.labels:
        lines.append('<g id="labels" font-family="sans-serif" fill="#000000">')
        for lb in sheet.labels:
            lines.append(f'<text x="{_f(lb.at[0])}" y="{_f(ymax - lb.at[1])}" font-size="{_f(lb.height)}">'
                         f"{escape(lb.text)}</text>")
        lines.append("</g>")
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def write_svg(sheet: Sheet, path: str | os.PathLike) -> None:
    """Write ``sheet`` as SVG to ``path`` atomically; :class:`ExportError` names the path."""
    atomic_write_text(path, sheet_svg(sheet))
