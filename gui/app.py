"""Start the desktop app: QApplication set-up, style, the main window, crash recovery, error hook.

``run_app(path)`` is what ``mechsketch`` / ``mechsketch open SCENE`` call. :func:`build` makes the
whole app without running the event loop (tests and the start-up benchmark use it) and takes
the dialog service, settings file, recovery folder and canvas components as arguments, so a test
injects fakes instead of patching Qt. The platform plugin is left to the user (tests set
``QT_QPA_PLATFORM=offscreen``); with no display at all we say so instead of letting Qt abort.
"""
from __future__ import annotations

import os
import sys
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Callable

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QApplication

from mechsketch import resources

from .autosave import Autosave
from .controller import SceneController
from .dialogs import DialogService, QtDialogService
from .file_ops import FileOps, make_settings
from .main_window import CanvasParts, Components, MainWindow
from .preferences import load_preferences

ExceptHook = Callable[[type[BaseException], BaseException, TracebackType | None], None]


def canvas_parts(controller: SceneController, window: MainWindow) -> CanvasParts:
    """The real canvas, tools, animation player and scrub bar, wired to each other and to the
    window's status bar (the :data:`Components` the app uses)."""
    from .animation import AnimationPlayer
    from .canvas.view import CanvasView
    from .canvas_menus import CanvasMenus
    from .scrubbar import ScrubBar

    view = CanvasView(controller)
    player = AnimationPlayer(controller)
    bar = ScrubBar(controller, player)
    view.set_tap_action(player.play_action)       # Space on the canvas plays/pauses
    view.dragStarted.connect(player.pause)        # a drag pauses the animation
    view.cursorMoved.connect(window.show_cursor)
    player.stopped.connect(window.show_message)
    animation = [player.play_action, player.direction_action, player.step_forward_action,
                 player.step_back_action, *player.dead_point_actions.actions()]
    menus = CanvasMenus(view, window)   # overlays, centrodes, Insert, Export Animation
    window.canvas_menus = menus
    return CanvasParts(view, player, bar, tools=view.tool_actions,
                       view_actions=[view.zoom_fit_action, view.snap_action, view.trace_action,
                                     view.labels_action],
                       animation_actions=animation, delete=view.delete_action,
                       zoom_fit=view.zoom_fit_action, stop=lambda: (player.pause(), menus.exporter.cancel(),
                                                                    menus.exporter.wait()),
                       menus=menus.menus)


def qapplication(argv: list[str] | None = None) -> QApplication:
    """The QApplication (created once), with the app's names and style."""
    app = QApplication.instance()
    if app is None:
        QApplication.setHighDpiScaleFactorRoundingPolicy(Qt.HighDpiScaleFactorRoundingPolicy.PassThrough)
        app = QApplication(argv if argv is not None else [sys.argv[0]])
    app.setApplicationName("mechsketch")
    app.setOrganizationName("mechsketch")
    app.setApplicationDisplayName("mechsketch")
    if "fusion" in [s.lower() for s in _styles()]:
        app.setStyle("Fusion")
    return app   # pyqtgraph's options are set where it is imported (gui/panels/plots.py), after the first frame


def _styles() -> list[str]:
    from PySide6.QtWidgets import QStyleFactory

    return QStyleFactory.keys()


@dataclass
class AppParts:
    """The running app's pieces (what :func:`build` made)."""

    app: QApplication
    controller: SceneController
    dialogs: DialogService
    file_ops: FileOps
    autosave: Autosave
    window: MainWindow
    started: float = field(default_factory=time.perf_counter)

    def close(self) -> None:
        """Close the window and stop the timers (tests; a clean exit)."""
        self.autosave.stop()
        self.window.close()


def build(scene_path: str | os.PathLike | None = None, *, dialogs: DialogService | None = None,
          settings_path: str | os.PathLike | None = None, state_dir: str | os.PathLike | None = None,
          components: Components | None = None, autosave_ms: int | None = None,
          offer_recovery: bool = True) -> AppParts:
    """Make the app: controller, file operations, autosave, main window; open ``scene_path``
    (or the default example), then offer a crash-recovery file if one is left. Not shown.
    ``autosave_ms``: the autosave interval (None: the preferences')."""
    started = time.perf_counter()
    app = qapplication()
    controller = SceneController()
    service = dialogs if dialogs is not None else QtDialogService()
    file_ops = FileOps(controller, service, make_settings(settings_path))
    if autosave_ms is None:
        autosave_ms = load_preferences(file_ops.settings).autosave_s * 1000
    autosave = Autosave(controller, Path(state_dir) if state_dir is not None else None, autosave_ms)
    window = MainWindow(controller, service, file_ops, autosave,
                        components if components is not None else canvas_parts)
    if isinstance(service, QtDialogService):
        service.parent = window
    parts = AppParts(app, controller, service, file_ops, autosave, window, started)
    if scene_path is not None:
        if not file_ops.open(scene_path, ask=False):
            controller.message.emit(f"could not open {scene_path}; starting with an empty scene")
    else:
        file_ops.open_example(resources.DEFAULT_EXAMPLE, ask=False)
    if offer_recovery:
        asked = time.perf_counter()
        offer_recovery_files(parts)
        parts.started += time.perf_counter() - asked   # start-up time without the user's answer
    autosave.start()
    return parts


