"""Atomic file writes: write a temporary file in the target's folder, then rename it over.

The old file stays intact if anything fails; failures become :class:`ExportError` naming the path.

- A symlink at the target is followed: the file it points to is replaced, the link stays.
- An overwritten file keeps its permission bits (and, where allowed, its owner and group); a new
  file gets ``0o666`` minus the process umask, as ``open(path, "w")`` would give it.
- The temporary is ``.NAME.XXXXXXXX.tmp`` beside the target, exclusively ``flock``-ed while it is
  written. A writer killed mid-write leaves it behind unlocked; :func:`remove_orphans` deletes
  such files, and every save runs it for its own target first.
"""
from __future__ import annotations

import os
import re
import stat
import time
from pathlib import Path
from typing import Callable

from ..errors import ExportError

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows: orphans are recognised by age instead
    fcntl = None  # type: ignore[assignment]

#: A temporary younger than this is never taken for an orphan (it may be between its creation
#: and its lock); without ``flock`` (Windows) the age alone decides, with ORPHAN_AGE_NO_LOCK_S.
FRESH_S = 1.0
ORPHAN_AGE_NO_LOCK_S = 3600.0

_TEMP = re.compile(r"^\.(?P<name>.+)\.[A-Za-z0-9_]{8}\.tmp$")


def resolve_target(path: str | os.PathLike) -> Path:
    """The file a write to ``path`` lands in: symlinks (chains, relative, dangling) followed."""
    return Path(os.path.realpath(os.fspath(path)))


def _is_orphan(path: Path, now: float) -> bool:
    """Whether ``path`` is a temporary no live writer holds (its lock is free, it is not fresh)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        return False
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or now - st.st_mtime < FRESH_S:
            return False
        if fcntl is None:  # pragma: no cover - Windows
            return now - st.st_mtime > ORPHAN_AGE_NO_LOCK_S
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            return False          # a live writer holds it (or locks are unsupported here)
        try:
            return os.stat(path, follow_symlinks=False).st_ino == st.st_ino
        except OSError:
            return False          # renamed into place meanwhile
    finally:
        os.close(fd)


def remove_orphans(folder: str | os.PathLike, target: str | os.PathLike | None = None) -> list[Path]:
    """Delete the temporaries of killed writers in ``folder`` (only ``target``'s if given).

    Returns the paths removed; never raises (an unreadable folder removes nothing).
    """
    name = Path(target).name if target is not None else None
    removed: list[Path] = []
    now = time.time()
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        m = _TEMP.match(entry.name)
        if m is None or (name is not None and m.group("name") != name):
            continue
        path = Path(entry.path)
        if _is_orphan(path, now):
            try:
                path.unlink()
            except OSError:
                continue
            removed.append(path)
    return removed


def _create_temp(folder: Path, name: str) -> tuple[int, Path]:
    """Create and lock a new temporary beside ``name``; mode 0o666 minus the umask."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        tmp = folder / f".{name}.{os.urandom(4).hex()}.tmp"
        try:
            fd = os.open(tmp, flags, 0o666)
        except FileExistsError:  # pragma: no cover - 2**32 names
            continue
        if fcntl is not None:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:  # pragma: no cover - a file system without locks: age decides
                pass
        return fd, tmp
    raise FileExistsError(17, "no free temporary name", str(folder))  # pragma: no cover


def _keep_mode(fd: int, target: Path) -> None:
    """Give the temporary the permission bits (and owner, where allowed) of an existing target."""
    try:
        st = os.stat(target)
    except OSError:
        return                    # a new file: the umask decided at creation
    if not stat.S_ISREG(st.st_mode):
        return
    os.fchmod(fd, stat.S_IMODE(st.st_mode))
    mine = os.fstat(fd)
    if (mine.st_uid, mine.st_gid) != (st.st_uid, st.st_gid):
        try:
            os.fchown(fd, st.st_uid, st.st_gid)
        except OSError:
            pass                  # not allowed: the file becomes ours, its mode bits stay
        else:
            os.fchmod(fd, stat.S_IMODE(st.st_mode))   # chown may clear set-id bits


def atomic_write(path: str | os.PathLike, write: Callable[[str], None]) -> None:
    """Call ``write(temporary_path)`` to produce the file, then rename it to ``path``.

    ``path`` may be a symlink (its target is replaced); an existing file keeps its mode.
    """
    shown = Path(path)
    target = resolve_target(path)
    folder = target.parent
    if not folder.is_dir():
        raise ExportError(f"cannot write {shown}: folder {folder} does not exist")
    remove_orphans(folder, target)
    fd, tmp = None, None
    try:
        fd, tmp = _create_temp(folder, target.name)
        _keep_mode(fd, target)
        write(str(tmp))
        os.replace(tmp, target)
        tmp = None
    except OSError as exc:
        raise ExportError(f"cannot write {shown}: {exc.strerror or exc}") from None
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        if fd is not None:
            os.close(fd)          # releases the lock, after the rename


def atomic_write_text(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8, LF line ends, synced to disk) to ``path`` atomically."""
    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())

    atomic_write(path, write)
