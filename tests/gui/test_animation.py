"""The animation player and the scrub bar: precomputed arrays only, limits and dead points."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt

from app_fakes import FakeClock
from canvas_user import example, make_view
from mechsketch.core.solver import plan as plan_mod
from mechsketch.gui.animation import AnimationPlayer
from mechsketch.gui.controller import SceneController
from mechsketch.gui.scrubbar import ScrubBar


@pytest.fixture
def no_solving(monkeypatch):
    """Make any solve fail loudly (switched on after the set-up has solved)."""
    def on():
        def boom(*a, **k):
            raise AssertionError("the animation solved something")
        monkeypatch.setattr(plan_mod.Plan, "evaluate", boom)
        monkeypatch.setattr(plan_mod.Plan, "sweep", boom)
        monkeypatch.setattr(plan_mod, "compile_plan", boom)
    return on


def test_playing_a_few_frames_moves_the_canvas_without_solving(qtbot, no_solving):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    player = AnimationPlayer(ctl)
    no_solving()
    frames = []
    ctl.frameChanged.connect(frames.append)
    clock = FakeClock()
    player.clock = clock
    player.play()
    assert player.is_playing and player.play_action.isChecked()
    for _ in range(3):
        clock.advance(0.016)   # a tick of the timer: 0.016 s of a 0.628 s cycle is 9 samples
        player.tick()
    player.pause()
    assert len(frames) == 3 and frames == [9, 18, 27]
    assert not player.is_playing and not player.play_action.isChecked()
    assert ctl.frame > 0 and frames == sorted(frames)
    sol = ctl.result("fourbar").solution
    pose = view._items["fourbar"].linkage.pose
    assert pose.index == ctl.frame and np.allclose(pose.at["E"], sol.position("E")[ctl.frame])


def test_the_player_moves_by_its_clock_not_by_wall_time(qtbot):
    """A tick advances by the time the player's clock says has passed (at most 0.25 s), so a
    test drives it without waiting and a stalled event loop never makes it jump."""
    ctl = SceneController(example("fourbar_crank_rocker"))   # 360 samples in 0.6283 s
    player = AnimationPlayer(ctl)
    clock = FakeClock()
    player.clock = clock
    player.play()
    player.tick()
    assert ctl.frame == 0                                     # no time has passed on its clock
    clock.advance(0.1)
    player.tick()
    assert ctl.frame == int(360 * 0.1 / player.period())      # 57
    clock.advance(30.0)                                       # the event loop stalled for 30 s
    player.tick()
    assert ctl.frame == (57 + int(360 * 0.25 / player.period() + 0.2)) % 360   # 0.25 s at most
    player.pause()
    clock.advance(1.0)
    player.tick()                                             # paused: a late tick does nothing
    assert ctl.frame == (57 + int(360 * 0.25 / player.period() + 0.2)) % 360


def test_speed_and_direction_follow_the_drivers_rpm(qtbot):
    ctl = SceneController(example("fourbar_crank_rocker"))   # 360 samples, 95.49 rpm: T = 0.6283 s
    player = AnimationPlayer(ctl)
    assert player.period() == pytest.approx(2 * math.pi / 10)
    player.advance(0.1)
    assert ctl.frame == int(360 * 0.1 / player.period())       # 57 samples in 0.1 s
    player.set_speed(0.5)
    player.advance(0.1)
    assert ctl.frame == 57 + 28
    player.set_direction(-1)
    assert player.direction_action.isChecked()
    player.set_speed(2.0)
    start = ctl.frame
    player.advance(0.2)
    moved = (start - ctl.frame) % 360                            # backwards, twice as fast
    assert abs(moved - 2.0 * 360 * 0.2 / player.period()) <= 1.0
    with pytest.raises(ValueError):
        player.set_speed(0)
    with pytest.raises(ValueError):
        player.set_dead_point_behaviour("jump")


def test_stop_at_the_limit_of_a_double_rocker_then_play_turns_back(qtbot, no_solving):
    ctl = SceneController(example("double_rocker"))
    player = AnimationPlayer(ctl)
    valid = ctl.result("double_rocker").solution.valid
    assert not valid.all()
    no_solving()
    player.set_dead_point_behaviour("stop")
    stops = []
    player.stopped.connect(stops.append)
    player.play()
    player.advance(60.0)                      # far more than one cycle
    assert not player.is_playing and stops and "limit" in stops[0]
    f = ctl.frame
    assert valid[f] and not valid[(f + 1) % len(valid)]     # the last sample before the gap
    player.play()                             # from a limit it turns away from the gap
    assert player.direction == -1
    player.advance(0.2)
    player.pause()
    assert ctl.frame != f and valid[ctl.frame]


def test_reverse_at_limits_walks_only_valid_samples_and_never_crosses_the_gap(qtbot, no_solving):
    ctl = SceneController(example("double_rocker"))
    player = AnimationPlayer(ctl)
    valid = ctl.result("double_rocker").solution.valid
    n = len(valid)
    no_solving()
    player.set_dead_point_behaviour("reverse")
    seen = [ctl.frame]
    flips = 0
    for _ in range(400):
        d = player.direction
        seen.append(player.step(7))
        flips += player.direction != d
    assert flips >= 2
    assert all(valid[k] for k in seen)
    jumps = np.abs(np.diff(seen))
    assert (np.minimum(jumps, n - jumps) <= 7).all()
    gap = np.flatnonzero(~valid)
    assert not np.intersect1d(seen, gap).size


def test_dead_points_inside_the_range_stop_or_reverse(qtbot):
    ctl = SceneController(example("fourbar_crank_rocker"))
    player = AnimationPlayer(ctl)
    n = ctl.sample_count()
    player._masks = (np.ones(n, dtype=bool), {100})    # a toggle at sample 100
    ctl.set_frame(90)
    player.set_dead_point_behaviour("stop")
    assert player.step(20) == 100                       # stops on the dead point
    assert player.step(5) == 105                        # the next play passes through it
    player.set_dead_point_behaviour("reverse")
    ctl.set_frame(95)
    assert player.step(10) == 95 and player.direction == -1


def test_space_on_the_canvas_plays_and_pauses(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    player = AnimationPlayer(ctl)
    view.set_tap_action(player.play_action)
    view.setFocus()
    qtbot.keyClick(view, Qt.Key.Key_Space)
    assert player.is_playing
    qtbot.keyClick(view, Qt.Key.Key_Space)
    assert not player.is_playing


def test_nothing_to_play_is_a_message(qtbot):
    ctl = SceneController()
    player = AnimationPlayer(ctl)
    msgs = []
    ctl.message.connect(msgs.append)
    player.play()
    assert not player.is_playing and "nothing to animate" in msgs[-1]
    assert player.step(3) == 0


def scrub(qtbot, name: str):
    ctl = SceneController(example(name))
    player = AnimationPlayer(ctl)
    bar = ScrubBar(ctl, player)
    qtbot.addWidget(bar)
    bar.resize(900, 40)
    bar.show()
    qtbot.waitExposed(bar)
    return ctl, player, bar


def test_scrub_bar_click_and_drag(qtbot):
    ctl, player, bar = scrub(qtbot, "fourbar_crank_rocker")
    track = bar.track
    x = round(track.x_of(180, 360))
    qtbot.mouseClick(track, Qt.MouseButton.LeftButton, pos=QPoint(x, 15))
    assert abs(ctl.frame - 180) <= 1
    assert "input" in bar.readout.text() and f"{ctl.frame + 1}/360" in bar.readout.text()
    bar.speed_box.setCurrentIndex(bar.speed_box.findData(2.0))
    assert player.speed == 2.0
    bar.dead_box.setCurrentIndex(0)
    assert player.dead_point_behaviour == "stop"
    bar.grab()


def test_scrub_bar_marks_and_respects_the_infeasible_range(qtbot):
    ctl, player, bar = scrub(qtbot, "double_rocker")
    track = bar.track
    valid = ctl.result("double_rocker").solution.valid
    n = len(valid)
    n_, mask, dead = track._data()
    assert n_ == n and (mask == valid).all() and len(dead) == 2
    bad = np.flatnonzero(~valid)
    mid = int(bad[len(bad) // 2])
    # a click in the red range goes to the nearest valid sample
    qtbot.mouseClick(track, Qt.MouseButton.LeftButton, pos=QPoint(round(track.x_of(mid, n)), 15))
    assert valid[ctl.frame]
    # dragging from the start across the red range stops at its edge
    qtbot.mousePress(track, Qt.MouseButton.LeftButton, pos=QPoint(round(track.x_of(0, n)), 15))
    for k in np.linspace(0, n - 1, 30):
        qtbot.mouseMove(track, QPoint(round(track.x_of(int(k), n)), 15))
    qtbot.mouseRelease(track, Qt.MouseButton.LeftButton, pos=QPoint(round(track.x_of(n - 1, n)), 15))
    assert ctl.frame == bad[0] - 1
    img = bar.track.grab().toImage()
    red = img.pixelColor(round(track.x_of(mid, n)), 15)
    assert red.red() > 150 and red.green() < 150     # the infeasible range is painted red
