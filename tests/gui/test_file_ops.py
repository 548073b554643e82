"""File commands through the app's actions and the fake dialogs: save, reopen, bad files, examples."""
from __future__ import annotations

import json
import os
import sys

import pytest

from mechsketch import resources
from mechsketch.core import MoveJoint, Scene, load_scene
from mechsketch.gui.file_ops import make_settings

from app_fakes import DISCARD, SAVE, shell  # noqa: F401 - fixture


def _edit(parts):
    parts.controller.push(MoveJoint("fourbar", "B", (22.5, 33.0)), "move joint B")


def test_save_as_then_reopen_gives_the_same_scene(shell, tmp_path):
    parts = shell()
    _edit(parts)
    target = tmp_path / "mine"                       # the .json suffix is added
    parts.dialogs.save_names.append(str(target))
    parts.window.actions["save_as"].trigger()
    saved = tmp_path / "mine.json"
    assert saved.is_file() and not parts.controller.is_dirty
    assert parts.window.windowTitle() == "mine.json — mechsketch"
    edited = parts.controller.scene
    parts.window.actions["new"].trigger()
    assert parts.controller.scene == Scene()
    parts.dialogs.open_names.append(str(saved))
    parts.window.actions["open"].trigger()
    assert parts.controller.scene == edited
    assert parts.controller.path == saved.resolve()
    assert parts.file_ops.recent_files()[0] == str(saved.resolve())


def test_save_writes_to_the_current_file_without_asking(shell, tmp_path):
    path = tmp_path / "s.json"
    path.write_text(resources.example_path("fourbar_crank_rocker").read_text())
    parts = shell(path)
    _edit(parts)
    parts.window.actions["save"].trigger()
    assert not parts.dialogs.questions
    assert load_scene(path).element("fourbar").joint("B").at == (22.5, 33.0)
    assert not list(tmp_path.glob(".*.tmp"))          # the atomic write left nothing behind


def test_save_of_an_example_asks_where(shell, tmp_path):
    parts = shell()
    parts.dialogs.save_names.append(None)           # the user cancels
    assert parts.file_ops.save() is False
    assert parts.dialogs.questions[-1][1].endswith("fourbar_crank_rocker.json")


def test_corrupt_file_lists_the_problems_and_keeps_the_document(shell, tmp_path):
    parts = shell()
    _edit(parts)
    before = parts.controller.scene
    bad = tmp_path / "bad.json"
    doc = json.loads(resources.example_path("fourbar_crank_rocker").read_text())
    doc["elements"][0]["joints"][1]["at"] = ["x", 3]
    doc["elements"][0]["driver"]["link"] = 7
    bad.write_text(json.dumps(doc))
    parts.dialogs.open_names.append(str(bad))
    parts.dialogs.save_changes.append(DISCARD)
    parts.window.actions["open"].trigger()
    title, text, details = parts.dialogs.errors[-1]
    assert title == "Cannot open scene" and "problem(s)" in text
    assert "$.elements[0].joints[1].at[0]" in text and "$.elements[0].driver.link" in details
    assert parts.controller.scene == before and parts.controller.is_dirty
    assert "bad.json cannot be opened" in parts.window.statusBar().currentMessage()


@pytest.mark.parametrize("content", [b"", b"\xff\xfe garbage", b"[1, 2]", b'{"format": "other"}'])
def test_other_bad_files_give_a_message(shell, tmp_path, content):
    parts = shell()
    bad = tmp_path / "bad.json"
    bad.write_bytes(content)
    assert parts.file_ops.open(bad) is False
    assert parts.dialogs.errors and parts.controller.scene.element("fourbar")


def test_unwritable_path_gives_a_message_and_keeps_the_unsaved_document(shell, tmp_path):
    parts = shell()
    _edit(parts)
    edited = parts.controller.scene
    target = tmp_path / "no such folder" / "x.json"
    parts.dialogs.save_names.append(str(target))
    parts.window.actions["save_as"].trigger()
    title, text, _ = parts.dialogs.errors[-1]
    assert title == "Cannot save scene" and "no such folder" in text and "Nothing was lost" in text
    assert parts.controller.scene == edited and parts.controller.is_dirty
    assert parts.controller.path is None and "*" in parts.window.windowTitle()


