"""The app shell driven as a user would: start-up, menus, undo/redo, delete, close, never dying."""
from __future__ import annotations

import sys

import pytest
from PySide6.QtCore import Qt
from PySide6.QtGui import QKeySequence

from mechsketch import resources
from mechsketch.core import MoveJoint, load_scene
from mechsketch.gui import app as app_module

from app_fakes import DISCARD, SAVE, FakeDialogs, shell  # noqa: F401 - fixture


def test_starts_on_the_built_in_example(shell):
    parts = shell()
    c = parts.controller
    assert [e.id for e in c.scene.elements] == ["fourbar"]
    assert c.result("fourbar").ok
    assert not c.is_dirty
    assert parts.window.windowTitle() == "fourbar_crank_rocker (example) — mechsketch"
    assert parts.window.isVisible()
    assert parts.autosave.timer.isActive()


def test_open_scene_from_the_command_line(shell):
    path = resources.example_path("slider_crank_offset")
    parts = shell(path)
    assert parts.controller.scene == load_scene(path)
    assert parts.controller.path == path.resolve()
    assert parts.window.windowTitle().startswith("slider_crank_offset.json — ")


def test_a_bad_scene_on_the_command_line_gives_a_message_and_an_empty_scene(shell, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    parts = shell(bad)
    assert parts.controller.scene.elements == ()
    assert "not valid JSON" in parts.dialogs.errors[0][1]


def test_menus_list_every_example_and_the_standard_shortcuts(shell):
    w = shell().window
    menus = {a.text().replace("&", ""): a.menu() for a in w.menuBar().actions()}
    assert list(menus) == ["File", "Edit", "View", "Tools", "Examples", "Help"]
    names = [a.text() for a in menus["Examples"].actions() if not a.isSeparator() and a.menu() is None]
    assert len(names) == len(resources.example_paths()) >= 5
    assert [a.text() for a in menus["Examples"].actions() if a.menu() is not None] == ["&Insert"]
    assert w.actions["undo"].shortcut() == QKeySequence(QKeySequence.StandardKey.Undo)
    assert w.actions["redo"].shortcut() == QKeySequence(QKeySequence.StandardKey.Redo)
    assert w.actions["save"].shortcut() == QKeySequence(QKeySequence.StandardKey.Save)
    assert w.actions["delete"].shortcut() == QKeySequence(QKeySequence.StandardKey.Delete)
    assert w.actions["zoom_fit"].shortcut().toString() == "F"
    toolbar_texts = [a.text() for a in w.findChildren(type(w.addToolBar("probe")))[0].actions()]
    assert "&Open…" in toolbar_texts and "&Undo" in " ".join(toolbar_texts)


def test_undo_and_redo_through_the_actions_and_the_title_star(shell):
    parts = shell()
    c, w = parts.controller, parts.window
    before = c.scene
    c.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    assert c.is_dirty and w.windowTitle().startswith("fourbar_crank_rocker (example) * ")
    w.actions["undo"].trigger()
    assert c.scene == before and not c.is_dirty
    assert "*" not in w.windowTitle()
    w.actions["redo"].trigger()
    assert c.scene.element("fourbar").joint("B").at == (21.0, 35.0)


def test_delete_a_joint_is_one_undo_step_and_a_broken_linkage_is_a_message(shell):
    parts = shell()
    c, w = parts.controller, parts.window
    before = c.scene
    c.set_selection([("fourbar", "joint", "E")])
    assert w.actions["delete"].isEnabled()
    w.actions["delete"].trigger()
    assert "E" not in c.scene.element("fourbar").joint_ids
    assert c.selection == []
    w.actions["undo"].trigger()
    assert c.scene == before
    c.set_selection([("fourbar", "joint", "C")])          # leaves coupler and rocker dangling
    w.actions["delete"].trigger()
    assert c.result("fourbar").error                       # not solvable: a message, no crash
    assert "cannot solve" in w.diagnostics.plain_text()


def test_zoom_to_fit_reaches_the_canvas(shell):
    parts = shell()
    canvas = parts.window.canvas
    calls = []
    canvas.zoom_to_fit = lambda: calls.append(1)
    parts.window.actions["zoom_fit"].trigger()
    assert calls == [1]


def test_status_bar_shows_messages_and_the_solve(shell):
    parts = shell()
    parts.controller.message.emit("hello")
    assert parts.window.statusBar().currentMessage() == "hello"
    assert "fourbar: 360 poses" in parts.window.solve_label.text()
    parts.controller.set_frame(90)
    assert "frame 91/360" in parts.window.frame_label.text()


def test_close_with_unsaved_changes_asks_and_cancel_keeps_the_window(shell, tmp_path):
    parts = shell()
    c = parts.controller
    c.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    parts.dialogs.save_changes.append("cancel")
    assert parts.window.close() is False
    assert parts.window.isVisible() and c.is_dirty
    target = tmp_path / "kept.json"
    parts.dialogs.save_changes.append(SAVE)
    parts.dialogs.save_names.append(str(target))
    assert parts.window.close() is True
    assert load_scene(target) == c.scene
    assert not parts.autosave.timer.isActive()


def test_the_error_hook_reports_autosaves_and_keeps_running(shell, tmp_path):
    parts = shell(state_dir=tmp_path / "state")
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    previous = app_module.install_excepthook(parts)
    try:
        try:
            raise RuntimeError("boom")
        except RuntimeError:
            sys.excepthook(*sys.exc_info())
    finally:
        sys.excepthook = previous
    title, text, details = parts.dialogs.errors[-1]
    assert title == "Unexpected error" and "RuntimeError: boom" in text and "autosaved" in text
    assert "Traceback" in details
    assert parts.autosave.recovery_file.is_file()
    assert parts.window.isVisible() and parts.controller.is_dirty


def test_no_display_is_a_message_not_a_qt_abort(monkeypatch, capsys):
    if not sys.platform.startswith("linux"):
        pytest.skip("display detection is for X11/Wayland platforms")
    for var in ("QT_QPA_PLATFORM", "DISPLAY", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(var, raising=False)
    assert app_module.run_app(None) == 1
    assert "no display found" in capsys.readouterr().err


def test_about_box(shell):
    parts = shell()
    parts.window.actions["about"].trigger()
    assert parts.dialogs.infos and "mechsketch" in parts.dialogs.infos[0][1]


def test_dock_toggles_are_in_the_view_menu(shell):
    w = shell().window
    view = next(a.menu() for a in w.menuBar().actions() if a.text() == "&View")
    texts = [a.text() for a in view.actions()]
    assert {"Properties", "Diagnostics", "Plots"} <= set(texts)
    w.docks["plots"].toggleViewAction().trigger()
    assert not w.docks["plots"].isVisible()
    assert w.docks["plots"].widget() is w.plots
    assert Qt.DockWidgetArea.RightDockWidgetArea == w.dockWidgetArea(w.docks["plots"])


def test_discard_on_close(shell):
    parts = shell()
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move joint B")
    parts.dialogs.save_changes.append(DISCARD)
    assert parts.window.close() is True
    assert not parts.autosave.recovery_file.exists()


def test_fake_dialogs_default_to_cancel():
    d = FakeDialogs()
    assert d.ask_save_changes("x") == "cancel" and d.open_file_name("t") is None


def test_qt_bindings_keep_none_alive(qtbot):
    """Regression: PySide6 6.12.0 on Python 3.11 dropped a reference to None on every void call,
    and the app died with 'deallocating None' after a few minutes of use (pinned out in pyproject)."""
    from PySide6.QtWidgets import QLabel

    label = QLabel()
    qtbot.addWidget(label)
    before = sys.getrefcount(None)
    for _ in range(2000):
        label.setText("x")
    assert abs(sys.getrefcount(None) - before) < 100


def test_window_layout_is_remembered(shell):
    first = shell()
    first.window.docks["diagnostics"].hide()
    first.dialogs.save_changes.append(DISCARD)
    assert first.window.close()
    second = shell()
    assert not second.window.docks["diagnostics"].isVisible()
    assert second.window.docks["plots"].isVisible()
    assert second.window.layout_restored and not first.window.layout_restored
