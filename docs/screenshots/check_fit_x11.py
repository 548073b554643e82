"""The Properties dock's fit checked in a real X11 window (not a test; issue 24 item 5).

Offscreen fonts are narrower than an X11 desktop's, so the sequence the issue names is run here:
at 1024 x 700 and 1440 x 900, open the rolling-lever examples and select the lever, then every
other example's joints, links and elements; the panel's content must fit the dock's viewport at
the default width (no control beyond it, its minimum width within it) and the dock must keep
that width. It also narrows the dock to 220 px on the Geneva drive, where "ω1 = … rad/s" wraps,
and saves a screenshot (``/tmp/x11_fit_units.png``) to look at. Run from the repository root::

    xvfb-run -a -s "-screen 0 1440x900x24" .venv/bin/python docs/screenshots/check_fit_x11.py

It prints one line per failed check and a summary, and exits 1 if one fails.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "gui"))
os.environ["QT_QPA_PLATFORM"] = "xcb"

EXAMPLES = ("rolling_lever_press", "rolling_lever_law", "fourbar_loaded", "sixbar_moving_guide", "geneva_z6",
            "gears_elliptic", "smooth_geneva_z5", "excavator_arm", "rolling_lever_inclined")


def main() -> int:
    from app_fakes import FakeDialogs
    from PySide6.QtCore import QPoint, Qt
    from PySide6.QtWidgets import QAbstractButton, QApplication, QComboBox, QGroupBox, QLabel, QLineEdit, QWidget

    from mechsketch.gui.app import build

    state = Path(tempfile.mkdtemp())
    parts = build(dialogs=FakeDialogs(), settings_path=state / "s.ini", state_dir=state / "st", offer_recovery=False)
    w, ctl = parts.window, parts.controller
    w.show()
    app = QApplication.instance()
    parts.dialogs.save_changes.extend(["discard"] * 50)

    def settle(seconds: float = 0.3) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            app.processEvents()
            time.sleep(0.01)

    def misfits() -> list[str]:
        content = w.properties._content
        width = content.parentWidget().width()
        need = content.layout().totalMinimumSize().width()
        out = [f"content needs {need} px > {width}"] if need > width else []
        for c in content.findChildren(QWidget):
            if isinstance(c, (QLineEdit, QAbstractButton, QLabel, QComboBox, QGroupBox)) and c.isVisibleTo(content):
                right = c.mapTo(content, QPoint(c.width(), 0)).x()
                if right > width + 1:
                    out.append(f"{type(c).__name__} {c.objectName()!r} ends at {right} > {width}")
        return out

    failures, checks = [], 0
    for size in ((1024, 700), (1440, 900)):
        w.resize(*size)
        settle(1.0)
        w.size_docks()
        settle()
        default = w.docks["properties"].width()
        for example in EXAMPLES:
            w.actions[f"example:{example}"].trigger()
            settle()
            picks = []
            for el in ctl.scene.elements:
                picks += ([(el.id, "joint", j) for j in el.joint_ids] + [(el.id, "link", k) for k in el.link_ids]
                          if el.type == "linkage" else [(el.id, "element", el.id)])
            for pick in picks:
                ctl.set_selection([pick])
                settle(0.2)
                checks += 1
                bad = misfits()
                if w.docks["properties"].width() != default:
                    bad.append(f"the dock went from {default} to {w.docks['properties'].width()} px")
                if bad:
                    failures.append(f"{size} {example} {pick[1]} {pick[2]}: {bad}")
    w.actions["example:geneva_z6"].trigger()
    ctl.set_selection([("indexer", "element", "indexer")])
    w.resizeDocks([w.docks["properties"]], [220], Qt.Orientation.Horizontal)
    settle(1.0)
    subprocess.run(["import", "-window", "root", str(Path(tempfile.gettempdir()) / "x11_fit_units.png")], check=False)
    for line in failures:
        print("FAIL", line)
    print(f"{checks - len(failures)}/{checks} selections fit the Properties dock at the default width")
    parts.autosave.stop()
    w.close()
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
