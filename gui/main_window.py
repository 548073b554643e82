"""The main window: wires the components together in one place and owns nothing else.

Central area: the canvas with the scrub bar under it. Docks: properties and diagnostics (left),
plots (right). Menus File / Edit / View / Tools / Examples / Help, a toolbar and a status bar.
Components never import each other: they talk through the :class:`SceneController`'s signals, and
the canvas parts (view, tools, animation player, scrub bar) come in through :class:`Components`,
so the window can be built with stand-ins.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from PySide6.QtCore import QObject, Qt
from PySide6.QtGui import QAction, QCloseEvent, QKeySequence
from PySide6.QtWidgets import QDockWidget, QLabel, QMainWindow, QMenu, QVBoxLayout, QWidget

from mechsketch.core import ExportError, MechsketchError, ReplaceElement
from mechsketch.core.model.linkage import Linkage

from .autosave import Autosave
from .controller import SceneController
from .dialogs import DialogService
from .file_ops import FileOps
from .panels.diagnostics import DiagnosticsPanel
from .panels.plots import PlotsPanel
from .panels.properties import PropertiesPanel


@dataclass
class Components:
    """Factories of the canvas-side parts, so tests and the app can choose them.

    ``canvas(controller)`` -> the view (a QWidget with ``zoom_to_fit()``);
    ``player(controller)`` -> the animation player (a QObject);
    ``scrubbar(controller, player)`` -> the scrub bar widget;
    ``tool_actions(canvas, parent)`` -> checkable, exclusive tool QActions;
    ``snap_action(canvas, parent)`` -> the snap toggle QAction (or None);
    ``player_actions(player, parent)`` -> play/pause... QActions.
    """

    canvas: Callable[[SceneController], QWidget]
    player: Callable[[SceneController], QObject]
    scrubbar: Callable[[SceneController, QObject], QWidget]
    tool_actions: Callable[[QWidget, QObject], list[QAction]]
    snap_action: Callable[[QWidget, QObject], QAction | None]
    player_actions: Callable[[QObject, QObject], list[QAction]]


class MainWindow(QMainWindow):
    """The app's window. ``actions`` maps names ("open", "save", "undo", "example:NAME", ...) to
    the QActions, which tests trigger as a user would."""

    def __init__(self, controller: SceneController, dialogs: DialogService, file_ops: FileOps,
                 autosave: Autosave, components: Components, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.dialogs = dialogs
        self.file_ops = file_ops
        self.autosave = autosave
        self.actions: dict[str, QAction] = {}
        self.setObjectName("mainWindow")
        self.resize(1440, 900)

        # -- components ---------------------------------------------------------------------
        self.canvas = components.canvas(controller)
        self.player = components.player(controller)
        self.scrubbar = components.scrubbar(controller, self.player)
        central = QWidget()
        column = QVBoxLayout(central)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(0)
        column.addWidget(self.canvas, 1)
        column.addWidget(self.scrubbar)
        self.setCentralWidget(central)
        self.properties = PropertiesPanel(controller)
        self.diagnostics = DiagnosticsPanel(controller)
        self.plots = PlotsPanel(controller)
        self.docks = {
            "properties": self._dock("Properties", self.properties, Qt.DockWidgetArea.LeftDockWidgetArea),
            "diagnostics": self._dock("Diagnostics", self.diagnostics, Qt.DockWidgetArea.LeftDockWidgetArea),
            "plots": self._dock("Plots", self.plots, Qt.DockWidgetArea.RightDockWidgetArea),
        }
        self.resizeDocks([self.docks["properties"], self.docks["plots"]], [330, 430], Qt.Orientation.Horizontal)
        self.resizeDocks([self.docks["properties"], self.docks["diagnostics"]], [470, 330], Qt.Orientation.Vertical)

        # -- actions, menus, toolbar, status bar --------------------------------------------
        self.tool_actions = components.tool_actions(self.canvas, self)
        self.snap = components.snap_action(self.canvas, self)
        self.player_actions = components.player_actions(self.player, self)
        self._make_actions()
        self._make_menus()
        self._make_toolbar()
        self.frame_label = QLabel()
        self.solve_label = QLabel()
        self.statusBar().addPermanentWidget(self.solve_label)
        self.statusBar().addPermanentWidget(self.frame_label)

        # -- wiring -------------------------------------------------------------------------
        controller.message.connect(self.show_message)
        controller.solveFailed.connect(lambda eid, msg: self.show_message(f"{eid}: {msg}"))
        controller.pathChanged.connect(self.update_title)
        controller.sceneChanged.connect(self.update_title)
        controller.solutionsChanged.connect(self._update_status)
        controller.frameChanged.connect(lambda _i: self._update_frame())
        controller.selectionChanged.connect(self._update_enabled)
        file_ops.recentChanged.connect(self._fill_recent)
        self.plots.add_header_actions([self.actions["export_png"], self.actions["export_csv"]])
        self.update_title()
        self._update_status()
        self._update_enabled()

    # -- construction helpers ----------------------------------------------------------------
    def _dock(self, title: str, widget: QWidget, area: Qt.DockWidgetArea) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(f"dock:{title}")
        dock.setWidget(widget)
        self.addDockWidget(area, dock)
        return dock

    def _action(self, name: str, text: str, slot: Callable[[], Any], shortcut: Any = None,
                tip: str = "") -> QAction:
        action = QAction(text, self)
        action.setObjectName(name)
        if shortcut is not None:
            action.setShortcut(QKeySequence(shortcut))
        if tip:
            action.setStatusTip(tip)
        action.triggered.connect(lambda _checked=False: slot())
        self.actions[name] = action
        return action

    def _make_actions(self) -> None:
        fo = self.file_ops
        K = QKeySequence.StandardKey
        self._action("new", "&New", fo.new, K.New, "Start an empty scene")
        self._action("open", "&Open…", fo.open, K.Open, "Open a scene file")
        self._action("save", "&Save", fo.save, K.Save, "Save the scene (atomic)")
        self._action("save_as", "Save &As…", fo.save_as, K.SaveAs, "Save the scene under a new name")
        self._action("export_png", "Export plots as &PNG…", self.export_plot_png, tip="Save the plots as an image")
        self._action("export_csv", "Export plot &data as CSV…", self.export_plot_csv,
                     tip="Save the plotted numbers as CSV")
        self._action("quit", "&Quit", self.close, K.Quit)
        undo = self.controller.undo_stack.createUndoAction(self, "&Undo")
        undo.setShortcut(QKeySequence(K.Undo))
        redo = self.controller.undo_stack.createRedoAction(self, "&Redo")
        redo.setShortcut(QKeySequence(K.Redo))
        self.actions["undo"], self.actions["redo"] = undo, redo
        self._action("delete", "&Delete", self.delete_selection, K.Delete, "Delete the selected joints and links")
        self._action("zoom_fit", "Zoom to &fit", self.zoom_to_fit, "F", "Show the whole scene")
        self._action("about", "&About mechsketch", self.about)
        for name in self.file_ops.examples():
            self._action(f"example:{name}", name.replace("_", " "),
                         lambda name=name: self.file_ops.open_example(name), tip=f"Open the example {name}")

    def _make_menus(self) -> None:
        a = self.actions
        bar = self.menuBar()
        file_menu = bar.addMenu("&File")
        file_menu.addActions([a["new"], a["open"]])
        self.recent_menu = QMenu("Open &Recent", self)
        file_menu.addMenu(self.recent_menu)
        file_menu.addActions([a["save"], a["save_as"]])
        file_menu.addSeparator()
        file_menu.addActions([a["export_png"], a["export_csv"]])
        file_menu.addSeparator()
        file_menu.addAction(a["quit"])
        self._fill_recent()
        edit = bar.addMenu("&Edit")
        edit.addActions([a["undo"], a["redo"]])
        edit.addSeparator()
        edit.addAction(a["delete"])
        view = bar.addMenu("&View")
        view.addAction(a["zoom_fit"])
        if self.player_actions:
            view.addSeparator()
            view.addActions(self.player_actions)
        view.addSeparator()
        for dock in self.docks.values():
            view.addAction(dock.toggleViewAction())
        tools = bar.addMenu("&Tools")
        tools.addActions(self.tool_actions)
        if self.snap is not None:
            tools.addSeparator()
            tools.addAction(self.snap)
        examples = bar.addMenu("E&xamples")
        for name in self.file_ops.examples():
            examples.addAction(a[f"example:{name}"])
        help_menu = bar.addMenu("&Help")
        help_menu.addAction(a["about"])

    def _make_toolbar(self) -> None:
        a = self.actions
        bar = self.addToolBar("Main")
        bar.setObjectName("toolbar:main")
        bar.addActions([a["new"], a["open"], a["save"]])
        bar.addSeparator()
        bar.addActions([a["undo"], a["redo"], a["delete"]])
        bar.addSeparator()
        bar.addAction(a["zoom_fit"])
        if self.tool_actions:
            tools = self.addToolBar("Tools")
            tools.setObjectName("toolbar:tools")
            tools.addActions(self.tool_actions)
            if self.snap is not None:
                tools.addSeparator()
                tools.addAction(self.snap)
        if self.player_actions:
            bar.addSeparator()
            bar.addActions(self.player_actions)

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        recent = self.file_ops.recent_files()
        for k, path in enumerate(recent):
            action = self.recent_menu.addAction(f"&{k + 1} {Path(path).name}")
            action.setStatusTip(path)
            action.triggered.connect(lambda _c=False, p=path: self.file_ops.open_recent(p))
        if recent:
            self.recent_menu.addSeparator()
            self.recent_menu.addAction("Clear list", self.file_ops.clear_recent)
        self.recent_menu.setEnabled(bool(recent))

    # -- state shown -------------------------------------------------------------------------
    def update_title(self) -> None:
        dirty = " *" if self.controller.is_dirty else ""
        self.setWindowTitle(f"{self.file_ops.display_name()}{dirty} — mechsketch")

    def show_message(self, text: str) -> None:
        self.statusBar().showMessage(text, 8000)

    def _update_status(self) -> None:
        parts = []
        for eid, res in self.controller.results().items():
            if res.error is not None:
                parts.append(f"{eid}: not solved")
            elif res.solution is not None:
                parts.append(f"{eid}: {len(res.solution):,} poses, {res.seconds * 1e3:.1f} ms")
        self.solve_label.setText("; ".join(parts))
        self._update_frame()

    def _update_frame(self) -> None:
        frame = self.controller.frame
        for res in self.controller.results().values():
            if res.solution is not None and frame < len(res.solution):
                deg = math.degrees(res.solution.input[frame]) % 360.0
                self.frame_label.setText(f"input {deg:.1f}° (frame {frame + 1}/{len(res.solution)})")
                return
        self.frame_label.setText("")

    def _update_enabled(self) -> None:
        self.actions["delete"].setEnabled(bool(self.controller.selection))

    # -- commands ----------------------------------------------------------------------------
    def zoom_to_fit(self) -> None:
        fit = getattr(self.canvas, "zoom_to_fit", None)
        if callable(fit):
            fit()

    def delete_selection(self) -> bool:
        """Delete the selected joints and links (one undo step); the ground link, the driver
        and its pivot are refused with a message."""
        picked: dict[str, list[tuple[str, str]]] = {}
        for eid, kind, ident in self.controller.selection:
            picked.setdefault(eid, []).append((kind, ident))
        edits = []
        for eid, items in picked.items():
            try:
                lk = self.controller.scene.element(eid)
            except KeyError:
                continue
            if not isinstance(lk, Linkage):
                continue
            protected = {("link", lk.ground), ("link", lk.driver.link), ("joint", lk.driver.pivot)}
            refused = [i for k, i in items if (k, i) in protected]
            if refused:
                self.show_message(f"cannot delete {', '.join(refused)}: the ground, the driver and "
                                  "its pivot stay (draw a new linkage instead)")
                return False
            new = lk
            try:
                for kind, ident in items:
                    new = new.without_joint(ident) if kind == "joint" else new.without_link(ident)
            except (KeyError, MechsketchError) as exc:
                self.show_message(f"cannot delete: {exc}")
                return False
            names = ", ".join(i for _, i in items)
            edits.append((ReplaceElement(new, f"delete {names}"), f"delete {names}"))
        if not edits:
            return False
        stack = self.controller.undo_stack
        stack.beginMacro(edits[0][1] if len(edits) == 1 else "delete selection")
        for edit, text in edits:
            self.controller.push(edit, text)
        stack.endMacro()
        self.controller.set_selection([])
        return True

    def _export(self, title: str, suffix: str, filt: str, write: Callable[[str], None]) -> bool:
        start = self.controller.path.with_suffix(suffix) if self.controller.path else Path.home() / f"plot{suffix}"
        name = self.dialogs.save_file_name(title, str(start), filt)
        if not name:
            return False
        try:
            write(name)
        except (ExportError, OSError) as exc:
            self.show_message(str(exc))
            self.dialogs.error(title, f"{exc}\n\nThe scene is not affected.")
            return False
        self.show_message(f"wrote {name}")
        return True

    def export_plot_png(self) -> bool:
        return self._export("Export plots as PNG", ".png", "PNG images (*.png)", self.plots.export_png)

    def export_plot_csv(self) -> bool:
        return self._export("Export plot data as CSV", ".csv", "CSV files (*.csv)", self.plots.export_csv)

    def about(self) -> None:
        from importlib.metadata import PackageNotFoundError, version

        try:
            v = version("mechsketch")
        except PackageNotFoundError:
            v = "(development)"
        self.dialogs.info("About mechsketch",
                          f"mechsketch {v}\nDesktop CAD for planar mechanisms: linkages solved by Assur "
                          "groups in closed form, Geneva drives, rolling levers, DXF export.")

    # -- closing -----------------------------------------------------------------------------
    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802 - Qt override
        if not self.file_ops.maybe_save():
            event.ignore()
            return
        stop = getattr(self.player, "stop", None)
        if callable(stop):
            stop()
        self.autosave.clean_exit()
        event.accept()
