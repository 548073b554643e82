"""The main window: wires the components together in one place and owns nothing else.

Central area: the canvas with the scrub bar under it. Docks: properties and diagnostics (left),
plots (right). Menus File / Edit / View / Tools / Examples / Help, a toolbar and a status bar.
Components never import each other: they talk through the :class:`SceneController`'s signals, and
the canvas parts (view, tools, animation player, scrub bar) come in through :class:`Components`,
so the window can be built with stand-ins.

Start-up (issue 14): the first frame does not wait for what it does not show. The plots panel
(pyqtgraph, about 0.2 s to import) is made right after the window's first frame is painted
(:class:`LazyDock`), or at once when code asks for :attr:`MainWindow.plots`; the part exporter
(shapely, the part builders) is made on the first export or on :attr:`MainWindow.exporter`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from PySide6.QtCore import QByteArray, QObject, QSize, Qt, QTimer
from PySide6.QtGui import QAction, QCloseEvent, QKeySequence
from PySide6.QtWidgets import QApplication, QDockWidget, QMainWindow, QMenu, QVBoxLayout, QWidget

from mechsketch.core import ExportError

from .autosave import Autosave
from .busy import BusyIndicator
from .controller import SceneController
from .dialogs import DialogService
from .status_label import StatusLabel
from .file_ops import FileOps
from .clipboard import ClipboardCommands
from .drops import DropTarget
from .help.actions import HelpCommands
from .underlays import UnderlayCommands
from .design_docks import DesignDocks
from .drawing_export import export_drawing, export_parts, export_target
from . import units
from .preferences import (Preferences, apply_preferences, load_preferences, open_preferences_dialog,
                          store_preferences)
from .panels.diagnostics import DiagnosticsPanel
from .panels.properties import PropertiesPanel
from .input_policy import InputPolicy
from .qtsafe import qt_safe


#: the tool buttons' labels on the toolbar (by action name; tools not listed keep their title)
TOOL_LABELS = {"tool_select": "Select", "tool_ground": "Pivot", "tool_crank": "Crank", "tool_rrr": "RRR",
               "tool_rrp": "RRP", "tool_rpr": "RPR", "tool_prp": "PRP", "tool_rpp": "RPP", "tool_coupler": "Point",
               "tool_geneva": "Geneva", "tool_rolling": "Lever", "tool_measure": "Measure", "tool_delete": "Delete",
               "tool_insert": "Insert"}


def redo_shortcuts() -> list[QKeySequence]:
    """Redo answers the platform's key and both common ones, Ctrl+Y and Ctrl+Shift+Z: on X11 the
    standard Redo is Ctrl+Shift+Z only, and the README documents Ctrl+Y."""
    keys = list(QKeySequence.keyBindings(QKeySequence.StandardKey.Redo))
    for extra in ("Ctrl+Y", "Ctrl+Shift+Z"):
        seq = QKeySequence(extra)
        if seq not in keys:
            keys.append(seq)
    return keys


#: version of the saved dock layout (bump when the docks change)
LAYOUT_VERSION = 1

#: the plots panel's size hint and minimum size hint (px), given to its stand-in until it is made
#: so that the first layout (and the canvas's first zoom to fit) is the one the panel gets
#: (tests/gui/test_startup_imports.py checks them against the real panel)
PLOTS_SIZE_HINT = (604, 511)
PLOTS_MINIMUM_SIZE_HINT = (175, 99)


@dataclass
class CanvasParts:
    """What the canvas side contributes to the window, already wired to each other.

    ``view``: the canvas; ``player``: the animation player; ``scrubbar``: the widget under the
    canvas; ``tools``: checkable, exclusive tool actions; ``view_actions``: zoom to fit, snap, ...;
    ``animation_actions``: play/pause, direction, steps...; ``delete`` / ``zoom_fit``: the canvas's
    own Delete and Zoom-to-fit actions; ``stop``: pause the animation (called on close).
    """

    view: QWidget
    player: QObject
    scrubbar: QWidget
    tools: list[QAction] = field(default_factory=list)
    view_actions: list[QAction] = field(default_factory=list)
    animation_actions: list[QAction] = field(default_factory=list)
    delete: QAction | None = None
    zoom_fit: QAction | None = None
    stop: Callable[[], None] | None = None
    #: more entries for the menus, by menu ("file", "view", "examples"): QActions or QMenus (submenus)
    menus: dict[str, list] = field(default_factory=dict)


#: makes the canvas parts for a controller and the window (status-bar sinks); see app.py
Components = Callable[[SceneController, "MainWindow"], CanvasParts]


@qt_safe
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
        self.cursor_label = StatusLabel()   # fixed size while it changes: no status-bar layout per move
        self.parts = components(controller, self)
        self.canvas, self.player, self.scrubbar = self.parts.view, self.parts.player, self.parts.scrubbar
        central = QWidget()
        column = QVBoxLayout(central)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(0)
        column.addWidget(self.canvas, 1)
        column.addWidget(self.scrubbar)
        self.setCentralWidget(central)
        self.properties = PropertiesPanel(controller)
        self.diagnostics = DiagnosticsPanel(controller)
        self.docks = {
            "properties": self._dock("Properties", self.properties, Qt.DockWidgetArea.LeftDockWidgetArea),
            "diagnostics": self._dock("Diagnostics", self.diagnostics, Qt.DockWidgetArea.LeftDockWidgetArea),
            "plots": self._dock("Plots", self._make_plots, Qt.DockWidgetArea.RightDockWidgetArea),
        }
        self.design_docks = DesignDocks(self, self.docks)   # Study and Design docks (issues 21, 22, 25), by the plots
        self.layout_restored = self.restore_layout()
        self._docks_sized = self.layout_restored

        # -- actions, menus, toolbar, status bar --------------------------------------------
        self._make_actions()
        self._make_menus()
        self._make_toolbar()
        self.frame_label = StatusLabel()
        self.solve_label = StatusLabel()
        self._exporter = None
        self.export_titles = ("DXF exported", "Export DXF")   # of the running export: done, failed
        self.statusBar().addPermanentWidget(self.cursor_label)
        self.statusBar().addPermanentWidget(self.solve_label)
        self.statusBar().addPermanentWidget(self.frame_label)
        self.busy = BusyIndicator(controller.background)   # a heavy solve off the GUI thread (issue 20)
        self.statusBar().addPermanentWidget(self.busy)

        # -- preferences (issue 24 item 9): units, snap, samples, dead points, new parts -----------
        self.preferences = load_preferences(file_ops.settings)
        self.preferences_dialog = None
        apply_preferences(self.preferences, self, autosave=False)   # the app sets the interval it starts with

        # -- wiring -------------------------------------------------------------------------
        self.drops = DropTarget(self)   # scene files open, drawings and pictures become underlays
        # keyboard and wheel habits (issue 24, items 1-2): Enter in a field gives the keys back to
        # the canvas; shortcuts beat an unchanged field; the wheel does not edit unfocused boxes
        self.properties.editingDone.connect(self.canvas.setFocus)
        self.input_policy = InputPolicy(self)
        QApplication.instance().installEventFilter(self.input_policy)
        controller.message.connect(self.show_message)
        controller.solveFailed.connect(self._on_solve_failed)
        controller.pathChanged.connect(self.update_title)
        controller.changed.connect(self._on_changed)
        controller.frameChanged.connect(self._update_frame)
        file_ops.recentChanged.connect(self._fill_recent)
        self.update_title()
        self._update_status()

    # -- construction helpers ----------------------------------------------------------------
    def _dock(self, title: str, widget: QWidget | Callable[[], QWidget], area: Qt.DockWidgetArea) -> QDockWidget:
        """A dock holding ``widget``, or (a function) the widget it makes after the first frame."""
        dock = QDockWidget(title, self) if isinstance(widget, QWidget) else \
            LazyDock(title, self, widget, QSize(*PLOTS_SIZE_HINT), QSize(*PLOTS_MINIMUM_SIZE_HINT))
        dock.setObjectName(f"dock:{title}")
        if isinstance(widget, QWidget):
            dock.setWidget(widget)
        self.addDockWidget(area, dock)
        return dock

    def _make_plots(self) -> QWidget:
        from .panels.plots import PlotsPanel

        plots = PlotsPanel(self.controller, settings=self.file_ops.settings)   # remembers the chosen plots
        plots.add_header_actions([self.actions["export_png"], self.actions["export_csv"]])
        return plots

    @property
    def plots(self):
        """The plots panel (:class:`~mechsketch.gui.panels.plots.PlotsPanel`), made now if the
        window has not made it yet."""
        return self.docks["plots"].widget()

    @property
    def exporter(self):
        """The part exporter (:class:`~mechsketch.gui.export_worker.DxfExporter`), made on first use
        with its status-bar widget :attr:`export_status`."""
        if self._exporter is None:
            from .export_worker import DxfExporter, ExportStatus

            self._exporter = DxfExporter(self)
            self._export_status = ExportStatus(self._exporter)
            self.statusBar().insertPermanentWidget(0, self._export_status)
            self._exporter.finished.connect(self._export_finished)
            self._exporter.failed.connect(self._export_failed)
            self._exporter.cancelled.connect(self.show_message)
        return self._exporter

    @property
    def export_status(self) -> QWidget:
        """The exporter's status-bar widget (busy bar, stage, Cancel)."""
        self.exporter
        return self._export_status

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
        self._action("export_dxf", "Export &DXF…", self.export_dxf, "Ctrl+E",
                     "Write the selected element's cut-ready parts as a DXF drawing (mm)")
        self._action("export_svg", "Export S&VG…", self.export_svg,
                     tip="Write the selected element's cut-ready parts as SVG (mm; laser cutters)")
        self._action("export_drawing", "Export Dra&wing (PDF)…", lambda: export_drawing(self),
                     tip="A drawing sheet per element: parts to scale, dimensioned, title block, analysis summary")
        self._action("quit", "&Quit", self.close, K.Quit)
        undo = self.controller.undo_stack.createUndoAction(self, "&Undo")
        undo.setShortcut(QKeySequence(K.Undo))
        redo = self.controller.undo_stack.createRedoAction(self, "&Redo")
        redo.setShortcuts(redo_shortcuts())
        self.actions["undo"], self.actions["redo"] = undo, redo
        if self.parts.delete is not None:
            self.actions["delete"] = self.parts.delete
        if self.parts.zoom_fit is not None:
            self.actions["zoom_fit"] = self.parts.zoom_fit
        self._action("about", "&About mechsketch", self.about)
        prefs = self._action("preferences", "Pre&ferences…", self.open_preferences, "Ctrl+,",
                             "Units, grid and snap, samples, autosave, dead points, defaults of new parts")
        keys = [QKeySequence("Ctrl+,")] + [k for k in QKeySequence.keyBindings(K.Preferences)
                                           if k.toString() != "Ctrl+,"]
        prefs.setShortcuts(keys)
        # -- clipboard, underlays (issue 24 item 10, issue 22 item 6): Ctrl+C/V/D, Import Underlay
        self.clipboard_commands = ClipboardCommands(self)
        self.underlay_commands = UnderlayCommands(self, self.dialogs)
        self.actions.update(self.clipboard_commands.actions)
        self.actions.update(self.underlay_commands.actions)
        # -- help (issue 24 item 8): Manual (F1, context help), Getting Started, Shortcuts
        self.help = HelpCommands(self)
        self.actions.update(self.help.actions)
        for name in self.file_ops.examples():
            self._action(f"example:{name}", name.replace("_", " "),
                         lambda name=name: self.file_ops.open_example(name), tip=f"Open the example {name}")

    def _make_menus(self) -> None:
        a = self.actions
        bar = self.menuBar()
        file_menu = bar.addMenu("&File")
        file_menu.addActions([a["new"], a["open"]])
        self.recent_menu = QMenu("Open &Recent", self)
        self.recent_menu.setToolTipsVisible(True)   # each entry's full path on hover
        file_menu.addMenu(self.recent_menu)
        file_menu.addActions([a["save"], a["save_as"]])
        file_menu.addSeparator()
        file_menu.addActions([a["export_dxf"], a["export_svg"], a["export_drawing"], a["export_png"], a["export_csv"]])
        file_menu.addSeparator()
        file_menu.addAction(a["import_underlay"])
        self._add_extra(file_menu, "file")
        file_menu.addSeparator()
        file_menu.addAction(a["quit"])
        self._fill_recent()
        edit = bar.addMenu("&Edit")
        edit.addActions([a["undo"], a["redo"]])
        edit.addSeparator()
        edit.addActions([a["copy"], a["paste"], a["duplicate"]])
        if "delete" in a:
            edit.addSeparator()
            edit.addAction(a["delete"])
        edit.addSeparator()
        edit.addAction(a["preferences"])
        view = bar.addMenu("&View")
        view.addActions(self.parts.view_actions)
        view.addMenu(self.underlay_commands.menu(self))
        self._add_extra(view, "view")
        if self.parts.animation_actions:
            animation = view.addMenu("&Animation")
            animation.addActions(self.parts.animation_actions)
        view.addSeparator()
        for dock in self.docks.values():
            view.addAction(dock.toggleViewAction())
        tools = bar.addMenu("&Tools")
        tools.addActions(self.parts.tools)
        examples = bar.addMenu("E&xamples")
        for name in self.file_ops.examples():
            examples.addAction(a[f"example:{name}"])
        self._add_extra(examples, "examples")
        help_menu = bar.addMenu("&Help")
        help_menu.addActions([a["manual"], a["getting_started"], a["shortcuts"]])
        help_menu.addSeparator()
        help_menu.addAction(a["about"])

    def _add_extra(self, menu: QMenu, key: str) -> None:
        """Append the canvas side's extra entries for ``key`` (actions, or submenus) to ``menu``."""
        extra = self.parts.menus.get(key, [])
        if extra:
            menu.addSeparator()
        for entry in extra:
            menu.addMenu(entry) if isinstance(entry, QMenu) else menu.addAction(entry)

    def _make_toolbar(self) -> None:
        a = self.actions
        bar = self.addToolBar("Main")
        bar.setObjectName("toolbar:main")
        bar.addActions([a["new"], a["open"], a["save"]])
        bar.addSeparator()
        bar.addActions([a["undo"], a["redo"]])
        if "zoom_fit" in a:
            bar.addSeparator()
            bar.addAction(a["zoom_fit"])
        if self.parts.tools:
            self.addToolBarBreak()   # the tools on a row of their own: a 1024 px screen shows them all
            tools = self.addToolBar("Tools")
            tools.setObjectName("toolbar:tools")
            tools.addActions(self.parts.tools)
            for action in self.parts.tools:   # short labels; the tooltip and the Tools menu say it in full
                button = tools.widgetForAction(action)
                short = TOOL_LABELS.get(action.objectName())
                if button is not None and short:
                    button.setText(short)

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        recent = self.file_ops.recent_files()
        for k, path in enumerate(recent):
            action = self.recent_menu.addAction(f"&{k + 1} {Path(path).name}")
            action.setStatusTip(path)
            action.setToolTip(path)
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
        """A transient status-bar message."""
        self.statusBar().showMessage(text, 8000)

    def show_cursor(self, x: float, y: float) -> None:
        """The pointer's world position in the status bar."""
        u = units.current()
        self.cursor_label.setText(f"{units.to_display(x, 'mm', u):.{2 if u.length == 'mm' else 4}f}, "
                                  f"{units.to_display(y, 'mm', u):.{2 if u.length == 'mm' else 4}f} {u.length}")

    def _on_changed(self, _change) -> None:
        self.update_title()
        self._update_status()

    def _update_status(self) -> None:
        parts = []
        for eid, res in self.controller.results().items():
            if res.error is not None:
                parts.append(f"{eid}: not solved")
            elif res.solution is not None:
                parts.append(f"{eid}: {len(res.solution):,} poses, {res.seconds * 1e3:.1f} ms")
        for eid, er in self.controller.element_results().items():
            parts.append(f"{eid}: not drawn" if er.n_frames == 0 else
                         f"{eid}: {er.n_frames:,} frames, {er.seconds * 1e3:.1f} ms")
        self.solve_label.setText("; ".join(parts))
        self._update_frame()

    def _on_solve_failed(self, element_id: str, message: str) -> None:
        self.show_message(f"{element_id}: {message}")

    def _update_frame(self, _frame: int = 0) -> None:
        text, _ok = self.controller.frame_text()
        self.frame_label.setText("" if self.controller.sample_count() == 0 else text)

    # -- commands ----------------------------------------------------------------------------
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

    def export_target(self):
        """The element to export: the selected one, else the only one (None if there are several)."""
        return export_target(self)

    def export_dxf(self) -> bool:
        """Ask for the options and a file, then export the parts as DXF off the GUI thread."""
        return export_parts(self, "dxf")

    def export_svg(self) -> bool:
        """Ask for the options and a file, then export the parts as SVG off the GUI thread."""
        return export_parts(self, "svg")

    def export_parts(self, fmt: str) -> bool:
        """File › Export DXF/SVG (:func:`.drawing_export.export_parts`; True: started)."""
        return export_parts(self, fmt)

    def _export_finished(self, report: str) -> None:
        self.show_message(report.splitlines()[0] if report else "exported")
        self.dialogs.info(self.export_titles[0], report)

    def _export_failed(self, message: str) -> None:
        self.show_message(message)
        self.dialogs.error(self.export_titles[1], f"{message}\n\nThe scene is not affected.")

    # -- preferences (gui/preferences.py) --------------------------------------------------------
    def open_preferences(self) -> None:
        """Edit › Preferences: the dialog (window-modal, not blocking); OK stores and applies."""
        open_preferences_dialog(self)

    def set_preferences(self, prefs: Preferences) -> bool:
        """Store ``prefs`` in the settings file and apply them (False, with the reason, if not)."""
        return store_preferences(self, prefs)

    def about(self) -> None:
        from importlib.metadata import PackageNotFoundError, version

        try:
            v = version("mechsketch")
        except PackageNotFoundError:
            v = "(development)"
        self.dialogs.info("About mechsketch",
                          f"mechsketch {v}\nDesktop CAD for planar mechanisms: linkages solved by Assur "
                          "groups in closed form, Geneva drives, rolling levers, DXF export.")

    def showEvent(self, event) -> None:  # noqa: N802 - Qt override
        super().showEvent(event)
        if not self._docks_sized:  # dock sizes only stick once the window is laid out
            self._docks_sized = True
            QTimer.singleShot(0, self.size_docks)

    def size_docks(self) -> None:
        """Share the width between the docks and the canvas (about 1 : 2.4 : 1.6); on a small
        screen (1024 px) the properties keep the 300 px their rows need and the plots give way."""
        side = max(300, min(340, self.width() // 5))
        plots = max(250, min(560, self.width() * 3 // 10))
        self.resizeDocks([self.docks["properties"], self.docks["plots"]], [side, plots],
                         Qt.Orientation.Horizontal)
        self.resizeDocks([self.docks["properties"], self.docks["diagnostics"]],
                         [self.height() * 11 // 20, self.height() * 9 // 20], Qt.Orientation.Vertical)

    # -- closing -----------------------------------------------------------------------------
    def restore_layout(self) -> bool:
        """Window size and dock layout from the settings (True if there was one to restore)."""
        settings = self.file_ops.settings
        geometry, state = settings.value("window/geometry"), settings.value("window/state")
        if not isinstance(geometry, QByteArray) or not isinstance(state, QByteArray):
            return False
        return self.restoreGeometry(geometry) and self.restoreState(state, LAYOUT_VERSION)

    def save_layout(self) -> None:
        settings = self.file_ops.settings
        settings.setValue("window/geometry", self.saveGeometry())
        settings.setValue("window/state", self.saveState(LAYOUT_VERSION))
        settings.sync()

    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802 - Qt override
        if not self.file_ops.maybe_save():
            event.ignore()
            return
        self.save_layout()
        if self._exporter is not None:
            self._exporter.cancel()
            self._exporter.wait()
        self.design_docks.shutdown()
        if self.parts.stop is not None:
            self.parts.stop()
        self.autosave.clean_exit()
        event.accept()


@qt_safe
class _FirstPaint(QWidget):
    """An empty widget that calls ``callback`` (through the event loop) once it has been painted;
    it asks for the size of the widget it stands in for."""

    def __init__(self, callback: Callable[[], Any], hint: QSize, minimum: QSize) -> None:
        super().__init__()
        self._callback: Callable[[], Any] | None = callback
        self._hint, self._minimum = hint, minimum

    def sizeHint(self) -> QSize:  # noqa: N802 - Qt override
        return self._hint

    def minimumSizeHint(self) -> QSize:  # noqa: N802 - Qt override
        return self._minimum

    def paintEvent(self, event) -> None:  # noqa: N802 - Qt override
        super().paintEvent(event)
        if self._callback is not None:
            callback, self._callback = self._callback, None
            QTimer.singleShot(0, self, callback)   # dropped if this widget is gone by then


@qt_safe
class LazyDock(QDockWidget):
    """A dock whose content ``factory()`` makes after the window's first frame: the dock first
    holds an empty widget; when that has been painted (the first frame is on screen), the content
    is made on the next turn of the event loop. :meth:`widget` makes it at once if it is not there
    yet, so code reading the dock always gets the real content. ``hint`` and ``minimum``: the
    content's size hints, which the stand-in reports so that the window lays out as with it."""

    def __init__(self, title: str, parent: QWidget, factory: Callable[[], QWidget], hint: QSize,
                 minimum: QSize) -> None:
        super().__init__(title, parent)
        self._factory: Callable[[], QWidget] | None = factory
        super().setWidget(_FirstPaint(self.ensure_content, hint, minimum))

    @property
    def pending(self) -> bool:
        """True until the content has been made."""
        return self._factory is not None

    def ensure_content(self) -> QWidget:
        """Make the content now if it is not made yet; returns it."""
        if self._factory is not None:
            factory, self._factory = self._factory, None
            placeholder = super().widget()
            self.setWidget(factory())
            if placeholder is not None:
                placeholder.deleteLater()
        return super().widget()

    def widget(self) -> QWidget:  # noqa: D102 - QDockWidget.widget, made on demand
        return self.ensure_content()
