"""Mouse and key routing of the canvas: Qt input events become tool events, pans and zooms.

:class:`CanvasInputMixin` is the input half of :class:`~mechsketch.gui.canvas.view.CanvasView`
(which inherits from it, before ``QGraphicsView``). A mouse event becomes a
:class:`~mechsketch.gui.canvas.events.CanvasEvent` (world and snapped positions, buttons,
modifiers, the pick under the cursor) that :meth:`~CanvasInputMixin.dispatch` hands to a handle, a
load's handle or the active tool; the middle button or Space + left drag pans, a middle
double-click fits, the right button or Esc cancels, a tapped Space triggers the tap action. A
click with the select tool on a Geneva drive or rolling lever selects the element.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from PySide6.QtCore import QEvent, QPointF, Qt
from PySide6.QtGui import QAction, QKeyEvent, QMouseEvent

from ..selection import ELEMENT
from .events import CanvasEvent, Hit

if TYPE_CHECKING:
    from PySide6.QtCore import SignalInstance

    from ..controller import SceneController
    from .extras import CanvasExtras
    from .items import OverlayItem
    from .toolbox import ToolBox
    from .tools import ToolContext

PICK_PX = 8.0                 # pick radius, screen pixels


class CanvasInputMixin:
    """Mouse and key handlers of :class:`~mechsketch.gui.canvas.view.CanvasView`.

    Not usable alone: it reads the view's controller, tool context, toolbox, extras, overlay item
    and signals (annotated below), and calls its ``px``, ``world``, ``snap``, ``zoom_to_fit``,
    ``element_at``, ``_highlight`` and ``_on_frame``; ``CanvasView`` sets and defines them all.
    """

    controller: SceneController
    ctx: ToolContext
    toolbox: ToolBox
    extras: CanvasExtras
    _overlay: OverlayItem
    _hover: Hit | None
    _pan_from: QPointF | None
    _space: bool
    _space_panned: bool
    _tap_action: QAction | None
    _busy: bool
    cursorMoved: SignalInstance
    dragStarted: SignalInstance
    dragFinished: SignalInstance

    # -- mouse ------------------------------------------------------------------------------------
    def _canvas_event(self, kind: str, e: QMouseEvent) -> CanvasEvent:
        raw = self.world(e.position())
        tol = PICK_PX * self.px()
        hit = self.ctx.pick(raw, tol)
        names = {Qt.MouseButton.LeftButton: "left", Qt.MouseButton.RightButton: "right",
                 Qt.MouseButton.MiddleButton: "middle"}
        held = frozenset(n for b, n in names.items() if e.buttons() & b)
        mods = e.modifiers()
        modifiers = frozenset(n for m, n in ((Qt.KeyboardModifier.ShiftModifier, "shift"),
                                             (Qt.KeyboardModifier.ControlModifier, "ctrl"),
                                             (Qt.KeyboardModifier.AltModifier, "alt")) if mods & m)
        return CanvasEvent(kind, self.snap(raw, hit), raw, names.get(e.button(), "none"), held, modifiers,
                           hit, tol)

    def dispatch(self, ev: CanvasEvent) -> None:
        """Hand ``ev`` to the active tool and show the result (public for tests and macros)."""
        tool = self.extras.handles.route(ev, self.toolbox.tool)   # a press on a handle drags it
        tool = self.extras.loads.route(ev, tool)                  # ... and on a load's handle
        if tool is self.toolbox.tool and self._select_element(ev):
            return
        tool.handle(ev)
        self._overlay.set_overlay(tool.overlay())
        if tool.busy != self._busy:
            self._busy = tool.busy
            (self.dragStarted if self._busy else self.dragFinished).emit()
            if not self._busy:
                self._on_frame()
        if ev.kind == "move" and not ev.buttons and ev.hit != self._hover:
            self._hover = ev.hit
            self._highlight()

    def mousePressEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        if e.button() == Qt.MouseButton.MiddleButton or (e.button() == Qt.MouseButton.LeftButton and self._space):
            self._pan_from = e.position()
            self._space_panned = True
            self.setCursor(Qt.CursorShape.ClosedHandCursor)
            return
        if e.button() == Qt.MouseButton.RightButton:
            self.cancel_tool()
            return
        self.dispatch(self._canvas_event("press", e))

    def mouseMoveEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        if self._pan_from is not None:
            d = e.position() - self._pan_from
            self._pan_from = e.position()
            self.horizontalScrollBar().setValue(self.horizontalScrollBar().value() - round(d.x()))
            self.verticalScrollBar().setValue(self.verticalScrollBar().value() - round(d.y()))
            return
        ev = self._canvas_event("move", e)
        self.cursorMoved.emit(ev.pos[0], ev.pos[1])
        self.dispatch(ev)

    def mouseReleaseEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        if self._pan_from is not None:
            self._pan_from = None
            self.setCursor(Qt.CursorShape.OpenHandCursor if self._space else
                           Qt.CursorShape.ArrowCursor if self.toolbox.name == "select" else Qt.CursorShape.CrossCursor)
            return
        if e.button() == Qt.MouseButton.RightButton:
            return
        self.dispatch(self._canvas_event("release", e))

    def mouseDoubleClickEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        if e.button() == Qt.MouseButton.MiddleButton:
            self.zoom_to_fit()
            return
        self.dispatch(self._canvas_event("double", e))

    def leaveEvent(self, event) -> None:  # noqa: N802 - Qt API
        if self._hover is not None:
            self._hover = None
            self._highlight()
        super().leaveEvent(event)

    def cancel_tool(self) -> None:
        """Abandon what the active tool is doing (a half-placed dyad, a drag)."""
        tool = self.toolbox.tool
        tool.cancel()
        self.extras.handles.cancel()
        self.extras.loads.cancel()
        self._overlay.set_overlay(tool.overlay())
        if self._busy:
            self._busy = False
            self.dragFinished.emit()
            self._on_frame()

    def _select_element(self, ev: CanvasEvent) -> bool:
        """With the select tool, a click on a Geneva drive or rolling lever (no joint or link
        under it) selects the element (Shift toggles it); True if the click was taken."""
        if ev.kind != "press" or ev.button != "left" or ev.hit is not None or self.toolbox.name != "select":
            return False
        eid = self.element_at(ev.raw, ev.tolerance)
        if eid is None:
            return False
        item = (eid, ELEMENT, eid)
        sel = list(self.controller.selection) if ev.shift else []
        sel.remove(item) if item in sel else sel.append(item)
        self.controller.set_selection(sel)
        return True

    # -- keys -------------------------------------------------------------------------------------
    def event(self, e: QEvent) -> bool:  # noqa: D401 - Qt API
        if (e.type() == QEvent.Type.ShortcutOverride and isinstance(e, QKeyEvent)
                and e.key() in (Qt.Key.Key_Space, Qt.Key.Key_Escape) and not e.modifiers()):
            e.accept()
            return True
        return super().event(e)

    def keyPressEvent(self, e: QKeyEvent) -> None:  # noqa: N802 - Qt API
        if e.key() == Qt.Key.Key_Escape:
            self.cancel_tool()
        elif e.key() == Qt.Key.Key_Space:
            if not e.isAutoRepeat():
                self._space, self._space_panned = True, False
                self.setCursor(Qt.CursorShape.OpenHandCursor)
        elif not e.modifiers() and self.toolbox.tool.key(e.text()):   # e.g. 3-9: Geneva slots
            self._overlay.set_overlay(self.toolbox.tool.overlay())
        else:
            super().keyPressEvent(e)

    def keyReleaseEvent(self, e: QKeyEvent) -> None:  # noqa: N802 - Qt API
        if e.key() == Qt.Key.Key_Space and not e.isAutoRepeat():
            self._space = False
            self.setCursor(Qt.CursorShape.ArrowCursor if self.toolbox.name == "select" else Qt.CursorShape.CrossCursor)
            if not self._space_panned and self._tap_action is not None:
                self._tap_action.trigger()
        else:
            super().keyReleaseEvent(e)
