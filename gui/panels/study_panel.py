"""The Study dock: tolerance and pin-clearance Monte Carlo, or optimisation, of a linkage, run on
a worker thread with progress and Cancel (issue 21, item 5).

The user picks a linkage and what to study. **Tolerance**: the variables are the rows of its
Dimensions table and its frame pivots, each with a ± tolerance (normal, ± = 3σ, or uniform), and
its pins with an ISO 286 fit each; Run builds that many copies with the batch engine; the result
is the band of the traced point drawn on the canvas (the envelope at the chosen confidence,
magnified and labelled so that microns can be seen), the histogram of its largest deviation over
the builds, and the sensitivity bars (each variable's and pin's share, first order), with the
summary and the agreement of the linearised band. **Optimise**: the variables get a range; one or
two objectives and a least transmission angle; the Pareto front is a scatter whose points preview
on the canvas, and *Apply* replaces the linkage by the picked variant (one undo step) or *Add as
new element* places it beside (one undo step).

A study never changes the scene while it runs; Cancel (or a failure, named in the status line)
leaves everything as it was. Signals for the canvas (wired by the main window):
``bandChanged(object)`` — the band dict of :func:`.study_runs.band` or None;
``previewChanged(object)`` — a linkage record to preview, or None.
"""
from __future__ import annotations

import shiboken6
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QKeySequence, QShortcut
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDoubleSpinBox, QFormLayout, QGroupBox, QHBoxLayout, QLabel,
                               QProgressBar, QPushButton, QScrollArea, QSpinBox, QVBoxLayout, QWidget)

from mechsketch.core import AddElement, ReplaceElement
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.transform import extent, fresh_id, renamed, translated

from .. import units
from ..qtsafe import qt_safe
from ..selection import ELEMENT
from . import study_runs as R
from .jobs import JobRunner, JobStatus
from .study_inputs import ClearanceTable, EntryError, VariableTable

MODES = (("tolerance", "Tolerance (Monte Carlo)"), ("optimize", "Optimise (Pareto front)"))
MAGNIFY = ("auto", "×1", "×10", "×100", "×1000")


def _spin(lo: int, hi: int, value: int, step: int = 1, name: str = "") -> QSpinBox:
    s = QSpinBox()
    s.setRange(lo, hi)
    s.setSingleStep(step)
    s.setValue(value)
    s.setGroupSeparatorShown(True)
    s.setObjectName(name)
    return s


