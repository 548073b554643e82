"""Export of any element's cut-ready parts (DXF or SVG) and of the drawing sheets (PDF) off the
GUI thread, with progress and Cancel.

:class:`DxfExporter` runs one :class:`ExportTask` at a time on its own ``QThreadPool``. A task
works in two stages: it first builds the parts (:func:`~mechsketch.core.analyses.parts.build.
element_parts`: a drive's exact geometry, a lever's synthesis, a linkage's solve for its slots and
coupler curves), then - unless Cancel was pressed meanwhile - checks and writes them with the
core's exporter (atomic: a temporary file, then a rename). Cancel therefore means "nothing is written"
whenever it arrives before the write starts; a write already under way finishes (it takes a few
milliseconds). The element is an immutable record, so the user may keep editing meanwhile.

:class:`ExportStatus` is the status-bar widget: a busy bar, the stage, and a Cancel button.
:class:`DrawingTask` (File › Export Drawing) builds and checks every element's parts, lays out one
sheet each and writes them with Qt's PDF writer (QPdfWriter paints off the GUI thread); Cancel is
looked at between elements and before the write, and a failed write leaves nothing
(:func:`~mechsketch.gui.drawing_pdf.write_pdf` writes a temporary file, then renames it).
Signals of :class:`DxfExporter`: ``started(str)`` (element id), ``progress(str)``,
``finished(str)`` (the core's report), ``failed(str)`` (the core's message: an unwritable path
gives ``ExportError``), ``cancelled(str)``; ``busyChanged(bool)``.
"""
from __future__ import annotations

import threading
from pathlib import Path

from PySide6.QtCore import QObject, QRunnable, QThreadPool, Signal
from PySide6.QtWidgets import QHBoxLayout, QLabel, QProgressBar, QToolButton, QWidget

from mechsketch.core.analyses.parts import build as parts_build
from mechsketch.core.errors import MechsketchError
from mechsketch.core.io.export_parts import export_parts
from mechsketch.core.model.gear_pair import GearPair
from mechsketch.core.model.geared_geneva import GearedGeneva
from mechsketch.core.model.geneva import Geneva
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.rolling_lever import RollingLever

from .export_dialog import ExportRequest
from .qtsafe import qt_safe

#: the tolerance of fitted curves (mm), as ``mechsketch export`` uses by default
DEFAULT_TOLERANCE = parts_build.DEFAULT_TOLERANCE
EXPORTABLE = (Geneva, RollingLever, Linkage, GearPair, GearedGeneva)


class _Signals(QObject):
    """Signals of one task (made in the GUI thread; emitted from the worker, delivered queued)."""

    progress = Signal(str)
    finished = Signal(str)
    failed = Signal(str)
    cancelled = Signal(str)
    done = Signal()


@qt_safe
class ExportTask(QRunnable):
    """Export ``element``'s parts to ``path`` as ``request`` says (default: DXF, apart, all
    parts); see the module docstring for the two stages."""

    def __init__(self, element, path: str, request: ExportRequest | None = None) -> None:
        super().__init__()
        self.setAutoDelete(False)
        self.element = element
        self.path = str(path)
        self.request = request if request is not None else ExportRequest(element.id)
        self.signals = _Signals()
        self._cancel = threading.Event()

    def cancel(self) -> None:
        """Ask the task to stop before it writes (thread-safe)."""
        self._cancel.set()

    @property
    def cancel_requested(self) -> bool:
        return self._cancel.is_set()

    def run(self) -> None:
        """Build, check Cancel, write; exactly one of finished/failed/cancelled, then done."""
        try:
            self._run()
        finally:
            self.signals.done.emit()

    def _run(self) -> None:
        el, req = self.element, self.request
        try:
            self.signals.progress.emit(f"building the parts of {el.id}…")
            ps = parts_build.element_parts(el, req.options)
            if self._stopped():
                return
            self.signals.progress.emit(f"checking and writing {Path(self.path).name}…")
            exp = export_parts(ps, self.path, req.fmt, req.layout, req.parts, req.split, req.arcs,
                               parts_build.min_web_of(el, req.options), req.options.vocabulary,
                               annotate=req.annotate, kerf=req.kerf)
        except (MechsketchError, OSError, ValueError) as exc:
            self.signals.failed.emit(str(exc))
            return
        self.signals.finished.emit(exp.report)

    def _stopped(self) -> bool:
        if self._cancel.is_set():
            self.signals.cancelled.emit(f"export of {self.element.id} cancelled: nothing was written")
            return True
        return False


