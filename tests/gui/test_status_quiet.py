"""A drag repaints only what changed outside the canvas (issue 26 item 1): the status bar's
read-outs (cursor position, solve time) change text on every move without laying the status bar
and the window out again, and the scrub bar repaints only when what it draws changed. What the
user reads stays the same: the labels' texts, and their own size once the text rests."""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QEvent, QObject, QPointF, Qt
from PySide6.QtWidgets import QApplication, QLabel, QStatusBar

from mechsketch.gui.status_label import StatusLabel

from app_fakes import shell  # noqa: F401 - fixture
from canvas_user import example


class Events(QObject):
    """Counts (event type, receiver class) of paint, layout and resize events."""

    def __init__(self) -> None:
        super().__init__()
        self.seen: list[tuple[QEvent.Type, str]] = []

    def eventFilter(self, obj, ev) -> bool:  # noqa: N802 - Qt API
        if ev.type() in (QEvent.Type.Paint, QEvent.Type.LayoutRequest, QEvent.Type.Resize):
            self.seen.append((ev.type(), type(obj).__name__))
        return False

    def count(self, kind: QEvent.Type, cls: str) -> int:
        return sum(1 for t, c in self.seen if t == kind and c == cls)


def test_a_status_label_keeps_its_size_while_a_button_is_held(qtbot):
    bar = QStatusBar()
    qtbot.addWidget(bar)
    label = StatusLabel()
    bar.addPermanentWidget(label)
    bar.show()
    qtbot.waitExposed(bar)
    plain = QLabel()
    for text in ("112.50, 3.25 mm", "1.00, 3.25 mm"):   # no button held: a plain label's size
        label.setText(text)
        plain.setText(text)
        assert label.size() == plain.sizeHint() and label.sizeHint() == plain.sizeHint()
    label.setText("112.50, 3.25 mm")
    wide = label.width()
    QApplication.processEvents()
    events = Events()
    bar.installEventFilter(events)
    qtbot.mousePress(bar, Qt.MouseButton.LeftButton)   # a drag (the button is held)
    assert QApplication.mouseButtons() != Qt.MouseButton.NoButton
    for text in ("1.00, 3.25 mm", "12.50, 3.25 mm", "8.1, 0.0 mm", "1.00, 3.25 mm"):   # narrower
        label.setText(text)
        QApplication.processEvents()
        assert label.text() == text and label.width() == wide
    assert events.count(QEvent.Type.LayoutRequest, "QStatusBar") == 0
    label.setText("-1112.50, 3.25 mm")   # wider: it grows (one layout) to the text's size
    QApplication.processEvents()
    plain.setText(label.text())
    assert label.width() == plain.sizeHint().width() > wide
    assert events.count(QEvent.Type.LayoutRequest, "QStatusBar") == 1
    n = len(events.seen)
    label.setText("-1112.50, 3.25 mm")   # the same text: nothing at all
    QApplication.processEvents()
    assert len(events.seen) == n
    qtbot.mouseRelease(bar, Qt.MouseButton.LeftButton)
    label.setText("8.1, 0.0 mm")   # after the drag: its own size again
    plain.setText(label.text())
    assert label.size() == plain.sizeHint()
    bar.removeEventFilter(events)


def test_a_drag_lays_out_no_status_bar_and_repaints_no_scrub_bar(shell, qtbot):
    parts = shell()
    ctl, win = parts.controller, parts.window
    ctl.reset(example("sixbar_moving_guide"))
    view = win.canvas
    view.snap_enabled = False
    vp = view.viewport()
    at = lambda xy: view.mapFromScene(QPointF(*xy))  # noqa: E731
    a = ctl.scene.element("sixbar").joint("C").at
    qtbot.mouseMove(vp, at(a))
    qtbot.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(a))
    qtbot.mouseMove(vp, at((a[0] + 0.5, a[1])))
    QApplication.processEvents()   # the first move's growth of the read-outs laid out
    events = Events()
    for w in (win, win.statusBar(), win.scrubbar, win.scrubbar.track):
        w.installEventFilter(events)
    texts = set()
    labels = (win.cursor_label, win.solve_label, win.frame_label)
    for t in np.linspace(0.0, 1.0, 9)[1:]:
        widths, layouts = [w.width() for w in labels], events.count(QEvent.Type.LayoutRequest, "QStatusBar")
        qtbot.mouseMove(vp, at((a[0] + 0.5 + 3.0 * t, a[1] - 2.0 * t)))
        QApplication.processEvents()
        texts.add((win.cursor_label.text(), win.solve_label.text()))
        grew = any(w.width() > w0 for w, w0 in zip(labels, widths))
        assert all(w.width() >= w0 for w, w0 in zip(labels, widths))   # never shrinks during the drag
        # a layout only when a read-out needs more room (a slower solve on a loaded machine)
        assert events.count(QEvent.Type.LayoutRequest, "QStatusBar") == layouts + (1 if grew else 0) or grew
    assert len(texts) >= 6                        # the read-outs changed on (nearly) every move
    assert events.count(QEvent.Type.LayoutRequest, "MainWindow") == 0
    assert events.count(QEvent.Type.Paint, "ScrubTrack") == 0
    assert events.count(QEvent.Type.Paint, "ScrubBar") == 0
    assert win.solve_label.text() == "; ".join(
        f"{eid}: {len(r.solution):,} poses, {r.seconds * 1e3:.1f} ms" for eid, r in ctl.results().items())
    qtbot.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at((a[0] + 3.5, a[1] - 2.0)))
    # the release brings the dead points back: the track repaints when what it draws changes
    track = win.scrubbar.track
    track._drawn = None
    track._on_changed(None)
    assert track._drawn is not None and track._drawn[0] == ctl.sample_count()