@qt_safe
class StudyPanel(JobStatus, QWidget):
    """The Study dock's widget (see the module docstring)."""

    bandChanged = Signal(object)
    previewChanged = Signal(object)
    variables_of: Linkage | None = None   # the linkage the tables show
    on_screen = False                     # the dock is in front (tabbed docks stay "visible" behind)
    _stale = True

    def __init__(self, controller, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.runner = JobRunner(self)
        self.outcome: R.ToleranceOutcome | R.OptimiseOutcome | None = None
        self.picked: int | None = None
        self.tolerance_view = None
        self.pareto_view = None
        self._build()
        self.runner.progress.connect(self._progress)
        self.runner.finished.connect(self._finished)
        self.runner.failed.connect(self._failed)
        self.runner.cancelled.connect(self._cancelled)
        self.runner.busyChanged.connect(self._busy)
        controller.changed.connect(self._invalidate)
        controller.selectionChanged.connect(self._invalidate)
        controller.documentReplaced.connect(self.clear_results)
        controller.changed.connect(self._band_still_true)
        units.subscribe(self._units_changed)

    def _units_changed(self) -> None:
        """Edit › Preferences changed the display units: the tables show theirs, typed values kept
        (nothing for a panel whose window was closed: its Python object may outlive its widgets)."""
        if not (shiboken6.isValid(self) and shiboken6.isValid(self.variables.widget)):
            return
        self.variables.redisplay()
        self.clearances.redisplay()

    # -- construction ------------------------------------------------------------------------
    def _build(self) -> None:
        body = QWidget()
        col = QVBoxLayout(body)
        col.setContentsMargins(4, 4, 4, 4)
        top = QFormLayout()
        top.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        self.element_box = QComboBox()
        self.element_box.setObjectName("studyElement")
        self.element_box.currentTextChanged.connect(self._element_chosen)
        self.mode_box = QComboBox()
        self.mode_box.setObjectName("studyMode")
        for key, text in MODES:
            self.mode_box.addItem(text, key)
        self.mode_box.currentIndexChanged.connect(self._mode_chosen)
        top.addRow("linkage", self.element_box)
        top.addRow("study", self.mode_box)
        col.addLayout(top)
        self.variables = VariableTable()
        self.clearances = ClearanceTable()
        self.var_box = self._group("Variables (the Dimensions table and the frame's pivots)", self.variables.widget)
        self.pin_box = self._group("Pin clearances (ISO 286 fit on the bore)", self.clearances.widget)
        col.addWidget(self.var_box)
        col.addWidget(self.pin_box)
        col.addWidget(self._tolerance_settings())
        col.addWidget(self._optimise_settings())
        col.addLayout(self._run_row())
        self.status = QLabel("Choose the variables and press Run (Ctrl+Enter).")
        self.status.setObjectName("studyStatus")
        self.status.setWordWrap(True)
        self.status.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        col.addWidget(self.status)
        self.results = QVBoxLayout()
        col.addLayout(self.results)
        col.addLayout(self._variant_row())
        col.addStretch(1)
        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(body)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        outer = QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        outer.addWidget(scroll)
        run = QShortcut(QKeySequence("Ctrl+Return"), self, self.run)
        run.setContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)
        self._mode_chosen()

    @staticmethod
    def _group(title: str, widget: QWidget) -> QGroupBox:
        box = QGroupBox(title)
        lay = QVBoxLayout(box)
        lay.setContentsMargins(4, 4, 4, 4)
        lay.addWidget(widget)
        return box

    def _tolerance_settings(self) -> QGroupBox:
        self.tol_box = QGroupBox("Monte Carlo")
        f = QFormLayout(self.tol_box)
        f.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        self.builds = _spin(10, 10_000_000, 2000, 1000, "studyBuilds")
        self.builds.setToolTip("How many copies of the linkage are built with random dimensions and plays")
        self.distribution = QComboBox()
        self.distribution.addItem("normal (± = 3σ)", "normal")
        self.distribution.addItem("uniform (± = the limits)", "uniform")
        self.joint_box = QComboBox()
        self.joint_box.setObjectName("studyJoint")
        self.confidence = QComboBox()
        self.confidence.addItems(list(R.CONFIDENCES))
        self.confidence.setCurrentText("99 %")
        self.confidence.currentIndexChanged.connect(self._redraw_band)
        self.magnify = QComboBox()
        self.magnify.addItems(MAGNIFY)
        self.magnify.setToolTip("The band is magnified about the nominal path so that microns can be seen")
        self.magnify.currentIndexChanged.connect(self._redraw_band)
        self.tol_samples = _spin(12, 3600, 180, 30, "studySamples")
        self.tol_seed = _spin(0, 2_000_000_000, 1, 1, "studySeed")
        for label, w in (("builds", self.builds), ("distribution", self.distribution), ("traced point", self.joint_box),
                         ("band", self.confidence), ("magnify", self.magnify), ("samples per cycle", self.tol_samples),
                         ("seed", self.tol_seed)):
            f.addRow(label, w)
        return self.tol_box

    def _optimise_settings(self) -> QGroupBox:
        self.opt_box = QGroupBox("Optimisation")
        f = QFormLayout(self.opt_box)
        f.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        self.objective1 = QComboBox()
        self.objective1.setObjectName("studyObjective1")
        self.objective2 = QComboBox()
        self.objective2.setObjectName("studyObjective2")
        row = QHBoxLayout()
        self.mu_on = QCheckBox("least μ ≥")
        self.mu_on.setChecked(True)
        self.mu_min = QDoubleSpinBox()
        self.mu_min.setRange(0.0, 89.0)
        self.mu_min.setValue(40.0)
        self.mu_min.setSuffix(" °")
        row.addWidget(self.mu_on)
        row.addWidget(self.mu_min, 1)
        self.population = _spin(4, 1000, 24, 4, "studyPopulation")
        self.generations = _spin(1, 1000, 12, 1, "studyGenerations")
        self.opt_samples = _spin(12, 3600, 90, 30, "studyOptSamples")
        self.opt_seed = _spin(0, 2_000_000_000, 1, 1, "studyOptSeed")
        for label, w in (("objective", self.objective1), ("and", self.objective2), ("constraint", row),
                         ("population", self.population), ("generations", self.generations),
                         ("samples per cycle", self.opt_samples), ("seed", self.opt_seed)):
            f.addRow(label, w)
        return self.opt_box

    def _run_row(self) -> QHBoxLayout:
        row = QHBoxLayout()
        self.run_button = QPushButton("Run")
        self.run_button.setObjectName("studyRun")
        self.run_button.setToolTip("Run the study on a worker thread (Ctrl+Enter)")
        self.run_button.clicked.connect(self.run)
        self.cancel_button = QPushButton("Cancel")
        self.cancel_button.setObjectName("studyCancel")
        self.cancel_button.clicked.connect(self.runner.cancel)
        self.cancel_button.setEnabled(False)
        self.clear_button = QPushButton("Clear")
        self.clear_button.setToolTip("Clear the results, the band and the preview")
        self.clear_button.clicked.connect(self.clear_results)
        self.bar = QProgressBar()
        self.bar.setRange(0, 1000)
        self.bar.setValue(0)
        self.bar.setTextVisible(False)
        for w in (self.run_button, self.cancel_button, self.clear_button):
            row.addWidget(w)
        row.addWidget(self.bar, 1)
        return row

    def _variant_row(self) -> QHBoxLayout:
        row = QHBoxLayout()
        self.variant_label = QLabel()
        self.variant_label.setWordWrap(True)
        self.apply_button = QPushButton("Apply")
        self.apply_button.setObjectName("studyApply")
        self.apply_button.setToolTip("Replace the linkage by the picked variant (one undo step)")
        self.apply_button.clicked.connect(self.apply_variant)
        self.add_button = QPushButton("Add as new element")
        self.add_button.setObjectName("studyAddVariant")
        self.add_button.setToolTip("Place the picked variant beside the linkage as a new element (one undo step)")
        self.add_button.clicked.connect(self.add_variant)
        for w in (self.apply_button, self.add_button):
            w.setVisible(False)
            row.addWidget(w)
        col = QVBoxLayout()
        col.addWidget(self.variant_label)
        col.addLayout(row)
        return col

    # -- what is shown -----------------------------------------------------------------------
    def linkage(self) -> Linkage | None:
        eid = self.element_box.currentText()
        scene = self.controller.scene
        el = scene.element(eid) if eid in scene.ids else None
        return el if isinstance(el, Linkage) else None

    @property
    def mode(self) -> str:
        return self.mode_box.currentData()

    def set_on_screen(self, on: bool) -> None:
        """The dock came to the front (or went behind another): it shows the scene from then on."""
        self.on_screen = bool(on)
        if self.on_screen and self._stale:
            self.refresh()

    def _invalidate(self, *args) -> None:
        """A change or a new selection: shown at once when the dock is in front, else when it comes
        there (a drag preview waits for its release)."""
        self._stale = True
        if self.on_screen and not (args and getattr(args[0], "preview", False)):
            self.refresh()

    def refresh(self) -> None:
        """The linkages of the scene in the chooser (the selected one first chosen)."""
        self._stale = False
        ids = [lk.id for lk in self.controller.linkages()]
        box = self.element_box
        current = box.currentText()
        chosen = next((e for e, _k, _i in self.controller.selection if e in ids), None)
        if [box.itemText(k) for k in range(box.count())] != ids:
            box.blockSignals(True)
            box.clear()
            box.addItems(ids)
            box.blockSignals(False)
            box.setCurrentText(current if current in ids else (chosen or (ids[0] if ids else "")))
        elif chosen and chosen != current and not self.runner.busy:
            box.setCurrentText(chosen)
        self._element_chosen()

    def _element_chosen(self, *_args) -> None:
        lk = self.linkage()
        if lk is self.variables_of:
            return
        self.variables_of = lk
        self.variables.set_linkage(lk)
        self.clearances.set_linkage(lk)
        self.joint_box.clear()
        self.objective1.clear()
        self.objective2.clear()
        self.objective2.addItem("none (one objective)", None)
        if lk is not None:
            self.joint_box.addItems(R.traced_default(lk) + [j for j in lk.joint_ids if j not in R.traced_default(lk)])
            for sense, metric, words in R.objectives(lk):
                self.objective1.addItem(words, f"{sense} {metric}")
                self.objective2.addItem(words, f"{sense} {metric}")
            out = lk.moving_links[-1] if lk.moving_links else None
            k = self.objective2.findData(f"maximize swing:{out}")
            self.objective2.setCurrentIndex(max(k, 0))
            self.tol_samples.setValue(min(lk.samples, 360))
        self.run_button.setEnabled(lk is not None and not self.runner.busy)
        if lk is None:
            self.status.setText("No linkage in the scene: draw one or open an example, then study it here.")

    def _mode_chosen(self, *_args) -> None:
        tol = self.mode == "tolerance"
        self.variables.set_mode(self.mode)
        self.pin_box.setVisible(tol)
        self.tol_box.setVisible(tol)
        self.opt_box.setVisible(not tol)

    # -- running -----------------------------------------------------------------------------
    def run(self) -> bool:
        """Check the entries and start the study on the worker thread (False, with the reason in
        the status line, if it cannot start)."""
        if self.runner.busy:
            return self._say("a study is running: wait for it or press Cancel")
        lk = self.linkage()
        if lk is None:
            return self._say("choose a linkage to study")
        try:
            title, work = self._request(lk)
        except EntryError as exc:
            if exc.table is not None and exc.row >= 0:
                exc.table.setCurrentCell(exc.row, exc.column)
                exc.table.setFocus()
            return self._say(str(exc), error=True)
        self.clear_results()
        self.outcome = None
        return self.runner.start(title, work)

    def _request(self, lk: Linkage):
        if self.mode == "tolerance":
            spec = self.variables.tolerances(self.distribution.currentData())
            pins = self.clearances.spec()
            if pins:
                spec["clearance"] = pins
            if not spec:
                raise EntryError("tick at least one variable or pin to study (the 'use' column)")
            builds, samples, seed = self.builds.value(), self.tol_samples.value(), self.tol_seed.value()
            joint = self.joint_box.currentText()
            return (f"tolerance of {lk.id}",
                    lambda t: R.tolerance_work(lk, spec, builds, samples, seed, joint, t))
        ranges = self.variables.ranges()
        if not ranges:
            raise EntryError("tick at least one variable to optimise and give its range")
        objs = [tuple(self.objective1.currentData().split(" ", 1))]
        second = self.objective2.currentData()
        if second is not None:
            if tuple(second.split(" ", 1)) == objs[0]:
                raise EntryError("the two objectives are the same: choose another second one, or none")
            objs.append(tuple(second.split(" ", 1)))
        data = R.study_dict(ranges, objs, self.mu_min.value() if self.mu_on.isChecked() else None,
                            self.opt_samples.value(), self.opt_seed.value(), self.population.value(),
                            self.generations.value())
        return f"optimisation of {lk.id}", lambda t: R.optimise_work(lk, data, t)

    def _can_run(self) -> bool:
        return self.linkage() is not None

    def _failed(self, exc) -> None:
        self.bar.setValue(0)
        self._say(f"{self.runner.title or 'the study'} failed: {exc}", error=True)

    def _finished(self, outcome) -> None:
        self.bar.setValue(1000)
        self.outcome = outcome
        if isinstance(outcome, R.ToleranceOutcome):
            self._show_tolerance(outcome)
        else:
            self._show_front(outcome)

    # -- tolerance results -------------------------------------------------------------------
    def _show_tolerance(self, out: R.ToleranceOutcome) -> None:
        from .study_results import ToleranceView

        if self.tolerance_view is None:
            self.tolerance_view = ToleranceView()
            self.results.addWidget(self.tolerance_view)
        self.tolerance_view.setVisible(True)
        res, j = out.result, out.joint
        dev = res.deviation(j)
        marks = {"median": res.percentile(j, 50), self.confidence.currentText(): res.percentile(
            j, 100 * R.CONFIDENCES[self.confidence.currentText()])}
        self.tolerance_view.show_result(dev, marks, res.sensitivity(j), j)
        lines = [res.summary(j)]
        if out.agreement is not None:
            lines.append(f"the linearised 3σ band (one solve) agrees with the Monte Carlo within "
                         f"{100 * out.agreement:.2g} %")
        self.status.setStyleSheet("")
        self.status.setText("\n".join(lines))
        self._redraw_band()

    def current_band(self) -> dict | None:
        """The band shown for the last tolerance run (None: none)."""
        out = self.outcome
        if not isinstance(out, R.ToleranceOutcome):
            return None
        text = self.magnify.currentText()
        factor = None if text == "auto" else float(text.lstrip("×"))
        return R.band(out, R.CONFIDENCES[self.confidence.currentText()], factor)

    def _band_still_true(self, change) -> None:
        """A band belongs to the linkage as it was studied: once that changes (an edit, undo), the
        band leaves the canvas and the status says to run the study again."""
        out = self.outcome
        if change.preview or not isinstance(out, R.ToleranceOutcome):
            return
        scene = self.controller.scene
        if out.linkage.id not in scene.ids or scene.element(out.linkage.id) is not out.linkage:
            self.outcome = None
            self.bandChanged.emit(None)
            self._say(f"{out.linkage.id} changed since its tolerance study: the band is gone; press Run "
                      "to study it again")

    def _redraw_band(self, *_args) -> None:
        band = self.current_band()
        if band is not None:
            self.bandChanged.emit(band)

    # -- optimisation results ----------------------------------------------------------------
    def _show_front(self, out: R.OptimiseOutcome) -> None:
        from .study_results import ParetoView

        if self.pareto_view is None:
            self.pareto_view = ParetoView()
            self.pareto_view.pointPicked.connect(self.pick)
            self.results.addWidget(self.pareto_view)
        self.pareto_view.setVisible(True)
        front, others = out.front_xy()
        units_of = out.result.units
        labels = [f"{m} ({units_of.get(m, '')})" for m in out.metrics]
        self.pareto_view.show_front(front, others, labels[0] if len(labels) > 1 else "evaluation",
                                    labels[1] if len(labels) > 1 else labels[0])
        s = out.result.summary
        self.pareto_view.note.setText(f"{s['evaluations']} designs evaluated ({s['feasible']} feasible) in "
                                      f"{s.get('seconds', 0):.2f} s with {s['algorithm'].upper()}; "
                                      f"{len(out.front)} on the front.")
        self.status.setStyleSheet("")
        self.status.setText(f"optimisation of {out.linkage.id}: click a point of the front to preview it")
        if out.front:
            self.pick(0)

    def pick(self, index: int) -> None:
        """Preview the front's design ``index`` on the canvas."""
        out = self.outcome
        if not isinstance(out, R.OptimiseOutcome) or not 0 <= index < len(out.front):
            return
        self.picked = index
        row, rec = out.front[index]
        cols = out.result.columns
        keys = list(out.result.study.variables)
        vals = ", ".join(f"{k.split(':', 1)[1]} {cols[k][row]:.4g}" for k in keys)
        objs = ", ".join(f"{m} {cols[m][row]:.4g} {out.result.units.get(m, '')}" for m in out.metrics)
        self.variant_label.setText(f"variant {index + 1} of {len(out.front)}: {objs}\n{vals}")
        self.apply_button.setText(f"Apply to {rec.id}")
        for w in (self.apply_button, self.add_button):
            w.setVisible(True)
        if self.pareto_view is not None:
            self.pareto_view.choose(index)
        self.previewChanged.emit(rec)

    def picked_variant(self) -> Linkage | None:
        out = self.outcome
        if not isinstance(out, R.OptimiseOutcome) or self.picked is None:
            return None
        return out.front[self.picked][1]

    def apply_variant(self) -> bool:
        """Replace the studied linkage by the picked variant: one undo step."""
        rec = self.picked_variant()
        if rec is None:
            return self._say("pick a point of the Pareto front first")
        if rec.id not in self.controller.scene.ids:
            return self._say(f"{rec.id} is no longer in the scene: use Add as new element")
        label = f"apply study variant {self.picked + 1} to {rec.id}"
        ok = self.controller.push(ReplaceElement(rec, label), label)
        if ok:
            self.previewChanged.emit(None)
            self._say(f"{rec.id} now has the dimensions of variant {self.picked + 1} (Ctrl+Z undoes it)")
        return ok

    def add_variant(self) -> bool:
        """Add the picked variant beside the studied linkage as a new element: one undo step."""
        rec = self.picked_variant()
        if rec is None:
            return self._say("pick a point of the Pareto front first")
        x0, _y0, x1, _y1 = extent(rec)
        new = translated(renamed(rec, fresh_id(f"{rec.id}_v{self.picked + 1}", self.controller.scene.ids)),
                         1.3 * (x1 - x0) + 20.0, 0.0)
        label = f"add study variant {new.id}"
        ok = self.controller.push(AddElement(new, label=label), label)
        if ok:
            self.previewChanged.emit(None)
            self.controller.set_selection([(new.id, ELEMENT, new.id)])
            self._say(f"added {new.id} beside {rec.id}: an ordinary linkage (Ctrl+Z removes it)")
        return ok

    def clear_results(self) -> None:
        """Forget the results: the band and the preview leave the canvas."""
        self.outcome, self.picked = None, None
        for view in (self.tolerance_view, self.pareto_view):
            if view is not None:
                view.setVisible(False)
        for w in (self.apply_button, self.add_button):
            w.setVisible(False)
        self.variant_label.setText("")
        self.bandChanged.emit(None)
        self.previewChanged.emit(None)

    def shutdown(self) -> None:
        """Cancel a running study and wait for it (the window closes)."""
        self.runner.cancel()
        self.runner.wait()


__all__ = ["StudyPanel"]
