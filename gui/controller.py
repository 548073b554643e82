"""The one place that owns the document, the undo stack and the current solutions.

Widgets never hold model state: they read ``controller.scene`` and the solve results, and change
the document only through ``push(edit)`` (one undo command) or a drag preview that ends in one
command. Signals are past tense and fire once the document and its solutions are consistent.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

from PySide6.QtCore import QObject, Signal
from PySide6.QtGui import QUndoCommand, QUndoStack

from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.edits import Document, Edit
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.scene import Scene
from mechsketch.core.solver.diagnostics import Diagnostics, diagnose
from mechsketch.core.solver.plan import Plan, Solution

from .canvas.pose import map_frame
from .element_results import ElementResult, ResultCache

DEFAULT_SAMPLES = 360


@dataclass
class SolveResult:
    """The solve of one linkage element: plan, solution and diagnostics, or the error message."""

    element_id: str
    plan: Plan | None = None
    solution: Solution | None = None
    diagnostics: Diagnostics | None = None
    error: str | None = None
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        return self.error is None


class EditCommand(QUndoCommand):
    """A QUndoCommand wrapping one reversible core edit."""

    def __init__(self, controller: "SceneController", edit: Edit, text: str) -> None:
        super().__init__(text)
        self._controller = controller
        self._edit = edit
        self._inverse: Edit | None = None

    def redo(self) -> None:
        self._inverse = self._controller._apply(self._edit)

    def undo(self) -> None:
        if self._inverse is not None:
            self._edit = self._controller._apply(self._inverse)


class SceneController(QObject):
    """Document + undo stack + solutions + selection + animation frame, with signals."""

    sceneChanged = Signal()            # the document changed (edit, undo, redo, open, new, preview)
    solutionsChanged = Signal()        # solutions recomputed (after sceneChanged)
    solveFailed = Signal(str, str)     # element id, message (the GUI shows it; never raises)
    selectionChanged = Signal()
    frameChanged = Signal(int)         # current sample index of the animation / scrub bar
    pathChanged = Signal()             # file path or clean state changed (window title)
    message = Signal(str)              # a line for the status bar

    def __init__(self, scene: Scene | None = None, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.document = Document(scene)
        self.undo_stack = QUndoStack(self)
        self.undo_stack.cleanChanged.connect(self._on_clean_changed)
        self.path: Path | None = None
        self.samples_override: int | None = None
        self.selection: list[tuple[str, str, str]] = []   # (element id, "joint"|"link", id)
        self.frame = 0
        self._results: dict[str, SolveResult] = {}
        self._element_results: dict[str, ElementResult] = {}   # Geneva drives, rolling levers
        self._element_cache = ResultCache()
        self._drag_base: Scene | None = None
        self._resolve()

    def _on_clean_changed(self, _clean: bool) -> None:
        # a bound slot (not a lambda): Qt drops the connection when the controller is destroyed,
        # so the undo stack's own clean-up at teardown cannot reach a deleted controller
        self.pathChanged.emit()

    # -- reading ----------------------------------------------------------------------------
    @property
    def scene(self) -> Scene:
        return self.document.scene

    def linkages(self) -> list[Linkage]:
        return [e for e in self.scene.elements if isinstance(e, Linkage)]

    def result(self, element_id: str) -> SolveResult | None:
        return self._results.get(element_id)

    def results(self) -> dict[str, SolveResult]:
        return dict(self._results)

    def element_result(self, element_id: str) -> ElementResult | None:
        """The result of a Geneva drive or rolling lever (None for a linkage or an unknown id)."""
        return self._element_results.get(element_id)

    def element_results(self) -> dict[str, ElementResult]:
        """Results of every Geneva drive and rolling lever, in scene order."""
        return dict(self._element_results)

    def check_element(self, element) -> str | None:
        """Solve ``element`` (a Geneva drive or rolling lever, not yet in the scene) as the
        controller would; the core's message if it fails, else None (the result is kept for
        when the edit lands)."""
        res = self._element_cache.solve(element, self.samples_override)
        return None if res is None else res.error

    @property
    def is_dirty(self) -> bool:
        return not self.undo_stack.isClean()

    # -- editing ----------------------------------------------------------------------------
    def push(self, edit: Edit, text: str | None = None) -> bool:
        """Apply ``edit`` as one undo command; False (and a message) if the edit is refused."""
        try:
            edit.apply_to(self.scene)  # dry run: refuse bad edits before they enter history
        except (MechsketchError, KeyError, ValueError) as exc:
            self.message.emit(f"cannot {text or getattr(edit, 'label', 'edit')}: {exc}")
            return False
        self.undo_stack.push(EditCommand(self, edit, text or getattr(edit, "label", "edit")))
        return True

    def _apply(self, edit: Edit) -> Edit:
        inverse = self.document.apply(edit)
        self._changed()
        return inverse

    def begin_preview(self) -> None:
        """Start a live drag: later ``preview`` calls show edits without history."""
        if self._drag_base is None:
            self._drag_base = self.scene

    def preview(self, edit: Edit) -> bool:
        """Show ``edit`` applied to the scene at ``begin_preview`` (no undo entry)."""
        base = self._drag_base if self._drag_base is not None else self.scene
        try:
            new, _ = edit.apply_to(base)
        except (MechsketchError, KeyError, ValueError) as exc:
            self.message.emit(str(exc))
            return False
        self.document.scene = new
        self._changed()
        return True

    def end_preview(self, edit: Edit | None, text: str | None = None) -> None:
        """Finish a drag: restore the base scene and push ``edit`` as one command (None: cancel)."""
        base, self._drag_base = self._drag_base, None
        if base is not None:
            self.document.scene = base
        if edit is None:
            self._changed()
            return
        if not self.push(edit, text):
            self._changed()

    def reset(self, scene: Scene, path: Path | None = None) -> None:
        """Replace the document (New, Open): clears history, selection and frame."""
        self._drag_base = None
        self.undo_stack.clear()
        self.document.reset(scene)
        self.path = path
        self.selection = []
        self.frame = 0
        self.undo_stack.setClean()
        self._changed()
        self.selectionChanged.emit()
        self.pathChanged.emit()

    def mark_saved(self, path: Path) -> None:
        self.path = path
        self.undo_stack.setClean()
        self.pathChanged.emit()

    # -- selection and frame ----------------------------------------------------------------
    def set_selection(self, items: list[tuple[str, str, str]]) -> None:
        if items != self.selection:
            self.selection = list(items)
            self.selectionChanged.emit()

    def set_frame(self, index: int) -> None:
        n = self.sample_count()
        index = int(index) % n if n else 0
        if index != self.frame:
            self.frame = index
            self.frameChanged.emit(index)

    def sample_count(self) -> int:
        """Frames of the animation cycle: the first solved linkage's samples, else the first
        animatable Geneva drive's or rolling lever's frames (others map by cycle phase)."""
        for r in self._results.values():
            if r.solution is not None:
                return len(r.solution)
        for e in self._element_results.values():
            if e.n_frames:
                return e.n_frames
        return 0

    def cycle_period(self) -> float:
        """Seconds per animation cycle: the first solved linkage's driver revolution, else the
        first animated Geneva drive's crank revolution (a rolling lever: a nominal 2 s)."""
        for lk in self.linkages():
            res = self.result(lk.id)
            if res is not None and res.solution is not None and lk.driver.speed_rpm:
                return 60.0 / abs(lk.driver.speed_rpm)
        for e in self._element_results.values():
            if e.n_frames:
                return float(e.period)
        return 1.0

    def frame_text(self) -> tuple[str, bool]:
        """The current frame in words for the read-outs, and whether it can be assembled."""
        n, frame = self.sample_count(), self.frame
        for lk in self.linkages():
            res = self.result(lk.id)
            if res is not None and res.solution is not None:
                sol = res.solution
                k = map_frame(frame, n, len(sol))
                deg = math.degrees(math.remainder(float(sol.input[k]), 2 * math.pi))
                return f"input {deg:.2f}°  t {float(sol.t[k]):.3f} s  frame {frame + 1}/{n}", bool(sol.valid[k])
        for e in self._element_results.values():
            if e.n_frames:
                return f"{e.element_id}: {e.frame_text(map_frame(frame, n, e.n_frames))}  frame {frame + 1}/{n}", True
        return "nothing to animate", True

    # -- solving ----------------------------------------------------------------------------
    def _changed(self) -> None:
        self._resolve()
        self.sceneChanged.emit()
        self.solutionsChanged.emit()

    def _resolve(self) -> None:
        """Re-solve every linkage over its whole cycle (errors become messages, never raise)."""
        results: dict[str, SolveResult] = {}
        for el in self.linkages():
            t0 = time.perf_counter()
            res = SolveResult(el.id)
            try:
                res.plan = el.compile()
                res.solution = res.plan.sweep(samples=self.samples_override or el.samples, order=2)
                res.diagnostics = diagnose(res.solution)
            except (MechsketchError, KeyError, ValueError, ZeroDivisionError) as exc:
                # a linkage half-drawn by the tools is normal: keep the message, never raise
                res.error = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
                self.solveFailed.emit(el.id, res.error)
            res.seconds = time.perf_counter() - t0
            results[el.id] = res
        self._results = results
        self._resolve_elements()
        n = self.sample_count()
        if n and self.frame >= n:
            self.frame = 0

    def _resolve_elements(self) -> None:
        """Solve each Geneva drive and rolling lever once per change of that element (cached by
        value: a linkage drag or an undo does not recompute them); failures become messages."""
        old, new = self._element_results, {}
        for el in self.scene.elements:
            if isinstance(el, Linkage):
                continue
            res = self._element_cache.solve(el, self.samples_override)
            if res is None:
                continue
            new[el.id] = res
            if res.error is not None and old.get(el.id) is not res:
                self.solveFailed.emit(el.id, res.error)
        self._element_results = new
