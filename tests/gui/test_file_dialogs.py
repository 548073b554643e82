"""The app's file dialogs never open the files they list (issue 20 item 11).

Typing ``/proc/`` into the Save dialog as root froze the app: Qt's own icon provider guesses each
listed file's type from its first bytes, on the GUI thread among others, and ``/proc/kmsg`` blocks
its reader. The probe here is the kernel's own record of opens (inotify on the folder): the
dialog the app uses, driven as a user types a path, must cause none; Qt's stock dialog on the same
folder does (so the probe can fail).
"""
from __future__ import annotations

import ctypes
import os
import struct
import sys

import pytest
from PySide6.QtCore import QFileInfo, Qt
from PySide6.QtWidgets import QFileDialog, QFileSystemModel, QLineEdit

from mechsketch.gui.dialogs import SCENE_FILTER, SafeIconProvider, file_dialog
from mechsketch.gui.file_ops import FileOps

from app_fakes import FakeDialogs, shell  # noqa: F401 - fixture

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="inotify is Linux's")

IN_OPEN, IN_ISDIR = 0x00000020, 0x40000000
NAMES = ("kmsg", "notes", "scene.json", "drawing.dxf")


class OpenProbe:
    """Names of the files in ``folder`` that anything opened since the probe was made."""

    def __init__(self, folder) -> None:
        self.libc = ctypes.CDLL(None, use_errno=True)
        self.fd = self.libc.inotify_init1(os.O_NONBLOCK | os.O_CLOEXEC)
        assert self.fd >= 0, os.strerror(ctypes.get_errno())
        assert self.libc.inotify_add_watch(self.fd, os.fsencode(folder), IN_OPEN) >= 0

    def opened(self) -> set[str]:
        names: set[str] = set()
        while True:
            try:
                data = os.read(self.fd, 65536)
            except BlockingIOError:
                return names
            at = 0
            while at < len(data):
                _wd, mask, _cookie, length = struct.unpack_from("iIII", data, at)
                name = data[at + 16:at + 16 + length].rstrip(b"\0").decode()
                if not mask & IN_ISDIR and name:
                    names.add(name)
                at += 16 + length

    def close(self) -> None:
        os.close(self.fd)


@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "listed"
    d.mkdir()
    for name in NAMES:
        (d / name).write_bytes(b"<6>kernel message\n" * 8 if name == "kmsg" else b"{}")
    return d


def _type_path_and_wait(qtbot, dlg: QFileDialog, folder) -> QFileSystemModel:
    """Type ``folder/k`` into the dialog's file-name box and wait until the dialog's model knows
    every listed file's type (the icon provider has seen them all)."""
    dlg.show()
    edit = dlg.findChild(QLineEdit, "fileNameEdit")
    edit.setFocus()
    qtbot.keyClicks(edit, f"{folder}/k")
    model = dlg.findChild(QFileSystemModel)
    qtbot.waitUntil(lambda: all(model.type(model.index(str(folder / n))) for n in NAMES), timeout=20000)
    for name in NAMES:                        # what a view paints: icon and type, on the GUI thread
        index = model.index(str(folder / name))
        model.data(index, Qt.ItemDataRole.DecorationRole)
        model.data(index.siblingAtColumn(2), Qt.ItemDataRole.DisplayRole)
    return model


def test_the_probe_sees_qts_own_dialog_read_the_files_it_lists(qtbot, folder):
    probe = OpenProbe(folder)
    dlg = QFileDialog(None, "stock", str(folder), SCENE_FILTER)
    dlg.setOption(QFileDialog.Option.DontUseNativeDialog)
    dlg.setAcceptMode(QFileDialog.AcceptMode.AcceptSave)
    qtbot.addWidget(dlg)
    _type_path_and_wait(qtbot, dlg, folder)
    try:
        assert "kmsg" in probe.opened()      # Qt sniffed the extension-less file's first bytes
    finally:
        probe.close()
        dlg.reject()


@pytest.mark.parametrize("save", [True, False])
def test_the_apps_file_dialogs_open_no_listed_file(qtbot, folder, save):
    probe = OpenProbe(folder)
    dlg = file_dialog(None, "Save scene as" if save else "Open scene", str(folder), SCENE_FILTER, save)
    dlg.setOption(QFileDialog.Option.DontUseNativeDialog)   # offscreen it is Qt's widget dialog anyway
    qtbot.addWidget(dlg)
    model = _type_path_and_wait(qtbot, dlg, folder)
    try:
        assert probe.opened() == set()
        assert model.type(model.index(str(folder / "scene.json")))   # types still shown, from names
        assert isinstance(dlg.iconProvider(), SafeIconProvider)
    finally:
        probe.close()
        dlg.reject()


def test_the_icon_provider_names_types_without_reading(folder):
    probe = OpenProbe(folder)
    provider = SafeIconProvider()
    try:
        for name in NAMES:
            info = QFileInfo(str(folder / name))
            assert not provider.icon(info).isNull() or True   # an icon or none: never a read
            assert provider.type(info)
        assert provider.type(QFileInfo(str(folder))) == "Folder"
        assert "JSON" in provider.type(QFileInfo(str(folder / "scene.json")))
        assert probe.opened() == set()
    finally:
        probe.close()


def test_a_system_file_is_refused_before_it_is_read(shell, tmp_path):
    """/proc/kmsg is a 'regular' file of size 0 that blocks (and is consumed) when read: Open
    refuses files of /proc, /sys and /dev by their place, reading nothing."""
    dialogs = FakeDialogs()
    parts = shell(dialogs=dialogs)
    fo: FileOps = parts.file_ops
    before = parts.controller.scene
    for path in ("/proc/kmsg", "/proc/self/status", "/sys/kernel/notes", "/dev/zero"):
        assert fo.open(path, ask=False) is False
        title, text, _ = dialogs.errors[-1]
        assert title == "Cannot open scene" and "system file" in text and path in text, text
    assert parts.controller.scene is before
