"""Editing a Geneva drive or a rolling lever from the properties panel: the shared plumbing.

Every edit builds the new element by round-tripping the old one's dict through the scene reader
(the element's JSON schema, then its module's ``parse``: :func:`~mechsketch.core.workspace.rebuild.rebuilt`),
then solves it once through the controller (a stroke beyond the working range, a drive that cannot
be drawn) and only then pushes one ``ReplaceElement`` command (a heavy element, e.g. a rolling
lever of 100,000 points, is solved off the GUI thread and its edit lands when it is solved:
``SceneController.push_when_solved``). A refused value raises
``ValueError`` with the core's message, which the panel's field shows in the status bar while the
document stays as it was. Widgets hold no model state: reads go to ``controller.scene``.
"""
from __future__ import annotations

from typing import Any, Callable

from PySide6.QtWidgets import QComboBox

from mechsketch.core import EditError, MechsketchError, ReplaceElement

from mechsketch.core.workspace import rebuilt


def push_changes(controller, element_id: str, changes: dict[str, Any], label: str) -> bool:
    """Replace element ``element_id`` by its copy with ``changes`` (dotted keys) as one undo step.

    Raises :class:`EditError` (a ValueError) with the core's message when the new values are
    refused (the document is unchanged); returns False if the controller refused the command.
    """
    old = controller.scene.element(element_id)
    new, problem = rebuilt(old, changes)
    if problem is not None:
        raise EditError(problem)
    if new == old:
        return False
    return controller.push_when_solved(new, ReplaceElement(new, label), label)


def whole_number(value: float, what: str) -> int:
    """``value`` as an int, or EditError (a ValueError) naming ``what`` if it is not whole."""
    if value != int(value):
        raise EditError(f"{what} must be a whole number, got {value:g}")
    return int(value)


def combo_field(panel, name: str, options: list[tuple[str, Any]], read: Callable[[], Any],
                write: Callable[[Any], None], tip: str = "") -> QComboBox:
    """A choice box kept in step with ``read()``; choosing calls ``write(value)``; a refusal
    (ValueError with the core's message) goes to the status bar and the box shows the document again."""
    box = QComboBox()
    box.setObjectName(name)
    box.setToolTip(tip)
    for text, value in options:
        box.addItem(text, value)
    panel.combos[name] = box
    values = [v for _, v in options]

    def show() -> None:
        box.blockSignals(True)
        try:
            current = read()
        except MechsketchError:   # the element went away: the panel rebuilds next
            current = None
        box.setCurrentIndex(values.index(current) if current in values else -1)
        box.blockSignals(False)

    def chosen(index: int) -> None:
        value = box.itemData(index)
        try:
            if value != read():
                write(value)
        except MechsketchError as exc:
            panel.controller.message.emit(f"{name}: {exc}")
        show()

    box.activated.connect(chosen)
    panel.add_refresher(show)
    return box
