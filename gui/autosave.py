"""Crash recovery: the unsaved scene is written every minute to a per-user recovery folder.

Each running app owns ``recovery-<pid>.json`` (the scene, written atomically),
``recovery-<pid>.meta.json`` (where it came from, when) and ``recovery-<pid>.lock``, which it
holds ``flock``-ed while it runs. All are removed when the document is saved or reset clean, and
on a clean exit; so a recovery file whose lock is free means that app crashed (the kernel drops
a dead process's locks), and the next start offers it back. The owner is identified by its lock,
not by its PID, which another process may have been given since; only where there is no lock
file (Windows, files of older versions) does the PID decide. The folder is
``$MECHSKETCH_STATE_DIR`` if set, else the platform's per-user state folder; each start removes
the temporaries a killed autosave left there.
"""
from __future__ import annotations

import json
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from PySide6.QtCore import QObject, QTimer, Signal

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: the PID decides
    fcntl = None  # type: ignore[assignment]

from mechsketch.core import ExportError, MechsketchError, Scene, SceneFormatError, load_scene
from mechsketch.core.io.atomic import remove_orphans
from mechsketch.core.io.scene_file import atomic_write_text, dumps_scene

from .controller import SceneController

INTERVAL_MS = 60_000


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


def _alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (ours counts as alive)."""
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


def _lock_held(lock: Path) -> bool | None:
    """Whether a live process holds ``lock`` (True), nobody does (False), or we cannot tell
    (None: no lock file, or no ``flock`` here)."""
    if fcntl is None:  # pragma: no cover - Windows
        return None
    try:
        fd = os.open(lock, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    except OSError:
        return None
    finally:
        os.close(fd)              # also releases the lock if we got it
    return False


@dataclass(frozen=True)
class Recovery:
    """A recovery file left by an app that did not exit cleanly."""

    scene_path: Path
    meta_path: Path
    original: str | None      # the file the scene was opened from (None: never saved)
    saved_at: float           # time.time() of the autosave
    lock_path: Path | None = None   # the dead owner's lock file, removed with the rest

    def describe(self) -> str:
        when = time.strftime("%Y-%m-%d %H:%M", time.localtime(self.saved_at))
        what = Path(self.original).name if self.original else "an unsaved scene"
        return f"{what}, autosaved {when}"

    def discard(self) -> None:
        for p in (self.scene_path, self.meta_path, self.lock_path):
            if p is None:
                continue
            try:
                p.unlink()
            except FileNotFoundError:
                pass


class Autosave(QObject):
    """Writes the dirty scene every ``interval_ms``; offers recovery files of crashed runs."""

    saved = Signal(str)   # path of the recovery file just written

    def __init__(self, controller: SceneController, folder: Path | None = None,
                 interval_ms: int = INTERVAL_MS, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.folder = Path(folder) if folder is not None else state_dir()
        pid = os.getpid()
        self.scene_file = self.folder / f"recovery-{pid}.json"
        self.meta_file = self.folder / f"recovery-{pid}.meta.json"
        self.lock_file = self.folder / f"recovery-{pid}.lock"
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

    def _hold_lock(self) -> None:
        """Create and ``flock`` this run's lock file (kept until :meth:`remove`)."""
        if self._lock_fd is not None or fcntl is None:
            return
        fd = os.open(self.lock_file, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise
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

    def save_now(self) -> bool:
        """Write the scene if it has unsaved changes; True if written. Never raises on I/O."""
        if not self.controller.is_dirty:
            return False
        meta = {"pid": os.getpid(), "time": time.time(),
                "original": str(self.controller.path) if self.controller.path else None}
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            self._hold_lock()
            atomic_write_text(self.scene_file, dumps_scene(self.controller.scene))
            atomic_write_text(self.meta_file, json.dumps(meta))
        except (ExportError, OSError) as exc:
            self.controller.message.emit(f"autosave failed: {exc}")
            return False
        self.saved.emit(str(self.scene_file))
        return True

    def remove(self) -> None:
        """Forget this run's recovery file (after a save, a clean reset, or a clean exit)."""
        for p in (self.scene_file, self.meta_file):
            try:
                p.unlink()
            except FileNotFoundError:
                pass
            except OSError as exc:
                self.controller.message.emit(f"cannot remove {p}: {exc}")
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
        """Recovery files of runs that are not alive, newest first."""
        out: list[Recovery] = []
        if not self.folder.is_dir():
            return out
        for meta_path in self.folder.glob("recovery-*.meta.json"):
            scene_path = meta_path.with_name(meta_path.name.replace(".meta.json", ".json"))
            try:
                meta = json.loads(meta_path.read_text(encoding="utf-8"))
                pid = int(meta.get("pid", -1))
                saved_at = float(meta.get("time", meta_path.stat().st_mtime))
                original = meta.get("original")
            except (OSError, ValueError, TypeError, AttributeError):
                continue
            if scene_path == self.scene_file or not scene_path.is_file():
                continue
            lock_path = scene_path.with_suffix(".lock")
            held = _lock_held(lock_path)
            if held or (held is None and (pid == os.getpid() or _alive(pid))):
                continue
            out.append(Recovery(scene_path, meta_path, original if isinstance(original, str) else None,
                                saved_at, lock_path if held is not None else None))
        return sorted(out, key=lambda r: r.saved_at, reverse=True)

    def _set_aside(self, recovery: Recovery) -> Path | None:
        """Rename a recovery file that cannot be restored to ``unrestorable-<time>-<name>`` (kept
        for the user, no longer offered) and drop its meta and lock files; the new path or None."""
        stamp = time.strftime("%Y%m%d-%H%M%S", time.localtime(recovery.saved_at))
        target = recovery.scene_path.with_name(f"unrestorable-{stamp}-{recovery.scene_path.name}")
        try:
            os.replace(recovery.scene_path, target)
        except OSError:
            target = None
        for p in (recovery.meta_path, recovery.lock_path):
            if p is not None:
                try:
                    p.unlink()
                except OSError:
                    pass
        return target

    def restore(self, recovery: Recovery) -> Scene | None:
        """Load a recovery file into the controller as an unsaved document; the file is then
        adopted (our own autosave takes over). Returns the scene, or None (with a message)."""
        try:
            scene = load_scene(recovery.scene_path)
        except (SceneFormatError, MechsketchError, OSError) as exc:
            kept = self._set_aside(recovery)
            where = f"; kept as {kept} (not offered again)" if kept else ""
            self.controller.message.emit(f"cannot restore {recovery.scene_path}{where}: {exc}")
            return None
        original = Path(recovery.original) if recovery.original else None
        self.controller.reset(scene, original)
        self.controller.undo_stack.resetClean()   # restored work is unsaved work
        self.controller.pathChanged.emit()
        recovery.discard()
        self.save_now()
        self.controller.message.emit(f"restored {recovery.describe()}")
        return scene
