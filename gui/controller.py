"""The Qt adapter over the core workspace: undo stack, selection, animation frame, signals.

The document and every result live in :class:`mechsketch.core.workspace.Workspace`; this class
only adds what Qt needs. Widgets read ``controller.scene`` and the results, and change the
document only through ``push(edit)`` (one undo command) or a drag preview that ends in one
command. Signals are past tense and fire once the document is consistent:

- ``changed(Change)`` after every edit, undo, redo and drag-preview move: which elements changed
  (added, removed, modified) and whether it is a preview. The changed elements are solved before
  the signal (the rest keep their cached results), so a drag re-solves only the element it moves,
  and only the groups that depend on it (the canvas then asks for the diagnostics it marks);
- ``documentReplaced()`` after New, Open or a restore (then ``changed`` follows with every id).
"""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QObject, Signal
from PySide6.QtGui import QUndoCommand, QUndoStack

from mechsketch.core.errors import EditError, MechsketchError
from mechsketch.core.model.edits import Edit
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.scene import Scene
from mechsketch.core.solver.diagnostics import Diagnostics
from mechsketch.core.workspace import (Change, ElementResult, GearResult, GenevaResult, LinkageResult, RollingResult,
                                      Workspace)

from .background import HEAVY_SECONDS, BackgroundSolver, estimated_seconds, solve_each
from .frames import map_frame
from .qtsafe import qt_safe

DEFAULT_SAMPLES = 360


@qt_safe
class EditCommand(QUndoCommand):
    """A QUndoCommand wrapping one reversible core edit."""

    def __init__(self, controller: "SceneController", edit: Edit, text: str) -> None:
        super().__init__(text)
        self._controller = controller
        self._edit = edit
        self._inverse: Edit | None = None

    def redo(self) -> None:
        self._controller.interrupt_preview()
        self._inverse = self._controller.workspace.apply(self._edit)

    def undo(self) -> None:
        self._controller.interrupt_preview()
        if self._inverse is not None:
            self._edit = self._controller.workspace.apply(self._inverse)


