"""Issue 13 item 3: a timer tick's cost does not depend on the driver's speed, and the walk through
valid samples (limits, dead points, stop or reverse) is the same as one sample at a time."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from canvas_user import example
from mechsketch.gui.animation import AnimationPlayer
from mechsketch.gui.controller import SceneController


class CountingMask(np.ndarray):
    """A boolean mask that counts the samples read from it one at a time."""

    reads = 0

    def __getitem__(self, key):
        if isinstance(key, (int, np.integer)):
            CountingMask.reads += 1
        return super().__getitem__(key)


def _player_with(monkeypatch, valid, barriers=frozenset()):
    ctl = SceneController(example("fourbar_crank_rocker"))
    player = AnimationPlayer(ctl)
    mask = np.asarray(valid, dtype=bool).view(CountingMask)
    monkeypatch.setattr(player, "masks", lambda: (mask, set(barriers)))
    monkeypatch.setattr(ctl, "sample_count", lambda: len(valid))
    CountingMask.reads = 0
    return ctl, player


@pytest.mark.parametrize("behaviour", ["stop", "reverse"])
def test_a_step_of_a_million_samples_reads_a_few_samples(qtbot, monkeypatch, behaviour):
    n = 1000
    valid = np.ones(n, bool)
    valid[700:760] = False                             # a double rocker's gap
    ctl, player = _player_with(monkeypatch, valid, {300})
    player.set_dead_point_behaviour(behaviour)
    player.step(1_000_003)
    assert CountingMask.reads < 200
    player.step(10 ** 18)                              # 1e9 rpm for hours: still a few jumps
    assert CountingMask.reads < 400
    assert valid[ctl.frame]


def test_one_tick_at_the_highest_speed_reads_a_few_samples(qtbot, monkeypatch):
    ctl, player = _player_with(monkeypatch, np.ones(1_000_000, bool))
    monkeypatch.setattr(player, "period", lambda: 60.0 / 1e5)    # 1e5 rpm, 1e6 samples
    player.advance(0.25)                                          # the longest tick
    assert CountingMask.reads < 50
    # 0.25 s at 1e5 rpm over 1e6 samples is 4.1667e8 samples: a whole number of cycles + rest
    assert ctl.frame == int(1e5 / 60.0 * 0.25 * 1e6) % 1_000_000


def _reference(valid, barriers, f, d, count, behaviour):
    """The walk one sample at a time (the player's former loop): (frame, direction, stopped)."""
    n = len(valid)
    start = f
    for _ in range(count):
        nxt = (f + d) % n
        if not valid[nxt]:
            if behaviour == "stop":
                return f, d, "limit"
            d = -d
            nxt = (f + d) % n
            if not valid[nxt]:
                return f, d, "limit"
        f = nxt
        if f in barriers and f != start:
            if behaviour == "stop":
                return f, d, "dead point"
            d = -d
    return f, d, None


@st.composite
def walks(draw):
    n = draw(st.integers(2, 40))
    valid = draw(st.lists(st.booleans(), min_size=n, max_size=n).map(np.array))
    start = draw(st.integers(0, n - 1))
    valid[start] = True
    barriers = set(draw(st.lists(st.integers(0, n - 1), max_size=4)))
    return (valid, barriers, start, draw(st.sampled_from([1, -1])), draw(st.integers(0, 300)),
            draw(st.sampled_from(["stop", "reverse"])))


@settings(max_examples=400, deadline=None, derandomize=True)
@given(walks())
def test_the_walk_equals_one_sample_at_a_time(case):
    from mechsketch.gui.animation import walk

    valid, barriers, start, d, count, behaviour = case
    got = walk(valid, sorted(barriers), start, d, count, behaviour)
    assert (got.frame, got.direction, got.stopped) == _reference(valid, barriers, start, d, count, behaviour)


def test_driver_speeds_have_limits_with_a_message(qtbot):
    from mechsketch.core import EditError, ReplaceElement
    from dataclasses import replace

    ctl = SceneController(example("fourbar_crank_rocker"))
    lk = ctl.scene.element("fourbar")
    messages = []
    ctl.message.connect(messages.append)
    for rpm in (1e6, 1e9, -1e300, 5e-324):
        edit = ReplaceElement(lk.with_driver(replace(lk.driver, speed_rpm=rpm)))
        assert not ctl.push(edit, "set driver speed")
        assert "speed_rpm" in messages[-1] and ("100000" in messages[-1] or "0.001" in messages[-1])
        with pytest.raises(EditError):
            ctl.workspace.apply(edit)
    assert ctl.scene.element("fourbar") == lk and ctl.undo_stack.count() == 0


@pytest.mark.parametrize("behaviour", ["stop", "reverse"])
@pytest.mark.parametrize("count", [10, 10 ** 6, 10 ** 18])
def test_the_walks_cost_is_a_few_jumps_whatever_the_count(behaviour, count):
    from mechsketch.gui.animation import walk

    n = 100_000
    valid = np.ones(n, bool)
    valid[70_000:76_000] = False
    for bars in ([], [30_000], [10_000, 50_000, 90_000]):
        got = walk(valid, bars, 5, 1, count, behaviour)
        assert got.jumps <= 8 and valid[got.frame]
    ring = walk(np.ones(n, bool), [], 5, -1, count, behaviour)
    assert ring.jumps <= 1 and ring.frame == (5 - count) % n
