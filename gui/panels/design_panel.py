"""The Design dock: a mechanism from what it must do (issue 22 item 6, issue 25).

**Linkage synthesis** — *Path* (a coupler point traces it), *Motion* (rigid-body poses) or
*Function* (input → output pairs). The target is typed in the table, read from a CSV file, or
taken from the canvas: **Click on canvas** (points one by one; poses: press at the point and
drag along its angle), **Draw** (a freehand stroke), **From underlay** (an underlay's polyline).
**Design** (Ctrl+Enter) runs the synthesis on a worker thread with progress and **Cancel**; the
candidates come back as a list — a thumbnail, the largest deviation, the least transmission
angle, the type and the time — and the chosen one moves on the canvas over the target. **Insert**
adds it as an ordinary linkage (one undo step): its Dimensions table, forces and export are those
of any linkage.

**From requirements** — *Geneva drive*, *Rolling lever* with a slider law, *Gears* from a
transmission function: a form of the REQ fields, **Design**, then the report (each requirement's
value, limit and margin; the binding one marked) and **Insert** (one undo step, placed beside
what the scene holds). A refusal names what to relax, as buttons that put the needed value in the
form.

Signals for the canvas (wired by the main window): ``targetChanged(object)`` (the canvas layer's
target dict, or None), ``previewChanged(object)`` (a linkage record, or None),
``targetRequested(str)`` ("click", "poses", "draw", "underlay": read the target from the canvas).
"""
from __future__ import annotations

from typing import Callable

import shiboken6
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QKeySequence, QShortcut
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDoubleSpinBox, QFormLayout, QGroupBox, QHBoxLayout, QLabel,
                               QProgressBar, QPushButton, QScrollArea, QSpinBox, QStackedWidget, QVBoxLayout, QWidget)

from mechsketch.core import AddElement
from mechsketch.core.model.rolling_lever import RollingLever
from mechsketch.core.model.transform import extent, fresh_id, renamed, translated

from .. import units
from ..qtsafe import qt_safe
from ..selection import ELEMENT
from . import design_runs as D
from .design_candidates import CandidateList
from .design_reqs import GearsForm, GenevaForm, ReportView, RollingForm
from .design_targets import TargetTable
from .jobs import JobRunner, JobStatus
from .study_inputs import EntryError


def _button(text: str, name: str, tip: str, slot) -> QPushButton:
    b = QPushButton(text)
    b.setObjectName(name)
    b.setToolTip(tip)
    b.clicked.connect(slot)
    return b