@qt_safe
class DrawingTask(ExportTask):
    """Write the drawing sheets of ``jobs`` — (element, part options, plan or None, summary lines)
    for every element with parts — to the PDF ``path``; ``scene_name`` goes in the title blocks."""

    def __init__(self, jobs: list[tuple], path: str, scene_name: str, title: str) -> None:
        super().__init__(jobs[0][0], path)
        self.jobs, self.scene_name, self.title = jobs, scene_name, title

    def _run(self) -> None:
        from mechsketch.core.analyses.parts import require_checked
        from mechsketch.core.io.drawing_sheet import drawing_page

        from .drawing_pdf import write_pdf

        try:
            sets = []
            for k, (el, opts, plan, summary) in enumerate(self.jobs):
                self.signals.progress.emit(f"building the parts of {el.id} ({k + 1}/{len(self.jobs)})…")
                ps = parts_build.element_parts(el, opts, plan)
                require_checked(ps, parts_build.min_web_of(el, opts))
                sets.append((ps, summary))
                if self._stopped():
                    return
            pages = [drawing_page(ps, self.scene_name, summary, sheet=(k + 1, len(sets)))
                     for k, (ps, summary) in enumerate(sets)]
            if self._stopped():
                return
            self.signals.progress.emit(f"writing {Path(self.path).name}…")
            write_pdf(pages, self.path, self.title)
        except (MechsketchError, OSError, ValueError) as exc:
            self.signals.failed.emit(str(exc))
            return
        sheets = ", ".join(f"{p.title[1][1]}: {p.paper} at {p.scale_text}" for p in pages)
        self.signals.finished.emit(f"wrote {self.path}: {len(pages)} sheet(s) ({sheets})")

    def _stopped(self) -> bool:
        if self._cancel.is_set():
            self.signals.cancelled.emit(f"drawing export cancelled: {Path(self.path).name} was not written")
            return True
        return False


class DxfExporter(QObject):
    """Runs export tasks one at a time off the GUI thread (see the module docstring)."""

    started = Signal(str)
    progress = Signal(str)
    finished = Signal(str)
    failed = Signal(str)
    cancelled = Signal(str)
    busyChanged = Signal(bool)

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.pool = QThreadPool(self)
        self.pool.setMaxThreadCount(1)
        self.task: ExportTask | None = None

    @property
    def busy(self) -> bool:
        return self.task is not None

    def start(self, element, path: str, request: ExportRequest | None = None) -> bool:
        """Start exporting ``element`` to ``path``; False (nothing started) if one is running."""
        if self.task is not None:
            return False
        return self.run(ExportTask(element, path, request))

    def start_drawing(self, jobs: list[tuple], path: str, scene_name: str, title: str) -> bool:
        """Start writing the drawing sheets of ``jobs`` (see :class:`DrawingTask`) to ``path``;
        False (nothing started) if an export is running."""
        if self.task is not None or not jobs:
            return False
        return self.run(DrawingTask(jobs, path, scene_name, title))

    def run(self, task: ExportTask) -> bool:
        """Start ``task`` (an :class:`ExportTask` or a subclass); False if one is running."""
        if self.task is not None:
            return False
        element = task.element
        for name in ("progress", "finished", "failed", "cancelled"):
            getattr(task.signals, name).connect(getattr(self, name))
        task.signals.done.connect(self._done)
        self.task = task
        self.busyChanged.emit(True)
        self.started.emit(element.id)
        self.pool.start(task)
        return True

    def cancel(self) -> None:
        """Stop the running export before it writes (if it has not started writing)."""
        if self.task is not None:
            self.task.cancel()
            self.progress.emit("cancelling…")

    def wait(self, msecs: int = 10000) -> bool:
        """Block until the running task ends (closing the window, tests); True if it did."""
        return self.pool.waitForDone(msecs)

    def _done(self) -> None:
        self.task = None
        self.busyChanged.emit(False)


class ExportStatus(QWidget):
    """A status-bar widget shown while an export runs: busy bar, stage text, Cancel."""

    def __init__(self, exporter: DxfExporter, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        lay = QHBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.label = QLabel()
        self.bar = QProgressBar()
        self.bar.setRange(0, 0)          # busy: the stages have no measurable fraction
        self.bar.setMaximumWidth(90)
        self.bar.setMaximumHeight(14)
        self.cancel_button = QToolButton()
        self.cancel_button.setText("Cancel")
        self.cancel_button.setObjectName("cancelExport")
        self.cancel_button.clicked.connect(exporter.cancel)
        for w in (self.label, self.bar, self.cancel_button):
            lay.addWidget(w)
        exporter.progress.connect(self.label.setText)
        exporter.busyChanged.connect(self.setVisible)
        self.setVisible(False)


def exportable(element) -> bool:
    """True for the element types the app exports (linkages, Geneva drives, rolling levers, gear pairs
    and smooth Geneva drives: every kind whose parts ``element_parts`` builds)."""
    return isinstance(element, EXPORTABLE)
