"""Shared set-up of the GUI tests: Qt offscreen, and no test may leave a QTimer running.

The timer check follows napari: ``QTimer.start`` is wrapped for the duration of each test, and a
timer started from Python that is still active at teardown fails the test (stop it, or close the
component that owns it). Mark a test ``allow_running_qtimer`` to opt out.
"""
from __future__ import annotations

import os

if not os.environ.get("QT_QPA_PLATFORM"):  # an empty value counts as unset
    os.environ["QT_QPA_PLATFORM"] = "offscreen"

import pytest


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "allow_running_qtimer: the test may leave a QTimer running")


@pytest.fixture(autouse=True)
def _no_running_qtimers(monkeypatch: pytest.MonkeyPatch, request: pytest.FixtureRequest):
    """Fail a test that leaves a QTimer (started from Python) running."""
    from PySide6.QtCore import QTimer
    from shiboken6 import isValid

    started: list[QTimer] = []
    base_start = QTimer.start

    def start(timer: QTimer, *args) -> None:
        started.append(timer)
        base_start(timer, *args)

    monkeypatch.setattr(QTimer, "start", start)
    yield
    monkeypatch.undo()
    if request.node.get_closest_marker("allow_running_qtimer"):
        return
    running = [t for t in started if isValid(t) and t.isActive()]
    for t in running:
        t.stop()
    if running:
        names = ", ".join(t.objectName() or repr(t) for t in running)
        pytest.fail(f"the test left {len(running)} QTimer(s) running: {names}")
