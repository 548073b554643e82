"""The canvas tools as checkable, exclusive QActions with single-key shortcuts.

The shell puts ``toolbox.actions.values()`` in a toolbar or menu; triggering an action (or its
shortcut) makes that tool active on the canvas. ``toolChanged(name)`` tells who cares.
"""
from __future__ import annotations

from functools import partial

from PySide6.QtCore import QObject, Signal
from PySide6.QtGui import QAction, QActionGroup, QKeySequence

from .tools import TOOLS, Tool, ToolContext


class ToolBox(QObject):
    """One instance of each tool, with an exclusive QActionGroup.

    ``actions``: name -> QAction, in toolbar order: select (S), ground (G), crank (C), rrr (R),
    rrp (P), rpr (I), coupler (K), delete (D), measure (M), geneva (W), rolling (O), prp (Y),
    rpp (X), and insert (made active by Examples -> Insert, not shown in the toolbar).
    """

    toolChanged = Signal(str)

    def __init__(self, ctx: ToolContext, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.ctx = ctx
        self.tools: dict[str, Tool] = {cls.name: cls(ctx) for cls in TOOLS}
        self.group = QActionGroup(self)
        self.group.setExclusive(True)
        self.actions: dict[str, QAction] = {}
        for name, tool in self.tools.items():
            act = QAction(tool.title, self)
            act.setObjectName(f"tool_{name}")
            act.setCheckable(True)
            act.setShortcut(QKeySequence(tool.shortcut))
            act.setToolTip(f"{tool.title} ({tool.shortcut})")
            act.setStatusTip(tool.hint)
            act.setData(name)
            act.triggered.connect(partial(self._triggered, name))
            self.group.addAction(act)
            self.actions[name] = act
        self._name = "select"
        self.actions["select"].setChecked(True)

    @property
    def name(self) -> str:
        """The active tool's name."""
        return self._name

    @property
    def tool(self) -> Tool:
        """The active tool."""
        return self.tools[self._name]

    def _triggered(self, name: str, _checked: bool = False) -> None:
        self.set_tool(name)

    def set_tool(self, name: str) -> None:
        """Make ``name`` the active tool (cancels what the previous one was doing)."""
        if name not in self.tools:
            raise KeyError(f"no canvas tool {name!r} (tools: {', '.join(self.tools)})")
        self.actions[name].setChecked(True)
        if name == self._name:
            return
        self.tool.deactivate()
        self._name = name
        self.tool.activate()
        self.toolChanged.emit(name)
