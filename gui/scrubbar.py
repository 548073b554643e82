"""The scrub bar: play/pause, direction, a track over the cycle, speed, dead-point behaviour.

The track shows one driver revolution (the controller's samples, from the drawn pose in the
driver's sense); ranges where the linkage cannot be assembled are painted red, dead points are
marked with ticks, the current frame with a handle. Clicking the track goes to the nearest valid
sample; dragging along it moves only through valid samples (it stops at a limit rather than jump
across an infeasible gap). It reads precomputed arrays only.

Embedding::

    bar = ScrubBar(controller, player)
    main_window.addDockWidget(...)  # or put it in a QVBoxLayout under the canvas
"""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, QSize, Qt
from PySide6.QtGui import QColor, QMouseEvent, QPainter, QPen, QPolygonF
from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QSizePolicy, QToolButton, QToolTip, QWidget

from mechsketch.core.model.drivers import input_text

from .animation import SPEEDS, AnimationPlayer
from .frames import dead_samples, walk_to
from .qtsafe import qt_safe

GROOVE = QColor("#e3e6eb")
GROOVE_EDGE = QColor("#b8bec8")
BAD = QColor(214, 39, 40, 170)
DEAD = QColor("#d62728")
HANDLE = QColor("#1e88e5")
MARGIN = 8.0


