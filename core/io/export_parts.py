"""Export of checked parts: check, lay out, write DXF or SVG (one file, or one per part), report.

The one place the CLI and the GUI call to write parts: :func:`export_parts` checks every part
(:func:`~mechsketch.core.analyses.parts.require_checked`) before anything is written, so a part
that is not closed, not valid or thinner than the minimum web never reaches a file.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from ..analyses.parts import (API, DEFAULT_MIN_WEB, PartCheck, PartSet, Sheet, Vocabulary, lay_out, report_lines,
                              require_checked)
from ..errors import ExportError
from .dxf_parts import ARC_STYLES, write_dxf
from .svg_parts import write_svg

FORMATS = ("dxf", "svg")


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


def export_parts(ps: PartSet, path: str | os.PathLike, fmt: str = "dxf", layout: str = "apart",
                 names: Sequence[str] | None = None, split: bool = False, arcs: str = "bulge",
                 min_web: float = DEFAULT_MIN_WEB, vocab: Vocabulary = API) -> PartsExport:
    """Check the parts of ``ps`` (only ``names`` if given), lay them out and write them.

    ``fmt`` "dxf" | "svg"; ``layout`` "apart" | "assembled"; ``split``: one file per part group
    (``stem_NAME.ext``); ``arcs`` (DXF) "bulge" | "entities"; ``min_web`` mm; ``vocab``: how
    messages name what to change (the front end's options). Raises
    :class:`~mechsketch.core.errors.GeometryError` (a check failed, with the key to change) or
    :class:`ExportError` (bad option, unwritable path); nothing is written unless all parts pass.
    """
    if fmt not in FORMATS:
        raise ExportError(f"format must be one of {', '.join(FORMATS)}; got {fmt!r}")
    if arcs not in ARC_STYLES:
        raise ExportError(f"--arcs must be one of {', '.join(ARC_STYLES)}; got {arcs!r}")
    ps = ps.select(names)
    checks = require_checked(ps, min_web, vocab)
    if split:
        groups: dict[str, list[str]] = {}
        for p in ps.parts:
            groups.setdefault(p.group or p.name, []).append(p.name)
        jobs = [(split_path(path, g), ps.select(members)) for g, members in groups.items()]
    else:
        jobs = [(Path(path), ps)]
    sheets = [(target, lay_out(sub, layout)) for target, sub in jobs]
    for target, sheet in sheets:
        if fmt == "dxf":
            write_dxf(sheet, target, arcs)
        else:
            write_svg(sheet, target)
    style = ("DXF R2010, millimetres ($INSUNITS = 4), arcs as " +
             ("LWPOLYLINE bulges" if arcs == "bulge" else "LINE/ARC entities") + ", bores as CIRCLEs"
             if fmt == "dxf" else "SVG, millimetres (1 user unit = 1 mm), arcs as SVG arcs")
    lines = [f"wrote {', '.join(str(t) for t, _ in sheets)}: {style}; layout {layout}"
             + (", each part named" if layout == "apart" else ""),
             f"{len(checks)} part(s) checked before writing (closed, valid, no self-intersection, "
             f"thinnest web ≥ {min_web:g} mm):"]
    lines += report_lines(checks, min_web)
    for _, sheet in sheets:
        lines += [f"  shared: {s}" for s in sheet.shared]
    for c in ps.curves:
        lines.append(f"  curve {c.name}: {'closed' if c.closed else 'open'}, {len(c.bulges) - (0 if c.closed else 1)} "
                     f"arcs/lines, max deviation {c.deviation:.3e} mm (tolerance {c.tolerance:g} mm), "
                     f"layer trace_{c.name}")
    lines += list(ps.notes)
    return PartsExport(tuple(str(t) for t, _ in sheets), tuple(s for _, s in sheets), tuple(checks), "\n".join(lines))
