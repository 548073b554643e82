"""The drawing sheet of a part set (issue 23, item 9): what ``mechsketch export --pdf`` and the
app's File › Export Drawing put on paper, as plain data in paper millimetres. The app's package
renders it with Qt's PDF writer (``mechsketch/gui/drawing_pdf.py``): core never imports Qt.

One landscape page per part set (an element's parts): A4 when the parts fit it at 1:2 or larger,
else A3. The parts are drawn to a standard scale (5:1 … 1:50, the largest that fits), each group
(parts cut together) flat as in the ``apart`` layout and packed in rows with room for its
dimensions: the overall width and height of its bounding box and the distances between the
centres of its round holes (an aligned dimension per pair of consecutive bores, at most
:data:`MAX_HOLE_DIMS` per part). A title block (scene, element, units, material, thickness,
scale, date, sheet) and the analysis summary (wrapped, cut at :data:`SUMMARY_LINES` lines) fill
the strip at the bottom. All coordinates: paper mm, origin at the lower-left corner, y up.
"""
from __future__ import annotations

import datetime
import math
import textwrap
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ..analyses.contour import Contour
from ..analyses.parts import Part, PartSet, is_circle, lay_out
from ..errors import ExportError

#: landscape paper sizes (mm)
PAPERS = {"A4": (297.0, 210.0), "A3": (420.0, 297.0)}
#: standard scales, largest first: paper mm per part mm, and how a drawing writes them
SCALES = ((5.0, "5:1"), (2.0, "2:1"), (1.0, "1:1"), (0.5, "1:2"), (0.2, "1:5"), (0.1, "1:10"), (0.05, "1:20"),
          (0.02, "1:50"))
MARGIN = 10.0        # mm, border to the paper's edge
STRIP = 62.0         # mm, height of the title block and summary strip
TITLE_WIDTH = 120.0  # mm
DIM_ROOM = 14.0      # mm of paper kept below and right of a group for its dimensions
GAP = 8.0            # mm between groups on paper
INSET = 6.0          # mm from the border to the drawing
TEXT = 2.5           # mm, dimension and title text height
SUMMARY_TEXT = 1.8   # mm
SUMMARY_LINES = 26
MAX_HOLE_DIMS = 6


@dataclass(frozen=True)
class Dimension:
    """A dimension line from ``p0`` to ``p1`` (paper mm), drawn ``offset`` mm to its left (the
    extension lines run back to the measured points), reading ``value`` mm of the part."""

    p0: tuple[float, float]
    p1: tuple[float, float]
    offset: float
    value: float
    kind: str     # "width" | "height" | "holes"
    part: str

    @property
    def text(self) -> str:
        return f"{self.value:.2f}"


@dataclass(frozen=True)
class Page:
    """One sheet: ``paper`` ("A4" | "A3") of ``size`` (w, h) mm; the parts scaled by ``scale``
    (paper mm per part mm, written ``scale_text``) and placed (``parts``, paper mm), their names
    at ``labels`` ((text, (x, y)) lower-left, paper mm), ``dimensions``, the ``title`` block
    fields ((field, value)) and the ``summary`` lines."""

    paper: str
    size: tuple[float, float]
    scale: float
    scale_text: str
    parts: tuple[Part, ...]
    labels: tuple[tuple[str, tuple[float, float]], ...]
    dimensions: tuple[Dimension, ...]
    title: tuple[tuple[str, str], ...]
    summary: tuple[str, ...]


def _scaled(p: Part, s: float, dx: float, dy: float) -> Part:
    def sc(c: Contour) -> Contour:
        return Contour(np.asarray(c.points, float) * s + (dx, dy), np.asarray(c.bulges, float), c.kinds)
    return Part(p.name, None if p.outer is None else sc(p.outer), tuple(sc(h) for h in p.holes), p.group)


def _groups(ps: PartSet) -> list[list[Part]]:
    out: dict[str, list[Part]] = {}
    for p in lay_out(ps, "apart").parts:
        out.setdefault(p.group or p.name, []).append(p)
    return list(out.values())


def _bounds(parts: Sequence[Part]) -> tuple[float, float, float, float]:
    b = np.array([p.bounds() for p in parts])
    return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())


def _pack(sizes: list[tuple[float, float]], width: float, height: float) -> list[tuple[float, float]] | None:
    """Lower-left corners (paper mm, from the area's top-left going down) of boxes ``sizes``
    packed in rows into ``width`` x ``height``, tallest first; None if they do not fit."""
    order = sorted(range(len(sizes)), key=lambda k: -sizes[k][1])
    at: list[tuple[float, float]] = [(0.0, 0.0)] * len(sizes)
    x = y = row = 0.0
    for k in order:
        w, h = sizes[k]
        if w > width:
            return None
        if x + w > width:
            x, y, row = 0.0, y + row + GAP, 0.0
        at[k] = (x, y + h)
        x, row = x + w + GAP, max(row, h)
    return at if y + row <= height else None