@pytest.mark.skipif(sys.platform.startswith("win") or os.geteuid() == 0, reason="root ignores file modes")
def test_read_only_folder(shell, tmp_path):  # pragma: no cover - only as a normal user
    parts = shell()
    _edit(parts)
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    try:
        assert parts.file_ops.save_as(folder / "x.json") is False
        assert parts.controller.is_dirty
    finally:
        folder.chmod(0o700)


def test_saving_over_a_folder_fails_cleanly(shell, tmp_path):
    parts = shell()
    _edit(parts)
    (tmp_path / "taken.json").mkdir()
    assert parts.file_ops.save_as(tmp_path / "taken.json") is False
    assert parts.controller.is_dirty and parts.dialogs.errors


@pytest.mark.parametrize("name", [p.stem for p in resources.example_paths()])
def test_open_every_example(shell, name):
    parts = shell()
    parts.window.actions[f"example:{name}"].trigger()
    c, w = parts.controller, parts.window
    assert c.scene == load_scene(resources.example_path(name))
    assert not c.is_dirty and w.windowTitle().startswith(f"{name} (example)")
    diag = w.diagnostics.plain_text()
    for el in c.scene.elements:               # every element is listed (solved or explained)
        assert el.id in diag
    for lk in c.linkages():
        assert c.result(lk.id).ok, c.result(lk.id).error
        assert "mobility: 1" in diag
    for el in c.scene.elements:               # Geneva drives and rolling levers: the CLI summary
        res = c.element_result(el.id)
        if res is not None:
            assert res.ok, res.error
            assert res.summary().splitlines()[0] in diag
    w.plots.refresh()
    assert w.plots.title.text()


def test_examples_menu_lists_every_scene_in_resources(shell):
    parts = shell()
    names = set(parts.file_ops.examples())
    on_disk = {p.stem for p in (resources.example_paths()[0].parent).glob("*.json")}
    assert names == on_disk


def test_opening_asks_to_save_unsaved_changes(shell, tmp_path):
    parts = shell()
    _edit(parts)
    parts.dialogs.save_changes.append("cancel")
    parts.window.actions["example:slider_crank_offset"].trigger()
    assert [e.id for e in parts.controller.scene.elements] == ["fourbar"]   # cancelled: kept
    parts.dialogs.save_changes.append(SAVE)
    parts.dialogs.save_names.append(str(tmp_path / "keep.json"))
    parts.window.actions["example:slider_crank_offset"].trigger()
    assert load_scene(tmp_path / "keep.json").element("fourbar").joint("B").at == (22.5, 33.0)
    assert [e.id for e in parts.controller.scene.elements] == ["slider_crank"]


def test_recent_files_persist_in_the_injected_settings(shell, tmp_path):
    parts = shell()
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    for p in (a, b):
        assert parts.file_ops.save_as(p)
    assert parts.file_ops.recent_files() == [str(b.resolve()), str(a.resolve())]
    menu = parts.window.recent_menu
    assert [x.text() for x in menu.actions()][:2] == ["&1 b.json", "&2 a.json"]
    again = make_settings(tmp_path / "settings.ini")
    assert json.loads(again.value("recent_files"))[0] == str(b.resolve())
    assert int(again.value("schema_version")) == 1
    menu.actions()[1].trigger()
    assert parts.controller.path == a.resolve()


def test_a_recent_file_that_is_gone_is_dropped_with_a_message(shell, tmp_path):
    parts = shell()
    gone = tmp_path / "gone.json"
    parts.file_ops.save_as(gone)
    gone.unlink()
    assert parts.file_ops.open_recent(str(gone.resolve())) is False
    assert "no longer exists" in parts.dialogs.errors[-1][1]
    assert parts.file_ops.recent_files() == []


def test_new_gives_an_empty_scene_the_panels_can_show(shell):
    parts = shell()
    parts.window.actions["new"].trigger()
    w = parts.window
    assert parts.controller.scene == Scene() and w.windowTitle() == "Untitled — mechsketch"
    assert "empty" in w.diagnostics.plain_text()
    assert "no linkage" in w.plots.title.text()
