"""Solving one element off the GUI thread, so that a heavy request never freezes the window.

A rolling lever of 100,000 points takes over a minute to synthesise, a geared Geneva drive of
360,000 samples some 20 s: solved on the GUI thread (as every edit's result was) the window froze
for that long (issue 20, the GUI monkey). :func:`estimated_seconds` says, before anything is
solved, roughly how long an element takes (a linear model of the solve time per point or sample,
measured on the examples, with a margin); an edit whose new element is estimated above
:data:`HEAVY_SECONDS` and not cached is solved by a :class:`BackgroundSolver` on a worker thread
while the window keeps working, with a busy indicator and Cancel in the status bar (the app's
``gui/busy.py``), and the edit lands when the result is there (see
``SceneController.push_when_solved``).

The worker only calls the core's pure :func:`~mechsketch.core.workspace.results.solve_element` on
an immutable record; the result comes back to the GUI thread through a queued signal and enters
the workspace's cache there. The core's solvers cannot be interrupted, so Cancel abandons the
job: it runs to its end and its result is dropped (asking for the same element again meanwhile
picks the running job up instead of starting another; a job cancelled before it started is
skipped). Jobs run one at a time on one thread, so cancelled work never piles up.
"""
from __future__ import annotations

import queue
import sys
import threading
import time
from typing import Any, Callable

from PySide6.QtCore import QObject, Signal

from mechsketch.core.errors import MechsketchError
from mechsketch.core.workspace import LinkageResult
from mechsketch.core.workspace.results import solve_element

#: an edit whose element is estimated to solve longer than this (s) is solved off the GUI thread
HEAVY_SECONDS = 0.4
#: seconds per point or sample (measured on the examples at 3,600-360,000 samples and 100-10,000
#: points, 2-core machine, with a margin of about 1.5)
_PER_POINT = {"rolling_lever": 1.0e-3, "geneva": 4.0e-6, "geared_geneva": 8.0e-5, "gear_pair": 1.0e-6}
#: a linkage: seconds per (joint + link) and sample, solve and diagnostics (a chain of 500 dyads,
#: 1,002 joints at 360 samples: 4.5 s at load 10 on 2 cores, about 6e-6; 100 dyads: 5e-6; taken
#: at 2e-6 for a quiet machine: 4e-7 called the 1,002-joint chain 0.3 s, solved on the GUI thread)
_PER_LINKAGE_SAMPLE = 2.0e-6


def estimated_seconds(element: Any, samples: int | None) -> float:
    """Rough seconds to solve ``element`` at ``samples`` (None: its own) on one core; 0 for an
    element type without a model here (they are all cheap)."""
    kind = getattr(element, "type", None)
    if kind == "rolling_lever":
        return _PER_POINT[kind] * float(getattr(element, "points", 0))
    n = float(samples or getattr(element, "samples", 0) or 0)
    if kind == "linkage":
        size = len(getattr(element, "joints", ())) + len(getattr(element, "links", ()))
        return _PER_LINKAGE_SAMPLE * size * n
    return _PER_POINT.get(kind, 0.0) * n


def _solve(element: Any, samples: int | None) -> Any:
    """The work of one job (worker thread): the result, with a linkage's diagnostics and summary
    computed (cached on the result)."""
    res = solve_element(element, samples)
    if isinstance(res, LinkageResult) and res.error is None:
        _ = res.diagnostics
        _ = res.summary()   # the Diagnostics dock's text: its classification searches too
    return res


class _Worker:
    """One daemon thread running the jobs of every solver in turn: a cancelled job still running
    never has company (the machine's cores stay with the window and the job waited for)."""

    def __init__(self) -> None:
        self._queue: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()

    def submit(self, work: Callable[[], None]) -> None:
        with self._lock:
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="mechsketch-solve", daemon=True)
                self._thread.start()
        self._queue.put(work)

    def _run(self) -> None:
        while True:
            self._queue.get()()


_WORKER = _Worker()


def start_thread(work: Callable[[], None]) -> None:
    """Queue ``work`` for the solve thread (the default way a :class:`BackgroundSolver` starts a
    job; jobs run one at a time)."""
    _WORKER.submit(work)


class _Relay(QObject):
    """Carries one job's outcome from its worker thread to the GUI thread (a queued signal)."""

    done = Signal(object)


