"""File commands of the app: New, Open, Save, Save As, recent files and the built-in examples.

:class:`FileOps` reads and writes scenes with :mod:`mechsketch.core` (saves are atomic) and talks
to the user only through the injected :class:`~mechsketch.gui.dialogs.DialogService`. A bad file
or a failed save gives a message and keeps the current document (and its unsaved state).
Recent files live in a :class:`QSettings` INI file whose path can be injected (tests use a
temporary one); the settings carry a ``schema_version`` with a chain of migrations.
"""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Callable

from PySide6.QtCore import QObject, QSettings, Signal

from mechsketch import resources
from mechsketch.core import ExportError, MechsketchError, Scene, SceneFormatError, load_scene, save_scene

from .controller import SceneController
from .dialogs import CANCEL, DISCARD, SCENE_FILTER, DialogService

SETTINGS_SCHEMA_VERSION = 1
MAX_RECENT = 10
#: problems listed in the message itself (all of them are in the details)
MAX_PROBLEMS_SHOWN = 8

#: settings migrations: version v -> function updating a v QSettings to v + 1 in place
SETTINGS_MIGRATIONS: dict[int, Callable[[QSettings], None]] = {}


#: folders of the kernel's pseudo files on Linux: reading one may block or consume it (/proc/kmsg
#: blocks its reader and loses what it read), whatever it claims to be; /dev/shm is ordinary memory
SYSTEM_FOLDERS = ("/proc", "/sys", "/dev")


def system_folder(path: str | os.PathLike) -> str | None:
    """The pseudo-file folder (/proc, /sys, /dev) ``path`` is in after symlinks, or None. Only a
    path is looked at: nothing is opened."""
    if not sys.platform.startswith("linux"):
        return None
    real = os.path.realpath(os.fspath(path))
    if real == "/dev/shm" or real.startswith("/dev/shm/"):
        return None
    return next((d for d in SYSTEM_FOLDERS if real == d or real.startswith(d + "/")), None)


def make_settings(path: str | os.PathLike | None = None) -> QSettings:
    """The app's settings: the INI file ``path``; else ``$MECHSKETCH_STATE_DIR/settings.ini``
    when that variable is set; else the per-user default location. Migrated to the current
    ``schema_version``."""
    if path is None and os.environ.get("MECHSKETCH_STATE_DIR"):
        path = Path(os.environ["MECHSKETCH_STATE_DIR"]) / "settings.ini"
    if path is not None:
        settings = QSettings(str(path), QSettings.Format.IniFormat)
    else:
        settings = QSettings(QSettings.Format.IniFormat, QSettings.Scope.UserScope, "mechsketch", "mechsketch")
    version = _int(settings.value("schema_version", SETTINGS_SCHEMA_VERSION))
    while version < SETTINGS_SCHEMA_VERSION:
        SETTINGS_MIGRATIONS[version](settings)
        version += 1
    settings.setValue("schema_version", SETTINGS_SCHEMA_VERSION)
    return settings


