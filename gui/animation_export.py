"""File -> Export Animation: one cycle of the scene as an animated GIF (or an MP4 video), off the
GUI thread, with progress and Cancel.

:class:`AnimationExporter` renders the canvas one frame per timer tick on the GUI thread (Qt's
graphics items live there; a frame costs a few milliseconds, so the window stays responsive) and
hands each image to a worker thread, which quantises it (GIF) or encodes it (MP4, ffmpeg from the
``imageio-ffmpeg`` wheel) and writes the file atomically when the cycle is done: a cancelled or
failed export leaves no file behind. The animation frame the user was at is restored at the end.
Frames are read from the precomputed solutions like the player's: nothing is solved.

Signals: ``progress(done, total)``, ``finished(report)``, ``failed(message)``,
``cancelled(message)``, ``busyChanged(bool)``.
"""
from __future__ import annotations

import importlib.util
import os
import queue
import shutil
import threading
from pathlib import Path

import numpy as np
from PySide6.QtCore import QObject, QRectF, QTimer, Signal
from PySide6.QtGui import QImage, QPainter
from PySide6.QtWidgets import QHBoxLayout, QLabel, QProgressBar, QToolButton, QWidget

from mechsketch.core.errors import ExportError
from mechsketch.core.io.atomic import atomic_write

from .frames import map_frame

#: frames per cycle at least / at most, and the playback rate aimed at (frames per second)
MIN_FRAMES, MAX_FRAMES, FPS = 36, 200, 25.0
#: longest side of the exported image (px), and MP4 sizes are multiples of this
MAX_SIDE, MACRO_BLOCK = 720, 16
GIF_FILTER = "Animated GIF (*.gif)"
MP4_FILTER = "MP4 video (*.mp4)"


def mp4_available() -> bool:
    """True when an ffmpeg encoder is installed (the ``imageio-ffmpeg`` package ships one)."""
    return importlib.util.find_spec("imageio_ffmpeg") is not None


def plan_frames(period: float, samples: int) -> tuple[int, float]:
    """(frames of one cycle, frames per second): about real time at :data:`FPS`, but never fewer
    than :data:`MIN_FRAMES` nor more than :data:`MAX_FRAMES` or the cycle's samples."""
    n = int(round(period * FPS)) if period > 0 else MIN_FRAMES
    n = max(MIN_FRAMES, min(MAX_FRAMES, n))
    n = max(2, min(n, samples)) if samples else n
    fps = min(50.0, max(5.0, n / period)) if period > 0 else FPS
    return n, fps


def image_array(img: QImage) -> np.ndarray:
    """An RGB888 QImage as a (H, W, 3) uint8 array (a copy)."""
    img = img.convertToFormat(QImage.Format.Format_RGB888)
    w, h = img.width(), img.height()
    buf = np.frombuffer(img.constBits(), np.uint8, count=img.sizeInBytes()).reshape(h, img.bytesPerLine())
    return buf[:, : 3 * w].reshape(h, w, 3).copy()


class _Encoder(threading.Thread):
    """Consumes frames from a queue and writes the file when told the cycle is complete."""

    def __init__(self, exporter: "AnimationExporter", path: Path, fps: float) -> None:
        super().__init__(daemon=True)
        self.exporter, self.path, self.fps = exporter, path, fps
        self.frames: queue.Queue = queue.Queue(maxsize=8)
        self.cancel = threading.Event()
        self.kind = "mp4" if path.suffix.lower() == ".mp4" else "gif"

    def run(self) -> None:
        ex = self.exporter
        scratch = None
        try:
            if self.kind == "gif":
                from PIL import Image

                images = []
                while (frame := self.frames.get()) is not None:
                    if self.cancel.is_set():
                        continue
                    images.append(Image.fromarray(frame).quantize(colors=128, method=Image.Quantize.MEDIANCUT,
                                                                  dither=Image.Dither.NONE))
                if self.cancel.is_set():
                    return ex._worker_cancelled()
                duration = max(20, int(round(1000.0 / self.fps / 10.0)) * 10)

                def write(tmp: str) -> None:
                    images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=duration,
                                   loop=0, optimize=False, disposal=1)
                atomic_write(self.path, write)
                ex._worker_done(f"wrote {self.path}: animated GIF, {len(images)} frames of "
                                f"{images[0].width} × {images[0].height} px, {duration} ms each (one cycle)")
            else:
                import imageio.v2 as imageio

                scratch = self.path.with_name(f".{self.path.stem}.{os.getpid()}.partial.mp4")
                writer = imageio.get_writer(str(scratch), format="FFMPEG", mode="I", fps=self.fps, codec="libx264",
                                            quality=7, macro_block_size=MACRO_BLOCK, ffmpeg_log_level="error")
                count, shape = 0, None
                try:
                    while (frame := self.frames.get()) is not None:
                        if not self.cancel.is_set():
                            writer.append_data(frame)
                            count, shape = count + 1, frame.shape
                finally:
                    writer.close()
                if self.cancel.is_set():
                    return ex._worker_cancelled()
                atomic_write(self.path, lambda tmp: shutil.copyfile(scratch, tmp))
                ex._worker_done(f"wrote {self.path}: MP4 (H.264), {count} frames of {shape[1]} × {shape[0]} px at "
                                f"{self.fps:.1f} frames/s (one cycle)")
        except (ExportError, OSError, ValueError, RuntimeError) as exc:
            ex._worker_failed(f"cannot write {self.path}: {exc}")
        finally:
            if scratch is not None and scratch.exists():
                scratch.unlink()


