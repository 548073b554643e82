"""Test doubles for the app shell: a scripted dialog service and stand-in canvas components.

``FakeDialogs`` answers from queues the test fills and records every message, so no test patches
Qt. ``stand_in_components`` gives minimal canvas parts for a subprocess that only needs the shell;
the ``shell`` fixture uses the app's real canvas, player and scrub bar.
"""
from __future__ import annotations

import sys
from collections import deque

import pytest

from PySide6.QtCore import QObject
from PySide6.QtGui import QAction
from PySide6.QtWidgets import QLabel, QWidget

from mechsketch.gui.dialogs import CANCEL, DISCARD, SAVE  # noqa: F401 - re-exported for tests
from mechsketch.gui.main_window import CanvasParts


class FakeDialogs:
    """A DialogService answering from queues; ``errors``/``questions``/``infos`` record what was shown."""

    def __init__(self) -> None:
        self.open_names: deque[str | None] = deque()
        self.save_names: deque[str | None] = deque()
        self.save_changes: deque[str] = deque()
        self.yes_no: deque[bool] = deque()
        self.errors: list[tuple[str, str, str]] = []
        self.questions: list[tuple[str, str]] = []
        self.infos: list[tuple[str, str]] = []
        self.export_requests: deque = deque()
        self.numbers: deque[float | None] = deque()

    def open_file_name(self, title, directory="", filter=""):
        self.questions.append((title, directory))
        return self.open_names.popleft() if self.open_names else None

    def save_file_name(self, title, directory="", filter=""):
        self.questions.append((title, directory))
        return self.save_names.popleft() if self.save_names else None

    def ask_save_changes(self, name):
        self.questions.append(("save changes", name))
        return self.save_changes.popleft() if self.save_changes else CANCEL

    def ask_yes_no(self, title, text):
        self.questions.append((title, text))
        return self.yes_no.popleft() if self.yes_no else False

    def error(self, title, text, details=""):
        self.errors.append((title, text, details))

    def info(self, title, text):
        self.infos.append((title, text))

    def ask_number(self, title, text, value, unit=""):
        self.questions.append((title, f"{text} [{value:g} {unit}]"))
        return self.numbers.popleft() if self.numbers else None

    def export_request(self, title, choices, default_id, fmt, min_webs=None, kinds=None, sizes=None):
        """The next queued ExportRequest (a callable gets the arguments), else the dialog's defaults."""
        from mechsketch.gui.export_dialog import ExportRequest

        self.questions.append((title, default_id))
        self.export_choices = choices
        if self.export_requests:
            req = self.export_requests.popleft()
            return req(default_id, fmt) if callable(req) else req
        return ExportRequest(default_id, fmt)


class FakeClock:
    """A monotonic clock (seconds) the test moves by hand: the animation player's ``clock``."""

    def __init__(self, now: float = 100.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now

    def advance(self, seconds: float) -> None:
        self.now += seconds


def play_ticks(player, ticks: int = 3, seconds: float = 0.016) -> FakeClock:
    """Play ``player`` for ``ticks`` timer ticks of ``seconds`` each on a fake clock (no waiting
    on wall time: the ticks are called here, as the timer would), then pause it."""
    clock = FakeClock()
    player.clock = clock
    player.play()
    for _ in range(ticks):
        clock.advance(seconds)
        player.tick()
    player.pause()
    return clock


def stand_in_components(controller, window) -> CanvasParts:
    """Minimal canvas parts (a label, a bare player, an empty bar) for tests of the shell alone."""
    return CanvasParts(QLabel("canvas"), QObject(), QWidget(), tools=[QAction("Select", window)])


def app_components(controller, window) -> CanvasParts:
    """The app's real canvas parts (the tests drive the shell with them)."""
    from mechsketch.gui.app import canvas_parts

    return canvas_parts(controller, window)


@pytest.fixture
def shell(qtbot, tmp_path):
    """``shell(scene_path=None, **build_kwargs) -> AppParts``: the whole app, shown offscreen, with
    FakeDialogs, a temporary settings file and recovery folder; closed (discarding) at teardown."""
    from mechsketch.gui.app import build

    made = []

    def make(scene_path=None, **kwargs):
        kwargs.setdefault("dialogs", FakeDialogs())
        kwargs.setdefault("settings_path", tmp_path / "settings.ini")
        kwargs.setdefault("state_dir", tmp_path / "state")
        kwargs.setdefault("components", app_components)
        kwargs.setdefault("offer_recovery", False)
        parts = build(scene_path, **kwargs)
        qtbot.addWidget(parts.window)
        parts.window.show()
        made.append(parts)
        return parts

    yield make
    for parts in made:
        parts.dialogs.save_changes.clear()
        parts.dialogs.save_changes.append(DISCARD)
        parts.close()


def type_into(qtbot, edit, text: str) -> None:
    """Type ``text`` into a line edit as a user would (select all, type, Enter)."""
    from PySide6.QtCore import Qt

    edit.setFocus()
    edit.selectAll()
    qtbot.keyClicks(edit, text)
    qtbot.keyClick(edit, Qt.Key.Key_Return)


def open_example(shell, name: str):
    """A fresh app with the example ``name`` opened from the Examples menu: (parts, controller, canvas)."""
    parts = shell()
    parts.window.actions[f"example:{name}"].trigger()
    return parts, parts.controller, parts.window.canvas


def patch_everywhere(monkeypatch, func, replacement) -> None:
    """Replace the core function ``func`` in its module and in every loaded mechsketch module that
    imported it (``from ... import func [as name]``), e.g. to prove that playback computes nothing."""
    for name, mod in list(sys.modules.items()):
        if name.startswith("mechsketch"):
            for attr, value in list(vars(mod).items()):
                if value is func:
                    monkeypatch.setattr(mod, attr, replacement)