@qt_safe
class ScrubTrack(QWidget):
    """The painted track (part of :class:`ScrubBar`)."""

    def __init__(self, controller, player: AnimationPlayer, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.player = player
        self._dragging = False
        self._drawn: tuple | None = None   # (N, valid mask bytes, dead points) last drawn
        self.setMinimumHeight(30)
        self.setMinimumWidth(80)
        self.setMouseTracking(True)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        controller.changed.connect(self._on_changed)
        controller.frameChanged.connect(self.update)

    def _on_changed(self, _change) -> None:
        """Repaint when what the track draws changed (a drag moves the linkage on every mouse
        move, the track's samples, ranges and dead points mostly stay as they were)."""
        n, valid, dead = self._data()
        drawn = (n, None if valid is None else valid.tobytes(), tuple(dead))
        if drawn != self._drawn:
            self._drawn = drawn
            self.update()

    def sizeHint(self) -> QSize:
        return QSize(400, 30)

    def _data(self) -> tuple[int, np.ndarray | None, list[tuple[int, str]]]:
        """(N, valid mask over global frames, [(frame, label)] of dead points)."""
        ctl = self.controller
        n = ctl.sample_count()
        valid, _ = self.player.masks()
        dead: list[tuple[int, str]] = []
        for lk in ctl.linkages():
            res = ctl.result(lk.id)
            diag = ctl.diagnostics(lk.id)   # none during a drag preview (back on release)
            if res is None or res.solution is None or diag is None:
                continue
            sol = res.solution
            m = len(sol)
            samples = dead_samples(sol, np.asarray(sol.valid, dtype=bool), [d.input for d in diag.dead_points])
            for d, k in zip(diag.dead_points, samples):
                g = k if m == n else int(round(k * n / m)) % n
                what = "limit" if d.kind == "limit" else "dead point"
                dead.append((g, f"{lk.id}: {what} at {input_text(d.input, d.unit, 2)} ({d.group})"))
        return n, valid, dead

    def x_of(self, k: int, n: int) -> float:
        w = self.width() - 2 * MARGIN
        return MARGIN + (k / max(n - 1, 1)) * w

    def frame_at(self, x: float) -> int:
        n = self.controller.sample_count()
        w = self.width() - 2 * MARGIN
        t = min(max((x - MARGIN) / max(w, 1.0), 0.0), 1.0)
        return int(round(t * max(n - 1, 0)))

    def paintEvent(self, event) -> None:  # noqa: N802 - Qt API
        p = QPainter(self)
        p.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        n, valid, dead = self._data()
        self._drawn = (n, None if valid is None else valid.tobytes(), tuple(dead))
        h = self.height()
        groove = QRectF(MARGIN, h / 2 - 4, self.width() - 2 * MARGIN, 8)
        p.setPen(QPen(GROOVE_EDGE, 1))
        p.setBrush(GROOVE)
        p.drawRoundedRect(groove, 3, 3)
        if n == 0 or valid is None:
            p.setPen(QColor("#6b7280"))
            p.drawText(self.rect(), Qt.AlignmentFlag.AlignCenter, "nothing to animate")
            return
        bad = ~valid
        if bad.any():
            edges = np.flatnonzero(np.diff(np.concatenate(([0], bad.view(np.int8), [0]))))
            p.setPen(Qt.PenStyle.NoPen)
            p.setBrush(BAD)
            for s, e in zip(edges[::2], edges[1::2]):
                x0, x1 = self.x_of(s, n) - 0.5, self.x_of(e - 1, n) + 0.5
                p.drawRect(QRectF(x0, groove.top() - 2, max(x1 - x0, 2.0), groove.height() + 4))
        p.setPen(QPen(DEAD, 1.5))
        p.setBrush(DEAD)
        for k, _label in dead:
            x = self.x_of(k, n)
            p.drawLine(QPointF(x, groove.top() - 5), QPointF(x, groove.bottom() + 5))
            p.drawPolygon(QPolygonF([QPointF(x - 4, 2), QPointF(x + 4, 2), QPointF(x, 8)]))
        x = self.x_of(self.controller.frame, n)
        p.setPen(QPen(QColor("white"), 1.5))
        p.setBrush(HANDLE)
        p.drawEllipse(QPointF(x, h / 2), 7, 7)

    def mousePressEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        if e.button() != Qt.MouseButton.LeftButton or self.controller.sample_count() == 0:
            return
        self.player.pause()
        self._dragging = True
        self.player.seek(self.frame_at(e.position().x()))

    def mouseMoveEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        n, valid, dead = self._data()
        if n == 0 or valid is None:
            return
        k = self.frame_at(e.position().x())
        if self._dragging:
            reached, blocked = walk_to(valid, self.controller.frame, k, cyclic=False)
            self.controller.set_frame(reached)
            if blocked:
                self.controller.message.emit("the linkage cannot be assembled there: the scrub bar stops at "
                                             "the limit of the reachable range")
            return
        near = [label for f, label in dead if abs(self.x_of(f, n) - e.position().x()) <= 5]
        tip = "; ".join(near) if near else ("cannot be assembled here" if not valid[k] else "")
        if tip:
            QToolTip.showText(e.globalPosition().toPoint(), tip, self)
        else:
            QToolTip.hideText()

    def mouseReleaseEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        self._dragging = False


class ScrubBar(QWidget):
    """Play/pause and direction buttons, the track, a speed box, the dead-point behaviour box,
    and a read-out of the driver input and time at the current frame."""

    def __init__(self, controller, player: AnimationPlayer, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.player = player
        lay = QHBoxLayout(self)
        lay.setContentsMargins(6, 2, 6, 2)
        lay.setSpacing(6)
        self.play_button = QToolButton(self)
        self.play_button.setDefaultAction(player.play_action)
        self.play_button.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonTextOnly)
        self.direction_button = QToolButton(self)
        self.direction_button.setDefaultAction(player.direction_action)
        self.direction_button.setText("Reverse")
        self.track = ScrubTrack(controller, player, self)
        self.speed_box = QComboBox(self)
        for s in SPEEDS:
            self.speed_box.addItem(f"{s:g}x", s)
        self.speed_box.setCurrentIndex(SPEEDS.index(1.0))
        self.speed_box.setToolTip("animation speed (1x: the driver's rpm in real time)")
        self.speed_box.currentIndexChanged.connect(lambda i: player.set_speed(self.speed_box.itemData(i)))
        self.dead_box = QComboBox(self)
        self.dead_box.addItem("stop at dead pts", "stop")
        self.dead_box.addItem("reverse at dead pts", "reverse")
        self.dead_box.setToolTip("what the animation does at a dead point or the limit of its range")
        self.dead_box.setCurrentIndex(1 if player.dead_point_behaviour == "reverse" else 0)
        self.dead_box.currentIndexChanged.connect(
            lambda i: player.set_dead_point_behaviour(self.dead_box.itemData(i)))
        for box in (self.speed_box, self.dead_box):   # they shrink on a small screen (1024 px)
            box.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
            box.setMinimumContentsLength(4)
        self.readout = QLabel(self)
        # the read-out gives way when the window is narrow (the status bar repeats it in full), so
        # the scrub bar never squeezes the docks
        self.readout.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.readout.setMinimumWidth(0)
        for w in (self.play_button, self.direction_button):
            lay.addWidget(w)
        lay.addWidget(self.track, 4)
        for w in (self.speed_box, self.dead_box):
            lay.addWidget(w)
        lay.addWidget(self.readout, 2)
        player.settingsChanged.connect(self._settings)
        controller.frameChanged.connect(self._readout)
        controller.changed.connect(self._readout)
        self._readout()

    def _settings(self) -> None:
        s = self.player.speed
        i = self.speed_box.findData(s)
        if i >= 0 and i != self.speed_box.currentIndex():
            self.speed_box.setCurrentIndex(i)
        want = 1 if self.player.dead_point_behaviour == "reverse" else 0
        if self.dead_box.currentIndex() != want:
            self.dead_box.setCurrentIndex(want)

    def _readout(self, *_args) -> None:
        text, ok = self.controller.frame_text()
        if text != self.readout.text():   # a QLabel's setText and setStyleSheet lay the bar out again
            self.readout.setText(text)
        style = "" if ok else "color: #d62728"
        if style != self.readout.styleSheet():
            self.readout.setStyleSheet(style)
            self.readout.setToolTip("" if ok else "the mechanism cannot be assembled at this input")
