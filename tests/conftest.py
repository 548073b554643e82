"""Test-wide set-up: Qt runs offscreen; MECHSKETCH_BLOCK_QT=1 makes PySide6/pyqtgraph unimportable
(to prove the core works on a machine without Qt)."""
from __future__ import annotations

import importlib.abc
import os
import sys

if not os.environ.get("QT_QPA_PLATFORM"):  # an empty value counts as unset
    os.environ["QT_QPA_PLATFORM"] = "offscreen"


class _BlockQt(importlib.abc.MetaPathFinder):
    BLOCKED = ("PySide6", "pyqtgraph", "shiboken6", "mechsketch.gui")

    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in self.BLOCKED or name.startswith("mechsketch.gui"):
            raise ModuleNotFoundError(f"{name} is blocked (MECHSKETCH_BLOCK_QT=1)", name=name)
        return None


if os.environ.get("MECHSKETCH_BLOCK_QT") == "1":
    sys.meta_path.insert(0, _BlockQt())
    collect_ignore_glob = ["gui/*"]
