"""The dialogs the app asks through: an injectable service, so tests answer with a fake.

Every component that needs a file name, a question or an error message calls a
:class:`DialogService` handed to it; nothing else in the app opens a modal dialog. Tests pass an
object with the same methods (see ``tests/gui/app_fakes.py``) and never patch Qt.

The file dialogs never open a file they list (:class:`SafeIconProvider`): Qt's own icon provider
reads each file's first bytes to guess its type, on the GUI thread among others, and a file such
as ``/proc/kmsg`` blocks its reader (typing ``/proc/`` froze the Save dialog as root).
"""
from __future__ import annotations

from typing import Protocol

from PySide6.QtCore import QFileInfo, QMimeDatabase
from PySide6.QtGui import QAbstractFileIconProvider, QIcon
from PySide6.QtWidgets import QDialog, QFileDialog, QFileIconProvider, QInputDialog, QMessageBox, QWidget

from .qtsafe import qt_safe

SCENE_FILTER = "mechsketch scenes (*.json);;All files (*)"

#: answers of :meth:`DialogService.ask_save_changes`
SAVE, DISCARD, CANCEL = "save", "discard", "cancel"


@qt_safe
class SafeIconProvider(QFileIconProvider):
    """A file's icon and type name from its name and kind alone (a stat, never a read)."""

    def __init__(self) -> None:
        super().__init__()
        self._mime = QMimeDatabase()

    def _by_name(self, info: QFileInfo):
        return self._mime.mimeTypeForFile(info.fileName(), QMimeDatabase.MatchMode.MatchExtension)

    def icon(self, what):  # noqa: D102 - QFileIconProvider.icon(IconType | QFileInfo)
        if not isinstance(what, QFileInfo):
            return super().icon(what)
        kind = QAbstractFileIconProvider.IconType
        if what.isRoot():
            return super().icon(kind.Drive)
        if what.isDir():
            return super().icon(kind.Folder)
        themed = QIcon.fromTheme(self._by_name(what).iconName())
        return themed if not themed.isNull() else super().icon(kind.File)

    def type(self, info: QFileInfo) -> str:  # noqa: D102 - QFileIconProvider.type
        if info.isDir():
            return "Folder"
        mime = self._by_name(info)
        return "File" if mime.isDefault() else mime.comment()


def file_dialog(parent: QWidget | None, title: str, directory: str, filter: str, save: bool) -> QFileDialog:
    """A file dialog (Save or Open) that lists files without opening any of them."""
    dlg = QFileDialog(parent, title, directory, filter)
    dlg.setAcceptMode(QFileDialog.AcceptMode.AcceptSave if save else QFileDialog.AcceptMode.AcceptOpen)
    dlg.setFileMode(QFileDialog.FileMode.AnyFile if save else QFileDialog.FileMode.ExistingFile)
    provider = SafeIconProvider()
    dlg.setIconProvider(provider)
    dlg._icon_provider = provider   # the dialog does not own it: keep it alive as long as the dialog
    return dlg


def _ask_file(parent: QWidget | None, title: str, directory: str, filter: str, save: bool) -> str | None:
    dlg = file_dialog(parent, title, directory, filter, save)
    if dlg.exec() != QDialog.DialogCode.Accepted:
        return None
    names = dlg.selectedFiles()
    return names[0] if names else None


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

    def ask_number(self, title: str, text: str, value: float, unit: str = "") -> float | None:
        """A positive number (shown with ``unit``), ``value`` offered; None if the user cancelled."""

    def export_request(self, title: str, choices: dict, default_id: str, fmt: str,
                       min_webs: dict | None = None, kinds: dict | None = None, sizes: dict | None = None):
        """The export options (an :class:`~mechsketch.gui.export_dialog.ExportRequest`) for one of
        the elements ``choices`` (id -> part names; ``kinds`` id -> type, ``sizes`` preferred plate
        sizes), or None if the user cancelled."""


class QtDialogService:
    """The real :class:`DialogService`: Qt's file dialogs and message boxes over ``parent``."""

    def __init__(self, parent: QWidget | None = None) -> None:
        self.parent = parent

    def open_file_name(self, title: str, directory: str = "", filter: str = SCENE_FILTER) -> str | None:
        return _ask_file(self.parent, title, directory, filter, save=False)

    def save_file_name(self, title: str, directory: str = "", filter: str = SCENE_FILTER) -> str | None:
        return _ask_file(self.parent, title, directory, filter, save=True)

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

    def ask_number(self, title: str, text: str, value: float, unit: str = "") -> float | None:
        label = f"{text} ({unit})" if unit else text
        number, ok = QInputDialog.getDouble(self.parent, title, label, value, 1e-9, 1e9, 6)
        return number if ok else None

    def export_request(self, title: str, choices: dict, default_id: str, fmt: str,
                       min_webs: dict | None = None, kinds: dict | None = None, sizes: dict | None = None):
        from .export_dialog import ExportDialog

        dlg = ExportDialog(title, choices, default_id, fmt, min_webs, self.parent, kinds, sizes)
        return dlg.request() if dlg.exec() == QDialog.DialogCode.Accepted else None