@qt_safe
class DesignPanel(JobStatus, QWidget):
    """The Design dock's widget (see the module docstring). ``ask_csv()`` returns the path of a CSV
    file the user picked (or None)."""

    targetChanged = Signal(object)
    previewChanged = Signal(object)
    targetRequested = Signal(str)

    def __init__(self, controller, ask_csv: Callable[[], str | None] | None = None,
                 parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.ask_csv = ask_csv or (lambda: None)
        self.runner = JobRunner(self)
        self.result = None          # a DesignResult, or a requirement design
        self.result_mode = ""
        self._build()
        self.runner.progress.connect(self._progress)
        self.runner.finished.connect(self._finished)
        self.runner.failed.connect(self._failed)
        self.runner.cancelled.connect(self._cancelled)
        self.runner.busyChanged.connect(self._busy)
        self.target.edited.connect(self._target_edited)
        controller.changed.connect(lambda _c: self.rolling.refresh())
        controller.documentReplaced.connect(self._replaced)
        units.subscribe(self._units_changed)

    # -- construction ------------------------------------------------------------------------
    def _build(self) -> None:
        body = QWidget()
        col = QVBoxLayout(body)
        col.setContentsMargins(4, 4, 4, 4)
        self.mode_box = QComboBox()
        self.mode_box.setObjectName("designMode")
        for key, text in {**D.LINKAGE_MODES, **D.REQUIREMENT_MODES}.items():
            self.mode_box.addItem(text, key)
        top = QFormLayout()
        top.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        top.addRow("design", self.mode_box)
        col.addLayout(top)
        self.stack = QStackedWidget()
        self.stack.addWidget(self._linkage_page())
        self.geneva, self.rolling, self.gears = GenevaForm(), RollingForm(self._levers), GearsForm()
        for form in (self.geneva, self.rolling, self.gears):
            self.stack.addWidget(form)
        col.addWidget(self.stack)
        row = QHBoxLayout()
        self.run_button = _button("Design", "designRun", "Run the design on a worker thread (Ctrl+Enter)", self.run)
        self.cancel_button = _button("Cancel", "designCancel", "Stop the design: nothing is changed", self.runner.cancel)
        self.cancel_button.setEnabled(False)
        self.bar = QProgressBar()
        self.bar.setRange(0, 1000)
        self.bar.setTextVisible(False)
        row.addWidget(self.run_button)
        row.addWidget(self.cancel_button)
        row.addWidget(self.bar, 1)
        col.addLayout(row)
        self.status = QLabel("Give a target and press Design (Ctrl+Enter).")
        self.status.setObjectName("designStatus")
        self.status.setWordWrap(True)
        self.status.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        col.addWidget(self.status)
        self.candidates = CandidateList()
        self.candidates.currentRowChanged.connect(self._candidate_chosen)
        self.candidates.itemDoubleClicked.connect(lambda _i: self.insert())
        self.report = ReportView()
        self.report.relax.connect(self._relax)
        self.insert_button = _button("Insert", "designInsert", "Add the chosen design to the scene (one undo step)",
                                     self.insert)
        for w in (self.candidates, self.report, self.insert_button):
            w.setVisible(False)
            col.addWidget(w)
        col.addStretch(1)
        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(body)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        outer = QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        outer.addWidget(scroll)
        QShortcut(QKeySequence("Ctrl+Return"), self, self.run).setContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)
        self.mode_box.currentIndexChanged.connect(self._mode_chosen)
        self._mode_chosen()

    def _linkage_page(self) -> QWidget:
        page = QWidget()
        col = QVBoxLayout(page)
        col.setContentsMargins(0, 0, 0, 0)
        box = QGroupBox("Target")
        lay = QVBoxLayout(box)
        lay.setContentsMargins(4, 4, 4, 4)
        picks = QHBoxLayout()
        self.click_button = _button("Click on canvas", "designClick", "Click the points on the canvas; Enter or a "
                                    "double click ends, Backspace removes the last, Esc cancels", self._ask_click)
        self.draw_button = _button("Draw", "designDraw", "Draw the path freehand on the canvas", self._ask_draw)
        self.underlay_button = _button("From underlay", "designUnderlay", "Click a line of an underlay",
                                       lambda: self.targetRequested.emit("underlay"))
        for b in (self.click_button, self.draw_button, self.underlay_button):
            picks.addWidget(b)
        lay.addLayout(picks)
        edits = QHBoxLayout()
        for b in (_button("CSV…", "designCsv", "Read the target from a CSV file (the columns of mechsketch design)",
                          self.read_csv),
                  _button("Add row", "designAddRow", "Add a row to type in", lambda: self.target.add_row()),
                  _button("Remove", "designRemoveRows", "Remove the selected rows", lambda: self.target.remove_rows()),
                  _button("Clear", "designClear", "Remove every row", lambda: self.target.clear())):
            edits.addWidget(b)
        lay.addLayout(edits)
        self.target = TargetTable(self)
        self.target.widget.setMinimumHeight(150)
        lay.addWidget(self.target.widget)
        flags = QHBoxLayout()
        self.closed = QCheckBox("closed loop")
        self.closed.setChecked(True)
        self.closed.toggled.connect(self._target_edited)
        self.timed = QCheckBox("timed (crank angle per point)")
        self.timed.toggled.connect(self.target.set_timed)
        self.output_unit = QComboBox()
        self.output_unit.addItem("output angle (°): a rocker", "°")
        self.output_unit.addItem("output position (mm): a slider", "mm")
        self.output_unit.currentIndexChanged.connect(self._output_unit_chosen)
        for w in (self.closed, self.timed, self.output_unit):
            flags.addWidget(w)
        lay.addLayout(flags)
        col.addWidget(box)
        opts = QGroupBox("Candidates")
        f = QFormLayout(opts)
        f.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        self.topology = QComboBox()
        self.topology.setObjectName("designTopology")
        self.count = QSpinBox()
        self.count.setRange(1, 50)
        self.count.setValue(5)
        self.min_mu = QDoubleSpinBox()
        self.min_mu.setRange(0.0, 89.0)
        self.min_mu.setValue(30.0)
        self.min_mu.setSuffix(" °")
        self.full_turn = QCheckBox("the crank turns fully")
        self.grashof = QComboBox()
        self.grashof.addItem("any type", None)
        self.grashof.addItem("crank-rocker", "crank-rocker")
        self.grashof.addItem("double crank", "double crank")
        for label, w in (("topology", self.topology), ("how many", self.count), ("least transmission angle", self.min_mu),
                         ("", self.full_turn), ("four-bar type", self.grashof)):
            f.addRow(label, w)
        col.addWidget(opts)
        return page

    # -- state -------------------------------------------------------------------------------
    @property
    def mode(self) -> str:
        return self.mode_box.currentData()

    def _levers(self) -> list:
        return [e for e in self.controller.scene.elements if isinstance(e, RollingLever)]

    def _mode_chosen(self, *_args) -> None:
        m = self.mode
        linkage = m in D.LINKAGE_MODES
        self.stack.setCurrentIndex(0 if linkage else 1 + list(D.REQUIREMENT_MODES).index(m))
        if linkage:
            self.target.set_mode(m)
            self.closed.setVisible(m == "path")
            self.timed.setVisible(m == "path")
            self.output_unit.setVisible(m == "function")
            canvas = m != "function"
            for b in (self.click_button, self.draw_button, self.underlay_button):
                b.setEnabled(canvas)
            self.draw_button.setEnabled(m == "path")
            self.underlay_button.setEnabled(m == "path")
            self.topology.clear()
            tops = {"path": D.PATH_TOPOLOGIES, "function": D.FUNCTION_TOPOLOGIES}.get(m, ("fourbar",))
            self.topology.addItems(list(tops))
            self.grashof.setEnabled(True)
        self.status.setText("Give a target and press Design (Ctrl+Enter)." if linkage else
                            "Fill in the requirements and press Design (Ctrl+Enter).")
        self._target_edited()

    def _output_unit_chosen(self, *_args) -> None:
        unit = self.output_unit.currentData()
        self.target.set_output_unit(unit)
        self.topology.setCurrentText("fourbar" if unit == "°" else "slider_crank")

    def _target_edited(self, *_args) -> None:
        shape = self.target.shape() if self.mode in D.LINKAGE_MODES else None
        if shape is not None:
            shape["closed"] = self.closed.isChecked()
        self.targetChanged.emit(shape if shape is not None and len(shape["points"]) else None)

    def _units_changed(self) -> None:
        """The display units changed: the forms show theirs (nothing for a panel whose window was
        closed: its Python object may outlive its widgets)."""
        if not (shiboken6.isValid(self) and shiboken6.isValid(self.target)):
            return
        self.target.redisplay()
        for form in (self.geneva, self.rolling, self.gears):
            form.redisplay()

    def _replaced(self) -> None:
        self._show_nothing()
        self.rolling.refresh()

    # -- the target from the canvas and files --------------------------------------------------
    def _ask_click(self) -> None:
        self.targetRequested.emit("poses" if self.mode == "motion" else "click")
        self._say("click the target's points on the canvas (poses: press at the point, drag along its angle); "
                  "Enter or a double click ends, Backspace removes the last point, Esc cancels")

    def _ask_draw(self) -> None:
        self.targetRequested.emit("draw")
        self._say("draw the path on the canvas with the left button held; end near the start for a closed loop")

    def target_placing(self, points, angles=None, pending=None) -> None:
        """The canvas is being clicked: show what is placed so far (the table is unchanged)."""
        self.targetChanged.emit({"points": points, "angles": angles, "closed": self.closed.isChecked(),
                                 "pending": pending})

    def target_picked(self, points, angles=None, closed: bool | None = None) -> None:
        """The canvas gave a target: it fills the table (poses with their angles)."""
        if closed is not None and self.mode == "path":
            self.closed.setChecked(bool(closed))
        if self.mode == "path":
            self.timed.setChecked(False)
        self.target.set_points(points, angles)
        self._say(f"target: {len(points)} points from the canvas; edit them in the table, then Design")

    def target_cancelled(self) -> None:
        self._target_edited()
        self._say("target picking cancelled: the table is as it was")

    def read_csv(self) -> bool:
        """Ask for a CSV file and read the target from it (False, with the reason, if not)."""
        from mechsketch.core.design.targets import DesignError

        path = self.ask_csv()
        if not path:
            return False
        try:
            n = self.target.read_csv(path)
        except DesignError as exc:
            return self._say(str(exc), error=True)
        if self.mode == "function":
            self.output_unit.setCurrentIndex(self.output_unit.findData(self.target.output_unit))
        self.timed.setChecked(self.target.timed)
        self._say(f"read {n} rows from {path}")
        return True

    # -- running -----------------------------------------------------------------------------
    def options(self):
        from mechsketch.core.design.options import LinkageOptions

        return LinkageOptions(candidates=self.count.value(), min_transmission_deg=self.min_mu.value(),
                              full_turn=self.full_turn.isChecked(), grashof=self.grashof.currentData(),
                              prefix=self.mode)

    def run(self) -> bool:
        """Check the target or the requirements and start the design on the worker thread (False,
        with the reason in the status line, if it cannot start)."""
        from mechsketch.core.design.targets import DesignError

        if self.runner.busy:
            return self._say("a design is running: wait for it or press Cancel")
        mode = self.mode
        try:
            if mode in D.LINKAGE_MODES:
                req = D.LinkageRequest(mode, self.target.rows(), self.options(), self.topology.currentText(),
                                       self.closed.isChecked(), self.timed.isChecked(),
                                       "mm" if self.target.output_unit == "mm" else "deg")
                target = D.linkage_target(req)
                work = lambda t: D.linkage_work(req, target, t)   # noqa: E731
                title = f"{mode} synthesis"
            else:
                form = {"geneva": self.geneva, "rolling": self.rolling, "gears": self.gears}[mode]
                reqs, eid = form.requirements(), form.design_id
                work = lambda t: D.requirement_work(mode, reqs, eid, t)   # noqa: E731
                title = f"{mode} design"
        except EntryError as exc:
            if exc.table is not None and exc.row >= 0:
                exc.table.setCurrentCell(exc.row, exc.column)
            return self._say(str(exc), error=True)
        except DesignError as exc:
            return self._say(str(exc), error=True)
        self._show_nothing()
        self.result_mode = mode
        return self.runner.start(title, work)

    def _failed(self, exc) -> None:
        self.bar.setValue(0)
        if self.result_mode in D.REQUIREMENT_MODES:
            self._say(f"{self.runner.title} refused: what to relax is below", error=True)
            self.report.show_refusal(str(exc), getattr(exc, "relax", ()))
            self.report.setVisible(True)
        else:
            self._say(f"{self.runner.title} refused: {exc}", error=True)

    def _finished(self, result) -> None:
        self.bar.setValue(1000)
        self.result = result
        if self.result_mode in D.LINKAGE_MODES:
            shape = self.target.shape()
            self.candidates.show_candidates(result.candidates, shape["points"] if shape else None)
            self.candidates.setVisible(True)
            self.insert_button.setVisible(True)
            n = len(result.candidates)
            self._say(f"{n} candidate{'s' if n != 1 else ''} in {result.seconds:.2f} s, best first: choose one to "
                      "see it move on the canvas, Insert adds it")
            if n:
                self.candidates.setCurrentRow(0)
        else:
            self.report.show_report(result.report)
            self.report.setVisible(True)
            self.insert_button.setVisible(True)
            b = result.report.binding
            self._say(f"{result.element.id}: every requirement met" + (f"; binding: {b.name}" if b else "")
                      + ". Insert adds it to the scene")

    def _show_nothing(self) -> None:
        self.result = None
        self.candidates.clear()
        for w in (self.candidates, self.report, self.insert_button):
            w.setVisible(False)
        self.previewChanged.emit(None)

    def _candidate_chosen(self, row: int) -> None:
        c = self.candidates.chosen()
        self.previewChanged.emit(c.linkage if c is not None else None)

    def _relax(self, name: str, value: float) -> None:
        form = {"geneva": self.geneva, "rolling": self.rolling, "gears": self.gears}.get(self.result_mode)
        if form is not None and form.set_value(name, value):
            self._say(f"{name} set to {value:.6g} in the form: press Design again")
        else:
            self._say(f"relax {name} to {value:.6g} in the requirements (the form has no field for it)")

    # -- inserting ---------------------------------------------------------------------------
    def insert(self) -> bool:
        """Add the chosen candidate, or the designed element, to the scene: one undo step."""
        scene = self.controller.scene
        if self.result_mode in D.LINKAGE_MODES:
            c = self.candidates.chosen()
            if c is None:
                return self._say("choose a candidate first")
            new = renamed(c.linkage, fresh_id(c.linkage.id, scene.ids))
            select = [(new.id, "link", new.driver.link)]
        elif self.result is not None:
            el = self.result.element
            new = _beside(renamed(el, fresh_id(el.id, scene.ids)), scene)
            select = [(new.id, ELEMENT, new.id)]
        else:
            return self._say("nothing designed yet: press Design")
        label = f"insert {new.id}"
        if not self.controller.push(AddElement(new, label=label), label):
            return False
        self.previewChanged.emit(None)
        self.controller.set_selection(select)
        return self._say(f"inserted {new.id}: an ordinary element (Properties, Plots, File › Export); "
                         "Ctrl+Z removes it") or True

    def shutdown(self) -> None:
        """Cancel a running design and wait for it (the window closes)."""
        self.runner.cancel()
        self.runner.wait()


def _beside(element, scene):
    """``element`` moved to the right of everything the scene holds (as it is in an empty scene)."""
    boxes = []
    for e in scene.elements:
        try:
            boxes.append(extent(e))
        except (ValueError, TypeError):
            continue
    if not boxes:
        return element
    x0, y0, x1, y1 = extent(element)
    right = max(b[2] for b in boxes)
    bottom = min(b[1] for b in boxes)
    return translated(element, right + 0.15 * (x1 - x0) + 20.0 - x0, bottom - y0)


__all__ = ["DesignPanel"]
