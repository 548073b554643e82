"""The Help menu's commands and F1: the manual, the getting-started page, the shortcuts, and
context help for what is under the pointer (a dock, or the canvas's active tool).

:class:`HelpCommands` is given the main window (read, never imported: the window is above this
package) and makes the help window on first use.
"""
from __future__ import annotations

from typing import Any

from PySide6.QtCore import QObject
from PySide6.QtGui import QAction, QCursor, QKeySequence
from PySide6.QtWidgets import QApplication, QMenu, QWidget

from .manual import START


def context_slug(widget: QWidget | None, docks: dict[str, QWidget], canvas: QWidget | None,
                 tool: str | None) -> str | None:
    """The help page for ``widget``: ``dock/NAME`` inside one of ``docks``, ``tool/TOOL`` on the
    canvas, None elsewhere."""
    w = widget
    while w is not None:
        for name, dock in docks.items():
            if w is dock:
                return f"dock/{name}"
        if canvas is not None and w is canvas:
            return f"tool/{tool}" if tool else "readme/the-desktop-app"
        w = w.parentWidget()
    return None


def menu_shortcuts(window: Any) -> list[tuple[str, str, str]]:
    """(menu, command, keys) of every action of the window with a shortcut: those in the menus
    under their menu's name (submenus as "View › Animation"), then the others."""
    rows: list[tuple[str, str, str]] = []
    seen: set[int] = set()

    def walk(menu: QMenu, path: str) -> None:
        for act in menu.actions():
            if act.menu() is not None:
                walk(act.menu(), f"{path} › {_text(act)}")
            elif not act.isSeparator() and id(act) not in seen and act.shortcuts():
                seen.add(id(act))
                rows.append((path, _text(act), _keys(act)))

    for top in window.menuBar().actions():
        if top.menu() is not None:
            walk(top.menu(), _text(top))
    for act in window.findChildren(QAction):
        if id(act) not in seen and act.shortcuts() and act.text():
            seen.add(id(act))
            rows.append(("—", _text(act), _keys(act)))
    return rows


def _text(act: QAction) -> str:
    return act.text().replace("&&", "\0").replace("&", "").replace("\0", "&").rstrip("…. ")


def _keys(act: QAction) -> str:
    return ", ".join(k.toString(QKeySequence.SequenceFormat.NativeText) for k in act.shortcuts())


class HelpCommands(QObject):
    """Help › Manual (F1: context help), Getting Started, Keyboard Shortcuts."""

    def __init__(self, window: Any) -> None:
        super().__init__(window)
        self.window = window
        self._help = None
        self.actions: dict[str, QAction] = {}
        for name, text, slot, key, tip in (
                ("manual", "&Manual", self.context_help, QKeySequence.StandardKey.HelpContents,
                 "The manual; F1 over a dock or the canvas opens its help"),
                ("getting_started", "&Getting Started", lambda: self.show(START), None,
                 "From an empty canvas to a cut-ready drawing"),
                ("shortcuts", "&Keyboard Shortcuts", lambda: self.show("shortcuts"), None,
                 "Every key of the window and the canvas")):
            act = QAction(text, window)
            act.setObjectName(f"help_{name}")
            if key is not None:
                act.setShortcuts(QKeySequence.keyBindings(key) or [QKeySequence("F1")])
            act.setStatusTip(tip)
            act.triggered.connect(lambda _c=False, s=slot: s())
            self.actions[name] = act

    @property
    def help_window(self):
        """The help window (:class:`~mechsketch.gui.help.window.HelpWindow`), made on first use."""
        if self._help is None:
            from .window import HelpWindow

            self._help = HelpWindow(parent=self.window, shortcuts=lambda: menu_shortcuts(self.window))
        return self._help

    def show(self, slug: str) -> None:
        """Open the manual at page ``slug``."""
        self.help_window.show_page(slug)

    def context_slug(self) -> str | None:
        """The page for what is under the pointer (else what has the focus), None for neither."""
        w = self.window
        docks = getattr(w, "docks", {})
        canvas = getattr(w, "canvas", None)
        toolbox = getattr(canvas, "toolbox", None)
        tool = toolbox.name if toolbox is not None else None
        underlays = getattr(w, "underlay_commands", None)
        if underlays is not None and underlays.session is not None:
            tool = "underlay"                 # placing or moving an underlay reads the canvas's clicks
        under = QApplication.widgetAt(QCursor.pos())
        if under is not None and under.window() is w:
            slug = context_slug(under, docks, canvas, tool)
            if slug is not None:
                return slug
        return context_slug(QApplication.focusWidget(), docks, canvas, tool)

    def context_help(self) -> None:
        """F1: the help of the dock or tool under the pointer, else the manual where it was left
        (the getting-started page the first time)."""
        slug = self.context_slug()
        if slug is None:
            if self._help is not None and self._help.current():
                self.help_window.show_page(self._help.current())
                return
            slug = START
        self.show(slug)
