"""Crash recovery with real processes and real signals (issue 20 item 10).

Each crashed run here is a separate Python process that builds the app, autosaves and dies: by
``SIGKILL`` sent to itself at a chosen moment of the autosave (between two writes, before a
rename), or by ``os._exit``. PID reuse is made real by running two apps in fresh PID namespaces
(``unshare --pid --fork``: both get the same PID, as apps in containers do); where the kernel
refuses namespaces the child's ``os.getpid`` is pinned instead, and the test says which it used.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import textwrap
from functools import lru_cache
from pathlib import Path

from app_fakes import FakeDialogs, shell  # noqa: F401 - fixture

HERE = os.path.dirname(__file__)

#: the start of every child: the app built with stand-in canvas parts, not offering recovery;
#: ``die()`` sends SIGKILL to the real process (its PID taken before any pinning)
PRELUDE = textwrap.dedent("""
    import os, signal, sys
    REAL_PID = os.getpid()
    PIN = os.environ.get("PIN_PID")
    if PIN:                                   # no PID namespace here: the same PID by decree
        os.getpid = lambda: int(PIN)
    from mechsketch.core import MoveJoint
    from mechsketch.gui.app import build
    from app_fakes import FakeDialogs, stand_in_components
    parts = build(dialogs=FakeDialogs(), components=stand_in_components, offer_recovery=False)
    auto = parts.autosave
    def move(x, y):
        parts.controller.push(MoveJoint("fourbar", "B", (x, y)), "move joint B")
    def die():
        sys.stdout.flush()
        os.kill(REAL_PID, signal.SIGKILL)
""")


def _script(body: str) -> str:
    return PRELUDE + textwrap.dedent(body)


def _env(folder: Path, **extra: str) -> dict:
    return dict(os.environ, MECHSKETCH_STATE_DIR=str(folder), QT_QPA_PLATFORM="offscreen",
                PYTHONPATH=os.pathsep.join([HERE, os.environ.get("PYTHONPATH", "")]), **extra)


@lru_cache(maxsize=None)
def _namespace_prefix() -> tuple[str, ...] | None:
    """A command prefix that runs a child in a fresh PID namespace (None if the kernel refuses)."""
    unshare = shutil.which("unshare")
    if unshare is None:
        return None
    for prefix in ((unshare, "--pid", "--fork"), (unshare, "--user", "--map-root-user", "--pid", "--fork")):
        try:
            ok = subprocess.run([*prefix, "true"], capture_output=True, timeout=30).returncode == 0
        except (OSError, subprocess.TimeoutExpired):
            ok = False
        if ok:
            return prefix
    return None


def _run(tmp_path: Path, folder: Path, body: str, *, same_pid: bool = False, stdin: str | None = None,
         timeout: float = 120) -> subprocess.CompletedProcess:
    """Run ``body`` after the prelude in a child process; ``same_pid``: in a fresh PID namespace
    (so every such child has the same PID), or with its PID pinned where namespaces are refused."""
    path = tmp_path / f"child_{abs(hash(body)) % 10**8}.py"
    path.write_text(_script(body))
    cmd: list[str] = [sys.executable, str(path)]
    extra: dict[str, str] = {}
    if same_pid:
        prefix = _namespace_prefix()
        if prefix is not None:
            # sh stays PID 1 (the namespace's init); python is its child, PID 2 in every namespace
            cmd = [*prefix, "sh", "-c", '"$0" "$1"; exit $?', *cmd]
        else:
            extra["PIN_PID"] = "4242"
    return subprocess.run(cmd, env=_env(folder, **extra), capture_output=True, text=True,
                          timeout=timeout, input=stdin)


def _b(parts) -> tuple[float, float]:
    return parts.controller.scene.element("fourbar").joint("B").at


def test_a_kill_between_the_autosave_writes_still_leaves_work_the_next_start_offers(shell, tmp_path):
    """The autosave used to write the scene, then its meta file: SIGKILL between the two left a
    scene no start ever offered. Now the first completed write holds everything."""
    folder = tmp_path / "state"
    run = _run(tmp_path, folder, """
        import mechsketch.gui.autosave as autosave_module
        real = autosave_module.atomic_write_text
        def write_then_die(path, text):
            real(path, text)
            die()                             # killed right after the first write completes
        autosave_module.atomic_write_text = write_then_die
        move(23.0, 31.0)
        auto.save_now()
    """)
    assert run.returncode == -signal.SIGKILL, run.stderr
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert [q[0] for q in dialogs.questions] == ["Restore unsaved work?"]
    assert _b(parts) == (23.0, 31.0) and parts.controller.is_dirty


def test_a_kill_inside_an_autosave_keeps_the_previous_one(shell, tmp_path):
    """SIGKILL after the new text is written but before it is renamed into place: the previous
    autosave is offered whole, and the half-done temporary is removed by the next start."""
    folder = tmp_path / "state"
    run = _run(tmp_path, folder, """
        move(23.0, 31.0)
        assert auto.save_now()
        move(40.0, 41.0)
        os.replace = lambda *a, **k: die()    # the rename of the next autosave never happens
        auto.save_now()
    """)
    assert run.returncode == -signal.SIGKILL, run.stderr
    temporaries = list(folder.glob(".*.tmp"))
    assert temporaries
    for t in temporaries:
        os.utime(t, (1e9, 1e9))              # older than a live writer's (atomic.FRESH_S)
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert _b(parts) == (23.0, 31.0)
    assert not list(folder.glob(".*.tmp"))


CRASH_AT = """
    move({x}, {y})
    assert auto.save_now()
    print("pid", os.getpid(), flush=True)
    os._exit(3)
