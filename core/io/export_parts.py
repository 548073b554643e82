"""Export of checked parts: check, lay out, write DXF or SVG (one file, or one per part), report.

The one place the CLI and the GUI call to write parts: :func:`export_parts` checks every part
(:func:`~mechsketch.core.analyses.parts.require_checked`) before anything is written, so a part
that is not closed, not valid or thinner than the minimum web never reaches a file. With a kerf,
the tool paths (:func:`~mechsketch.core.analyses.parts.kerf.kerf_part`) are checked again and
written instead of the edges. The report lists, per part, its area and the length and enclosed
area of what was written (a CAM program's cut length), so a reader of the file can be checked
against it; and which readers need LINE/ARC entities.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Sequence

from ..analyses.parts import (API, DEFAULT_MIN_WEB, PartCheck, PartSet, Sheet, Vocabulary, check_part, lay_out,
                              name_of, report_lines, require_checked)
from ..analyses.contour import Contour
from ..analyses.parts.kerf import kerf_part
from ..errors import ExportError, GeometryError
from .dxf_parts import ARC_STYLES, write_dxf
from .svg_parts import write_svg

FORMATS = ("dxf", "svg")
#: what the report says about bulge polylines (the measured misreadings are issue 23's)
BULGE_READERS = ("read exactly by AutoCAD, LibreCAD, QCAD, FreeCAD, ezdxf and GDAL/OGR (every arc is at most "
                 "180°); CAM importers that drop or misread bulges (dxf2gcode, dime-based and some plasma and "
                 "laser software: 2–42 % off in a test) need LINE and ARC entities")


@dataclass(frozen=True)
class PartsExport:
    """What was written: the files, the sheets (one per file), the checks and the report text."""

    paths: tuple[str, ...]
    sheets: tuple[Sheet, ...]
    checks: tuple[PartCheck, ...]
    report: str


def split_path(path: str | os.PathLike, name: str) -> Path:
    """The file of one part when writing one file per part: ``stem_NAME.suffix`` beside ``path``."""
    p = Path(path)
    return p.with_name(f"{p.stem}_{name}{p.suffix}")


def tool_paths(ps: PartSet, kerf: float, min_web: float, vocab: Vocabulary = API) -> PartSet:
    """The parts' tool paths for a cut ``kerf`` mm wide, each checked again (closed, not crossing
    itself, apart by the web plus the kerf); :class:`GeometryError` names what cannot be cut."""
    if not (math.isfinite(kerf) and kerf >= 0):
        raise ExportError(f"{name_of('option:kerf', vocab)} must be a number of millimetres >= 0; got {kerf:g}")
    if kerf == 0:
        return ps
    out, bad = [], []
    for p in ps.parts:
        path = kerf_part(p, kerf)
        chk = check_part(path, min_web + kerf)
        if not chk.ok:
            bad.append(f"part {p.name!r}: its tool paths {'; '.join(chk.problems)}")
        out.append(path)
    if bad:
        raise GeometryError(f"{ps.element_id!r} cannot be cut with a kerf of {kerf:g} mm: " + " | ".join(bad)
                            + f" (change {name_of('option:kerf', vocab)} or the part's sizes)")
    return replace(ps, parts=tuple(out))


def export_parts(ps: PartSet, path: str | os.PathLike, fmt: str = "dxf", layout: str = "apart",
                 names: Sequence[str] | None = None, split: bool = False, arcs: str = "bulge",
                 min_web: float = DEFAULT_MIN_WEB, vocab: Vocabulary = API, *, annotate: bool = False,
                 kerf: float = 0.0) -> PartsExport:
    """Check the parts of ``ps`` (only ``names`` if given), lay them out and write them.

    ``fmt`` "dxf" | "svg"; ``layout`` "apart" | "assembled"; ``split``: one file per part group
    (``stem_NAME.ext``); ``arcs`` (DXF) "bulge" | "entities"; ``min_web`` mm; ``vocab``: how
    messages name what to change (the front end's options); ``annotate``: part names and drawn
    curves on ``NOTES_*`` layers (default: cut geometry only); ``kerf`` (mm): write the tool paths
    (see :func:`tool_paths`). Raises :class:`~mechsketch.core.errors.GeometryError` (a check
    failed, with the key to change) or :class:`ExportError` (bad option, unwritable path);
    nothing is written unless all parts pass.
    """
    if fmt not in FORMATS:
        raise ExportError(f"format must be one of {', '.join(FORMATS)}; got {fmt!r}")
    if arcs not in ARC_STYLES:
        raise ExportError(f"--arcs must be one of {', '.join(ARC_STYLES)}; got {arcs!r}")
    ps = ps.select(names)
    checks = require_checked(ps, min_web, vocab)
    written = tool_paths(ps, kerf, min_web, vocab)
    if split:
        groups: dict[str, list[str]] = {}
        for p in written.parts:
            groups.setdefault(p.group or p.name, []).append(p.name)
        jobs = [(split_path(path, g), written.select(members)) for g, members in groups.items()]
    else:
        jobs = [(Path(path), written)]
    sheets = [(target, lay_out(sub, layout)) for target, sub in jobs]
    for target, sheet in sheets:
        if fmt == "dxf":
            write_dxf(sheet, target, arcs, annotate)
        else:
            write_svg(sheet, target, annotate)
    lines = _report_head([str(t) for t, _ in sheets], fmt, arcs, layout, annotate, kerf, vocab, ps)
    lines.append(f"{len(checks)} part(s) checked before writing (closed, valid, no self-intersection, "
                 f"thinnest web ≥ {min_web:g} mm):")
    placed = {p.name: p for _, sheet in sheets for p in sheet.parts}   # as written (shared contours once)
    lines += report_lines(checks, min_web, [placed[c.name] for c in checks], kerf)
    for _, sheet in sheets:
        lines += [f"  shared: {s}" for s in sheet.shared]
    for c in ps.curves:
        where = f"layer NOTES_TRACE_{c.name}" if annotate else f"not written (only with {name_of('option:annotate', vocab)})"
        n = len(c.bulges) - (0 if c.closed else 1)
        length = float(Contour(c.points, c.bulges).segments().length[:n].sum())
        lines.append(f"  curve {c.name}: {'closed' if c.closed else 'open'}, {n} arcs/lines, length {length:.6f} mm, "
                     f"max deviation {c.deviation:.3e} mm (tolerance {c.tolerance:g} mm), {where}")
    lines += list(ps.notes)
    return PartsExport(tuple(str(t) for t, _ in sheets), tuple(s for _, s in sheets), tuple(checks), "\n".join(lines))


def _report_head(paths: list[str], fmt: str, arcs: str, layout: str, annotate: bool, kerf: float,
                 vocab: Vocabulary, ps: PartSet) -> list[str]:
    """The report's first lines: what was written, in which style, and for which readers."""
    if fmt == "dxf":
        style = ("DXF R2010, millimetres ($INSUNITS = 4), arcs as " +
                 ("LWPOLYLINE bulges" if arcs == "bulge" else "LINE/ARC entities") + ", bores as CIRCLEs")
    else:
        style = "SVG, millimetres (1 user unit = 1 mm), arcs as SVG arcs of at most 90°"
    lines = [f"wrote {', '.join(paths)}: {style}; layout {layout}; "
             + ("part names and drawn curves on NOTES_* layers (not to be cut)" if annotate
                else "cut geometry only: one layer per part, outlines and holes")]
    if fmt == "dxf" and arcs == "bulge":
        lines.append(f"readers: bulge polylines are {BULGE_READERS}: export again with "
                     f"{name_of('option:arcs_entities', vocab)} for them")
    if kerf:
        lines.append(f"kerf {kerf:g} mm: the tool paths are written, outlines {kerf / 2:g} mm outside, holes "
                     f"{kerf / 2:g} mm inside (round joins as true arcs), checked again before writing")
    return lines
