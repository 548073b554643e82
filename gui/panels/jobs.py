"""Long work of a dock (a study, a synthesis, a design from requirements) on a worker thread, with
progress and Cancel, its outcome delivered back in the GUI thread.

:class:`JobRunner` runs one job at a time on its own ``QThreadPool``. A job is a function
``work(ticket) -> result`` called on the worker thread; it reports through its :class:`Ticket`,
which also carries the cancel request in the form each core API takes:

- ``ticket.event`` — a ``threading.Event`` (the studies' ``cancel=``), with
  ``ticket.study_progress(done, total)`` for their ``progress=``;
- ``ticket.synthesis_progress(fraction, text)`` — the linkage syntheses' callback (returns True
  to stop: :class:`~mechsketch.core.design.targets.Progress`);
- ``ticket.requirement_progress(fraction, text)`` — the requirement designs' callback (returns
  False to stop: :mod:`mechsketch.core.design.design_report`).

Signals (delivered queued, in the GUI thread): ``started(str)`` (the job's title),
``progress(float, str)`` (fraction 0..1 and a short text), then exactly one of ``finished(object)``
(the result), ``failed(object)`` (the core's exception: its message says what to change),
``cancelled(str)``; ``busyChanged(bool)`` around it. An exception that is not the core's (a bug)
is handed to ``sys.excepthook`` in the GUI thread (the app shows it and keeps running) and the job
ends as failed. The work function reads immutable records only, so the user may keep editing.
"""
from __future__ import annotations

import sys
import threading
from typing import Any, Callable

from PySide6.QtCore import QObject, QRunnable, QThreadPool, Signal

from mechsketch.core.design.design_report import DesignCancelled
from mechsketch.core.design.targets import Cancelled
from mechsketch.core.errors import MechsketchError
from mechsketch.core.studies.execute import StudyCancelled

from ..qtsafe import qt_safe

#: the exceptions the core raises when its progress callback asked it to stop
CANCELLED = (StudyCancelled, Cancelled, DesignCancelled)


class _Signals(QObject):
    """Signals of one job (made in the GUI thread; emitted from the worker, delivered queued)."""

    progress = Signal(float, str)
    finished = Signal(object)
    failed = Signal(object)
    cancelled = Signal(str)
    crashed = Signal(object)   # (type, value, traceback) of a bug: for sys.excepthook
    done = Signal()


class Ticket:
    """What a job's work function reports through, and its cancel request (thread-safe)."""

    def __init__(self, signals: _Signals) -> None:
        self._signals = signals
        self.event = threading.Event()
        self.fraction = 0.0

    @property
    def cancelled(self) -> bool:
        return self.event.is_set()

    def report(self, fraction: float, text: str) -> None:
        """Progress: ``fraction`` of the work done (0..1; never goes back) and what it is doing."""
        self.fraction = max(self.fraction, min(max(float(fraction), 0.0), 1.0))
        self._signals.progress.emit(self.fraction, text)

    def study_progress(self, done: int, total: int, text: str = "") -> None:
        """The studies' ``progress(done, total)``."""
        self.report(done / total if total else 0.0, text or f"{done} of {total} blocks")

    def synthesis_progress(self, fraction: float, text: str) -> bool:
        """The linkage syntheses' callback: True asks them to stop."""
        self.report(fraction, text)
        return self.cancelled

    def requirement_progress(self, fraction: float, text: str) -> bool:
        """The requirement designs' callback: False asks them to stop."""
        self.report(fraction, text)
        return not self.cancelled