def _fit(groups: list[list[Part]], paper: str) -> tuple[float, str, list[tuple[float, float]]] | None:
    w, h = PAPERS[paper]
    area_w, area_h = w - 2 * MARGIN - 2 * INSET, h - 2 * MARGIN - STRIP - 2 * INSET
    boxes = [_bounds(g) for g in groups]
    for s, text in SCALES:
        sizes = [((x1 - x0) * s + DIM_ROOM, (y1 - y0) * s + DIM_ROOM + TEXT * 2) for x0, y0, x1, y1 in boxes]
        at = _pack(sizes, area_w, area_h)
        if at is not None:
            return s, text, at
    return None


def _dimensions(p: Part, box: tuple[float, float, float, float]) -> list[Dimension]:
    x0, y0, x1, y1 = box
    out = [Dimension((x0, y0), (x1, y0), -6.0, 0.0, "width", p.name),
           Dimension((x1, y0), (x1, y1), -6.0, 0.0, "height", p.name)]
    centres = [c[0] for c in (is_circle(h) for h in p.holes) if c is not None]
    for a, b in list(zip(centres, centres[1:]))[:MAX_HOLE_DIMS]:
        out.append(Dimension(a, b, 0.0, 0.0, "holes", p.name))
    return out


def _summary(lines: Sequence[str], width_mm: float) -> tuple[str, ...]:
    chars = max(40, int(width_mm / (0.52 * SUMMARY_TEXT)))
    out = [w for line in lines for w in (textwrap.wrap(line, chars, subsequent_indent="    ") or [""])]
    if len(out) > SUMMARY_LINES:
        out = out[:SUMMARY_LINES - 1] + [f"… ({len(out) - SUMMARY_LINES + 1} more lines: mechsketch analyze --summary)"]
    return tuple(out)


def drawing_page(ps: PartSet, scene: str, summary: Sequence[str] = (), material: str = "", thickness: str = "",
                 date: datetime.date | None = None, sheet: tuple[int, int] = (1, 1)) -> Page:
    """The drawing sheet of ``ps`` (see the module docstring). ``scene``: its file name;
    ``summary``: the analysis summary's lines; ``material``, ``thickness``: title block fields
    (left blank to fill in by hand when empty). :class:`ExportError` if the parts do not fit
    an A3 sheet at 1:50."""
    groups = _groups(ps)
    if not groups:
        raise ExportError(f"element {ps.element_id!r} has no parts to draw")
    fit = None
    for paper in PAPERS:
        fit = _fit(groups, paper)
        if fit is not None and (fit[0] >= 0.5 or paper == "A3"):
            break
    if fit is None:
        raise ExportError(f"the parts of {ps.element_id!r} do not fit an A3 sheet at 1:50")
    s, scale_text, at = fit
    w, h = PAPERS[paper]
    top = h - MARGIN - INSET
    parts, labels, dims = [], [], []
    for group, (ax, ay) in zip(groups, at):
        gx0, gy0, _, _ = _bounds(group)
        dx, dy = MARGIN + INSET + ax - gx0 * s, top - ay + DIM_ROOM + 2 * TEXT - gy0 * s
        for p in group:
            q = _scaled(p, s, dx, dy)
            parts.append(q)
            qb = q.bounds()
            dims += [Dimension(d.p0, d.p1, d.offset, _measured(d, s), d.kind, d.part) for d in _dimensions(q, qb)]
        gb = _bounds(parts[-len(group):])
        labels.append((" + ".join(p.name for p in group), (gb[0], gb[1] - DIM_ROOM - TEXT)))
    today = (date or datetime.date.today()).isoformat()
    title = (("scene", scene), ("element", ps.element_id), ("units", "mm"), ("material", material),
             ("thickness", f"{thickness} mm" if thickness else ""), ("scale", scale_text),
             ("date", today), ("sheet", f"{sheet[0]} of {sheet[1]} ({paper})"))
    return Page(paper, (w, h), s, scale_text, tuple(parts), tuple(labels), tuple(dims), title,
                _summary(summary, w - 2 * MARGIN - TITLE_WIDTH - 4.0))


def _measured(d: Dimension, s: float) -> float:
    """The part's length (mm) a dimension drawn on paper at scale ``s`` stands for."""
    return math.dist(d.p0, d.p1) / s
