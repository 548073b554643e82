"""Deferred panel redraws during a drag take a bounded share of the drag (gui/panels/lazy.py,
issue 26 item 1): the next redraw waits PREVIEW_SHARE times as long as the last one took, never
less than PREVIEW_INTERVAL_MS; the release redraws at once. Driven by a fake clock, no waits."""
from __future__ import annotations

from types import SimpleNamespace

from PySide6.QtWidgets import QWidget

from mechsketch.gui.panels import lazy


def test_a_slow_redraw_spaces_the_next_ones_and_a_fast_one_keeps_the_interval(qtbot, monkeypatch):
    now = [100.0]
    monkeypatch.setattr(lazy, "clock", lambda: now[0])
    w = QWidget()
    qtbot.addWidget(w)
    took = [0.120]      # seconds the redraw takes on the fake clock
    runs = []

    def redraw():
        runs.append(now[0])
        now[0] += took[0]

    move, release = SimpleNamespace(preview=True), SimpleNamespace(preview=False)
    assert lazy.defer_preview(w, move, redraw)
    timer = w._preview_timer
    assert timer.isActive() and timer.interval() == lazy.PREVIEW_INTERVAL_MS
    for _ in range(5):                       # more moves meanwhile: one pending redraw
        assert lazy.defer_preview(w, move, redraw)
    assert timer.interval() == lazy.PREVIEW_INTERVAL_MS and runs == []
    timer.stop()
    timer.timeout.emit()                     # the timer fires: the redraw runs, taking 120 ms
    assert len(runs) == 1
    assert lazy.defer_preview(w, move, redraw)
    assert timer.interval() == round(lazy.PREVIEW_SHARE * 120)   # 960 ms: an eighth of the drag
    timer.stop()
    took[0] = 0.004
    timer.timeout.emit()                     # a fast redraw: back to the plain interval
    assert lazy.defer_preview(w, move, redraw)
    assert timer.interval() == lazy.PREVIEW_INTERVAL_MS
    assert not lazy.defer_preview(w, release, redraw) and not timer.isActive()   # the release: now
    assert len(runs) == 2
