"""Insert: place an example or a saved scene into the current scene where the user clicks.

:class:`InsertTool` is made active by a command (Examples -> Insert), not from the toolbar: it
holds the elements to place, shows their box following the mouse and, on a click, adds them
moved so that their centre lands on the click - renamed where an id is taken
(:func:`mechsketch.core.model.transform.placed`) - as one undo step. Esc cancels.
:func:`insert_menu` builds the submenu: one entry per built-in example, and "Scene File…".
"""
from __future__ import annotations

from PySide6.QtGui import QAction
from PySide6.QtWidgets import QMenu, QWidget

from mechsketch import resources
from mechsketch.core import MechsketchError, load_scene
from mechsketch.core.model.edits import AddElement
from mechsketch.core.model.transform import extent, placed

from ..selection import ELEMENT
from .events import CanvasEvent
from .items import Overlay
from .tool_base import Tool


class InsertTool(Tool):
    """Click to place the loaded elements (see the module docstring)."""

    name, title, shortcut = "insert", "Insert scene", ""
    hint = "Insert: click where the inserted scene's centre goes (Esc cancels)"
    in_toolbar = False

    def __init__(self, ctx) -> None:
        self.elements: list = []
        self.source = ""
        super().__init__(ctx)

    def load(self, elements: list, source: str) -> None:
        """The elements to place next (an example's or a file's), from ``source`` (for messages)."""
        self.elements, self.source = list(elements), source

    def _box(self) -> tuple[float, float, float, float]:
        boxes = [extent(e) for e in self.elements]
        return (min(b[0] for b in boxes), min(b[1] for b in boxes), max(b[2] for b in boxes), max(b[3] for b in boxes))

    def on_move(self, ev: CanvasEvent) -> None:
        if not self.elements:
            return
        x0, y0, x1, y1 = self._box()
        cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
        dx, dy = ev.pos[0] - cx, ev.pos[1] - cy
        a, b = (x0 + dx, y0 + dy), (x1 + dx, y1 + dy)
        self._overlay = Overlay(rect=(a, b), points=[ev.pos],
                                labels=[(b, f"{self.source}: {', '.join(e.id for e in self.elements)}")])

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        if not self.elements:
            self.explain("insert: choose an example or a scene file first (Examples → Insert)")
            return
        ctl = self.ctx.controller
        new = placed(self.elements, ev.pos, ctl.scene.ids)
        stack = ctl.undo_stack
        text = f"insert {self.source}"
        stack.beginMacro(text)
        try:
            done = [ctl.push(AddElement(e, label=text), text) for e in new]
        finally:
            stack.endMacro()
        if all(done):
            ctl.set_selection([(e.id, ELEMENT, e.id) for e in new if e.type != "linkage"])
            renamed = [f"{o.id} → {n.id}" for o, n in zip(self.elements, new) if o.id != n.id]
            self.explain(f"inserted {self.source} at ({ev.pos[0]:.1f}, {ev.pos[1]:.1f})"
                         + (f"; renamed {', '.join(renamed)}" if renamed else ""))
        self.elements = []
        self._overlay = Overlay()

    def cancel(self) -> None:
        self.elements = []
        super().cancel()


def insert_menu(view, dialogs, parent: QWidget | None = None) -> QMenu:
    """The Examples -> Insert submenu: the built-in examples and "Scene File…" (asks ``dialogs``)."""
    menu = QMenu("&Insert", parent)
    menu.setObjectName("insertMenu")

    def start(path, source: str) -> None:
        try:
            scene = load_scene(path)
        except (MechsketchError, OSError) as exc:
            view.controller.message.emit(f"cannot insert {source}: {exc}")
            dialogs.error("Insert", f"{source} cannot be inserted: {exc}\n\nThe current scene is kept.")
            return
        if not scene.elements:
            view.controller.message.emit(f"{source} has no elements to insert")
            return
        tool = view.toolbox.tools["insert"]
        view.set_tool("insert")
        tool.load(scene.elements, source)
        view.controller.message.emit(f"insert {source}: click where it goes (Esc cancels)")

    for path in resources.example_paths():
        act = QAction(path.stem.replace("_", " "), menu)
        act.setObjectName(f"insert:{path.stem}")
        act.triggered.connect(lambda _c=False, p=path: start(p, p.stem))
        menu.addAction(act)
    menu.addSeparator()
    act = QAction("Scene &File…", menu)
    act.setObjectName("insert:file")

    def from_file() -> None:
        name = dialogs.open_file_name("Insert scene", "", "mechsketch scenes (*.json);;All files (*)")
        if name:
            start(name, name.rsplit("/", 1)[-1])

    act.triggered.connect(lambda _c=False: from_file())
    menu.addAction(act)
    return menu

