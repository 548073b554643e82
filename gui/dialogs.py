"""The dialogs the app asks through: an injectable service, so tests answer with a fake.

Every component that needs a file name, a question or an error message calls a
:class:`DialogService` handed to it; nothing else in the app opens a modal dialog. Tests pass an
object with the same methods (see ``tests/gui/app_fakes.py``) and never patch Qt.
"""
from __future__ import annotations

from typing import Protocol

from PySide6.QtWidgets import QDialog, QFileDialog, QMessageBox, QWidget

SCENE_FILTER = "mechsketch scenes (*.json);;All files (*)"

#: answers of :meth:`DialogService.ask_save_changes`
SAVE, DISCARD, CANCEL = "save", "discard", "cancel"


class DialogService(Protocol):
    """What the app may ask the user. Each method blocks until answered."""

    def open_file_name(self, title: str, directory: str = "", filter: str = SCENE_FILTER) -> str | None:
        """A file to open, or None if the user cancelled."""

    def save_file_name(self, title: str, directory: str = "", filter: str = SCENE_FILTER) -> str | None:
        """A file to write, or None if the user cancelled."""

    def ask_save_changes(self, name: str) -> str:
        """Unsaved changes in ``name``: returns SAVE, DISCARD or CANCEL."""

    def ask_yes_no(self, title: str, text: str) -> bool:
        """A yes/no question; True for yes."""

    def error(self, title: str, text: str, details: str = "") -> None:
        """Tell the user something failed (``details``: the full list of problems, if any)."""

    def info(self, title: str, text: str) -> None:
        """Tell the user something (the About box)."""

    def export_request(self, title: str, choices: dict, default_id: str, fmt: str,
                       min_webs: dict | None = None):
        """The export options (an :class:`~mechsketch.gui.export_dialog.ExportRequest`) for one of
        the elements ``choices`` (id -> part names), or None if the user cancelled."""


class QtDialogService:
    """The real :class:`DialogService`: Qt's file dialogs and message boxes over ``parent``."""

    def __init__(self, parent: QWidget | None = None) -> None:
        self.parent = parent

    def open_file_name(self, title: str, directory: str = "", filter: str = SCENE_FILTER) -> str | None:
        name, _ = QFileDialog.getOpenFileName(self.parent, title, directory, filter)
        return name or None

    def save_file_name(self, title: str, directory: str = "", filter: str = SCENE_FILTER) -> str | None:
        name, _ = QFileDialog.getSaveFileName(self.parent, title, directory, filter)
        return name or None

    def ask_save_changes(self, name: str) -> str:
        box = QMessageBox(QMessageBox.Icon.Warning, "Unsaved changes",
                          f"Save the changes to {name}?", parent=self.parent)
        box.setInformativeText("Your changes are lost if you don't save them.")
        box.setStandardButtons(QMessageBox.StandardButton.Save | QMessageBox.StandardButton.Discard
                               | QMessageBox.StandardButton.Cancel)
        box.setDefaultButton(QMessageBox.StandardButton.Save)
        answer = box.exec()
        if answer == QMessageBox.StandardButton.Save:
            return SAVE
        if answer == QMessageBox.StandardButton.Discard:
            return DISCARD
        return CANCEL

    def ask_yes_no(self, title: str, text: str) -> bool:
        answer = QMessageBox.question(self.parent, title, text,
                                      QMessageBox.StandardButton.Yes | QMessageBox.StandardButton.No,
                                      QMessageBox.StandardButton.Yes)
        return answer == QMessageBox.StandardButton.Yes

    def error(self, title: str, text: str, details: str = "") -> None:
        box = QMessageBox(QMessageBox.Icon.Critical, title, text, parent=self.parent)
        if details:
            box.setDetailedText(details)
        box.exec()

    def info(self, title: str, text: str) -> None:
        QMessageBox.information(self.parent, title, text)

    def export_request(self, title: str, choices: dict, default_id: str, fmt: str,
                       min_webs: dict | None = None):
        from .export_dialog import ExportDialog

        dlg = ExportDialog(title, choices, default_id, fmt, min_webs, self.parent)
        return dlg.request() if dlg.exec() == QDialog.DialogCode.Accepted else None