"""

CLEAN_RUN = """
    print("pid", os.getpid(), flush=True)
    print("pending", len(auto.pending()), flush=True)
    move(50.0, 51.0)
    assert auto.save_now()                    # its own autosave, beside the crashed run's
    auto.clean_exit()                         # what closing the window does at the end
    print("exited", flush=True)
"""


def _pid_of(run: subprocess.CompletedProcess) -> int:
    return int(next(line.split()[1] for line in run.stdout.splitlines() if line.startswith("pid ")))


def test_an_app_given_the_crashed_apps_pid_neither_hides_nor_deletes_its_work(shell, tmp_path):
    """Two apps with the same PID (fresh PID namespaces, as in containers): the second used to
    skip the crashed run's file, overwrite it with its own autosave and delete it on a clean exit."""
    folder = tmp_path / "state"
    crashed = _run(tmp_path, folder, CRASH_AT.format(x=23.0, y=31.0), same_pid=True)
    assert crashed.returncode == 3, crashed.stderr
    second = _run(tmp_path, folder, CLEAN_RUN, same_pid=True)
    assert second.returncode == 0, second.stderr
    assert _pid_of(second) == _pid_of(crashed), "the test did not give both apps one PID"
    assert "pending 1" in second.stdout        # the second app sees the crashed run's work
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert len(dialogs.questions) == 1
    assert _b(parts) == (23.0, 31.0)           # the crashed run's work, not the second app's


def test_every_crashed_run_is_offered_newest_first(shell, tmp_path):
    """Two runs crashed: No to the newest deletes it, and the older one is offered next."""
    folder = tmp_path / "state"
    for x in (23.0, 24.0):
        run = _run(tmp_path, folder, CRASH_AT.format(x=x, y=31.0))
        assert run.returncode == 3, run.stderr
    dialogs = FakeDialogs()
    dialogs.yes_no.extend([False, True])
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert len(dialogs.questions) == 2
    assert _b(parts) == (23.0, 31.0)           # the older run, restored after No to the newer
    offered = list(folder.glob("recovery-*.json"))
    assert offered == [parts.autosave.recovery_file]   # adopted; the declined one is gone


def test_a_running_app_with_any_pid_is_never_offered(shell, tmp_path):
    """A live app's autosave is not offered by a second app, whatever the two PIDs are."""
    folder = tmp_path / "state"
    live_body = """
        move(23.0, 31.0)
        assert auto.save_now()
        print("saved", flush=True)
        sys.stdin.readline()
        auto.clean_exit()
    """
    path = tmp_path / "live.py"
    path.write_text(_script(live_body))
    live = subprocess.Popen([sys.executable, str(path)], env=_env(folder), stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)
    try:
        assert live.stdout.readline().strip() == "saved"
        parts = shell(state_dir=folder, offer_recovery=True)
        assert not parts.dialogs.questions
        assert parts.autosave.pending() == []
    finally:
        live.communicate("\n", timeout=60)
    assert live.returncode == 0
    assert not list(folder.glob("recovery-*"))


def test_two_apps_starting_together_never_both_take_one_crashed_run(shell, tmp_path):
    """While one app is asking about a crashed run's file, it holds it: a second app does not offer it."""
    folder = tmp_path / "state"
    assert _run(tmp_path, folder, CRASH_AT.format(x=23.0, y=31.0)).returncode == 3
    first = shell(state_dir=folder)
    (claimed,) = first.autosave.pending()
    assert claimed.claim()
    try:
        second = shell(state_dir=folder)
        assert second.autosave.pending() == []
    finally:
        claimed.release()
    assert len(second.autosave.pending()) == 1
