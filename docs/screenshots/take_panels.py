"""Retake the README screenshot of the docks (plots with their read-out, properties) from the real
window (not a test). Run under a virtual X server, from the repository root::

    xvfb-run -s "-screen 0 1440x900x24" .venv/bin/python docs/screenshots/take_panels.py

Writes docs/screenshots/plots_readout.png: the loaded four-bar at 1440 x 860, joint C selected,
the pointer over the velocity plot (every legend reads its curves at that input).
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "tests" / "gui"))
os.environ["QT_QPA_PLATFORM"] = "xcb"


def main() -> None:
    from app_fakes import FakeDialogs
    from PySide6.QtCore import QPoint
    from PySide6.QtWidgets import QApplication

    from mechsketch.gui.app import build

    state = Path(tempfile.mkdtemp())
    parts = build(dialogs=FakeDialogs(), settings_path=state / "s.ini", state_dir=state / "st", offer_recovery=False)
    w = parts.window
    w.resize(1440, 860)
    w.show()
    app = QApplication.instance()

    def settle(seconds: float = 0.5) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            app.processEvents()
            time.sleep(0.01)

    settle(1.5)
    w.actions["example:fourbar_loaded"].trigger()
    parts.controller.set_selection([("loaded_fourbar", "joint", "C")])
    parts.controller.set_frame(100)
    settle(1.0)
    row = w.plots.rows["velocity"]
    vp = row.widget.viewport()
    p = vp.mapToGlobal(QPoint(vp.width() * 2 // 3, vp.height() // 2))
    subprocess.run(["xdotool", "mousemove", str(p.x()), str(p.y())], check=True)
    settle(0.8)
    w.grab().save(str(HERE / "plots_readout.png"))
    parts.autosave.stop()
    os._exit(0)


if __name__ == "__main__":
    main()
