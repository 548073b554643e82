"""Autosave and crash recovery: the unsaved scene is written, removed when saved, offered back."""
from __future__ import annotations

import fcntl
import json
import os
import re
import subprocess
import sys
import textwrap

from mechsketch.core import MoveJoint
from mechsketch.core.io.scene_file import dumps_scene, loads_scene
from mechsketch.gui.autosave import read_recovery, state_dir

from app_fakes import FakeDialogs, shell  # noqa: F401 - fixture


def test_the_timer_writes_the_unsaved_scene_atomically(shell, qtbot, tmp_path):
    parts = shell(state_dir=tmp_path / "state", autosave_ms=50)
    auto = parts.autosave
    assert auto.timer.interval() == 50
    ticks = []
    auto.timer.timeout.connect(lambda: ticks.append(1))
    qtbot.waitUntil(lambda: len(ticks) >= 2, timeout=20000)   # the timer ran, twice
    assert not auto.recovery_file.exists()               # nothing unsaved: nothing written
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    with qtbot.waitSignal(auto.saved, timeout=20000):
        pass
    meta, doc = read_recovery(auto.recovery_file)        # scene and meta data: one file, one write
    assert loads_scene(json.dumps(doc)) == parts.controller.scene
    assert meta["pid"] == os.getpid() and meta["original"] is None and meta["run"] == auto.run
    assert str(os.getpid()) in auto.recovery_file.name and auto.run in auto.recovery_file.name
    assert not list(auto.folder.glob(".*.tmp"))
    assert sorted(p.name for p in auto.folder.iterdir()) == sorted([auto.recovery_file.name,
                                                                    auto.lock_file.name])


def test_each_run_has_a_name_of_its_own(shell, tmp_path):
    """Two apps of one process (one PID) never share a recovery file."""
    a, b = shell(state_dir=tmp_path / "s"), shell(state_dir=tmp_path / "s")
    assert a.autosave.recovery_file != b.autosave.recovery_file


def test_default_interval_is_a_minute(shell):
    assert shell().autosave.timer.interval() == 60_000


def test_saving_removes_the_recovery_file(shell, tmp_path):
    parts = shell(state_dir=tmp_path / "state")
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    assert parts.autosave.save_now()
    assert parts.file_ops.save_as(tmp_path / "s.json")
    assert not parts.autosave.recovery_file.exists() and not parts.autosave.lock_file.exists()


def test_undo_back_to_clean_removes_it_too(shell, tmp_path):
    parts = shell(state_dir=tmp_path / "state")
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    parts.autosave.save_now()
    parts.window.actions["undo"].trigger()
    assert not parts.autosave.recovery_file.exists()


