"""File › Export Drawing… (issue 23, item 9) and File › Export DXF / SVG (the dialog, then the
window's exporter: :func:`export_parts`).

Export Drawing (issue 23, item 9): a PDF drawing sheet per element with parts — the
parts to scale, dimensioned, a title block and the analysis summary — laid out by
:mod:`mechsketch.core.io.drawing_sheet` and written by Qt's PDF writer (:mod:`.drawing_pdf`),
the same sheets as ``mechsketch export --pdf``. The window's preferred plate sizes apply. The
analysis summaries (cached results) are read on the GUI thread; building and checking the parts,
laying out the sheets and writing the PDF run on the window's exporter
(:class:`~mechsketch.gui.export_worker.DrawingTask`), with progress and Cancel in the status bar.
A failure (parts that cannot be cut, an unwritable path) is a message naming what is wrong; the
scene is kept and nothing is written.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from mechsketch.core.errors import MechsketchError

from .preferences import part_options
from .selection import ELEMENT

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


def drawing_jobs(window) -> list[tuple]:
    """(element, part options, plan or None, summary lines) of every element of the window's
    scene that has parts: what :class:`~mechsketch.gui.export_worker.DrawingTask` draws."""
    from mechsketch.core.analyses.parts.build import PartOptions
    from mechsketch.core.model.linkage import Linkage

    from .export_worker import exportable

    ws = window.controller.workspace
    jobs = []
    for el in (e for e in window.controller.scene.elements if exportable(e)):
        opts = part_options(window.preferences, PartOptions(min_web=window.preferences.min_web or None))
        jobs.append((el, opts, ws.plan(el.id) if isinstance(el, Linkage) else None, _summary(ws, el)))
    return jobs


def export_drawing(window) -> bool:
    """Ask for a PDF file name and start writing the drawing sheets off the GUI thread (True:
    started; the exporter reports the result in the status bar and a message)."""
    from .export_worker import exportable

    ctl = window.controller
    if window.exporter.busy:
        window.show_message("an export is running: wait for it or cancel it")
        return False
    if not any(exportable(e) for e in ctl.scene.elements):
        window.show_message("nothing to draw: draw a linkage, a Geneva drive, a rolling lever or a gear pair first")
        return False
    stem = ctl.path.stem if ctl.path else "drawing"
    folder = ctl.path.parent if ctl.path else Path.home()
    try:
        jobs = drawing_jobs(window)
    except MechsketchError as exc:
        window.dialogs.error(TITLE, f"{exc}\n\nThe scene is not affected.")
        return False
    name = window.dialogs.save_file_name(TITLE, str(folder / f"{stem}.pdf"), "PDF drawings (*.pdf)")
    if not name:
        return False
    path = Path(name) if Path(name).suffix else Path(name).with_suffix(".pdf")
    window.show_message(f"drawing {path}…")
    window.export_titles = ("Drawing exported", TITLE)
    return window.exporter.start_drawing(jobs, str(path), ctl.path.name if ctl.path else "(unsaved scene)",
                                         f"{stem}: drawing")


# -- File › Export DXF / SVG: the dialog, the file name, then the window's exporter ---------------
def export_target(window):
    """The element to export: the selected one, else the only one (None if there are several)."""
    from .export_worker import exportable

    scene = window.controller.scene
    for eid, kind, _ in window.controller.selection:
        if kind == ELEMENT and eid in scene.ids and exportable(scene.element(eid)):
            return scene.element(eid)
    candidates = [e for e in scene.elements if exportable(e)]
    return candidates[0] if len(candidates) == 1 else None


def export_parts(window, fmt: str) -> bool:
    """The export dialog (element, parts, layout, tolerance, entities, minimum web), the file
    name, then the export off the GUI thread with progress and Cancel (True: started)."""
    from mechsketch.core.analyses.parts.build import PartOptions, min_web_of, part_names

    from .export_worker import exportable

    if window.exporter.busy:
        window.show_message("an export is running: wait for it or cancel it")
        return False
    scene = window.controller.scene
    elements = [e for e in scene.elements if exportable(e)]
    if not elements:
        window.show_message("nothing to export: draw a linkage, a Geneva drive, a rolling lever or a gear pair first")
        return False
    target = export_target(window) or elements[0]
    choices = {e.id: part_names(e) for e in elements}
    preferred = PartOptions(min_web=window.preferences.min_web or None)
    min_webs = {e.id: min_web_of(e, preferred) for e in elements}
    title = f"Export {fmt.upper()}"
    kinds = {e.id: e.type for e in elements}
    sizes = {k: getattr(window.preferences, k) for k in ("boss_radius", "bore_diameter", "link_width")}
    req = window.dialogs.export_request(title, choices, target.id, fmt, min_webs, kinds, sizes)
    if req is None:
        return False
    req = replace(req, options=part_options(window.preferences, req.options))   # preferred plate sizes
    el = scene.element(req.element_id)
    folder = window.controller.path.parent if window.controller.path else Path.home()
    name = window.dialogs.save_file_name(f"Export {el.id} as {fmt.upper()}", str(folder / f"{el.id}.{fmt}"),
                                         "DXF drawings (*.dxf)" if fmt == "dxf" else "SVG drawings (*.svg)")
    if not name:
        return False
    path = Path(name) if Path(name).suffix else Path(name).with_suffix(f".{fmt}")
    window.show_message(f"exporting {el.id} to {path}…")
    window.export_titles = (f"{fmt.upper()} exported", f"Export {fmt.upper()}")
    return window.exporter.start(el, str(path), req)

