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


@pytest.fixture(autouse=True)
def _delete_the_tests_windows():
    """Carry out the deletes pytest-qt asked for, when the test ends.

    pytest-qt closes the widgets given to ``qtbot.addWidget`` (every app shell, every canvas of
    ``make_view``) and calls ``deleteLater`` on them, but a deferred delete posted outside an event
    loop waits for one: every app shell (about 830 widgets, 65 of them top-level menus and docks)
    stayed alive until some later test ran a nested event loop. Each event-loop turn, layout pass
    and ``QApplication.allWidgets`` walk in between paid for all of them, so a test's CPU grew with
    the number of tests before it in the same worker, and the test that finally ran the deletes
    paid for tens of thousands at once. Autouse fixtures tear down last, after pytest-qt has closed
    the widgets and the test's own fixtures have closed what they made. Only what pytest-qt (or
    the app) scheduled for deletion is deleted: a window a test made without ``qtbot.addWidget``
    is left alone (it may still be running work).
    """
    from PySide6.QtCore import QCoreApplication, QEvent

    yield
    QCoreApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)
