"""Panels that redraw from the controller only when someone can see them, and at most a few
times a second during a live drag (a drag preview moves many times a frame's worth).

A panel's redraw during a drag also takes at most about 1/:data:`PREVIEW_SHARE` of the drag's
time: the next redraw waits at least ``PREVIEW_SHARE`` times as long as the last one took (wall
clock), so on a slow or busy machine, where a redraw takes longer, the panels redraw less often
and the canvas keeps up with the mouse (issue 26 item 1); the release redraws them at once."""
from __future__ import annotations

import time
from typing import Callable

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QWidget

#: during a drag preview a panel redraws at most once per this many milliseconds
PREVIEW_INTERVAL_MS = 200
#: ... and waits at least this many times as long as its last redraw took
PREVIEW_SHARE = 8.0
#: the clock the redraws are timed with (seconds; tests drive it)
clock: Callable[[], float] = time.perf_counter


def _timed(widget: QWidget, slot: Callable[[], None]) -> Callable[[], None]:
    """``slot``, recording on ``widget`` how long it took (``_preview_took``, seconds)."""
    def run() -> None:
        t0 = clock()
        try:
            slot()
        finally:
            widget._preview_took = clock() - t0
    return run


def defer_preview(widget: QWidget, change: object, slot: Callable[[], None],
                  interval_ms: int | None = PREVIEW_INTERVAL_MS) -> bool:
    """For a slot of ``changed(Change)``: True when ``change`` is a drag preview whose redraw is
    deferred — ``slot`` then runs once within ``interval_ms`` however many moves come meanwhile
    (``interval_ms`` None: not until the release, whose final change redraws), and not sooner
    than :data:`PREVIEW_SHARE` times the last deferred redraw took. False for any other change
    (the caller redraws now; a pending deferred redraw is dropped)."""
    timer: QTimer | None = getattr(widget, "_preview_timer", None)
    if not getattr(change, "preview", False):
        if timer is not None:
            timer.stop()
        return False
    if interval_ms is None:
        return True
    if timer is None:
        timer = QTimer(widget)
        timer.setSingleShot(True)
        timer.timeout.connect(_timed(widget, slot))
        widget._preview_timer = timer
    if not timer.isActive():
        took_ms = 1e3 * getattr(widget, "_preview_took", 0.0)
        timer.start(int(max(interval_ms, PREVIEW_SHARE * took_ms)))
    return True


class LazyRefresh:
    """Mixin for a QWidget panel with a ``refresh()``: a change marks it stale; it redraws at once
    when visible, else when next shown (a hidden dock costs nothing while the user drags). During
    a drag preview a visible panel redraws at most once per ``preview_interval_ms`` (None: only
    on the release)."""

    _stale = True
    preview_interval_ms: int | None = PREVIEW_INTERVAL_MS

    def _invalidate(self, *args) -> None:
        """Slot of ``changed(Change)`` and ``selectionChanged()``: redraw now if visible."""
        self._stale = True
        if not self.isVisible():
            return
        if args and defer_preview(self, args[0], self.refresh_if_stale, self.preview_interval_ms):
            return
        self.refresh()

    def showEvent(self, event) -> None:  # noqa: N802 - Qt override
        super().showEvent(event)
        if self._stale:
            self.refresh()

    def refresh_if_stale(self) -> None:
        if self._stale:
            self.refresh()
