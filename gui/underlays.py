"""Underlay commands: File › Import Underlay…, and View › Underlays ▸ Show, Place by Two Points,
Move, Remove — each change one undo step (issue 22 item 6).

An imported drawing keeps its own coordinates in millimetres (a DXF's units, an SVG's CSS pixels);
a picture, or a drawing dropped on the canvas, is centred where it was dropped (else in the view),
a picture 80 % of the view wide. Right after an import the app asks for two points of known
distance: click two points of the underlay (its vertices snap), type the distance between them,
and the underlay is scaled about the first point (Esc keeps the placement as it is). *Move*
drags the underlay with the mouse (one undo step on release). A hidden underlay is not drawn and
its points do not snap.

The clicks of a placement or a move are read by :class:`CanvasSession`, an event filter on the
canvas (the canvas tools see none of them while it runs).
"""
from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any, Callable

from PySide6.QtCore import QEvent, QObject, QPointF, Qt
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QMenu

from mechsketch.core import MechsketchError
from mechsketch.core.model.edits import AddElement, RemoveElement, ReplaceElement
from mechsketch.core.model.transform import fresh_id
from mechsketch.core.model.underlay import Underlay

from . import units
from .dialogs import DialogService
from .selection import ELEMENT
from .qtsafe import qt_safe

UNDERLAY_FILTER = ("Drawings and pictures (*.dxf *.svg *.png *.jpg *.jpeg *.bmp *.gif *.tif *.tiff *.webp);;"
                   "DXF drawings (*.dxf);;SVG drawings (*.svg);;Pictures (*.png *.jpg *.jpeg *.bmp *.gif *.tif "
                   "*.tiff *.webp);;All files (*)")
XY = tuple[float, float]


@qt_safe
class CanvasSession(QObject):
    """Reads left clicks (and drags) on the canvas for a command until it ends; Esc cancels.

    ``on_press(world)``, ``on_move(world)``, ``on_release(world)`` get world points (mm);
    ``on_cancel()`` is called on Esc or when another session starts."""

    def __init__(self, view, on_press: Callable[[XY], None], on_move: Callable[[XY], None] | None = None,
                 on_release: Callable[[XY], None] | None = None, on_cancel: Callable[[], None] | None = None):
        super().__init__(view)
        self.view = view
        self.on_press, self.on_move, self.on_release, self.on_cancel = on_press, on_move, on_release, on_cancel
        self.pressed = False
        view.viewport().installEventFilter(self)
        view.installEventFilter(self)

    def end(self) -> None:
        self.view.viewport().removeEventFilter(self)
        self.view.removeEventFilter(self)
        self.deleteLater()

    def cancel(self) -> None:
        self.end()
        if self.on_cancel is not None:
            self.on_cancel()

    def _world(self, event) -> XY:
        p = self.view.mapToScene(event.position().toPoint())
        return (p.x(), p.y())

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:  # noqa: N802 - Qt override
        kind = event.type()
        if kind == QEvent.Type.KeyPress and event.key() == Qt.Key.Key_Escape:
            self.cancel()
            return True
        if obj is not self.view.viewport():
            return False
        if kind == QEvent.Type.MouseButtonPress and event.button() == Qt.MouseButton.LeftButton:
            self.pressed = True
            self.on_press(self._world(event))
            return True
        if kind == QEvent.Type.MouseMove and self.on_move is not None:
            self.on_move(self._world(event))
            return self.pressed
        if kind == QEvent.Type.MouseButtonRelease and event.button() == Qt.MouseButton.LeftButton:
            self.pressed = False
            if self.on_release is not None:
                self.on_release(self._world(event))
            return True
        return kind in (QEvent.Type.MouseButtonDblClick,)


