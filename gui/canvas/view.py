"""The canvas: a QGraphicsView in world millimetres with y up, drawing the controller's scene.

Embedding (the shell does this once)::

    view = CanvasView(controller)                 # a QWidget; setCentralWidget(view)
    toolbar.addActions(list(view.toolbox.actions.values()))   # select, ground, crank, ... (S G C R P I K D M)
    view_menu.addActions([view.zoom_fit_action, view.snap_action, view.trace_action, view.labels_action])
    edit_menu.addAction(view.delete_action)       # Del: delete the selection (one undo command)
    view.set_tap_action(player.play_action)       # Space tapped on the canvas plays/pauses,
                                                  # Space held + drag pans
    view.dragStarted.connect(player.pause)        # a drag on the canvas pauses the animation
    view.cursorMoved.connect(lambda x, y: status.showMessage(f"{x:.2f}, {y:.2f} mm"))

It shows every linkage at the controller's current frame when it has a solution, else at its
drawn pose (with a short note if it does not solve yet). Mouse input becomes
:class:`~mechsketch.gui.canvas.events.CanvasEvent` for the active tool of :attr:`toolbox`.
Zoom with the wheel (about the cursor), pan with the middle button or Space + drag, fit with F
or a middle double-click, cancel a tool's half-done placement with Esc or the right button.

This module keeps the view's set-up, actions, syncing of the graphics items with the controller
and zoom; its mouse and key events go to the :class:`~mechsketch.gui.canvas.view_input.CanvasInput`
it owns (view_input.py), and gui/canvas/grid.py paints the grid and scale bar.
"""
from __future__ import annotations

from PySide6.QtCore import QEvent, QPointF, QRectF, Qt, Signal
from PySide6.QtGui import QAction, QKeyEvent, QKeySequence, QMouseEvent, QPainter, QTransform, QWheelEvent
from PySide6.QtWidgets import QGraphicsScene, QGraphicsView, QWidget

from mechsketch.core.model.edits import RemoveElement
from mechsketch.core.model.linkage import JointKind, Linkage
from mechsketch.core.workspace import ElementChange, GenevaResult

from ..selection import ELEMENT
from ..frames import map_frame
from .events import XY, CanvasEvent, Hit
from .extras import CanvasExtras
from .gear_items import element_item as gear_item
from .geneva_items import GenevaItem
from .grid import (BACKGROUND, GRID_AXES, GRID_MAJOR, GRID_MIN_PX, GRID_MINOR,  # noqa: F401 - re-exported
                   grid_steps, paint_grid, paint_scale_bar)
from .items import DeadPointItem, LinkageItem, OverlayItem, TraceItem
from .rolling_items import RollingItem
from .toolbox import ToolBox
from .typed_input import TypedBox
from .tools import ToolContext, delete_selection
from .underlay_item import UnderlayLayer   # underlays (issue 22 item 6)
from .design_layer import DesignLayer      # the Study and Design docks' band, target and preview
from .view_input import PICK_PX, CanvasInput  # noqa: F401 - PICK_PX re-exported
from ..qtsafe import qt_safe

SCALE_RANGE = (0.02, 400.0)   # pixels per millimetre; zooming out goes further for a larger scene
WORLD = 1.0e5                 # the scene spans +-WORLD mm, or more for a larger mechanism


def default_traced(linkage: Linkage) -> set[str]:
    """Coupler points: revolute joints carried by exactly one link other than the frame (a point
    on a coupler, a rocker or the crank itself). Their paths are traced unless the user switches
    them off."""
    out = set()
    for j in linkage.joints:
        carriers = linkage.links_of(j.id)
        if j.kind is JointKind.R and len(carriers) == 1 and carriers[0] != linkage.ground:
            out.add(j.id)
    return out


def _same_drawing(a: tuple, b: tuple) -> bool:
    """The items drawn for (linkage, arrays, index, traced, px, note) ``a`` also show ``b``:
    the same linkage record and solution arrays (by identity), frame, traced joints, scale."""
    return a[0] is b[0] and a[1] is b[1] and a[2:] == b[2:]


