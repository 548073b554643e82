"""The canvas side's entries in the window's menus, made in one place (see ``CanvasParts.menus``).

- File: Export Animation… (GIF, or MP4 when an encoder is installed; off the GUI thread with
  progress and Cancel in the status bar), Export Centrodes as CSV… / DXF…;
- View: the overlays (vectors, instant centres, transmission angles, Geneva phase and force) and
  Centrodes of Selected Link;
- Examples: Insert ▸ (an example or a scene file, placed where the user clicks).

Dialogs come from the window's injectable :class:`~mechsketch.gui.dialogs.DialogService`.
"""
from __future__ import annotations

from pathlib import Path

from PySide6.QtGui import QAction

from mechsketch.core.errors import MechsketchError

from .animation_export import GIF_FILTER, MP4_FILTER, AnimationExporter, AnimationExportStatus, mp4_available
from .canvas.insert_tool import insert_menu


class CanvasMenus:
    """Owns the exporter and the actions; ``menus`` is what ``CanvasParts.menus`` takes."""

    def __init__(self, view, window) -> None:
        self.view, self.window = view, window
        self.controller = view.controller
        self.dialogs = window.dialogs
        self.exporter = AnimationExporter(view, self.controller, window)
        self.status = AnimationExportStatus(self.exporter)
        window.statusBar().addPermanentWidget(self.status)
        self.exporter.finished.connect(self._said)
        self.exporter.failed.connect(self._failed)
        self.exporter.cancelled.connect(self._said)
        self.actions: dict[str, QAction] = {}
        self._action("export_animation", "Export &Animation…", self.export_animation,
                     "Write one cycle of the scene as an animated GIF (or MP4)")
        self._action("export_centrodes_csv", "Export Centrodes as CS&V…", self.export_centrodes_csv,
                     "Write the shown centrodes (View → Centrodes) as a CSV table")
        self._action("export_centrodes_dxf", "Export Centrodes as D&XF…", self.export_centrodes_dxf,
                     "Write the shown centrodes as arc-fitted DXF curves (mm), the maximum deviation reported")
        self.insert = insert_menu(view, self.dialogs, window)
        extras = view.extras.actions
        self.menus = {"file": [self.actions[k] for k in ("export_animation", "export_centrodes_csv",
                                                          "export_centrodes_dxf")],
                      "view": [extras[k] for k in ("vectors", "centres", "transmission", "geneva", "forces",
                                                   "centrodes")],
                      "examples": [self.insert]}

    def _action(self, name: str, text: str, slot, tip: str) -> None:
        act = QAction(text, self.window)
        act.setObjectName(name)
        act.setStatusTip(tip)
        act.triggered.connect(lambda _c=False: slot())
        self.actions[name] = act

    def _start(self, suffix: str) -> str:
        path = self.controller.path
        return str(path.with_suffix(suffix)) if path else str(Path.home() / f"scene{suffix}")

    def _said(self, text: str) -> None:
        self.controller.message.emit(text.splitlines()[0] if text else "")

    def _failed(self, text: str) -> None:
        self._said(text)
        self.dialogs.error("Export", f"{text}\n\nThe scene is not affected.")

    # -- commands -----------------------------------------------------------------------------
    def export_animation(self) -> bool:
        """Ask for a file and start exporting one cycle (True: started)."""
        filters = GIF_FILTER + (f";;{MP4_FILTER}" if mp4_available() else "")
        name = self.dialogs.save_file_name("Export animation", self._start(".gif"), filters)
        if not name:
            return False
        return self.exporter.start(name)

    def export_centrodes_csv(self) -> bool:
        name = self.dialogs.save_file_name("Export centrodes as CSV", self._start(".csv"), "CSV files (*.csv)")
        if not name:
            return False
        try:
            self._said(self.view.extras.overlays.centrodes.export_csv(name))
        except (MechsketchError, OSError) as exc:
            self._failed(str(exc))
            return False
        return True

    def export_centrodes_dxf(self) -> bool:
        name = self.dialogs.save_file_name("Export centrodes as DXF", self._start(".dxf"), "DXF drawings (*.dxf)")
        if not name:
            return False
        try:
            report = self.view.extras.overlays.centrodes.export_dxf(name)
        except (MechsketchError, OSError) as exc:
            self._failed(str(exc))
            return False
        self._said(report.report())
        self.dialogs.info("Centrodes exported", report.report())
        return True
