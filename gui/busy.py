"""The status bar's busy indicator for an element solved off the GUI thread (gui/background.py):
what is being solved, the seconds so far against the estimate, and Cancel (the edit then does not
land and the document stays as it was)."""
from __future__ import annotations

import time

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QHBoxLayout, QLabel, QProgressBar, QPushButton, QWidget

from .background import BackgroundSolver


class BusyIndicator(QWidget):
    """Shown while ``solver`` has a job the window waits for; hidden otherwise."""

    def __init__(self, solver: BackgroundSolver, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setObjectName("busy")
        self.solver = solver
        self.label = QLabel()
        self.bar = QProgressBar()
        self.bar.setRange(0, 0)        # the core reports no fraction: a busy bar
        self.bar.setMaximumWidth(120)
        self.bar.setTextVisible(False)
        self.cancel = QPushButton("Cancel")
        self.cancel.setObjectName("busy_cancel")
        self.cancel.setToolTip("Stop waiting: the edit is not applied, the document stays as it was")
        self.cancel.clicked.connect(self._cancel)
        lay = QHBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        for w in (self.label, self.bar, self.cancel):
            lay.addWidget(w)
        self.timer = QTimer(self)
        self.timer.setInterval(500)
        self.timer.timeout.connect(self.refresh)
        solver.busyChanged.connect(self._on_busy)
        self.hide()

    def _on_busy(self, text: str) -> None:
        self.setVisible(bool(text))
        if text:
            self.refresh()
            self.timer.start()
        else:
            self.timer.stop()

    def refresh(self) -> None:
        """The label: what is solved, seconds so far and the estimate."""
        job = self.solver.job
        if job is None:
            return
        spent = time.perf_counter() - job.started
        self.label.setText(f"solving {job.text}: {spent:.0f} s of about {max(job.estimate, 1.0):.0f} s")

    def _cancel(self) -> None:
        job = self.solver.job
        self.solver.cancel()
        if job is not None and self.window() is not None:
            self.window().statusBar().showMessage(f"{job.text}: cancelled, nothing was changed", 8000)
