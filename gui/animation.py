"""The animation player: walks the controller's frame through the precomputed solution arrays.

It never solves. Each timer tick advances the frame by speed x (samples per cycle) x elapsed /
(cycle period), through *valid* samples only: at the edge of a reachable range (the linkage
cannot be assembled beyond it) or at a dead point it stops or reverses (a setting), and it never
crosses an infeasible gap, so it cannot jump to the other assembly branch.

Embedding (the shell does this once)::

    player = AnimationPlayer(controller)
    toolbar.addAction(player.play_action)            # Space; checkable Play/Pause
    anim_menu.addActions([player.play_action, player.direction_action,
                          player.step_forward_action, player.step_back_action])
    anim_menu.addSeparator(); anim_menu.addActions(player.dead_point_actions.actions())
    player.stopped.connect(status_bar.showMessage)   # why it stopped by itself
    view.dragStarted.connect(player.pause)
    # quit: player.pause() (stops the timer)

Signals: ``playingChanged(bool)``, ``stopped(str)`` (stopped by itself at a limit or dead
point), ``settingsChanged()`` (speed, direction or dead-point behaviour).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
from PySide6.QtCore import QObject, Qt, QTimer, Signal
from PySide6.QtGui import QAction, QActionGroup, QKeySequence

from .frames import dead_samples, input_value_text, map_frame, nearest_valid

TICK_MS = 16
SPEEDS = (0.1, 0.25, 0.5, 1.0, 2.0, 4.0)
DEAD_POINT_BEHAVIOURS = ("stop", "reverse")


@dataclass(frozen=True)
class Walk:
    """Where :func:`walk` ended: the frame, the direction then, and why it stopped by itself
    ("limit", "dead point") or None; ``jumps`` counts the stretches walked (the cost)."""

    frame: int
    direction: int
    stopped: str | None
    jumps: int


def _steps_to_next(sorted_idx: np.ndarray, f: int, d: int, n: int) -> int | None:
    """Steps (1..n) from ``f`` in direction ``d`` round a cycle of ``n`` samples to the nearest
    index of ``sorted_idx`` (``f`` itself counts only after a whole turn); None if it is empty."""
    m = len(sorted_idx)
    if m == 0:
        return None
    if d > 0:
        j = int(sorted_idx[int(np.searchsorted(sorted_idx, f, side="right")) % m])
        return (j - f) % n or n
    j = int(sorted_idx[int(np.searchsorted(sorted_idx, f, side="left")) - 1])
    return (f - j) % n or n


def walk(valid: np.ndarray, barriers: Sequence[int], start: int, direction: int, count: int,
         behaviour: str = "reverse", own: bool = True) -> Walk:
    """Walk ``count`` samples from the valid sample ``start`` through the valid ones of ``valid``
    ``(N,)``, round the cycle, as the player does one sample at a time: at the edge of a gap (a
    limit) and on a dead point of ``barriers`` (other than ``start``) it reverses or stops
    (``behaviour``). ``own`` False (a step the user asked for in a given direction) stops at a
    limit without a message and ignores dead points.

    The cost does not depend on ``count``: each stretch between two events is one jump (found by
    bisection), and once the walk bounces between the same events the rest is taken modulo the
    bounce period.
    """
    valid = np.asarray(valid, dtype=bool)
    n = len(valid)
    f, d, remaining = int(start) % n, (1 if direction >= 0 else -1), max(int(count), 0)
    walls = np.flatnonzero(~valid)
    bars = np.array(sorted({int(b) % n for b in barriers} - {f}) if own else [], dtype=np.int64)
    bar_set = set(bars.tolist())
    seen: dict[tuple[int, int], int] = {}
    jumps = 0
    while remaining > 0:
        jumps += 1
        to_wall = _steps_to_next(walls, f, d, n)
        free = None if to_wall is None else to_wall - 1       # steps before the gap
        to_bar = _steps_to_next(bars, f, d, n)
        if to_bar is not None and (free is None or to_bar <= free):
            if remaining < to_bar:
                break
            f, remaining = (f + d * to_bar) % n, remaining - to_bar
            if behaviour == "stop":
                return Walk(f, d, "dead point", jumps)
            d = -d
        elif free is not None and remaining > free:
            f, remaining = (f + d * free) % n, remaining - free
            if not own or behaviour == "stop":
                return Walk(f, d, "limit" if own else None, jumps)
            d = -d
            if not valid[(f + d) % n]:
                return Walk(f, d, "limit", jumps)
            f, remaining = (f + d) % n, remaining - 1
            if f in bar_set:
                if behaviour == "stop":
                    return Walk(f, d, "dead point", jumps)
                d = -d
        else:
            break
        key = (f, d)
        if key in seen:                     # bouncing between the same events: skip whole periods
            remaining %= seen[key] - remaining
            seen.clear()
        else:
            seen[key] = remaining
    return Walk((f + d * remaining) % n, d, None, jumps)


class AnimationPlayer(QObject):
    """Play/pause, speed, direction and dead-point behaviour over ``controller.frame``.

    ``speed`` is a multiple of real time (1.0: the driver turns at its ``speed_rpm``);
    ``direction`` +1 follows the driver's turning sense, -1 runs backwards;
    ``dead_point_behaviour`` is "stop" or "reverse".
    """

    playingChanged = Signal(bool)
    stopped = Signal(str)
    settingsChanged = Signal()

    def __init__(self, controller, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self._timer = QTimer(self)
        self._timer.setObjectName("AnimationPlayer.timer")
        self._timer.setTimerType(Qt.TimerType.PreciseTimer)
        self._timer.setInterval(TICK_MS)
        self._timer.timeout.connect(self.tick)
        #: seconds, monotonic: what a tick measures the elapsed time with (tests give their own)
        self.clock: Callable[[], float] = time.perf_counter
        self._speed = 1.0
        self._direction = 1
        self._dead = "reverse"
        self._acc = 0.0
        self._last = 0.0
        self._masks: tuple | None = None
        self._make_actions()
        controller.changed.connect(self._invalidate)

    def _make_actions(self) -> None:
        self.play_action = QAction("Play", self)
        self.play_action.setCheckable(True)
        self.play_action.setShortcut(QKeySequence(Qt.Key.Key_Space))
        self.play_action.setStatusTip("play or pause the animation (Space)")
        self.play_action.toggled.connect(self._play_toggled)
        self.direction_action = QAction("Reverse Direction", self)
        self.direction_action.setCheckable(True)
        self.direction_action.setShortcut(QKeySequence("Shift+R"))
        self.direction_action.setStatusTip("run the animation against the driver's turning sense")
        self.direction_action.toggled.connect(lambda on: self.set_direction(-1 if on else 1))
        self.step_forward_action = QAction("Step Forward", self)
        self.step_forward_action.setShortcut(QKeySequence("."))
        self.step_forward_action.triggered.connect(lambda: self.step(1, self._direction))
        self.step_back_action = QAction("Step Back", self)
        self.step_back_action.setShortcut(QKeySequence(","))
        self.step_back_action.triggered.connect(lambda: self.step(1, -self._direction))
        self.dead_point_actions = QActionGroup(self)
        self.dead_point_actions.setExclusive(True)
        self._dead_actions: dict[str, QAction] = {}
        for name, text in (("stop", "Stop at Dead Points"), ("reverse", "Reverse at Dead Points")):
            act = QAction(text, self.dead_point_actions)
            act.setCheckable(True)
            act.triggered.connect(lambda _c=False, n=name: self.set_dead_point_behaviour(n))
            self._dead_actions[name] = act
        self._dead_actions[self._dead].setChecked(True)

    # -- settings ---------------------------------------------------------------------------------
    @property
    def speed(self) -> float:
        return self._speed

    def set_speed(self, speed: float) -> None:
        """Multiple of real time, > 0."""
        if not (speed > 0 and math.isfinite(speed)):
            raise ValueError(f"animation speed must be a positive number, got {speed}")
        if speed != self._speed:
            self._speed = float(speed)
            self.settingsChanged.emit()

    @property
    def direction(self) -> int:
        return self._direction

    def set_direction(self, direction: int) -> None:
        """+1: the driver's turning sense; -1: backwards."""
        d = 1 if direction >= 0 else -1
        if d != self._direction:
            self._direction = d
            self.direction_action.setChecked(d < 0)
            self.settingsChanged.emit()

    @property
    def dead_point_behaviour(self) -> str:
        return self._dead

    def set_dead_point_behaviour(self, behaviour: str) -> None:
        """"stop" or "reverse" at a dead point or the edge of a reachable range."""
        if behaviour not in DEAD_POINT_BEHAVIOURS:
            raise ValueError(f"dead-point behaviour must be one of {DEAD_POINT_BEHAVIOURS}, got {behaviour!r}")
        self._dead_actions[behaviour].setChecked(True)
        if behaviour != self._dead:
            self._dead = behaviour
            self.settingsChanged.emit()

    # -- play / pause -----------------------------------------------------------------------------
    @property
    def is_playing(self) -> bool:
        return self._timer.isActive()

    def play(self) -> None:
        """Start the timer (from a limit, turn away from the gap first)."""
        if self.is_playing:
            return
        valid, _ = self.masks()
        if valid is None or not valid.any():
            self.controller.message.emit("nothing to animate: no linkage solves yet")
            self.play_action.setChecked(False)
            return
        f = self.controller.frame % len(valid)
        near = nearest_valid(valid, f)
        if near != f:
            self.controller.set_frame(near)
            f = near
        n = len(valid)
        if not valid[(f + self._direction) % n] and valid[(f - self._direction) % n]:
            self.set_direction(-self._direction)
        self._acc = 0.0
        self._last = self.clock()
        self._timer.start()
        self.play_action.setChecked(True)
        self.play_action.setText("Pause")
        self.playingChanged.emit(True)

    def pause(self) -> None:
        """Stop the timer (the frame stays where it is)."""
        was = self._timer.isActive()
        self._timer.stop()
        self.play_action.setChecked(False)
        self.play_action.setText("Play")
        if was:
            self.playingChanged.emit(False)

    def toggle(self) -> None:
        self.pause() if self.is_playing else self.play()

    def _play_toggled(self, on: bool) -> None:
        if on and not self.is_playing:
            self.play()
        elif not on and self.is_playing:
            self.pause()

    # -- reading the precomputed arrays -----------------------------------------------------------
    def _invalidate(self, *_args) -> None:
        self._masks = None
        if self.is_playing:
            valid, _ = self.masks()
            if valid is None or not valid.any():
                self.pause()

    def masks(self) -> tuple[np.ndarray | None, set[int]]:
        """(valid (N,), dead-point samples) over the global frames: the AND of every solved
        linkage's mask, and the samples of their toggles (None if nothing solves). Cached per solve."""
        if self._masks is not None:
            return self._masks
        ctl = self.controller
        n = ctl.sample_count()
        if n == 0:
            return None, set()
        valid = np.ones(n, dtype=bool)
        barriers: set[int] = set()
        for lk in ctl.linkages():
            res = ctl.result(lk.id)
            if res is None or res.solution is None:
                continue
            sol = res.solution
            m = len(sol)
            own = np.asarray(sol.valid, dtype=bool)
            valid &= own if m == n else own[[map_frame(int(k), n, m) for k in range(n)]]
            diag = ctl.diagnostics(lk.id)   # none during a drag preview: no barriers until the release
            toggles = [d.input for d in (diag.dead_points if diag else []) if d.kind == "toggle"]
            for k in dead_samples(sol, own, toggles):
                barriers.add(k if m == n else int(round(k * n / m)) % n)
        self._masks = (valid, barriers)
        return self._masks

    def period(self) -> float:
        """Seconds per animation cycle at 1x (the controller's cycle period)."""
        return self.controller.cycle_period()

    # -- stepping ---------------------------------------------------------------------------------
    def tick(self) -> None:
        """What the timer does every ``TICK_MS``: advance by the time :attr:`clock` says has
        passed since the last tick (at most 0.25 s: a stalled event loop does not jump)."""
        if not self.is_playing:
            return
        now = self.clock()
        dt, self._last = now - self._last, now
        self.advance(min(max(dt, 0.0), 0.25))

    def advance(self, seconds: float) -> None:
        """Move by ``seconds`` of animation time at the current speed (what a tick does)."""
        n = self.controller.sample_count()
        if n == 0:
            return
        self._acc += self._speed * n * seconds / self.period()
        whole = int(self._acc)
        self._acc -= whole
        if whole:
            self.step(whole)

    def seek(self, index: int) -> int:
        """Show sample ``index`` (the nearest valid one); returns the frame shown."""
        valid, _ = self.masks()
        if valid is None:
            return self.controller.frame
        k = nearest_valid(valid, int(index))
        if k is not None:
            self.controller.set_frame(k)
        return self.controller.frame

    def step(self, count: int = 1, direction: int | None = None) -> int:
        """Advance ``count`` valid samples (in ``direction``, default the player's), stopping or
        reversing at limits and dead points; returns the frame reached."""
        valid, barriers = self.masks()
        ctl = self.controller
        if valid is None:
            return ctl.frame
        n = len(valid)
        f = nearest_valid(valid, ctl.frame)
        if f is None:
            self.pause()
            return ctl.frame
        own = direction is None
        d = self._direction if own else (1 if direction >= 0 else -1)
        res = walk(valid, sorted(barriers), f, d, count, self._dead, own)
        if own and res.direction != self._direction:
            self.set_direction(res.direction)
        if res.stopped is not None:
            self._stop(res.frame, res.stopped)
        ctl.set_frame(res.frame)
        return res.frame

    def _stop(self, f: int, what: str) -> None:
        self.pause()
        shown = self._input_text(f)
        where = f" at input {shown}" if shown is not None else ""
        beyond = " (the linkage cannot be assembled beyond it)" if what == "limit" else ""
        msg = f"animation stopped at the {what}{where}{beyond}"
        self.stopped.emit(msg)
        self.controller.message.emit(msg)

    def _input_text(self, f: int) -> str | None:
        """The first solved linkage's input at frame ``f`` (degrees, or mm for an actuator)."""
        for lk in self.controller.linkages():
            res = self.controller.result(lk.id)
            if res is not None and res.solution is not None:
                sol = res.solution
                return input_value_text(sol, map_frame(f, self.controller.sample_count(), len(sol)))
        return None
