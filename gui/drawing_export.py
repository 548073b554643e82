"""File › Export Drawing… (issue 23, item 9): a PDF drawing sheet per element with parts — the
parts to scale, dimensioned, a title block and the analysis summary — laid out by
:mod:`mechsketch.core.io.drawing_sheet` and written by Qt's PDF writer (:mod:`.drawing_pdf`),
the same sheets as ``mechsketch export --pdf``. The window's preferred plate sizes apply. A few
hundred milliseconds of work, done on the GUI thread; a failure is a message, the scene is kept.
"""
from __future__ import annotations

from pathlib import Path

from mechsketch.core.errors import MechsketchError

from .preferences import part_options

TITLE = "Export Drawing"


def _summary(ws, el) -> list[str]:
    """The element's analysis summary (with the forces of a loaded linkage: the peak torque)."""
    from mechsketch.core.analyses.forces.report import force_summary

    res = ws.result(el.id)
    lines = res.summary().splitlines() if res is not None else []
    if getattr(el, "loads", ()):
        try:
            lines += force_summary(ws.forces(el.id)).splitlines()
        except MechsketchError as exc:
            lines.append(f"forces: {exc}")
    return lines


def drawing_pages(window, scene_name: str) -> list:
    """The drawing pages of every element of the window's scene that has parts (checked first)."""
    from mechsketch.core.analyses.parts import require_checked
    from mechsketch.core.analyses.parts.build import PartOptions, element_parts, min_web_of
    from mechsketch.core.io.drawing_sheet import drawing_page
    from mechsketch.core.model.linkage import Linkage

    from .export_worker import exportable

    ws = window.controller.workspace
    sets = []
    for el in (e for e in window.controller.scene.elements if exportable(e)):
        opts = part_options(window.preferences, PartOptions(min_web=window.preferences.min_web or None))
        ps = element_parts(el, opts, ws.plan(el.id) if isinstance(el, Linkage) else None)
        require_checked(ps, min_web_of(el, opts))
        sets.append((el, ps))
    return [drawing_page(ps, scene_name, _summary(ws, el), sheet=(k + 1, len(sets))) for k, (el, ps) in enumerate(sets)]


def export_drawing(window) -> bool:
    """Ask for a PDF file name and write the drawing sheets (True: written)."""
    from .drawing_pdf import write_pdf

    ctl = window.controller
    stem = ctl.path.stem if ctl.path else "drawing"
    folder = ctl.path.parent if ctl.path else Path.home()
    try:
        pages = drawing_pages(window, ctl.path.name if ctl.path else "(unsaved scene)")
    except MechsketchError as exc:
        window.dialogs.error(TITLE, f"{exc}\n\nThe scene is not affected.")
        return False
    if not pages:
        window.show_message("nothing to draw: draw a linkage, a Geneva drive, a rolling lever or a gear pair first")
        return False
    name = window.dialogs.save_file_name(TITLE, str(folder / f"{stem}.pdf"), "PDF drawings (*.pdf)")
    if not name:
        return False
    path = Path(name) if Path(name).suffix else Path(name).with_suffix(".pdf")
    try:
        write_pdf(pages, path, f"{stem}: drawing")
    except MechsketchError as exc:
        window.dialogs.error(TITLE, f"{exc}\n\nThe scene is not affected.")
        return False
    sheets = ", ".join(f"{p.title[1][1]}: {p.paper} at {p.scale_text}" for p in pages)
    window.show_message(f"wrote {path}")
    window.dialogs.info("Drawing exported", f"wrote {path}: {len(pages)} sheet(s) ({sheets})")
    return True
