"""Mouse, wheel and key routing of the canvas: Qt input events become tool events, pans and zooms.

:class:`CanvasInput` is the input half of :class:`~mechsketch.gui.canvas.view.CanvasView`: the
view owns one and its Qt event handlers are one-line calls into it. A mouse event becomes a
:class:`~mechsketch.gui.canvas.events.CanvasEvent` (world and snapped positions, buttons,
modifiers, the pick under the cursor) that :meth:`~CanvasInput.dispatch` hands to a handle, a
load's handle or the active tool; the middle button or Space + left drag pans, a middle
double-click fits, the wheel zooms, the right button or Esc cancels, a tapped Space triggers the
tap action. A click with the select tool on a Geneva drive or rolling lever selects the element.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from PySide6.QtCore import QEvent, QPointF, Qt, SignalInstance
from PySide6.QtGui import QAction, QCursor, QKeyEvent, QMouseEvent, QWheelEvent
from PySide6.QtWidgets import QScrollBar

from ..selection import ELEMENT
from .events import XY, CanvasEvent, Hit
from .items import OverlayItem
from .typed_input import STARTS, snap_polar


class InputHost(Protocol):
    """What :class:`CanvasInput` uses of its view (the canvas view imports this module, so the
    input names the view's members instead of importing its class)."""

    ctx: Any                 # the tool context: ``ctx.pick(world, tol)``
    toolbox: Any             # ``.tool``, ``.name``
    extras: Any              # ``.handles``, ``.loads``: ``route``, ``cancel``
    controller: Any          # ``selection``, ``set_selection``
    cursorMoved: SignalInstance
    dragStarted: SignalInstance
    dragFinished: SignalInstance

    def world(self, pos: QPointF) -> XY: ...
    def px(self) -> float: ...
    def snap(self, raw: XY, hit: Hit | None) -> XY: ...
    def element_at(self, pos: XY, tol: float) -> str | None: ...
    def setCursor(self, cursor: QCursor | Qt.CursorShape) -> None: ...
    def horizontalScrollBar(self) -> QScrollBar: ...
    def verticalScrollBar(self) -> QScrollBar: ...
    def zoom_to_fit(self) -> None: ...
    def zoom_by(self, factor: float) -> None: ...


PICK_PX = 8.0                 # pick radius, screen pixels


class CanvasInput:
    """Mouse and key handling of one :class:`~mechsketch.gui.canvas.view.CanvasView`.

    It owns the input state: :attr:`hover` (the pick under the idle cursor, which the view's
    highlighting reads), the pan anchor, the Space key state, the tap action and whether a tool
    is busy (dragging). What it uses of the view, and nothing else:

    - positions: ``view.world(pos)``, ``view.px()``, ``view.snap(raw, hit)``, ``view.ctx.pick``;
    - routing: ``view.toolbox`` (``.tool``, ``.name``), ``view.extras.handles`` and
      ``view.extras.loads`` (``route``, ``cancel``);
    - element clicks: ``view.element_at(pos, tol)``, ``view.controller`` (``selection``,
      ``set_selection``);
    - feedback: the signals ``view.cursorMoved``, ``view.dragStarted``, ``view.dragFinished``;
      ``view.setCursor``, ``view.horizontalScrollBar()`` / ``verticalScrollBar()`` (pan),
      ``view.zoom_to_fit()`` (middle double-click), ``view.zoom_by(factor)`` (wheel);
    - passed in by the view: ``overlay`` (the tool overlay item), ``highlight()`` (redraw the
      hover and selection highlights) and ``show_frame()`` (re-pose the items at the displayed
      frame, after a drag).

    The ``*_event`` methods take the view's Qt events; ``key_press``, ``key_release`` and
    ``shortcut_override`` return False for an event they leave to ``QGraphicsView``.
    """

    def __init__(self, view: InputHost, overlay: OverlayItem, highlight: Callable[[], None],
                 show_frame: Callable[[], None]) -> None:
        self._view = view
        self._overlay = overlay
        self._highlight = highlight
        self._show_frame = show_frame
        self.hover: Hit | None = None
        self._pan_from: QPointF | None = None
        self._space = False
        self._space_panned = False
        self.tap_action: QAction | None = None
        self._busy = False

    # -- mouse ------------------------------------------------------------------------------------
    def _canvas_event(self, kind: str, e: QMouseEvent) -> CanvasEvent:
        view = self._view
        raw = view.world(e.position())
        tol = PICK_PX * view.px()
        hit = view.ctx.pick(raw, tol)
        names = {Qt.MouseButton.LeftButton: "left", Qt.MouseButton.RightButton: "right",
                 Qt.MouseButton.MiddleButton: "middle"}
        held = frozenset(n for b, n in names.items() if e.buttons() & b)
        mods = e.modifiers()
        modifiers = frozenset(n for m, n in ((Qt.KeyboardModifier.ShiftModifier, "shift"),
                                             (Qt.KeyboardModifier.ControlModifier, "ctrl"),
                                             (Qt.KeyboardModifier.AltModifier, "alt")) if mods & m)
        pos = view.snap(raw, hit)
        anchor = view.toolbox.tool.anchor() if "shift" in modifiers and view.toolbox.name != "select" else None
        if anchor is not None:   # Shift: 15° steps and whole grid steps from the tool's anchor
            pos = snap_polar(anchor, raw, view.snap_step())
        return CanvasEvent(kind, pos, raw, names.get(e.button(), "none"), held, modifiers, hit, tol)

    def dispatch(self, ev: CanvasEvent) -> None:
        """Hand ``ev`` to the active tool and show the result."""
        view = self._view
        tool = view.extras.handles.route(ev, view.toolbox.tool)   # a press on a handle drags it
        tool = view.extras.loads.route(ev, tool)                  # ... and on a load's handle
        if tool is view.toolbox.tool and self._select_element(ev):
            return
        tool.handle(ev)
        self._overlay.set_overlay(tool.overlay())
        if tool.busy != self._busy:
            self._busy = tool.busy
            (view.dragStarted if self._busy else view.dragFinished).emit()
            if not self._busy:
                self._show_frame()
        if ev.kind == "move" and not ev.buttons and ev.hit != self.hover:
            self.hover = ev.hit
            self._highlight()

    def press_event(self, e: QMouseEvent) -> None:
        if e.button() == Qt.MouseButton.MiddleButton or (e.button() == Qt.MouseButton.LeftButton and self._space):
            self._pan_from = e.position()
            self._space_panned = True
            self._view.setCursor(Qt.CursorShape.ClosedHandCursor)
            return
        if e.button() == Qt.MouseButton.RightButton:
            self.cancel_tool()
            return
        self.dispatch(self._canvas_event("press", e))

    def move_event(self, e: QMouseEvent) -> None:
        if self._pan_from is not None:
            view = self._view
            d = e.position() - self._pan_from
            self._pan_from = e.position()
            view.horizontalScrollBar().setValue(view.horizontalScrollBar().value() - round(d.x()))
            view.verticalScrollBar().setValue(view.verticalScrollBar().value() - round(d.y()))
            return
        ev = self._canvas_event("move", e)
        self._view.cursorMoved.emit(ev.pos[0], ev.pos[1])
        self.dispatch(ev)

    def release_event(self, e: QMouseEvent) -> None:
        if self._pan_from is not None:
            self._pan_from = None
            self._view.setCursor(Qt.CursorShape.OpenHandCursor if self._space else
                                 Qt.CursorShape.ArrowCursor if self._view.toolbox.name == "select"
                                 else Qt.CursorShape.CrossCursor)
            return
        if e.button() == Qt.MouseButton.RightButton:
            return
        self.dispatch(self._canvas_event("release", e))

    def double_click_event(self, e: QMouseEvent) -> None:
        if e.button() == Qt.MouseButton.MiddleButton:
            self._view.zoom_to_fit()
            return
        self.dispatch(self._canvas_event("double", e))

    def wheel_event(self, e: QWheelEvent) -> None:
        """Zoom about the cursor (the view's transformation anchor)."""
        delta = e.angleDelta().y() or e.angleDelta().x()
        if delta:
            self._view.zoom_by(1.0015 ** delta)
        e.accept()

    def leave_event(self) -> None:
        """The cursor left the view: nothing is hovered any more."""
        if self.hover is not None:
            self.hover = None
            self._highlight()

    def cancel_tool(self) -> None:
        """Abandon what the active tool is doing (a half-placed dyad, a drag)."""
        view = self._view
        tool = view.toolbox.tool
        tool.cancel()
        view.extras.handles.cancel()
        view.extras.loads.cancel()
        self._overlay.set_overlay(tool.overlay())
        if self._busy:
            self._busy = False
            view.dragFinished.emit()
            self._show_frame()

    def forget(self, gone: set[str] | frozenset[str] | None = None) -> None:
        """Elements ``gone`` were removed (None: the document was replaced): every tool, handle
        and load drag that refers to one of them starts again, and a drag ends."""
        view = self._view
        for tool in view.toolbox.tools.values():
            tool.forget(gone)
        view.extras.handles.forget(gone)
        view.extras.loads.forget(gone)
        if self.hover is not None and (gone is None or self.hover.element in gone):
            self.hover = None
        self._overlay.set_overlay(view.toolbox.tool.overlay())
        if self._busy and not (view.toolbox.tool.busy or view.extras.handles.busy or view.extras.loads.busy):
            self._busy = False
            view.dragFinished.emit()
            self._show_frame()

    def _select_element(self, ev: CanvasEvent) -> bool:
        """With the select tool, a click on a Geneva drive or rolling lever (no joint or link
        under it) selects the element (Shift toggles it); True if the click was taken."""
        view = self._view
        if ev.kind != "press" or ev.button != "left" or ev.hit is not None or view.toolbox.name != "select":
            return False
        eid = view.element_at(ev.raw, ev.tolerance)
        if eid is None:
            return False
        item = (eid, ELEMENT, eid)
        sel = list(view.controller.selection) if ev.shift else []
        sel.remove(item) if item in sel else sel.append(item)
        view.controller.set_selection(sel)
        return True

    # -- keys -------------------------------------------------------------------------------------
    def shortcut_override(self, e: QEvent) -> bool:
        """Keep Space and Esc for the canvas (not a window shortcut); True if ``e`` was taken."""
        if (e.type() == QEvent.Type.ShortcutOverride and isinstance(e, QKeyEvent)
                and e.key() in (Qt.Key.Key_Space, Qt.Key.Key_Escape) and not e.modifiers()):
            e.accept()
            return True
        return False

    def key_press(self, e: QKeyEvent) -> bool:
        """Esc cancels, Space starts a tap or a pan, a plain key goes to the tool (e.g. 3-9:
        Geneva slots); True if ``e`` was taken."""
        if e.key() == Qt.Key.Key_Escape:
            self.cancel_tool()
        elif e.key() == Qt.Key.Key_Space:
            if not e.isAutoRepeat():
                self._space, self._space_panned = True, False
                self._view.setCursor(Qt.CursorShape.OpenHandCursor)
        elif not e.modifiers() and self._view.toolbox.tool.key(e.text()):
            self._overlay.set_overlay(self._view.toolbox.tool.overlay())
        elif not e.modifiers() and e.text() in STARTS and self.open_typed(e.text()):
            pass
        else:
            return False
        return True

    # -- typed input (typed_input.py) ---------------------------------------------------------------
    def open_typed(self, first: str) -> bool:
        """A number typed while a placing tool is active: open the inline box beside the pointer
        (True), or not for the select and delete tools (False)."""
        view = self._view
        tool = view.toolbox.tool
        if tool.name in ("select", "delete") or not hasattr(view, "typed"):
            return False
        at = view.mapFromGlobal(QCursor.pos())
        if not view.viewport().rect().contains(at):
            at = view.viewport().rect().center()
        start = view.world(QPointF(at))
        view.typed.open(first, at, tool.anchor(), start)
        return True

    def place_typed(self, x: float, y: float) -> None:
        """The typed point: a click there for the active tool (no snapping)."""
        view = self._view
        tol = PICK_PX * view.px()
        hit = view.ctx.pick((x, y), tol)
        for kind in ("move", "press", "release"):
            self.dispatch(CanvasEvent(kind, (x, y), (x, y), "left" if kind != "move" else "none",
                                      frozenset({"left"}) if kind == "press" else frozenset(), frozenset(), hit, tol))

    def key_release(self, e: QKeyEvent) -> bool:
        """Space released: a tap (no pan since the press) triggers the tap action; True if taken."""
        if e.key() == Qt.Key.Key_Space and not e.isAutoRepeat():
            self._space = False
            self._view.setCursor(Qt.CursorShape.ArrowCursor if self._view.toolbox.name == "select"
                                 else Qt.CursorShape.CrossCursor)
            if not self._space_panned and self.tap_action is not None:
                self.tap_action.trigger()
            return True
        return False
