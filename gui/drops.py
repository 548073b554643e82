"""Files dropped on the window: a scene file (.json) opens (after asking to save unsaved changes);
a DXF or SVG drawing or a picture becomes an underlay, centred where it was dropped on the canvas
(a DXF keeps its own coordinates when dropped elsewhere). Other files are refused with a message.

:class:`DropTarget` is an event filter on the window and on the canvas's viewport (where a drop
over the drawing lands first), so neither needs to know the other.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

from PySide6.QtCore import QEvent, QObject
from PySide6.QtGui import QDropEvent
from .qtsafe import qt_safe

SCENE_SUFFIXES = (".json",)
DRAWING_SUFFIXES = (".dxf", ".svg")
PICTURE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".gif", ".tif", ".tiff", ".webp")


def dropped_files(event) -> list[Path]:
    """The local files a drag carries."""
    data = event.mimeData()
    if data is None or not data.hasUrls():
        return []
    return [Path(u.toLocalFile()) for u in data.urls() if u.isLocalFile()]


def wanted(path: Path) -> str | None:
    """"scene", "underlay" or None for a dropped file (by its suffix)."""
    suffix = path.suffix.lower()
    if suffix in SCENE_SUFFIXES:
        return "scene"
    if suffix in DRAWING_SUFFIXES + PICTURE_SUFFIXES:
        return "underlay"
    return None


@qt_safe
class DropTarget(QObject):
    """Accepts drags of scene, drawing and picture files on ``window`` and its canvas."""

    def __init__(self, window: Any) -> None:
        super().__init__(window)
        self.window = window
        window.setAcceptDrops(True)
        window.installEventFilter(self)
        view = getattr(window, "canvas", None)
        self.viewport = view.viewport() if hasattr(view, "viewport") else None
        if self.viewport is not None:
            self.viewport.setAcceptDrops(True)
            self.viewport.installEventFilter(self)

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt override
        kind = event.type()
        if kind in (QEvent.Type.DragEnter, QEvent.Type.DragMove):
            files = dropped_files(event)
            if not files:
                return False              # not files: the canvas's own business
            if any(wanted(p) for p in files):
                event.acceptProposedAction()
            else:
                event.ignore()            # files we cannot take: the pointer says so
            return True
        if kind == QEvent.Type.Drop and isinstance(event, QDropEvent):
            files = dropped_files(event)
            if not any(wanted(p) for p in files):
                return False
            event.acceptProposedAction()
            at = None
            if obj is self.viewport:
                p = self.window.canvas.mapToScene(event.position().toPoint())
                at = (p.x(), p.y())
            self.drop(files, at)
            return True
        return False

    def drop(self, files: list[Path], at: tuple[float, float] | None = None) -> int:
        """Open the first scene file, import every drawing and picture as an underlay; the number
        of files taken."""
        taken = 0
        scenes = [p for p in files if wanted(p) == "scene"]
        if scenes and self.window.file_ops.open(scenes[0]):
            taken += 1
        for path in files:
            if wanted(path) == "underlay":
                taken += bool(self.window.underlay_commands.import_file(path, at, place=len(files) == 1))
        refused = [p.name for p in files if wanted(p) is None]
        if refused:
            self.window.controller.message.emit(
                f"not opened: {', '.join(refused)} (drop a scene .json, a DXF or SVG drawing or a picture)")
        return taken