def offer_recovery_files(parts: AppParts) -> bool:
    """Offer the recovery files crashed runs left, newest first, one at a time, until one is
    restored: Yes restores it, No deletes it. Files not asked about (after a restore) stay and are
    offered at the next start. A file another starting app is offering is skipped. True if restored."""
    pending = parts.autosave.pending()
    for k, recovery in enumerate(pending):
        if not recovery.claim():
            continue
        more = len(pending) - k - 1
        also = f"\n\n{more} older recovery file(s) will be offered after this one." if more else ""
        if parts.dialogs.ask_yes_no("Restore unsaved work?",
                                    f"mechsketch did not exit cleanly.\n\nRestore {recovery.describe()}?\n"
                                    f"(No deletes the recovery file.){also}"):
            if parts.autosave.restore(recovery) is not None:
                if more:
                    parts.controller.message.emit(
                        f"restored {recovery.describe()}; {more} older recovery file(s) kept in "
                        f"{parts.autosave.folder}, offered at the next start")
                return True
            continue
        recovery.discard()
    return False


def install_excepthook(parts: AppParts) -> ExceptHook:
    """Show unexpected errors in a message box, autosave, and keep running. Returns the old hook."""
    previous = sys.excepthook
    busy = {"now": False}

    def hook(exc_type: type[BaseException], exc: BaseException, tb: TracebackType | None) -> None:
        if issubclass(exc_type, KeyboardInterrupt):
            previous(exc_type, exc, tb)
            return
        text = "".join(traceback.format_exception(exc_type, exc, tb))
        sys.stderr.write(text)
        if busy["now"]:  # an error while reporting an error: stderr only
            return
        busy["now"] = True
        try:
            saved = parts.autosave.save_now()
            note = " Your unsaved scene was autosaved." if saved else ""
            parts.controller.message.emit(f"internal error: {exc_type.__name__}: {exc}")
            parts.dialogs.error("Unexpected error",
                                f"{exc_type.__name__}: {exc}\n\nmechsketch keeps running and your scene is "
                                f"still open.{note} Please report this with the details.", text)
        finally:
            busy["now"] = False

    sys.excepthook = hook
    return previous


def fit_to_screen(window: MainWindow) -> None:
    """Shrink the window to 95 % of the screen's free area if it is larger, and centre it."""
    screen = window.screen() or QApplication.primaryScreen()
    if screen is None:
        return
    free = screen.availableGeometry()
    w = min(window.width(), int(free.width() * 0.95))
    h = min(window.height(), int(free.height() * 0.95))
    window.resize(w, h)
    window.move(free.x() + (free.width() - w) // 2, free.y() + (free.height() - h) // 2)


def _no_display() -> bool:
    """True on Linux/BSD when no display is reachable and the user chose no platform plugin."""
    if os.environ.get("QT_QPA_PLATFORM") or not sys.platform.startswith(("linux", "freebsd", "openbsd")):
        return False
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def run_app(scene_path: str | os.PathLike | None = None) -> int:
    """Run the desktop app on ``scene_path`` (None: the built-in example); returns the exit code."""
    if _no_display():
        print("mechsketch: no display found (DISPLAY and WAYLAND_DISPLAY are unset). Run it in a desktop "
              "session, or set QT_QPA_PLATFORM (e.g. offscreen); the headless commands work anywhere "
              "(mechsketch --help).", file=sys.stderr)
        return 1
    parts = build(scene_path)
    previous = install_excepthook(parts)
    try:
        if not parts.window.layout_restored:
            fit_to_screen(parts.window)
        parts.window.show()
        parts.controller.message.emit(
            f"ready in {time.perf_counter() - parts.started:.2f} s")
        return parts.app.exec()
    finally:
        parts.autosave.stop()
        sys.excepthook = previous
