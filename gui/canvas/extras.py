"""What the canvas shows beyond the mechanisms: handles, View overlays and the centrodes view.

:class:`CanvasExtras` is made once by :class:`~mechsketch.gui.canvas.view.CanvasView` and keeps
itself up to date from the controller's signals (``changed``, ``frameChanged``,
``selectionChanged``). It owns

- :attr:`handles` (:class:`~.handles.HandleLayer`) and the item drawing them;
- the View overlays (:mod:`.overlays`): velocity and acceleration vectors of the selected joints,
  instant centres of the selected links, RRR transmission angles, the Geneva phase / contact force
  / most loaded place - each toggled by a checkable action in :attr:`actions`;
- the centrodes view (:mod:`.centrode_view`): View -> Centrodes of the selected link (relative to
  the frame, or to a second selected link), with CSV and DXF export actions.

Everything is drawn from precomputed arrays; nothing here solves per frame.
"""
from __future__ import annotations

from PySide6.QtCore import QObject
from PySide6.QtGui import QAction, QKeySequence

from .handles import HandleLayer
from .loads_layer import LoadLayer, LoadsItem
from .overlays import HandlesItem, OverlaySet


class CanvasExtras(QObject):
    """Handles, overlays and centrodes of one canvas view (see the module docstring)."""

    def __init__(self, view) -> None:
        super().__init__(view)
        self.view = view
        self.controller = view.controller
        self.handles = HandleLayer(view.ctx)
        self.handles_item = HandlesItem()
        view.scene().addItem(self.handles_item)
        self.loads = LoadLayer(view.ctx, view.px)   # loads drawn on their links, moved by their handles
        self.loads_item = LoadsItem()
        view.scene().addItem(self.loads_item)
        self.overlays = OverlaySet(view)
        self.actions: dict[str, QAction] = {}
        for name, text, key, tip in self.overlays.ACTIONS:
            act = QAction(text, view)
            act.setObjectName(f"overlay_{name}")
            act.setCheckable(True)
            if key:
                act.setShortcut(QKeySequence(key))
            act.setStatusTip(tip)
            act.toggled.connect(lambda on, n=name: self._toggled(n, on))
            view.addAction(act)
            self.actions[name] = act
        ctl = self.controller
        ctl.changed.connect(self.refresh)
        ctl.frameChanged.connect(self.refresh)
        ctl.selectionChanged.connect(self.refresh)
        ctl.documentReplaced.connect(self._on_replaced)
        self.refresh()

    def _on_replaced(self) -> None:
        """A new document: the centrodes of a link of the old one are switched off."""
        act = self.actions.get("centrodes")
        if act is not None and act.isChecked():
            act.setChecked(False)

    def _toggled(self, name: str, on: bool) -> None:
        """Switch an overlay; a switch that cannot be on (centrodes without a link) goes back off."""
        self.overlays.set_shown(name, on)
        act = self.actions[name]
        if act.isChecked() != self.overlays.shown[name]:
            act.blockSignals(True)
            act.setChecked(self.overlays.shown[name])
            act.blockSignals(False)

    def refresh(self, *_args) -> None:
        """Redraw handles and overlays for the displayed frame and the current selection."""
        self.handles_item.set_handles(self.handles.handles())
        self.handles_item.set_px(self.view.px())
        self.loads_item.set_records(*self.loads.records())
        self.loads_item.set_px(self.view.px())
        self.overlays.refresh()

    def set_px(self, px: float) -> None:
        """The zoom changed (mm per pixel)."""
        self.handles_item.set_px(px)
        self.loads_item.set_records(*self.loads.records())   # grips sit a screen distance from points
        self.loads_item.set_px(px)
        self.overlays.set_px(px)
