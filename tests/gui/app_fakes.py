"""Test doubles for the app shell: a scripted dialog service and stand-in canvas components.

``FakeDialogs`` answers from queues the test fills and records every message, so no test patches
Qt. ``stand_in_components()`` gives minimal widgets with the canvas parts' public names; the
app's real components are used whenever they can be imported (see ``app_components``).
"""
from __future__ import annotations

from collections import deque

import pytest

from PySide6.QtCore import QObject
from PySide6.QtGui import QAction
from PySide6.QtWidgets import QLabel, QWidget

from mechsketch.gui.dialogs import CANCEL, DISCARD, SAVE  # noqa: F401 - re-exported for tests
from mechsketch.gui.main_window import Components


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


class StandInCanvas(QLabel):
    """Stands in for CanvasView until (or where) it cannot be imported."""

    def __init__(self, controller) -> None:
        super().__init__("canvas")
        self.controller = controller
        self.fitted = 0

    def zoom_to_fit(self) -> None:
        self.fitted += 1


class StandInPlayer(QObject):
    def __init__(self, controller) -> None:
        super().__init__()
        self.controller = controller

    def stop(self) -> None:
        pass


def stand_in_components() -> Components:
    return Components(
        canvas=StandInCanvas,
        player=StandInPlayer,
        scrubbar=lambda controller, player: QWidget(),
        tool_actions=lambda view, parent: [QAction("Select", parent)],
        snap_action=lambda view, parent: None,
        player_actions=lambda player, parent: [],
    )


def app_components() -> Components:
    """The real components when the canvas modules exist, else the stand-ins."""
    try:
        from mechsketch.gui.app import default_components

        return default_components()
    except ImportError:
        return stand_in_components()


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
        kwargs.setdefault("components", app_components())
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
