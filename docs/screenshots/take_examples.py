"""Retake the README screenshots of the examples from the real window (not a test): the Geneva
drive mid-indexing, the rolling-lever press, the double rocker's dead points, the six-bar with a
moving guide, the loaded four-bar's forces (torque and joint-force plots, forces on the canvas) and
the four-bar shown in inches. Run under a virtual
X server, from the repository root::

    xvfb-run -a -s "-screen 0 1440x900x24" .venv/bin/python docs/screenshots/take_examples.py

Each shot is the whole X screen (``import -window root``) with the window at 1440 x 860.
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

#: (file, example, selection or None, frame as a fraction of the cycle)
SHOTS = (("geneva.png", "geneva_z6", ("indexer", "element", "indexer"), 0.5),
         ("rolling_lever.png", "rolling_lever_press", ("press", "element", "press"), 0.4),
         ("double_rocker_dead_points.png", "double_rocker", None, 0.0),
         ("sixbar_moving_guide.png", "sixbar_moving_guide", ("sixbar", "joint", "E"), 0.25),
         ("forces_torque.png", "fourbar_loaded", ("loaded_fourbar", "joint", "C"), 0.21))


def main() -> None:
    from app_fakes import FakeDialogs
    from PySide6.QtWidgets import QApplication

    from mechsketch.gui import units
    from mechsketch.gui.app import build

    state = Path(tempfile.mkdtemp())
    parts = build(dialogs=FakeDialogs(), settings_path=state / "s.ini", state_dir=state / "st", offer_recovery=False)
    w, ctl = parts.window, parts.controller
    w.resize(1440, 860)
    w.show()
    app = QApplication.instance()
    parts.dialogs.save_changes.extend(["discard"] * 20)

    def settle(seconds: float = 0.5) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            app.processEvents()
            time.sleep(0.01)

    def shot(name: str) -> None:
        subprocess.run(["import", "-window", "root", str(HERE / name)], check=True)
        print("wrote", HERE / name)

    settle(1.5)
    for name, example, selection, at in SHOTS:
        w.actions[f"example:{example}"].trigger()
        settle(0.8)
        if selection is not None:
            ctl.set_selection([selection])
        ctl.set_frame(int(at * ctl.sample_count()))
        forces = name == "forces_torque.png"
        for row, _ in w.plots.data.rows:   # forces: the torque and the joint force; else every plot
            w.plots.set_shown(row, row in ("torque", "reaction") if forces else True)
        w.canvas.extras.actions["forces"].setChecked(forces)
        settle(1.2)
        shot(name)
    # the four-bar in inches (Edit › Preferences: length unit in)
    w.actions["example:fourbar_crank_rocker"].trigger()
    ctl.set_selection([("fourbar", "joint", "E")])
    from dataclasses import replace

    w.set_preferences(replace(w.preferences, length_unit="in"))
    settle(0.5)
    for row, _ in w.plots.data.rows:
        w.plots.set_shown(row, True)
    settle(1.2)
    shot("preferences_inch.png")
    print("units now", units.current())
    parts.autosave.stop()
    os._exit(0)


if __name__ == "__main__":
    main()