class _Job:
    """One element being solved: who waits for it, and what came out."""

    def __init__(self, element: Any, samples: int | None, text: str) -> None:
        self.element, self.samples, self.text = element, samples, text
        self.key = (element, samples)
        self.started = time.perf_counter()
        self.estimate = estimated_seconds(element, samples)
        self.then: Callable[[Any], None] | None = None   # None: abandoned (cancelled)
        self.relay = _Relay()
        self.work: Callable[[], None] = lambda: None


class BackgroundSolver(QObject):
    """Solves one element at a time for the GUI on a worker thread (see the module docstring).

    ``busyChanged(str)``: the text of the job the window waits for, "" when none. ``spawn(work)``
    starts a job's work (a thread by default; tests pass a fake that runs it when told).
    """

    busyChanged = Signal(str)

    def __init__(self, parent: QObject | None = None,
                 spawn: Callable[[Callable[[], None]], None] = start_thread) -> None:
        super().__init__(parent)
        self.spawn = spawn
        self._jobs: dict[Any, _Job] = {}        # running, by (element, samples)
        self._waiting: _Job | None = None

    @property
    def busy(self) -> bool:
        """Whether the window waits for a job."""
        return self._waiting is not None

    @property
    def job(self) -> _Job | None:
        """The job the window waits for (its text, start and estimate), or None."""
        return self._waiting

    def solve(self, element: Any, samples: int | None, text: str, then: Callable[[Any], None]) -> None:
        """Solve ``element`` at ``samples`` off the GUI thread and call ``then(result)`` in the GUI
        thread when done (never if cancelled first): the result, or the core's exception if it
        raised one. A job already waited for is cancelled."""
        self.cancel()
        job = self._jobs.get((element, samples))   # records are hashable (the workspace caches by them)
        if job is None:
            job = _Job(element, samples, text)
            self._jobs[job.key] = job
            job.relay.done.connect(self._deliver)
            relay = job.relay

            def work() -> None:
                try:
                    # cancelled while queued: skipped (picked up again if asked for meanwhile)
                    out: tuple = ("skipped", None) if job.then is None else ("ok", _solve(element, samples))
                except (MechsketchError, ValueError, ArithmeticError, OSError) as exc:   # the core's answer
                    out = ("error", exc)
                except Exception:   # noqa: BLE001 - the thread boundary: a bug is shown, never dropped
                    out = ("bug", sys.exc_info())
                try:
                    relay.done.emit((job.key, out))
                except RuntimeError:   # the app went away while this ran
                    pass

            job.work = work
            self.spawn(work)
        job.text, job.then = text, then
        self._waiting = job
        self.busyChanged.emit(text)

    def cancel(self) -> None:
        """Stop waiting for the current job (its thread runs out, its result is dropped)."""
        job, self._waiting = self._waiting, None
        if job is not None:
            job.then = None
            self.busyChanged.emit("")

    def _deliver(self, message: tuple) -> None:
        key, (how, value) = message
        job = self._jobs.pop(key, None)
        if job is None:
            return
        if how == "skipped":
            if job.then is not None:   # asked for again after it was skipped: queue it again
                self._jobs[key] = job
                self.spawn(job.work)
            return
        then, job.then = job.then, None
        if job is self._waiting:
            self._waiting = None
            self.busyChanged.emit("")
        if how == "bug":
            sys.excepthook(*value)
            return
        if then is not None:
            then(value)


def solve_each(solver: BackgroundSolver, workspace: Any, elements: list, text: str,
               done: Callable[[list[str]], None]) -> None:
    """Solve ``elements`` one after another on ``solver``'s thread, keep each result in
    ``workspace`` (as :meth:`Workspace.keep_result`: the next request finds it), then call
    ``done(problems)`` in the GUI thread: the core's messages of those that raised (an element
    whose result carries an error is kept as it is; the document shows it). Never called if the
    user cancels. ``text`` names the work in the status bar ("open big.json": "… (2/3: chain)")."""
    problems: list[str] = []

    def step(k: int) -> None:
        while k < len(elements) and workspace.has_result(elements[k]):   # cached meanwhile
            k += 1
        if k == len(elements):
            done(problems)
            return
        el = elements[k]

        def landed(result: Any) -> None:
            if isinstance(result, (MechsketchError, ValueError, ArithmeticError, OSError)):
                problems.append(f"{el.id}: {result}")
            else:
                workspace.keep_result(el, result)
            step(k + 1)

        label = text if len(elements) == 1 else f"{text} ({k + 1}/{len(elements)}: {el.id})"
        solver.solve(el, workspace.samples_for(el), label, landed)

    step(0)