class SceneController(QObject):
    """Workspace + undo stack + selection + animation frame, with signals."""

    changed = Signal(object)           # Change: element ids, added/removed/modified, preview or final
    documentReplaced = Signal()        # New, Open, restore: a different document (history cleared)
    solveFailed = Signal(str, str)     # element id, message (the GUI shows it; never raises)
    selectionChanged = Signal()
    frameChanged = Signal(int)         # current sample index of the animation / scrub bar
    pathChanged = Signal()             # file path or clean state changed (window title)
    message = Signal(str)              # a line for the status bar
    previewInterrupted = Signal()      # an edit, undo or redo ended a drag's preview (the drag stops)

    def __init__(self, scene: Scene | None = None, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.workspace = Workspace(scene)
        self.undo_stack = QUndoStack(self)
        self.undo_stack.cleanChanged.connect(self._on_clean_changed)
        self.path: Path | None = None
        self.selection: list[tuple[str, str, str]] = []   # (element id, SelectionKind, id)
        self.frame = 0
        self._reported: dict[str, object] = {}            # element id -> result whose error was shown
        #: heavy solves off the GUI thread (push_when_solved); its busyChanged drives the status bar
        self.background = BackgroundSolver(self)
        self.workspace.subscribe(self._on_change)
        self._solve(self.scene.ids, final=True)

    def _on_clean_changed(self, _clean: bool) -> None:
        # a bound slot (not a lambda): Qt drops the connection when the controller is destroyed,
        # so the undo stack's own clean-up at teardown cannot reach a deleted controller
        self.pathChanged.emit()

    # -- reading ----------------------------------------------------------------------------
    @property
    def scene(self) -> Scene:
        return self.workspace.scene

    @property
    def samples_override(self) -> int | None:
        """Samples per cycle for every linkage and Geneva drive (None: each element's own)."""
        return self.workspace.samples

    @samples_override.setter
    def samples_override(self, value: int | None) -> None:
        self.workspace.samples = value

    def linkages(self) -> list[Linkage]:
        return [e for e in self.scene.elements if isinstance(e, Linkage)]

    def any_result(self, element_id: str) -> ElementResult | None:
        """The workspace's result of any element (None for an unknown id)."""
        if element_id not in self.scene.ids:
            return None
        return self.workspace.result(element_id)

    def result(self, element_id: str) -> LinkageResult | None:
        """The result of a linkage (None for another element type or an unknown id)."""
        res = self.any_result(element_id)
        return res if isinstance(res, LinkageResult) else None

    def results(self) -> dict[str, LinkageResult]:
        """Results of every linkage, in scene order."""
        return {lk.id: self.result(lk.id) for lk in self.linkages()}

    def diagnostics(self, element_id: str) -> Diagnostics | None:
        """The diagnostics of linkage ``element_id`` for a widget to show (None for another
        element or one that does not solve). Computed on first request, except during a drag
        preview, which never waits for them: then only those already computed for the shown
        result (None until the release, whose final change computes them)."""
        res = self.result(element_id)
        if res is None:
            return None
        return res.diagnostics_if_computed if self.workspace.previewing else res.diagnostics

    def element_result(self, element_id: str) -> GenevaResult | RollingResult | None:
        """The result of a Geneva drive or rolling lever (None for a linkage or an unknown id)."""
        res = self.any_result(element_id)
        return res if isinstance(res, (GenevaResult, RollingResult, GearResult)) else None

    def element_results(self) -> dict[str, GenevaResult | RollingResult]:
        """Results of every Geneva drive and rolling lever, in scene order."""
        out = {}
        for el in self.scene.elements:
            res = self.element_result(el.id)
            if res is not None:
                out[el.id] = res
        return out

    def check_element(self, element) -> str | None:
        """Solve ``element`` (not yet in the scene) as the workspace would; the core's message if
        it fails, else None (the result is kept for when the edit lands)."""
        return self.workspace.check_element(element)

    @property
    def is_dirty(self) -> bool:
        return not self.undo_stack.isClean()

    # -- editing ----------------------------------------------------------------------------
    def push(self, edit: Edit, text: str | None = None) -> bool:
        """Apply ``edit`` as one undo command; False (and a message) if the edit is refused."""
        label = text or getattr(edit, "label", "edit")
        self.interrupt_preview()
        try:
            new = self.workspace.check(edit)  # dry run: refuse bad edits before they enter history
        except MechsketchError as exc:
            self.message.emit(f"cannot {label}: {exc}")
            return False
        old = {e.id: e for e in self.scene.elements}
        heavy = [e for e in new.elements if old.get(e.id) is not e and self.is_heavy(e)]
        if heavy:   # a canvas tool's or a drag's edit of a heavy element: solved off the GUI thread
            self._land_when_solved(heavy, edit, label)
            return True
        self.undo_stack.push(EditCommand(self, edit, label))
        return True

    def is_heavy(self, element) -> bool:
        """Whether solving ``element`` (a candidate) would block the window: estimated above
        :data:`~.background.HEAVY_SECONDS` and not cached."""
        samples = self.workspace.samples_for(element)
        return estimated_seconds(element, samples) > HEAVY_SECONDS and not self.workspace.has_result(element)

    def push_when_solved(self, element, edit: Edit, text: str) -> bool:
        """Push ``edit``, which puts the candidate ``element`` in the scene, once ``element`` is
        solved: at once when that is quick (then as :meth:`push`; the core's message raised as
        :class:`EditError` if it does not solve), else on a worker thread while the window keeps
        working (``background``: busy indicator and Cancel), the edit landing when the result is
        there if the document did not change meanwhile. Returns False if refused at once."""
        if not self.is_heavy(element):
            error = self.check_element(element)
            if error is not None:
                raise EditError(error)
            return self.push(edit, text)
        self._land_when_solved([element], edit, text)
        return True

    def _land_when_solved(self, elements: list, edit: Edit, text: str) -> None:
        """Solve ``elements`` (the heavy ones ``edit`` brings) off the GUI thread, then push
        ``edit`` if the document did not change meanwhile (their results are kept either way)."""
        base = self.scene
        element = elements[0]

        def landed(problems: list[str]) -> None:
            kept = [self.workspace.result_of(e) for e in elements if self.workspace.has_result(e)]   # cached
            errors = problems + [f"{r.error}" for r in kept if r is not None and r.error is not None]
            if errors:
                self.message.emit(f"cannot {text}: {'; '.join(errors)}")
            elif self.scene is not base:
                self.message.emit(f"{text}: not applied, the document changed while it was solved "
                                  "(its result is kept: do it again to apply it at once)")
            else:
                self.push(edit, text)

        solve_each(self.background, self.workspace, elements,
                   text if element.id in text else f"{text} ({element.id})", landed)
        self.message.emit(f"solving {element.id} for '{text}' off the main window (Cancel in the status bar)")

    def reset_when_solved(self, scene: Scene, path: Path | None, text: str, then=None) -> bool:
        """Replace the document by ``scene`` (Open) once its heavy elements are solved off the GUI
        thread (busy indicator and Cancel in the status bar; Cancel keeps the current document),
        at once when none is heavy; then call ``then()``. False if the document changed while its
        elements were solved (the results are kept: opening it again is quick)."""
        heavy = [e for e in scene.elements if self.is_heavy(e)]
        if not heavy:
            self.reset(scene, path)
            if then is not None:
                then()
            return True
        base, clean = self.scene, self.undo_stack.index()

        def landed(problems: list[str]) -> None:
            if self.scene is not base or self.undo_stack.index() != clean:
                self.message.emit(f"{text}: not opened, the document changed meanwhile (open it again: "
                                  "its results are kept)")
                return
            self.reset(scene, path)
            if then is not None:
                then()

        solve_each(self.background, self.workspace, heavy, text, landed)
        self.message.emit(f"{text}: solving {len(heavy)} large element(s) off the main window "
                          "(Cancel in the status bar keeps this document)")
        return True

    def interrupt_preview(self) -> None:
        """An edit, undo or redo lands while a drag previews (a shortcut pressed mid-drag): the
        preview ends first, so the edit applies to the document and not to a preview of it, and
        ``previewInterrupted`` tells the drag to stop. A drag's own release ends its preview
        before it pushes, so this does nothing then."""
        if self.workspace.previewing:
            self.workspace.end_preview(notify=True)
            self.previewInterrupted.emit()

    def begin_preview(self) -> None:
        """Start a live drag: later ``preview`` calls show edits without history."""
        self.workspace.begin_preview()

    def preview(self, edit: Edit) -> bool:
        """Show ``edit`` applied to the scene at ``begin_preview`` (no undo entry)."""
        try:
            self.workspace.preview(edit)
        except MechsketchError as exc:
            self.message.emit(str(exc))
            return False
        return True

    def end_preview(self, edit: Edit | None, text: str | None = None) -> None:
        """Finish a drag: restore the base scene and push ``edit`` as one command (None: cancel).
        Listeners see one change on release."""
        self.workspace.end_preview(notify=edit is None)
        if edit is not None and not self.push(edit, text):
            self.workspace.flush()   # refused: report what the preview touched, now back at base

    def reset(self, scene: Scene, path: Path | None = None) -> None:
        """Replace the document (New, Open): clears history, selection and frame."""
        self.background.cancel()
        self.undo_stack.clear()
        self.path = path
        self.selection = []
        self.frame = 0
        self._reported.clear()
        self.workspace.reset(scene)
        self.undo_stack.setClean()
        self.selectionChanged.emit()
        self.pathChanged.emit()

    def mark_saved(self, path: Path) -> None:
        self.path = path
        self.undo_stack.setClean()
        self.pathChanged.emit()

    def _on_change(self, change: Change) -> None:
        """From the workspace: report failures of the changed elements, keep the frame in range,
        then tell the widgets."""
        self._solve(change.ids, final=not change.preview)
        n = self.sample_count()
        if n and self.frame >= n:
            self.frame = 0
        if change.replaced:
            self.documentReplaced.emit()
        self.changed.emit(change)

    def _solve(self, ids, final: bool) -> None:
        """Solve the elements ``ids`` now (the others keep their cached results) and report
        failures once per result; on a ``final`` change, a linkage's diagnostics too (the
        animation and the dead-point marks read them; a drag preview does not need them)."""
        for eid in ids:
            if eid not in self.scene.ids:
                self._reported.pop(eid, None)
                continue
            res = self.workspace.result(eid)
            if isinstance(res, LinkageResult) and final:
                _ = res.diagnostics
            if res is not None and res.error is not None and self._reported.get(eid) is not res:
                self._reported[eid] = res
                self.solveFailed.emit(eid, res.error)

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

    def _clock(self) -> ElementResult | None:
        """The result that sets the animation cycle: the first solved linkage, else the first
        animatable Geneva drive or rolling lever (the others map by cycle phase)."""
        for lk in self.linkages():
            res = self.result(lk.id)
            if res is not None and res.n_frames:
                return res
        return next((e for e in self.element_results().values() if e.n_frames), None)

    def sample_count(self) -> int:
        """Frames of the animation cycle (see :meth:`_clock`); 0 when nothing can be animated."""
        res = self._clock()
        return res.n_frames if res is not None else 0

    def cycle_period(self) -> float:
        """Seconds per animation cycle: the first solved linkage's driver revolution, else the
        first animated Geneva drive's crank revolution (a rolling lever: a nominal 2 s)."""
        res = self._clock()
        return float(res.period) if res is not None else 1.0

    def frame_text(self) -> tuple[str, bool]:
        """The current frame in words for the read-outs, and whether it can be assembled."""
        res = self._clock()
        if res is None:
            return "nothing to animate", True
        n = res.n_frames
        k = map_frame(self.frame, n, res.n_frames)
        if isinstance(res, LinkageResult):
            return f"{res.frame_text(k)}  frame {self.frame + 1}/{n}", bool(res.solution.valid[k])
        return f"{res.element_id}: {res.frame_text(k)}  frame {self.frame + 1}/{n}", True
