"""Atomic writes keep the target's mode, follow the umask for new files, write through symlinks,
and remove the temporaries of writers that were killed (issue 13, item 12)."""
from __future__ import annotations

import os
import signal
import stat
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from mechsketch.core.io import atomic
from mechsketch.core.io.atomic import atomic_write, atomic_write_text, remove_orphans

pytestmark = pytest.mark.skipif(sys.platform.startswith("win"), reason="POSIX modes and signals")


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


@pytest.fixture
def umask():
    """Set the process umask for one test and restore it after."""
    old = os.umask(0o022)
    os.umask(old)
    yield lambda value: os.umask(value)
    os.umask(old)


@pytest.mark.parametrize("mode", [0o644, 0o640, 0o664, 0o600, 0o755])
def test_an_overwritten_file_keeps_its_mode(tmp_path, umask, mode):
    umask(0o077)                                   # the umask must not matter for an overwrite
    target = tmp_path / "part.dxf"
    target.write_text("old")
    os.chmod(target, mode)
    atomic_write_text(target, "new")
    assert target.read_text() == "new"
    assert _mode(target) == mode


@pytest.mark.parametrize("mask, expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664),
                                            (0o000, 0o666)])
def test_a_new_file_follows_the_umask(tmp_path, umask, mask, expected):
    umask(mask)
    target = tmp_path / "new.csv"
    atomic_write_text(target, "a,b\n")
    assert _mode(target) == expected
    assert sorted(os.listdir(tmp_path)) == ["new.csv"]


def test_a_writer_callback_that_opens_the_path_itself_gets_the_same_modes(tmp_path, umask):
    umask(0o022)
    target = tmp_path / "d.dxf"

    def write(tmp: str) -> None:          # like ezdxf's saveas: opens the name afresh
        with open(tmp, "w") as fh:
            fh.write("0\nEOF\n")
    atomic_write(target, write)
    assert _mode(target) == 0o644
    os.chmod(target, 0o640)
    atomic_write(target, write)
    assert _mode(target) == 0o640


def test_a_symlink_is_written_through_to_its_target(tmp_path):
    real_dir = tmp_path / "shared"
    real_dir.mkdir()
    real = real_dir / "scene.json"
    real.write_text("old")
    os.chmod(real, 0o644)
    link = tmp_path / "link.json"
    link.symlink_to(real)
    atomic_write_text(link, "new")
    assert link.is_symlink() and os.readlink(link) == str(real)
    assert real.read_text() == "new" and _mode(real) == 0o644
    assert sorted(os.listdir(tmp_path)) == ["link.json", "shared"]
    assert sorted(os.listdir(real_dir)) == ["scene.json"]


def test_a_chain_of_relative_symlinks_and_a_dangling_one(tmp_path):
    (tmp_path / "real.txt").write_text("old")
    (tmp_path / "a").symlink_to("real.txt")
    (tmp_path / "b").symlink_to("a")
    atomic_write_text(tmp_path / "b", "new")
    assert (tmp_path / "b").is_symlink() and (tmp_path / "a").is_symlink()
    assert (tmp_path / "real.txt").read_text() == "new"
    (tmp_path / "dangling").symlink_to("created.txt")     # a link to a file not yet written
    atomic_write_text(tmp_path / "dangling", "made")
    assert (tmp_path / "dangling").is_symlink()
    assert (tmp_path / "created.txt").read_text() == "made"


KILLED_WRITER = textwrap.dedent("""
    import os, sys, time
    from mechsketch.core.io.atomic import atomic_write
    def write(tmp):
        with open(tmp, "w") as fh:
            fh.write("half a file")
        print("writing", flush=True)
        time.sleep(60)
    atomic_write(sys.argv[1], write)
""")


def _killed_mid_write(target) -> None:
    """Start a writer in another process and SIGKILL it while its temporary file is open."""
    proc = subprocess.Popen([sys.executable, "-c", KILLED_WRITER, str(target)],
                            stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "writing"
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=20)
    for name in os.listdir(target.parent):     # an orphan is never younger than FRESH_S
        if name.endswith(".tmp"):
            past = time.time() - 10 * atomic.FRESH_S
            os.utime(target.parent / name, (past, past))


def test_a_save_removes_the_temporary_of_a_killed_writer(tmp_path):
    target = tmp_path / "scene.json"
    target.write_text("kept")
    _killed_mid_write(target)
    orphans = [n for n in os.listdir(tmp_path) if n.endswith(".tmp")]
    assert len(orphans) == 1 and orphans[0].startswith(".scene.json.")
    assert target.read_text() == "kept"                      # the kill lost nothing
    (tmp_path / ".other.json.x1234567.tmp").write_text("x")  # another file's temporary stays
    os.utime(tmp_path / ".other.json.x1234567.tmp", (1e9, 1e9))
    atomic_write_text(target, "saved")
    assert sorted(os.listdir(tmp_path)) == [".other.json.x1234567.tmp", "scene.json"]
    assert target.read_text() == "saved"


def test_remove_orphans_at_start_keeps_a_live_writers_temporary(tmp_path):
    target = tmp_path / "scene.json"
    _killed_mid_write(target)
    seen: dict[str, object] = {}
    started, release = threading.Event(), threading.Event()

    def write(tmp: str) -> None:
        with open(tmp, "w") as fh:
            fh.write("live")
        seen["tmp"] = tmp
        started.set()
        release.wait(20)
    worker = threading.Thread(target=atomic_write, args=(tmp_path / "other.json", write))
    worker.start()
    try:
        assert started.wait(20)
        removed = remove_orphans(tmp_path)                   # what an app start does
        assert len(removed) == 1 and removed[0].name.startswith(".scene.json.")
        assert os.path.exists(seen["tmp"])                   # the live one is untouched
    finally:
        release.set()
        worker.join(20)
    assert sorted(os.listdir(tmp_path)) == ["other.json"]
    assert (tmp_path / "other.json").read_text() == "live"


def test_remove_orphans_of_one_target_only(tmp_path):
    names = (".a.json.k1234567.tmp", ".b.json.k2345678.tmp", ".a.json.abcdefgh.tmp", "a.json",
             ".a.jsonx.tmp", ".a.json.short.tmp", ".a.json.fresh123.tmp")
    for name in names:
        (tmp_path / name).write_text("x")
        if name != ".a.json.fresh123.tmp":
            os.utime(tmp_path / name, (1e9, 1e9))
    removed = remove_orphans(tmp_path, target=tmp_path / "a.json")
    assert sorted(p.name for p in removed) == [".a.json.abcdefgh.tmp", ".a.json.k1234567.tmp"]
    assert sorted(os.listdir(tmp_path)) == [".a.json.fresh123.tmp", ".a.json.short.tmp",
                                            ".a.jsonx.tmp", ".b.json.k2345678.tmp", "a.json"]
    assert remove_orphans(tmp_path / "missing") == []


def test_failures_still_leave_no_temporary(tmp_path, monkeypatch):
    target = tmp_path / "t.txt"
    target.write_text("old")
    os.chmod(target, 0o640)

    def boom(tmp: str) -> None:
        raise OSError(28, "No space left on device")
    with pytest.raises(OSError, match="No space left"):
        atomic_write(target, boom)
    assert sorted(os.listdir(tmp_path)) == ["t.txt"] and _mode(target) == 0o640
    assert atomic.ExportError is not None