@qt_safe
class _Task(QRunnable):
    """One job on the pool: ``work(ticket)``, then exactly one outcome signal and ``done``."""

    def __init__(self, title: str, work: Callable[[Ticket], Any]) -> None:
        super().__init__()
        self.setAutoDelete(False)
        self.title = title
        self.work = work
        self.signals = _Signals()
        self.ticket = Ticket(self.signals)

    def run(self) -> None:
        try:
            self._run()
        finally:
            self.signals.done.emit()

    def _run(self) -> None:
        s = self.signals
        try:
            result = self.work(self.ticket)
        except CANCELLED:
            s.cancelled.emit(f"{self.title}: cancelled, nothing was changed")
            return
        except (MechsketchError, ValueError, ArithmeticError, OSError) as exc:   # the core's answer to bad input
            if self.ticket.cancelled:
                s.cancelled.emit(f"{self.title}: cancelled, nothing was changed")
            else:
                s.failed.emit(exc)
            return
        except Exception as exc:   # noqa: BLE001 - the thread boundary: a bug is reported, never dropped
            s.crashed.emit(sys.exc_info())
            s.failed.emit(exc)
            return
        if self.ticket.cancelled:
            s.cancelled.emit(f"{self.title}: cancelled, nothing was changed")
        else:
            s.finished.emit(result)


class JobRunner(QObject):
    """Runs jobs one at a time off the GUI thread (see the module docstring)."""

    started = Signal(str)
    progress = Signal(float, str)
    finished = Signal(object)
    failed = Signal(object)
    cancelled = Signal(str)
    busyChanged = Signal(bool)

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.pool = QThreadPool(self)
        self.pool.setMaxThreadCount(1)
        self.task: _Task | None = None
        self.title = ""

    @property
    def busy(self) -> bool:
        return self.task is not None

    def start(self, title: str, work: Callable[[Ticket], Any]) -> bool:
        """Run ``work(ticket)`` on the worker thread; False (nothing started) if a job runs."""
        if self.task is not None:
            return False
        task = _Task(title, work)
        s = task.signals
        s.progress.connect(self.progress)
        s.finished.connect(self.finished)
        s.failed.connect(self.failed)
        s.cancelled.connect(self.cancelled)
        s.crashed.connect(self._crashed)
        s.done.connect(self._done)
        self.task, self.title = task, title
        self.busyChanged.emit(True)
        self.started.emit(title)
        self.pool.start(task)
        return True

    def cancel(self) -> None:
        """Ask the running job to stop at its next progress report (thread-safe)."""
        if self.task is not None:
            self.task.ticket.event.set()
            self.progress.emit(self.task.ticket.fraction, "cancelling…")

    def wait(self, msecs: int = 30000) -> bool:
        """Block until the running job ends (closing the window); True if it did."""
        return self.pool.waitForDone(msecs)

    def _crashed(self, info) -> None:
        sys.excepthook(*info)

    def _done(self) -> None:
        self.task = None
        self.busyChanged.emit(False)


__all__ = ["CANCELLED", "JobRunner", "Ticket"]


class JobStatus:
    """The status line, progress bar and Run/Cancel buttons of a dock that runs a :class:`JobRunner`
    (the Study and Design docks). The dock provides ``status`` (QLabel), ``bar`` (QProgressBar on
    0..1000), ``run_button``, ``cancel_button``, ``runner`` and ``controller``; it may override
    :meth:`_can_run` (whether Run is offered when nothing runs)."""

    def _can_run(self) -> bool:
        return True

    def _say(self, text: str, error: bool = False) -> bool:
        """Show ``text`` in the dock and the status bar (red when ``error``); False, for returns."""
        self.status.setText(text)
        self.status.setStyleSheet("color: #b00020;" if error else "")
        self.controller.message.emit(text)
        return False

    def _busy(self, busy: bool) -> None:
        self.run_button.setEnabled(not busy and self._can_run())
        self.cancel_button.setEnabled(busy)
        if busy:
            self.bar.setValue(0)

    def _progress(self, fraction: float, text: str) -> None:
        self.bar.setValue(int(round(1000 * fraction)))
        self.status.setStyleSheet("")
        self.status.setText(f"{self.runner.title}: {text}")

    def _cancelled(self, text: str) -> None:
        self.bar.setValue(0)
        self._say(text)