def test_an_unwritable_state_folder_is_a_message(shell, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    parts = shell(state_dir=blocker / "state")
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    assert parts.autosave.save_now() is False
    assert "autosave failed" in parts.window.statusBar().currentMessage()


def _leave_recovery(folder, scene, pid=999_999_999, original=None):
    """A crashed run's files as versions before issue 20 wrote them: ``recovery-<pid>.json`` (the
    bare scene) and ``recovery-<pid>.meta.json``; they are still offered."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"recovery-{pid}.json").write_text(dumps_scene(scene))
    (folder / f"recovery-{pid}.meta.json").write_text(json.dumps({"pid": pid, "time": 1.7e9,
                                                                  "original": original}))


def test_a_fresh_start_offers_the_recovery_file_back(shell, tmp_path):
    donor = shell(state_dir=tmp_path / "other")
    donor.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    lost = donor.controller.scene
    folder = tmp_path / "state"
    _leave_recovery(folder, lost, original=str(tmp_path / "orig.json"))
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert dialogs.questions[0][0] == "Restore unsaved work?" and "orig.json" in dialogs.questions[0][1]
    assert parts.controller.scene == lost and parts.controller.is_dirty
    assert "*" in parts.window.windowTitle()
    assert not (folder / "recovery-999999999.json").exists()   # adopted: now our own file
    assert not (folder / "recovery-999999999.meta.json").exists()
    assert loads_scene(json.dumps(read_recovery(parts.autosave.recovery_file)[1])) == lost


def test_an_older_versions_scene_without_its_meta_file_is_offered_too(shell, tmp_path):
    """An older version killed between its scene write and its meta write left a bare scene."""
    folder = tmp_path / "state"
    donor = shell(state_dir=tmp_path / "other")
    donor.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    _leave_recovery(folder, donor.controller.scene)
    (folder / "recovery-999999999.meta.json").unlink()
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert "an unsaved scene" in dialogs.questions[0][1]
    assert parts.controller.scene == donor.controller.scene


def test_declining_deletes_the_recovery_file(shell, tmp_path):
    folder = tmp_path / "state"
    first = shell(state_dir=tmp_path / "x")
    _leave_recovery(folder, first.controller.scene)
    dialogs = FakeDialogs()
    dialogs.yes_no.append(False)
    parts = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert not list(folder.glob("recovery-*"))
    assert not parts.controller.is_dirty


def test_files_whose_lock_is_held_are_not_offered_whatever_their_pid(shell, tmp_path):
    folder = tmp_path / "state"
    first = shell(state_dir=tmp_path / "x")
    _leave_recovery(folder, first.controller.scene, pid=999_999_999)    # a PID that says "dead"
    fd = os.open(folder / "recovery-999999999.lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX)                                      # the lock says "alive"
    try:
        parts = shell(state_dir=folder, offer_recovery=True)
        assert not parts.dialogs.questions
    finally:
        os.close(fd)
    assert len(parts.autosave.pending()) == 1                           # released: offered


def test_a_files_pid_of_a_live_process_does_not_hide_it(shell, tmp_path):
    folder = tmp_path / "state"
    first = shell(state_dir=tmp_path / "x")
    _leave_recovery(folder, first.controller.scene, pid=os.getpid())    # our own PID, no lock
    parts = shell(state_dir=folder, offer_recovery=True)
    assert parts.dialogs.questions and parts.dialogs.questions[0][0] == "Restore unsaved work?"


def test_state_dir_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("MECHSKETCH_STATE_DIR", str(tmp_path / "s"))
    assert state_dir() == tmp_path / "s"
    monkeypatch.delenv("MECHSKETCH_STATE_DIR")
    assert state_dir().name == "mechsketch"


CRASH = textwrap.dedent("""
    import os
    from mechsketch.core import MoveJoint
    from mechsketch.gui.app import build
    from app_fakes import FakeDialogs, stand_in_components
    parts = build(dialogs=FakeDialogs(), components=stand_in_components, offer_recovery=False)
    parts.controller.push(MoveJoint("fourbar", "B", (23.0, 31.0)), "move joint B")
    assert parts.autosave.save_now()
    os._exit(3)   # a crash: no clean exit, the recovery file stays
""")


def test_a_real_crash_leaves_a_file_the_next_start_restores(shell, tmp_path):
    env = dict(os.environ, MECHSKETCH_STATE_DIR=str(tmp_path / "state"), QT_QPA_PLATFORM="offscreen",
               PYTHONPATH=os.pathsep.join([os.path.dirname(__file__), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run([sys.executable, "-c", CRASH], env=env, capture_output=True, text=True, timeout=60)
    assert run.returncode == 3, run.stderr
    assert len(list((tmp_path / "state").glob("recovery-*.json"))) == 1     # scene and meta: one file
    assert len(list((tmp_path / "state").glob("recovery-*.lock"))) == 1     # free: its owner is dead
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=tmp_path / "state", dialogs=dialogs, offer_recovery=True)
    assert parts.controller.scene.element("fourbar").joint("B").at == (23.0, 31.0)
    assert parts.controller.is_dirty


def test_recovery_is_offered_when_the_dead_apps_pid_belongs_to_another_process(shell, tmp_path):
    """Issue 13 item 13: a crashed app's PID reused by a live process must not hide its work."""
    env = dict(os.environ, MECHSKETCH_STATE_DIR=str(tmp_path / "state"), QT_QPA_PLATFORM="offscreen",
               PYTHONPATH=os.pathsep.join([os.path.dirname(__file__), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run([sys.executable, "-c", CRASH], env=env, capture_output=True, text=True, timeout=60)
    assert run.returncode == 3, run.stderr
    (path,) = (tmp_path / "state").glob("recovery-*.json")
    doc = json.loads(path.read_text())
    doc["pid"] = os.getppid()             # the dead app's PID now names a live, unrelated process
    path.write_text(json.dumps(doc))
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    parts = shell(state_dir=tmp_path / "state", dialogs=dialogs, offer_recovery=True)
    assert dialogs.questions and dialogs.questions[0][0] == "Restore unsaved work?"
    assert parts.controller.scene.element("fourbar").joint("B").at == (23.0, 31.0)


LIVE = textwrap.dedent("""
    import sys
    from mechsketch.core import MoveJoint
    from mechsketch.gui.app import build
    from app_fakes import FakeDialogs, stand_in_components
    parts = build(dialogs=FakeDialogs(), components=stand_in_components, offer_recovery=False)
    parts.controller.push(MoveJoint("fourbar", "B", (23.0, 31.0)), "move joint B")
    assert parts.autosave.save_now()
    print("saved", flush=True)
    sys.stdin.read()              # runs until the test closes our stdin
    parts.autosave.clean_exit()
""")


def test_a_live_app_is_recognised_by_more_than_its_pid(shell, tmp_path):
    """A running app's recovery file is never offered, even if its PID looked dead."""
    folder = tmp_path / "state"
    env = dict(os.environ, MECHSKETCH_STATE_DIR=str(folder), QT_QPA_PLATFORM="offscreen",
               PYTHONPATH=os.pathsep.join([os.path.dirname(__file__), os.environ.get("PYTHONPATH", "")]))
    live = subprocess.Popen([sys.executable, "-c", LIVE], env=env, stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)
    try:
        assert live.stdout.readline().strip() == "saved"
        (path,) = folder.glob("recovery-*.json")
        doc = json.loads(path.read_text())
        doc["pid"] = 999_999_999          # a PID that says "dead"; the lock says "alive"
        path.write_text(json.dumps(doc))
        parts = shell(state_dir=folder, offer_recovery=True)
        assert not parts.dialogs.questions
    finally:
        live.communicate("", timeout=60)
    assert live.returncode == 0
    assert not list(folder.glob("recovery-*"))               # a clean exit leaves nothing


def test_a_start_removes_temporaries_a_killed_autosave_left(shell, tmp_path):
    folder = tmp_path / "state"
    folder.mkdir()
    orphan = folder / ".recovery-4242.json.abcd1234.tmp"
    orphan.write_text("half")
    os.utime(orphan, (1e9, 1e9))
    shell(state_dir=folder, offer_recovery=True)
    assert not orphan.exists()


def test_a_recovery_file_that_cannot_be_restored_is_kept_aside_and_not_offered_again(shell, tmp_path):
    """Issue 13 item 2: an unreadable recovery file was offered at every start."""
    folder = tmp_path / "state"
    donor = shell(state_dir=tmp_path / "x")
    _leave_recovery(folder, donor.controller.scene)
    bad = folder / "recovery-999999999.json"
    bad.write_text(re.sub(r"34\.64\d*", "1e10", bad.read_text(), count=1))   # beyond ±1e9 mm
    dialogs = FakeDialogs()
    dialogs.yes_no.append(True)
    first = shell(state_dir=folder, dialogs=dialogs, offer_recovery=True)
    assert len(dialogs.questions) == 1
    msg = first.window.statusBar().currentMessage()
    assert "cannot restore" in msg and "kept as" in msg and "beyond" in msg, msg
    kept = list(folder.glob("unrestorable-*.json"))
    assert len(kept) == 1 and "1e10" in kept[0].read_text()
    again = FakeDialogs()
    shell(state_dir=folder, dialogs=again, offer_recovery=True)
    assert not again.questions