def _int(value: object) -> int:
    try:
        return int(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return SETTINGS_SCHEMA_VERSION


def problems_text(exc: SceneFormatError) -> tuple[str, str]:
    """(short list for the message, full list for the details) of a scene's problems."""
    lines = [str(p) for p in exc.problems] or [str(exc)]
    shown = lines[:MAX_PROBLEMS_SHOWN]
    if len(lines) > len(shown):
        shown.append(f"... and {len(lines) - len(shown)} more (see details)")
    return "\n".join(shown), "\n".join(lines)


class FileOps(QObject):
    """New / Open / Save / Save As / recent files / examples over one :class:`SceneController`."""

    recentChanged = Signal()

    def __init__(self, controller: SceneController, dialogs: DialogService,
                 settings: QSettings | None = None, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.dialogs = dialogs
        self.settings = settings if settings is not None else make_settings()
        #: name of the built-in example the unsaved document came from (None: not an example)
        self.example_name: str | None = None

    # -- naming ------------------------------------------------------------------------------
    def display_name(self) -> str:
        """The document's name for the title bar: file name, example name, or "Untitled"."""
        if self.controller.path is not None:
            return self.controller.path.name
        if self.example_name:
            return f"{self.example_name} (example)"
        return "Untitled"

    def _start_dir(self) -> str:
        if self.controller.path is not None:
            return str(self.controller.path.parent)
        recent = self.recent_files()
        return str(Path(recent[0]).parent) if recent else str(Path.home())

    # -- commands ----------------------------------------------------------------------------
    def maybe_save(self) -> bool:
        """If the document has unsaved changes, ask to save them; False if the user cancelled
        (or the save failed), so the caller must not throw the document away."""
        if not self.controller.is_dirty:
            return True
        answer = self.dialogs.ask_save_changes(self.display_name())
        if answer == CANCEL:
            return False
        if answer == DISCARD:
            return True
        return self.save()

    def new(self) -> bool:
        """An empty scene (after asking to save unsaved changes)."""
        if not self.maybe_save():
            return False
        self.example_name = None
        self.controller.reset(Scene(), None)
        self.controller.message.emit("new empty scene")
        return True

    def open(self, path: str | os.PathLike | None = None, ask: bool = True) -> bool:
        """Open ``path`` (or ask for one). On a bad file: a message listing the problems, and the
        current document is kept. ``ask=False`` skips the unsaved-changes question."""
        if ask and not self.maybe_save():
            return False
        if path is None:
            name = self.dialogs.open_file_name("Open scene", self._start_dir(), SCENE_FILTER)
            if not name:
                return False
            path = name
        scene = self._load(Path(path))
        if scene is None:
            return False
        def opened() -> None:
            self.example_name = None
            self.controller.pathChanged.emit()   # the title names the file, not the example before
            self._add_recent(Path(path).resolve())
            self.controller.message.emit(f"opened {Path(path).name}: {self._summary(scene)}")
        # a large scene is solved off the GUI thread first (issue 20): Cancel keeps this document
        return self.controller.reset_when_solved(scene, Path(path).resolve(), f"open {Path(path).name}", opened)

    def open_example(self, name: str, ask: bool = True) -> bool:
        """Open a built-in example as an unsaved document (Save asks where to put it)."""
        if ask and not self.maybe_save():
            return False
        try:
            path = resources.example_path(name)
        except FileNotFoundError as exc:
            self._fail("Cannot open example", str(exc))
            return False
        scene = self._load(path)
        if scene is None:
            return False
        def opened() -> None:
            self.example_name = path.stem
            self.controller.pathChanged.emit()   # the title names the example
            self.controller.message.emit(f"opened example {path.stem}: {self._summary(scene)}")
        return self.controller.reset_when_solved(scene, None, f"open example {path.stem}", opened)

    def save(self) -> bool:
        """Save to the current file (Save As if there is none). False if it failed or was cancelled."""
        if self.controller.path is None:
            return self.save_as()
        return self._write(self.controller.path)

    def save_as(self, path: str | os.PathLike | None = None) -> bool:
        """Ask for a file name (unless given) and save there atomically."""
        if path is None:
            start = self._start_dir()
            if self.controller.path is None and self.example_name:
                start = str(Path(start) / f"{self.example_name}.json")
            name = self.dialogs.save_file_name("Save scene as", start, SCENE_FILTER)
            if not name:
                return False
            path = name
        target = Path(path)
        if not target.suffix:
            target = target.with_suffix(".json")
        return self._write(target.resolve())

    # -- recent files ------------------------------------------------------------------------
    def recent_files(self) -> list[str]:
        """Most recent first; absolute paths."""
        raw = self.settings.value("recent_files", "[]")
        try:
            items = json.loads(raw) if isinstance(raw, str) else []
        except ValueError:
            items = []
        return [str(p) for p in items if isinstance(p, str)][:MAX_RECENT]

    def open_recent(self, path: str) -> bool:
        """Open a recent file; a file that is gone is dropped from the list (with a message)."""
        if not Path(path).exists():
            self._set_recent([p for p in self.recent_files() if p != path])
            self._fail("Cannot open recent file", f"{path} no longer exists; it was removed from the list.")
            return False
        return self.open(path)

    def clear_recent(self) -> None:
        self._set_recent([])

    def _add_recent(self, path: Path) -> None:
        items = [str(path)] + [p for p in self.recent_files() if p != str(path)]
        self._set_recent(items[:MAX_RECENT])

    def _set_recent(self, items: list[str]) -> None:
        self.settings.setValue("recent_files", json.dumps(items))
        self.settings.sync()
        self.recentChanged.emit()

    # -- helpers -----------------------------------------------------------------------------
    def _load(self, path: Path) -> Scene | None:
        system = system_folder(path)
        if system is not None:
            self._fail("Cannot open scene", f"{path} is a system file (in {system}), not a scene file; "
                                            "nothing was read. The current scene is kept.")
            return None
        try:
            return load_scene(path)
        except SceneFormatError as exc:
            short, full = problems_text(exc)
            n = len(exc.problems)
            self._fail("Cannot open scene",
                       f"{path.name} cannot be opened: {n} problem(s). The current scene is kept.\n\n{short}",
                       full)
        except (MechsketchError, OSError) as exc:
            self._fail("Cannot open scene", f"{path.name} cannot be opened: {exc}. The current scene is kept.")
        return None

    def _write(self, path: Path) -> bool:
        try:
            save_scene(self.controller.scene, path)
        except (ExportError, OSError) as exc:
            self._fail("Cannot save scene",
                       f"{exc}\n\nNothing was lost: the scene is still open, with its changes unsaved.")
            return False
        self.example_name = None
        self.controller.mark_saved(path)
        self._add_recent(path)
        self.controller.message.emit(f"saved {path}")
        return True

    def _fail(self, title: str, text: str, details: str = "") -> None:
        self.controller.message.emit(text.splitlines()[0])
        self.dialogs.error(title, text, details)

    @staticmethod
    def _summary(scene: Scene) -> str:
        if not scene.elements:
            return "no elements"
        return ", ".join(f"{e.id} ({e.type})" for e in scene.elements)

    @staticmethod
    def examples() -> list[str]:
        """Names of the built-in example scenes (every scene in ``resources/examples``)."""
        return [p.stem for p in resources.example_paths()]