class _ElementItems:
    """The few graphics items of one linkage."""

    def __init__(self, scene: QGraphicsScene, pose) -> None:
        self.linkage = LinkageItem(pose)
        self.trace = TraceItem()
        self.dead = DeadPointItem()
        for it in (self.trace, self.dead, self.linkage):
            scene.addItem(it)
        self.drawn: tuple | None = None   # what the items show: see _same_drawing

    def all(self) -> tuple:
        return (self.linkage, self.trace, self.dead)


@qt_safe
class CanvasView(QGraphicsView):
    """The mechanism canvas. See the module docstring for embedding.

    Signals: ``cursorMoved(x_mm, y_mm)``, ``dragStarted()``, ``dragFinished()`` (a joint,
    link or crank drag), ``toolChanged(name)`` (forwarded from :attr:`toolbox`).
    """

    cursorMoved = Signal(float, float)
    dragStarted = Signal()
    dragFinished = Signal()
    toolChanged = Signal(str)

    def __init__(self, controller, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._overlay = OverlayItem()
        #: mouse and key handling (view_input.py), made first: Qt sends events (ChildAdded) from here on
        self._input = CanvasInput(self, self._overlay, self._highlight, self._on_frame)
        self.controller = controller
        self.ctx = ToolContext(controller)
        self.toolbox = ToolBox(self.ctx, self)
        self.toolbox.toolChanged.connect(self._tool_changed)
        self._scene = QGraphicsScene(self)
        self._scene.setSceneRect(-WORLD, -WORLD, 2 * WORLD, 2 * WORLD)
        self._scene.setItemIndexMethod(QGraphicsScene.ItemIndexMethod.NoIndex)
        self.setScene(self._scene)
        self.underlays = UnderlayLayer(self._scene)   # drawings and pictures under everything, snapped to
        self.design_layer = DesignLayer(self._scene, self)   # tolerance band, synthesis target, preview
        self._items: dict[str, _ElementItems] = {}
        #: Geneva drives and rolling levers: one item each, rebuilt when their result changes
        self.element_items: dict[str, GenevaItem | RollingItem] = {}
        self._scene.addItem(self._overlay)
        self._trace_override: dict[tuple[str, str], bool] = {}
        self._key: tuple | None = None
        self._fit_pending = False   # a replaced document is fitted at its first sync
        self._new: list[str] = []   # elements added by the last change (brought into view)
        self._snap = True
        self.fixed_snap_step = 0.0   # mm; > 0: snap to this step instead of the grid's (Preferences)
        self._fitted = False
        self._labels = True

        self.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        self.setViewportUpdateMode(QGraphicsView.ViewportUpdateMode.FullViewportUpdate)
        self.setCacheMode(QGraphicsView.CacheModeFlag.CacheBackground)   # the grid: a blit per frame
        self.setTransformationAnchor(QGraphicsView.ViewportAnchor.AnchorUnderMouse)
        self.setResizeAnchor(QGraphicsView.ViewportAnchor.AnchorViewCenter)
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setVerticalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setTransform(QTransform(3.0, 0, 0, -3.0, 0, 0))
        self.setCursor(Qt.CursorShape.ArrowCursor)
        self._make_actions()

        controller.documentReplaced.connect(self._on_replaced)
        controller.changed.connect(self._forget_removed)
        controller.changed.connect(self._sync)
        controller.previewInterrupted.connect(self.cancel_tool)
        controller.frameChanged.connect(self._on_frame)
        controller.selectionChanged.connect(self._highlight)
        self._sync()
        #: handles of selected Geneva drives / rolling levers, View overlays, centrodes (extras.py)
        self.extras = CanvasExtras(self)
        #: the inline box for typed coordinates, length and angle (typed_input.py)
        self.typed = TypedBox(self)
        self.typed.placed.connect(self._input.place_typed)
        self.typed.closed.connect(self.setFocus)

    # -- actions ------------------------------------------------------------------------------
    def _make_actions(self) -> None:
        def action(text: str, shortcut: QKeySequence | str, slot, checkable: bool = False,
                   tip: str = "") -> QAction:
            act = QAction(text, self)
            act.setShortcut(QKeySequence(shortcut))
            act.setCheckable(checkable)
            act.setStatusTip(tip)
            act.triggered.connect(slot)
            self.addAction(act)
            return act

        self.snap_action = action("Snap to Grid", "F9", self._snap_toggled, True,
                                  "snap to the grid and to joints")
        self.snap_action.setChecked(True)
        self.zoom_fit_action = action("Zoom to Fit", "F", lambda: self.zoom_to_fit(), tip="show the whole mechanism")
        self.trace_action = action("Trace Selected Joints", "T", lambda: self.toggle_trace_selected(),
                                   tip="draw (or stop drawing) the paths of the selected joints")
        self.labels_action = action("Show Ids", "L", self._labels_toggled, True, "label joints and links")
        self.labels_action.setChecked(True)
        self.delete_action = action("Delete", QKeySequence.StandardKey.Delete, lambda: self.delete_selected(),
                                    tip="delete the selected joints and links")
        self.addActions(list(self.toolbox.actions.values()))

    @property
    def tool_actions(self) -> list[QAction]:
        """The tool actions in toolbar order (tools made active by a command, like Insert, excluded)."""
        return [a for n, a in self.toolbox.actions.items() if self.toolbox.tools[n].in_toolbar]

    def set_tool(self, name: str) -> None:
        self.toolbox.set_tool(name)

    def set_tap_action(self, action: QAction | None) -> None:
        """The action a tap on Space triggers while the canvas has focus (Space + drag pans)."""
        self._input.tap_action = action

    @property
    def snap_enabled(self) -> bool:
        """Snapping to the grid (and to joints) is on."""
        return self._snap

    @snap_enabled.setter
    def snap_enabled(self, on: bool) -> None:
        self._snap = bool(on)
        if self.snap_action.isChecked() != self._snap:
            self.snap_action.setChecked(self._snap)

    def _snap_toggled(self, on: bool) -> None:
        self.snap_enabled = on
        self.controller.message.emit("snapping on" if on else "snapping off")

    def _labels_toggled(self, on: bool) -> None:
        self._labels = on
        for items in self._items.values():
            items.linkage.show_labels = on
            items.linkage.update()

    def _tool_changed(self, name: str) -> None:
        self._overlay.set_overlay(self.toolbox.tool.overlay())
        self.setCursor(Qt.CursorShape.ArrowCursor if name == "select" else Qt.CursorShape.CrossCursor)
        self.toolChanged.emit(name)

    def delete_selected(self) -> bool:
        """Delete the selected joints and links (and whole selected elements) as one undo command."""
        sel = list(self.controller.selection)
        whole = [e for e, k, _ in sel if k == ELEMENT and e in self.controller.scene.ids]
        if not whole:
            return delete_selection(self.ctx, sel)
        stack = self.controller.undo_stack
        stack.beginMacro(f"delete {', '.join(whole)}")
        try:
            done = any([self.controller.push(RemoveElement(e, f"delete {e}"), f"delete {e}") for e in whole])
            rest = [s for s in sel if s[1] != ELEMENT]
            if rest:
                done = delete_selection(self.ctx, rest) or done
        finally:
            stack.endMacro()
        self.controller.set_selection([])
        return done

    # -- geometry helpers -----------------------------------------------------------------------
    def px(self) -> float:
        """Millimetres per screen pixel."""
        return 1.0 / abs(self.transform().m11())

    def world(self, view_pos: QPointF) -> XY:
        p = self.mapToScene(view_pos.toPoint())
        return (p.x(), p.y())

    def snap_step(self) -> float:
        """The grid step positions snap to at the current zoom, mm (or the preferred fixed step)."""
        return self.fixed_snap_step if self.fixed_snap_step > 0 else grid_steps(self.px())[0]

    def snap(self, raw: XY, hit: Hit | None = None) -> XY:
        """``raw`` snapped to the joint under the cursor, else to the grid (if snapping is on)."""
        if not self._snap:
            return raw
        if hit is not None and hit.kind == "joint" and not self.toolbox.tool.busy:
            return self.ctx.at(hit.element, hit.id)
        near = self.underlays.snap(raw, PICK_PX * self.px())   # a vertex of a visible underlay
        if near is not None:
            return near
        s = self.snap_step()
        return (round(raw[0] / s) * s + 0.0, round(raw[1] / s) * s + 0.0)

    # -- syncing with the controller ------------------------------------------------------------
    def traced_joints(self, linkage: Linkage) -> list[str]:
        """Joints of ``linkage`` whose paths are drawn."""
        base = default_traced(linkage)
        out = [j for j in linkage.joint_ids
               if self._trace_override.get((linkage.id, j), j in base)]
        return out

    def set_traced(self, element_id: str, joint_id: str, on: bool) -> None:
        """Draw (or stop drawing) the path of one joint."""
        self._trace_override[(element_id, joint_id)] = bool(on)
        self._key = None
        self._sync()

    def toggle_trace_selected(self) -> None:
        """Trace the selected joints (or stop, if all of them are traced already)."""
        joints = [(el, i) for el, kind, i in self.controller.selection if kind == "joint"]
        if not joints:
            self.controller.message.emit("select joints first, then T traces their paths")
            return
        traced = {(lk.id, j) for lk in self.controller.linkages() for j in self.traced_joints(lk)}
        on = not all(j in traced for j in joints)
        for el, j in joints:
            self._trace_override[(el, j)] = on
        self._key = None
        self._sync()
        names = ", ".join(j for _, j in joints)
        self.controller.message.emit(f"tracing {names}" if on else f"not tracing {names}")

    def _on_replaced(self) -> None:
        """A different document (New, Open, restore): every tool starts again (the select tool
        active), and the view fits the document once its items exist."""
        self._input.forget(None)
        self.toolbox.set_tool("select")
        self._fit_pending = True

    def _forget_removed(self, change) -> None:
        """Tools and drags that refer to a removed element start again; a Geneva drive or rolling
        lever just added is brought into view (after the items are made: see _sync)."""
        gone = {eid for eid, how in change.elements if how is ElementChange.REMOVED}
        if gone and not change.replaced:
            self._input.forget(gone)
        if not change.replaced and not change.preview:
            self._new = [eid for eid, how in change.elements if how is ElementChange.ADDED]

    def _sync(self, *_args) -> None:
        """Rebuild items after the document or its solutions changed (cheap when nothing did)."""
        ctl = self.controller
        # identity of the scene and of each solution (references held, so ids cannot be reused)
        key = (ctl.scene, [(el, r.solution, r.error) for el, r in ctl.results().items()],
               list(ctl.element_results().items()))
        old = self._key
        if (old is not None and old[0] is key[0] and len(old[1]) == len(key[1])
                and all(a[0] == b[0] and a[1] is b[1] and a[2] == b[2] for a, b in zip(old[1], key[1]))
                and len(old[2]) == len(key[2]) and all(a[1] is b[1] for a, b in zip(old[2], key[2]))):
            return
        self._key = key
        self.underlays.sync(ctl.scene)
        self._sync_elements()
        poses = self.ctx.poses()
        live = {p.element for p in poses}
        for gone in set(self._items) - live:
            for it in self._items.pop(gone).all():
                self._scene.removeItem(it)
        px = self.px()
        for pose in poses:
            items = self._items.get(pose.element)
            if items is None:
                items = self._items[pose.element] = _ElementItems(self._scene, pose)
                items.linkage.show_labels = self._labels
            traced = tuple(self.traced_joints(pose.linkage))
            drawn = (pose.linkage, pose.arrays, pose.index, traced, px, pose.error)
            if items.drawn is not None and _same_drawing(items.drawn, drawn):
                continue   # an element the change did not touch: its items stay as they are
            items.drawn = drawn
            for it in items.all():
                it.set_px(px)
            items.linkage.set_pose(pose)
            items.trace.set_data(pose, list(traced))
            items.dead.set_data(pose)   # during a drag: at the samples' resolution, refined on release
        self._highlight()
        new, self._new = self._new, []
        if new and self.isVisible() and not self._fit_pending:
            self.show_new(new)
        if self._fit_pending:
            self._fit_pending = False
            if self.isVisible():
                self.zoom_to_fit(quiet=True)

    def _sync_elements(self) -> None:
        """One item per Geneva drive / rolling lever, rebuilt only when its result changed."""
        results = self.controller.element_results()
        for gone in [eid for eid, it in self.element_items.items()
                     if eid not in results or it.result is not results[eid]]:
            self._scene.removeItem(self.element_items.pop(gone))
        px = self.px()
        for eid, res in results.items():
            if eid not in self.element_items:
                item = gear_item(res) or (GenevaItem(res) if isinstance(res, GenevaResult) else RollingItem(res))
                item.set_px(px)
                self._scene.addItem(item)
                self.element_items[eid] = item
        self._frame_elements()

    def _frame_elements(self) -> None:
        """Show the element items at the displayed frame (cycle phase across sample counts)."""
        frame, total = self.ctx.display_frame(), self.controller.sample_count()
        for item in self.element_items.values():
            if item.n_frames:
                item.set_frame(map_frame(frame, total, item.n_frames))

    def _on_frame(self, _frame: int = 0) -> None:
        for pose in self.ctx.poses():
            items = self._items.get(pose.element)
            if items is not None:
                items.linkage.set_pose(pose)
        self._frame_elements()

    def element_at(self, pos: XY, tol: float) -> str | None:
        """The Geneva drive or rolling lever under the world point ``pos`` (mm), if any."""
        for eid, item in reversed(list(self.element_items.items())):
            if item.hit(pos, tol):
                return eid
        return None

    def _highlight(self) -> None:
        sel = self.controller.selection
        for el, items in self._items.items():
            items.linkage.set_highlight(self._input.hover, {(k, i) for e, k, i in sel if e == el})
        chosen = {e for e, k, _ in sel if k == ELEMENT}
        for eid, item in self.element_items.items():
            item.set_selected(eid in chosen)

    # -- zoom -------------------------------------------------------------------------------------
    def extent(self) -> QRectF:
        """Everything shown, over the whole cycle where solved, in mm."""
        rect = QRectF()
        for pose in self.ctx.poses():
            pts = list(pose.at.values())
            if pose.arrays is not None:
                ext = pose.arrays.extent()
                if ext:
                    pts += [(ext[0], ext[1]), (ext[2], ext[3])]
            if pts:
                xs, ys = [p[0] for p in pts], [p[1] for p in pts]
                rect = rect.united(QRectF(min(xs), min(ys), max(xs) - min(xs), max(ys) - min(ys)))
        for item in self.element_items.values():
            rect = rect.united(item.extent())
        return rect.united(self.underlays.extent()).united(self.design_layer.extent())

    def zoom_to_fit(self, quiet: bool = False) -> None:
        """Show the whole mechanism (its motion included) with a margin."""
        rect = self.extent()
        if rect.width() < 1.0 and rect.height() < 1.0:
            c = rect.center() if not rect.isNull() else QPointF(0, 0)
            rect = QRectF(c.x() - 100, c.y() - 80, 200, 160)
        self.zoom_to_rect(rect.adjusted(-0.08 * rect.width() - 15, -0.08 * rect.height() - 15,
                                        0.08 * rect.width() + 15, 0.08 * rect.height() + 15))
        self._fitted = True

    def scale_range(self) -> tuple[float, float]:
        """(least, greatest) zoom in pixels per mm: zooming out reaches a third of the whole
        scene's fit (a 160 m mechanism is seen whole), never less than ``SCALE_RANGE``."""
        ext = self.extent()
        vp = self.viewport().rect()
        if ext.isNull() or ext.width() <= 0 and ext.height() <= 0:
            return SCALE_RANGE
        fit = min(vp.width() / max(ext.width(), 1e-9), vp.height() / max(ext.height(), 1e-9))
        return min(SCALE_RANGE[0], fit / 3.0), SCALE_RANGE[1]

    def _grow_world(self, rect: QRectF) -> None:
        """The scene rect covers ``rect`` with room around it (the view can be panned there)."""
        need = rect.adjusted(-rect.width(), -rect.height(), rect.width(), rect.height())
        if not self._scene.sceneRect().contains(need):
            self._scene.setSceneRect(self._scene.sceneRect().united(need))

    def zoom_to_rect(self, rect: QRectF) -> None:
        """Fit ``rect`` (mm) in the viewport, keeping y up and equal scales."""
        vp = self.viewport().rect()
        self._grow_world(rect)
        s = min(vp.width() / max(rect.width(), 1e-9), vp.height() / max(rect.height(), 1e-9))
        lo, hi = self.scale_range()
        s = min(max(s, min(lo, s)), hi)
        self.setTransform(QTransform(s, 0, 0, -s, 0, 0))
        self.centerOn(rect.center())
        self._zoomed()

    def zoom_by(self, factor: float) -> None:
        s = abs(self.transform().m11())
        lo, hi = self.scale_range()
        factor = min(max(factor, min(lo, s) / s), hi / s)
        self.scale(factor, factor)
        self._zoomed()

    def show_new(self, element_ids) -> None:
        """Elements just added (a placement, an insert): if one is not wholly in view, the view
        fits what it showed and the new elements."""
        shown = self.mapToScene(self.viewport().rect()).boundingRect()
        rect = QRectF()
        for eid in element_ids:
            item = self.element_items.get(eid)
            if item is not None:
                rect = rect.united(item.extent())
        if rect.isNull() or shown.contains(rect):
            return
        both = shown.united(rect)
        self.zoom_to_rect(both.adjusted(-0.05 * both.width(), -0.05 * both.height(),
                                        0.05 * both.width(), 0.05 * both.height()))

    def _zoomed(self) -> None:
        px = self.px()
        for items in self._items.values():
            for it in items.all():
                it.set_px(px)
        for item in self.element_items.values():
            item.set_px(px)
        self._overlay.set_px(px)
        self.design_layer.set_px(px)
        if hasattr(self, "extras"):
            self.extras.set_px(px)
        self.viewport().update()

    # -- input: handed to self._input (view_input.CanvasInput) ------------------------------------
    def dispatch(self, ev: CanvasEvent) -> None:
        """Hand ``ev`` to the active tool and show the result (public for tests and macros)."""
        self._input.dispatch(ev)

    def cancel_tool(self) -> None:
        """Abandon what the active tool is doing (a half-placed dyad, a drag)."""
        self._input.cancel_tool()

    def mousePressEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        self._input.press_event(e)
    def mouseMoveEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        self._input.move_event(e)
    def mouseReleaseEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        self._input.release_event(e)
    def mouseDoubleClickEvent(self, e: QMouseEvent) -> None:  # noqa: N802 - Qt API
        self._input.double_click_event(e)
    def leaveEvent(self, event: QEvent) -> None:  # noqa: N802 - Qt API
        self._input.leave_event()
        super().leaveEvent(event)
    def event(self, e: QEvent) -> bool:  # noqa: D401 - Qt API
        return self._input.shortcut_override(e) or super().event(e)
    def keyPressEvent(self, e: QKeyEvent) -> None:  # noqa: N802 - Qt API
        self._input.key_press(e) or super().keyPressEvent(e)
    def keyReleaseEvent(self, e: QKeyEvent) -> None:  # noqa: N802 - Qt API
        self._input.key_release(e) or super().keyReleaseEvent(e)
    def wheelEvent(self, event: QWheelEvent) -> None:  # noqa: N802 - Qt API
        self._input.wheel_event(event)

    def showEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().showEvent(event)
        if not self._fitted:
            self.zoom_to_fit(quiet=True)

    # -- painting ---------------------------------------------------------------------------------
    def drawBackground(self, painter: QPainter, rect: QRectF) -> None:  # noqa: N802 - Qt API
        """The background and grid (see :func:`~mechsketch.gui.canvas.grid.paint_grid`)."""
        paint_grid(painter, rect, self.px())

    def drawForeground(self, painter: QPainter, rect: QRectF) -> None:  # noqa: N802 - Qt API
        """A scale bar in the bottom-left corner."""
        paint_scale_bar(painter, self.px(), self.viewport().height())