class AnimationExporter(QObject):
    """Exports one cycle of what the canvas shows (see the module docstring)."""

    progress = Signal(int, int)
    finished = Signal(str)
    failed = Signal(str)
    cancelled = Signal(str)
    busyChanged = Signal(bool)
    _done = Signal(str, str)          # kind, message: from the worker, delivered on the GUI thread

    def __init__(self, view, controller, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.view, self.controller = view, controller
        self._timer = QTimer(self)
        self._timer.setObjectName("AnimationExporter.timer")
        self._timer.setInterval(0)
        self._timer.timeout.connect(self._tick)
        self._done.connect(self._finish)
        self._encoder: _Encoder | None = None
        self._frames: list[int] = []
        self._next = 0
        self._restore = 0
        self._size = (0, 0)

    @property
    def busy(self) -> bool:
        return self._encoder is not None

    def start(self, path: str, frames: int | None = None, size: tuple[int, int] | None = None) -> bool:
        """Export to ``path`` (.gif, or .mp4 when :func:`mp4_available`); False if one is running
        or there is nothing to animate (a message says why)."""
        ctl = self.controller
        total = ctl.sample_count()
        if self._encoder is not None:
            ctl.message.emit("an animation export is running: wait for it or cancel it")
            return False
        if total == 0:
            ctl.message.emit("nothing to animate: the scene has no solved mechanism")
            return False
        target = Path(path)
        if target.suffix.lower() not in (".gif", ".mp4"):
            target = target.with_suffix(".gif")
        if target.suffix.lower() == ".mp4" and not mp4_available():
            ctl.message.emit("MP4 needs the imageio-ffmpeg package; exporting a GIF instead")
            target = target.with_suffix(".gif")
        n, fps = plan_frames(ctl.cycle_period(), total)
        if frames is not None:
            n = max(2, int(frames))
        self._frames = [map_frame(i, n, total) for i in range(n)]
        vp = self.view.viewport().rect()
        w, h = (size if size is not None else (vp.width(), vp.height()))
        scale = min(1.0, MAX_SIDE / max(w, h, 1))
        w, h = max(MACRO_BLOCK, int(w * scale) // MACRO_BLOCK * MACRO_BLOCK), max(MACRO_BLOCK, int(h * scale) // MACRO_BLOCK * MACRO_BLOCK)
        self._size = (w, h)
        self._restore, self._next = ctl.frame, 0
        self._encoder = _Encoder(self, target, fps)
        self._encoder.start()
        self.busyChanged.emit(True)
        self.progress.emit(0, n)
        self._timer.start()
        return True

    def cancel(self) -> None:
        """Stop rendering; nothing is written."""
        if self._encoder is not None and not self._encoder.cancel.is_set():
            self._encoder.cancel.set()
            self._timer.stop()
            self._encoder.frames.put(None)

    def wait(self, timeout: float = 30.0) -> None:
        """Block until the worker has ended (closing the window, tests)."""
        enc = self._encoder
        if enc is not None:
            enc.join(timeout)

    def render(self, k: int) -> np.ndarray:
        """The canvas at sample ``k`` of the cycle as an (H, W, 3) image."""
        self.controller.set_frame(k)
        w, h = self._size
        img = QImage(w, h, QImage.Format.Format_RGB888)
        painter = QPainter(img)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        self.view.render(painter, QRectF(0, 0, w, h), self.view.viewport().rect())
        painter.end()
        return image_array(img)

    def _tick(self) -> None:
        enc = self._encoder
        if enc is None or enc.cancel.is_set():
            self._timer.stop()
            return
        if self._next >= len(self._frames):
            self._timer.stop()
            self.controller.set_frame(self._restore)
            enc.frames.put(None)
            return
        try:
            enc.frames.put(self.render(self._frames[self._next]), timeout=0.05)
        except queue.Full:
            return   # the encoder is behind: try again at the next tick
        self._next += 1
        self.progress.emit(self._next, len(self._frames))

    # -- from the worker -------------------------------------------------------------------------
    def _worker_done(self, report: str) -> None:
        self._done.emit("finished", report)

    def _worker_failed(self, message: str) -> None:
        self._done.emit("failed", message)

    def _worker_cancelled(self) -> None:
        self._done.emit("cancelled", "animation export cancelled: nothing was written")

    def _finish(self, kind: str, message: str) -> None:
        enc, self._encoder = self._encoder, None
        if enc is not None:
            enc.join(5.0)
        self._timer.stop()
        self.controller.set_frame(self._restore)
        self.busyChanged.emit(False)
        getattr(self, kind).emit(message)


class AnimationExportStatus(QWidget):
    """Status-bar widget while an animation export runs: progress and Cancel."""

    def __init__(self, exporter: AnimationExporter, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        lay = QHBoxLayout(self)
        lay.setContentsMargins(0, 0, 0, 0)
        self.label = QLabel("animation")
        self.bar = QProgressBar()
        self.bar.setMaximumWidth(110)
        self.bar.setMaximumHeight(14)
        self.cancel_button = QToolButton()
        self.cancel_button.setText("Cancel")
        self.cancel_button.setObjectName("cancelAnimationExport")
        self.cancel_button.clicked.connect(exporter.cancel)
        for w in (self.label, self.bar, self.cancel_button):
            lay.addWidget(w)
        exporter.progress.connect(self._progress)
        exporter.busyChanged.connect(self.setVisible)
        self.setVisible(False)

    def _progress(self, done: int, total: int) -> None:
        self.bar.setRange(0, total)
        self.bar.setValue(done)
        self.label.setText(f"animation frame {done}/{total}")
