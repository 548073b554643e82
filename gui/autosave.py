"""Crash recovery: the unsaved scene is written every minute to a per-user recovery folder.

Each run of the app has a name of its own, ``<time>-<pid>-<random>``, never reused: another app
that gets this one's PID later (common in containers) never takes, overwrites or deletes its
file. A run writes ``recovery-<run>.json`` (its meta data — where the scene came from, when — and
the scene in one document, written atomically: a kill at any moment leaves the previous autosave
or the new one, whole) and holds ``recovery-<run>.lock`` ``flock``-ed while it runs. Both are
removed when the document is saved or reset clean, and on a clean exit; so a recovery file whose
lock is free, or that has none, was left by a run that crashed (the kernel drops a dead process's
locks), whatever its PID, and the next start offers it back (every one of them, newest first).
A start that offers a file holds its lock meanwhile, so two apps starting together never both take
it. Files of older versions (``recovery-<pid>.json`` with or without its ``.meta.json``) are
offered too. Without ``flock`` (Windows) a file whose recorded PID is alive is not offered. The
folder is ``$MECHSKETCH_STATE_DIR`` if set, else the platform's per-user state folder; each start
removes the temporaries a killed autosave left there.
"""
from __future__ import annotations

import json
import os
import secrets
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from PySide6.QtCore import QObject, QTimer, Signal

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: the PID decides
    fcntl = None  # type: ignore[assignment]

from mechsketch.core import ExportError, MechsketchError, Scene, SceneFormatError
from mechsketch.core.io.atomic import remove_orphans
from mechsketch.core.io.scene_file import atomic_write_text, dumps_scene, read_scene_text, scene_from_dict

from .controller import SceneController

INTERVAL_MS = 60_000

#: the ``format`` of a recovery document: {"format", "version", "run", "pid", "time", "original", "scene"}
RECOVERY_FORMAT = "mechsketch-recovery"
RECOVERY_VERSION = 1


def state_dir() -> Path:
    """The per-user folder for recovery files (and default settings when overridden)."""
    env = os.environ.get("MECHSKETCH_STATE_DIR")
    if env:
        return Path(env)
    if sys.platform.startswith("win"):
        base = Path(os.environ.get("LOCALAPPDATA", Path.home() / "AppData" / "Local"))
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Application Support"
    else:
        base = Path(os.environ.get("XDG_STATE_HOME") or Path.home() / ".local" / "state")
    return base / "mechsketch"


def new_run_name() -> str:
    """A name no other run of the app has: start time, PID and 32 random bits."""
    return f"{time.strftime('%Y%m%d-%H%M%S')}-{os.getpid()}-{secrets.token_hex(4)}"


