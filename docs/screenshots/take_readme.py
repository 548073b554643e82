"""Retake the README screenshots of the help, the preferences and the Study and Design docks from
the real window (not a test; the plots' read-out is docs/screenshots/take_panels.py). Run under a
virtual X server, from the repository root::

    xvfb-run -s "-screen 0 1440x900x24" .venv/bin/python docs/screenshots/take_readme.py

Writes docs/screenshots/main.png (the four-bar, joint E selected), help_manual.png (F1 over the
canvas with the Geneva tool active),
preferences.png (Edit › Preferences), study.png (a tolerance study of the four-bar's crank
and rocker, its band on the canvas) and design.png (three typed poses, the candidates).
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
    from PySide6.QtCore import QPoint, Qt
    from PySide6.QtWidgets import QApplication, QScrollArea

    from mechsketch.gui.app import build

    state = Path(tempfile.mkdtemp())
    parts = build(dialogs=FakeDialogs(), settings_path=state / "s.ini", state_dir=state / "st", offer_recovery=False)
    w, ctl = parts.window, parts.controller
    w.resize(1440, 860)
    w.show()
    app = QApplication.instance()

    def settle(seconds: float = 0.5) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            app.processEvents()
            time.sleep(0.01)

    def xdo(*args: str) -> None:
        subprocess.run(["xdotool", *args], check=True)
        settle()

    def centre(widget) -> list[str]:
        p = widget.mapToGlobal(QPoint(widget.width() // 2, widget.height() // 2))
        return [str(p.x()), str(p.y())]

    def until(done, seconds: float = 600.0) -> None:
        end = time.monotonic() + seconds
        while not done() and time.monotonic() < end:
            settle(0.2)

    settle(1.5)
    # the main window: the four-bar crank-rocker, joint E selected
    w.actions["example:fourbar_crank_rocker"].trigger()
    ctl.set_selection([("fourbar", "joint", "E")])
    settle(1.0)
    w.grab().save(str(HERE / "main.png"))
    # the manual: F1 over the canvas with the Geneva tool active
    w.canvas.toolbox.actions["geneva"].trigger()
    w.activateWindow()
    w.canvas.setFocus()
    xdo("mousemove", *centre(w.canvas))
    xdo("key", "F1")
    settle(1.0)
    help_window = w.help.help_window
    help_window.resize(1100, 760)
    settle(0.8)
    help_window.grab().save(str(HERE / "help_manual.png"))
    help_window.close()
    w.canvas.toolbox.actions["select"].trigger()
    # Edit › Preferences
    w.actions["preferences"].trigger()
    settle(0.8)
    w.preferences_dialog.grab().save(str(HERE / "preferences.png"))
    w.preferences_dialog.close()
    # the Study dock: a tolerance study of the four-bar (crank and rocker ± their defaults)
    w.actions["example:fourbar_crank_rocker"].trigger()
    dock = w.docks["study"]
    dock.show()
    dock.raise_()
    settle(0.8)
    study = w.design_docks.study
    study.run_button.click()
    until(lambda: not study.runner.busy)
    settle(1.0)
    for area in study.findChildren(QScrollArea):   # down to the results: histogram, sensitivity
        area.verticalScrollBar().setValue(area.verticalScrollBar().maximum())
    settle(0.5)
    w.grab().save(str(HERE / "study.png"))
    # the Design dock: three typed poses of a coupler, two exact four-bars
    parts.dialogs.save_changes.append("discard")
    w.actions["new"].trigger()
    dock = w.docks["design"]
    dock.show()
    dock.raise_()
    settle(0.8)
    design = w.design_docks.design
    design.mode_box.setCurrentIndex(design.mode_box.findData("motion"))
    table = design.target.widget
    add = design.findChild(type(design.run_button), "designAddRow")
    for r, pose in enumerate([(0.0, 0.0, 0.0), (40.0, 10.0, 20.0), (70.0, 40.0, 45.0)]):
        add.click()
        for c, v in enumerate(pose):
            table.item(r, c).setText(f"{v:g}") if table.item(r, c) else None
    settle(0.5)
    design.count.setValue(3)
    design.run_button.click()
    until(lambda: not design.runner.busy)
    settle(1.0)
    w.grab().save(str(HERE / "design.png"))
    parts.autosave.stop()
    del Qt
    os._exit(0)


if __name__ == "__main__":
    main()