class UnderlayCommands(QObject):
    """The underlay actions of one window (``window``: the main window, read for its canvas,
    controller and dialogs)."""

    def __init__(self, window: Any, dialogs: DialogService) -> None:
        super().__init__(window)
        self.window = window
        self.controller = window.controller
        self.dialogs = dialogs
        self.session: CanvasSession | None = None
        self._points: list[XY] = []
        self._drag: tuple[Underlay, XY] | None = None
        self.actions: dict[str, QAction] = {}
        for name, text, slot, key, tip in (
                ("import_underlay", "Import &Underlay…", self.import_dialog, "Ctrl+Shift+I",
                 "Put a DXF or SVG drawing or a picture under the canvas to draw over"),
                ("place_underlay", "&Place by Two Points…", self.start_placing, None,
                 "Click two points of the underlay and type their distance: it is scaled to it"),
                ("move_underlay", "&Move", self.start_moving, None, "Drag the underlay with the mouse"),
                ("remove_underlay", "&Remove", self.remove, None, "Remove the underlay from the scene"),
                ("show_underlays", "&Show Underlays", self.toggle_visible, "Ctrl+Shift+U",
                 "Show or hide the underlays (hidden ones do not snap)")):
            act = QAction(text, window)
            act.setObjectName(name)
            if key:
                act.setShortcut(QKeySequence(key))
            act.setStatusTip(tip)
            act.triggered.connect(lambda _c=False, s=slot: s())
            self.actions[name] = act
        self.actions["show_underlays"].setCheckable(True)
        self.controller.changed.connect(self._update_actions)
        self.controller.documentReplaced.connect(self._on_replaced)
        self._update_actions()

    def menu(self, parent) -> QMenu:
        """View › Underlays ▸ (show, place, move, remove)."""
        menu = QMenu("&Underlays", parent)
        a = self.actions
        menu.addActions([a["show_underlays"], a["place_underlay"], a["move_underlay"], a["remove_underlay"]])
        return menu

    # -- state -------------------------------------------------------------------------------
    def underlays(self) -> list[Underlay]:
        return [e for e in self.controller.scene.elements if isinstance(e, Underlay)]

    def target(self) -> Underlay | None:
        """The selected underlay, else the last one of the scene."""
        scene = self.controller.scene
        for eid, kind, _ in self.controller.selection:
            if kind == ELEMENT and eid in scene.ids and isinstance(scene.element(eid), Underlay):
                return scene.element(eid)
        found = self.underlays()
        return found[-1] if found else None

    def _update_actions(self, *_args) -> None:
        found = self.underlays()
        show = self.actions["show_underlays"]
        show.blockSignals(True)
        show.setChecked(any(u.visible for u in found))
        show.blockSignals(False)
        for name in ("show_underlays", "place_underlay", "move_underlay", "remove_underlay"):
            self.actions[name].setEnabled(bool(found))

    def _on_replaced(self) -> None:
        self.stop()
        self._update_actions()

    def _say(self, text: str) -> None:
        self.controller.message.emit(text)

    # -- import ------------------------------------------------------------------------------
    def import_dialog(self) -> bool:
        """File › Import Underlay…: ask for a file, then :meth:`import_file`."""
        start = str(self.controller.path.parent) if self.controller.path else str(Path.home())
        name = self.dialogs.open_file_name("Import underlay", start, UNDERLAY_FILTER)
        return bool(name) and self.import_file(name)

    def import_file(self, path: str | Path, at: XY | None = None, place: bool = True) -> bool:
        """Read ``path`` as an underlay and add it (one undo step); ``at``: where it was dropped.
        Then, with ``place``, ask for two points of known distance. False (with the reason) if the
        file cannot be read."""
        from mechsketch.core.io.underlay_files import placed, read_underlay

        view = self._view()
        try:
            u, mm = read_underlay(path, fresh_id(id_from(path), self.controller.scene.ids))
        except MechsketchError as exc:
            self._say(str(exc))
            self.dialogs.error("Cannot import underlay", f"{exc}\n\nThe scene is not affected.")
            return False
        centre, width = at, None
        if view is not None:
            r = view.mapToScene(view.viewport().rect()).boundingRect()
            centre = centre or (r.center().x(), r.center().y())
            width = 0.8 * r.width()
        if u.image is None and at is None and Path(path).suffix.lower() == ".dxf":
            centre = None                     # a DXF keeps its own coordinates
        u = placed(u, mm, centre if u.image is not None or centre is not None else None, width)
        text = f"import underlay {u.name}"
        if not self.controller.push(AddElement(u, label=text), text):
            return False
        self.controller.set_selection([(u.id, ELEMENT, u.id)])
        if view is not None and not _inside(view, u.world_bounds()):
            view.zoom_to_fit()
        what = f"{len(u.paths)} path(s)" if u.image is None else f"{u.image.width}×{u.image.height} px"
        self._say(f"underlay {u.id}: {u.name} ({what})")
        if place and view is not None:
            self.start_placing()
        return True

    # -- two points of known distance ----------------------------------------------------------
    def _view(self):
        view = getattr(self.window, "canvas", None)
        return view if hasattr(view, "viewport") and hasattr(view, "mapToScene") else None

    def _start(self, **handlers) -> CanvasSession | None:
        self.stop()
        view = self._view()
        if view is None:
            return None
        self.session = CanvasSession(view, **handlers)
        return self.session

    def stop(self) -> None:
        """End a running placement or move without changing anything."""
        if self.session is not None:
            session, self.session = self.session, None
            session.cancel()

    def start_placing(self) -> bool:
        """Place by two points: click two points of the underlay, then type their distance."""
        u = self.target()
        if u is None:
            self._say("no underlay: File › Import Underlay… first")
            return False
        self._points = []
        self._placing = u.id
        if self._start(on_press=self._place_click, on_cancel=self._place_cancelled) is None:
            return False
        self._say(f"underlay {u.id}: click the first of two points of known distance (Esc keeps it as it is)")
        return True

    def _snapped(self, world: XY) -> XY:
        view = self._view()
        near = view.underlays.snap(world, 8.0 * view.px()) if hasattr(view, "underlays") else None
        return near if near is not None else world

    def _place_click(self, world: XY) -> None:
        self._points.append(self._snapped(world))
        if len(self._points) == 1:
            x, y = self._points[0]
            self._say(f"first point ({units.format_length(x)}, {units.format_length(y)}); click the second")
            return
        a, b = self._points
        session, self.session = self.session, None
        if session is not None:
            session.end()
        self.place(self._placing, a, b)

    def _place_cancelled(self) -> None:
        self._say("placement cancelled: the underlay stays as it is")

    def place(self, element_id: str, a: XY, b: XY, distance_mm: float | None = None) -> bool:
        """Scale underlay ``element_id`` about ``a`` so that ``a``–``b`` is ``distance_mm`` long
        (asked for when None, in the display unit); one undo step."""
        now = math.dist(a, b)
        if now <= 1e-9:
            self._say("the two points coincide: click two different points of the underlay")
            return False
        if distance_mm is None:
            u = units.current()
            shown = self.dialogs.ask_number("Distance between the two points",
                                            "The distance the two points are apart", units.to_display(now, "mm", u),
                                            units.display_unit("mm", u))
            if shown is None:
                self._say("placement cancelled: the underlay stays as it is")
                return False
            distance_mm = units.to_model(shown, "mm", u)
        if not (distance_mm > 0 and math.isfinite(distance_mm)):
            self._say(f"a distance must be a positive number, not {distance_mm}")
            return False
        el = self.controller.scene.element(element_id)
        new = el.with_placement(el.placement.scaled_about(a, distance_mm / now))
        text = f"place underlay {element_id}"
        if self.controller.push(ReplaceElement(new, text), text):
            self._say(f"underlay {element_id} scaled ×{distance_mm / now:.6g}: the two points are "
                      f"{units.format_length(distance_mm)} apart")
            return True
        return False

    # -- move ----------------------------------------------------------------------------------
    def start_moving(self) -> bool:
        """Drag the underlay: press, move, release (one undo step)."""
        u = self.target()
        if u is None:
            self._say("no underlay to move")
            return False
        self._drag = None
        self._moving = u.id
        self._start(on_press=self._move_press, on_move=self._move_to, on_release=self._move_release,
                    on_cancel=self._move_cancel)
        self._say(f"underlay {u.id}: drag it where it belongs (Esc cancels)")
        return True

    def _move_press(self, world: XY) -> None:
        self._drag = (self.controller.scene.element(self._moving), world)
        self.controller.begin_preview()

    def _moved(self, world: XY) -> Underlay | None:
        if self._drag is None:
            return None
        base, start = self._drag
        return base.with_placement(base.placement.moved(world[0] - start[0], world[1] - start[1]))

    def _move_to(self, world: XY) -> None:
        new = self._moved(world)
        if new is not None:
            self.controller.preview(ReplaceElement(new, "move underlay"))

    def _move_release(self, world: XY) -> None:
        new = self._moved(world)
        self._drag = None
        session, self.session = self.session, None
        if session is not None:
            session.end()
        if new is not None:
            self.controller.end_preview(ReplaceElement(new, f"move underlay {new.id}"), f"move underlay {new.id}")
            self._say(f"underlay {new.id} moved")

    def _move_cancel(self) -> None:
        if self._drag is not None:
            self._drag = None
            self.controller.end_preview(None)
        self._say("move cancelled")

    # -- show, remove --------------------------------------------------------------------------
    def toggle_visible(self) -> None:
        """Show or hide every underlay, as the action's check mark now says; one undo step."""
        on = self.actions["show_underlays"].isChecked()
        self.set_visible(on)

    def set_visible(self, on: bool) -> bool:
        changed = [u for u in self.underlays() if u.visible != on]
        if not changed:
            return False
        text = "show underlays" if on else "hide underlays"
        stack = self.controller.undo_stack
        stack.beginMacro(text)
        try:
            for u in changed:
                self.controller.push(ReplaceElement(u.with_visible(on), text), text)
        finally:
            stack.endMacro()
        self._say(f"{len(changed)} underlay(s) {'shown' if on else 'hidden (they do not snap)'}")
        return True

    def remove(self) -> bool:
        u = self.target()
        if u is None:
            return False
        self.stop()
        text = f"remove underlay {u.id}"
        return self.controller.push(RemoveElement(u.id, text), text)


def id_from(path: str | Path) -> str:
    """An element id from a file name: its stem, spaces and control characters as ``_``."""
    stem = re.sub(r"[\s\x00-\x1f\x7f]+", "_", Path(path).stem).strip("_")[:48]
    return stem or "underlay"


def _inside(view, bounds: tuple[float, float, float, float]) -> bool:
    r = view.mapToScene(view.viewport().rect()).boundingRect()
    return r.contains(QPointF(bounds[0], bounds[1])) and r.contains(QPointF(bounds[2], bounds[3]))
