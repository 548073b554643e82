"""A heavy request never freezes the window (issue 20, the GUI monkey's hang): a rolling lever's
points set to 100,000 (over a minute of synthesis) is solved off the GUI thread with a busy
indicator and Cancel in the status bar; the edit lands when it is solved, with a result equal bit
for bit to the one solved in place, and nothing changes when it is cancelled or the document
changed meanwhile. The worker's jobs are held by a fake and run when the test says (no waits),
except in the one test of the real thread."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from mechsketch.core import ReplaceElement
from mechsketch.core.workspace.results import solve_element

from app_fakes import shell  # noqa: F401 - fixture
from app_fakes import open_example, type_into


class HeldJobs:
    """A ``spawn`` that keeps the jobs until :meth:`run` (in the test's thread)."""

    def __init__(self) -> None:
        self.works: list = []

    def __call__(self, work) -> None:
        self.works.append(work)

    def run(self) -> None:
        works, self.works = self.works, []
        for work in works:
            work()


@pytest.fixture
def rolling(shell, monkeypatch):
    parts, c, view = open_example(shell, "rolling_lever_press")
    held = HeldJobs()
    c.background.spawn = held
    el = c.scene.elements[0]
    c.set_selection([(el.id, "element", el.id)])
    return parts, c, held, el


def test_typing_100000_points_returns_at_once_and_lands_when_solved(rolling, qtbot, monkeypatch):
    parts, c, held, el = rolling
    assert c.is_heavy(replace(el, points=100_000))     # the monkey's hang: ~75 s
    assert not c.is_heavy(el)                           # the example (200 points): solved in place
    assert not c.is_heavy(replace(el, points=250))
    solves = c.workspace.stats["solve:rolling_lever"]
    undo = c.undo_stack.count()
    field = parts.window.properties.fields["points"]
    type_into(qtbot, field, "100000")
    # nothing was solved on the GUI thread and nothing changed yet; the status bar says what runs
    assert c.workspace.stats["solve:rolling_lever"] == solves
    assert c.scene.element(el.id).points == el.points and c.undo_stack.count() == undo
    busy = parts.window.busy
    assert busy.isVisible() and "points" in busy.label.text() and "about 100 s" in busy.label.text()
    assert len(held.works) == 1
    # a smaller value is quick to run here: the same path (the threshold set to 0)
    monkeypatch.setattr("mechsketch.gui.controller.HEAVY_SECONDS", 0.0)
    type_into(qtbot, field, "300")
    assert c.scene.element(el.id).points == el.points and busy.isVisible()
    held.run()   # the 100,000-point job was cancelled by the newer request: skipped, not solved
    assert not busy.isVisible()
    assert c.scene.element(el.id).points == 300 and c.undo_stack.count() == undo + 1
    assert c.workspace.stats["solve:rolling_lever"] == solves     # solved on the worker only
    # the result shown is the one solved in place, bit for bit
    got = c.element_result(el.id)
    ref = solve_element(replace(el, points=300))
    for name in ("theta", "P0", "P1"):
        a, b = getattr(got.frames, name, None), getattr(ref.frames, name, None)
        if a is not None:
            assert np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True), name
    assert np.array_equal(got.synthesis.P, ref.synthesis.P)
    c.undo_stack.undo()
    assert c.scene.element(el.id).points == el.points


def test_cancel_changes_nothing(rolling, qtbot, monkeypatch):
    parts, c, held, el = rolling
    monkeypatch.setattr("mechsketch.gui.controller.HEAVY_SECONDS", 0.0)
    undo = c.undo_stack.count()
    type_into(qtbot, parts.window.properties.fields["points"], "300")
    busy = parts.window.busy
    assert busy.isVisible()
    busy.cancel.click()
    assert not busy.isVisible()
    held.run()
    assert c.scene.element(el.id).points == el.points and c.undo_stack.count() == undo
    assert "cancelled" in parts.window.statusBar().currentMessage()


def test_a_document_changed_meanwhile_is_not_overwritten(rolling, qtbot, monkeypatch):
    parts, c, held, el = rolling
    monkeypatch.setattr("mechsketch.gui.controller.HEAVY_SECONDS", 0.0)
    type_into(qtbot, parts.window.properties.fields["points"], "300")
    # another edit lands first (the user kept working): the pin holes' diameter, quick to solve
    monkeypatch.setattr("mechsketch.gui.controller.HEAVY_SECONDS", 1e9)
    c.push(ReplaceElement(replace(el, pin_diameter=el.pin_diameter + 1.0)), "pin")
    messages = []
    c.message.connect(messages.append)
    held.run()
    now = c.scene.element(el.id)
    assert now.points == el.points and now.pin_diameter == el.pin_diameter + 1.0
    assert any("not applied" in m for m in messages)
    # the result is kept: back on that document, asking again applies at once, with no job
    c.undo_stack.undo()
    type_into(qtbot, parts.window.properties.fields["points"], "300")
    assert not held.works and c.scene.element(el.id).points == 300


def test_the_real_worker_thread_delivers(rolling, qtbot, monkeypatch):
    parts, c, held, el = rolling
    from mechsketch.gui.background import start_thread

    c.background.spawn = start_thread
    monkeypatch.setattr("mechsketch.gui.controller.HEAVY_SECONDS", 0.0)
    type_into(qtbot, parts.window.properties.fields["points"], "240")
    with qtbot.waitSignal(c.changed, timeout=120_000):
        pass
    assert c.scene.element(el.id).points == 240
    assert not parts.window.busy.isVisible()