def _alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (ours counts as alive); only used without ``flock``."""
    if pid == os.getpid():
        return True
    if sys.platform.startswith("win"):  # pragma: no cover - no cheap check; assume it crashed
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except OSError:
        return False
    return True


def _try_lock(path: Path, create: bool) -> int | None:
    """Open ``path`` (creating it if ``create``) and ``flock`` it without waiting: the open
    descriptor if we now hold it, None if someone else does or it cannot be opened."""
    flags = os.O_RDWR | getattr(os, "O_CLOEXEC", 0) | (os.O_CREAT if create else 0)
    try:
        fd = os.open(path, flags, 0o600)
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return None
    return fd


def _lock_held(lock: Path) -> bool | None:
    """Whether a live process holds ``lock`` (True), nobody does (False), or there is no lock
    file (None)."""
    if not lock.exists():
        return None
    fd = _try_lock(lock, create=False)
    if fd is None:
        return lock.exists()      # held (or it vanished meanwhile: its owner exited cleanly)
    os.close(fd)                  # also releases the lock we just took
    return False


def read_recovery(path: Path) -> tuple[dict[str, Any], Any]:
    """(meta, scene document) of a recovery file: a recovery document, or a bare scene file of an
    older version with its ``.meta.json`` beside it (or none: then its time is the file's).
    Raises :class:`SceneFormatError` if it cannot be read."""
    doc, problems = read_scene_text(path)
    if problems:
        raise SceneFormatError(problems, str(path))
    if isinstance(doc, dict) and doc.get("format") == RECOVERY_FORMAT:
        return {k: v for k, v in doc.items() if k != "scene"}, doc.get("scene")
    meta: dict[str, Any] = {}
    legacy = path.with_name(path.name[:-len(".json")] + ".meta.json")
    try:
        loaded = json.loads(legacy.read_text(encoding="utf-8"))
        meta = loaded if isinstance(loaded, dict) else {}
    except (OSError, ValueError):
        pass
    return meta, doc


@dataclass
class Recovery:
    """A recovery file left by a run of the app that did not exit cleanly."""

    scene_path: Path
    meta_path: Path | None    # the separate meta file of an older version's autosave
    original: str | None      # the file the scene was opened from (None: never saved)
    saved_at: float           # time.time() of the autosave
    lock_path: Path | None = None   # the dead owner's lock file, removed with the rest
    pid: int | None = None
    _claim: int | None = field(default=None, repr=False, compare=False)

    def describe(self) -> str:
        when = time.strftime("%Y-%m-%d %H:%M", time.localtime(self.saved_at))
        what = Path(self.original).name if self.original else "an unsaved scene"
        return f"{what}, autosaved {when}"

    def claim(self) -> bool:
        """Hold this file's lock while it is offered, so that no other starting app offers it too;
        False if another app holds it. Without ``flock`` always True."""
        if self._claim is not None or fcntl is None:
            return True
        lock = self.lock_path or self.scene_path.with_suffix(".lock")
        fd = _try_lock(lock, create=True)
        if fd is None:
            return False
        if not self.scene_path.exists():      # restored or discarded by another app meanwhile
            os.close(fd)
            return False
        self.lock_path, self._claim = lock, fd
        return True

    def release(self) -> None:
        """Let go of the claim (the files stay, to be offered again)."""
        if self._claim is not None:
            os.close(self._claim)
            self._claim = None

    def discard(self) -> None:
        """Delete the recovery file, its meta and lock files."""
        for p in (self.scene_path, self.meta_path, self.lock_path):
            if p is None:
                continue
            try:
                p.unlink()
            except FileNotFoundError:
                pass
        self.release()


class Autosave(QObject):
    """Writes the dirty scene every ``interval_ms``; offers recovery files of crashed runs."""

    saved = Signal(str)   # path of the recovery file just written

    def __init__(self, controller: SceneController, folder: Path | None = None,
                 interval_ms: int = INTERVAL_MS, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.folder = Path(folder) if folder is not None else state_dir()
        self.run = new_run_name()
        self.recovery_file = self.folder / f"recovery-{self.run}.json"
        self.lock_file = self.folder / f"recovery-{self.run}.lock"
        self._lock_fd: int | None = None
        self.timer = QTimer(self)
        self.timer.setObjectName("autosave")
        self.timer.setInterval(interval_ms)
        self.timer.timeout.connect(self.save_now)
        controller.pathChanged.connect(self._on_path_changed)

    def start(self) -> None:
        """Remove temporaries a killed autosave left in the folder, then start the timer."""
        remove_orphans(self.folder)
        self.timer.start()

    def set_interval(self, ms: int) -> None:
        """Autosave every ``ms`` milliseconds from now on (a preference)."""
        self.timer.setInterval(max(1000, int(ms)))

    def _hold_lock(self) -> None:
        """Create and ``flock`` this run's lock file (kept until :meth:`remove`)."""
        if self._lock_fd is not None or fcntl is None:
            return
        fd = _try_lock(self.lock_file, create=True)
        if fd is None:
            raise OSError(f"cannot lock {self.lock_file}")
        self._lock_fd = fd

    def _release_lock(self) -> None:
        if self._lock_fd is None:
            return
        try:
            self.lock_file.unlink()   # while still held: no one can take a stale one for dead
        except FileNotFoundError:
            pass
        finally:
            os.close(self._lock_fd)
            self._lock_fd = None

    def stop(self) -> None:
        self.timer.stop()

    def document(self) -> str:
        """This run's recovery document: its meta data and the scene, one JSON text."""
        head = {"format": RECOVERY_FORMAT, "version": RECOVERY_VERSION, "run": self.run,
                "pid": os.getpid(), "time": time.time(),
                "original": str(self.controller.path) if self.controller.path else None}
        return json.dumps(head)[:-1] + ', "scene": ' + dumps_scene(self.controller.scene) + "}\n"

    def save_now(self) -> bool:
        """Write the scene if it has unsaved changes, with its meta data, in one atomic write;
        True if written. Never raises on I/O."""
        if not self.controller.is_dirty:
            return False
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            self._hold_lock()                 # before the file exists: it is never seen unowned
            atomic_write_text(self.recovery_file, self.document())
        except (ExportError, OSError) as exc:
            self.controller.message.emit(f"autosave failed: {exc}")
            return False
        self.saved.emit(str(self.recovery_file))
        return True

    def remove(self) -> None:
        """Forget this run's recovery file (after a save, a clean reset, or a clean exit)."""
        try:
            self.recovery_file.unlink()
        except FileNotFoundError:
            pass
        except OSError as exc:
            self.controller.message.emit(f"cannot remove {self.recovery_file}: {exc}")
        try:
            self._release_lock()
        except OSError as exc:
            self.controller.message.emit(f"cannot remove {self.lock_file}: {exc}")

    def clean_exit(self) -> None:
        self.stop()
        self.remove()

    def _on_path_changed(self) -> None:
        if not self.controller.is_dirty:
            self.remove()

    # -- recovery ----------------------------------------------------------------------------
    def pending(self) -> list[Recovery]:
        """Recovery files of runs that are not running, whatever their PIDs, newest first."""
        if not self.folder.is_dir():
            return []
        out = [r for path in self.folder.glob("recovery-*.json")
               if (r := self._recovery(path)) is not None]
        return sorted(out, key=lambda r: r.saved_at, reverse=True)

    def _recovery(self, path: Path) -> Recovery | None:
        """The :class:`Recovery` for a file of the folder, or None (ours, a live run's, not a
        recovery file)."""
        if path.name.endswith(".meta.json") or path == self.recovery_file or not path.is_file():
            return None
        lock_path = path.with_suffix(".lock")
        held = _lock_held(lock_path) if fcntl is not None else None
        if held:
            return None
        try:
            meta, _scene = read_recovery(path)
            saved_at = float(meta.get("time", path.stat().st_mtime))
            pid = int(meta["pid"]) if "pid" in meta else None
        except (SceneFormatError, OSError, ValueError, TypeError):
            meta, saved_at, pid = {}, _mtime(path), None   # offered; restoring says what is wrong
        if fcntl is None and pid is not None and _alive(pid):   # pragma: no cover - Windows
            return None
        original = meta.get("original")
        legacy = path.with_name(path.name[:-len(".json")] + ".meta.json")
        return Recovery(path, legacy if legacy.exists() else None,
                        original if isinstance(original, str) else None, saved_at,
                        lock_path if held is not None else None, pid)

    def _set_aside(self, recovery: Recovery) -> Path | None:
        """Rename a recovery file that cannot be restored to ``unrestorable-<time>-<name>`` (kept
        for the user, no longer offered) and drop its meta and lock files; the new path or None."""
        stamp = time.strftime("%Y%m%d-%H%M%S", time.localtime(recovery.saved_at))
        target: Path | None = recovery.scene_path.with_name(f"unrestorable-{stamp}-{recovery.scene_path.name}")
        try:
            os.replace(recovery.scene_path, target)
        except OSError:
            target = None
        recovery.discard()
        return target

    def restore(self, recovery: Recovery) -> Scene | None:
        """Load a recovery file into the controller as an unsaved document; the file is then
        adopted (our own autosave takes over). Returns the scene, or None (with a message)."""
        try:
            _meta, doc = read_recovery(recovery.scene_path)
            scene, problems = scene_from_dict(doc, str(recovery.scene_path))
            if scene is None:
                raise SceneFormatError(problems, str(recovery.scene_path))
        except (SceneFormatError, MechsketchError, OSError) as exc:
            kept = self._set_aside(recovery)
            where = f"; kept as {kept} (not offered again)" if kept else ""
            self.controller.message.emit(f"cannot restore {recovery.scene_path}{where}: {exc}")
            return None
        original = Path(recovery.original) if recovery.original else None
        self.controller.reset(scene, original)
        self.controller.undo_stack.resetClean()   # restored work is unsaved work
        self.controller.pathChanged.emit()
        if self.save_now():                   # ours first, then theirs: never neither
            recovery.discard()
        else:
            recovery.release()
        self.controller.message.emit(f"restored {recovery.describe()}")
        return scene


def _mtime(path: Path) -> float:
    try:
        return path.stat().st_mtime
    except OSError:
        return time.time()
