"""Retake the README screenshot of an underlay from the real window (not a test).

Run under a virtual X server, from the repository root::

    xvfb-run -s "-screen 0 1440x900x24" .venv/bin/python docs/screenshots/take_underlay.py

It starts the app, chooses File -> New, imports ``press_frame.svg`` (written here: a press frame's
outline saved without physical units, so it arrives at the wrong size) with File -> Import
Underlay, clicks the two bottom corners of the outline and answers 380 mm, then draws a four-bar
on the frame with the ground, crank and RRR tools (the pivots snap to the outline's corners), and
captures the X screen with ImageMagick's ``import -window root``.
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

from PySide6.QtCore import QEvent, QPointF, Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QApplication

from mechsketch.gui.app import build

OUT = Path(__file__).resolve().parent
SVG = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 420 300">
  <path d="M 20 280 L 400 280 L 400 250 L 340 250 L 340 60 L 300 20 L 120 20 L 80 60 L 80 250 L 20 250 Z"
        fill="none" stroke="black"/>
  <rect x="130" y="70" width="160" height="120" fill="none" stroke="black"/>
  <circle cx="210" cy="130" r="18" fill="none" stroke="black"/>
  <circle cx="110" cy="230" r="8" fill="none" stroke="black"/>
  <circle cx="310" cy="230" r="8" fill="none" stroke="black"/>
</svg>
"""


class Answers:
    """The file to import and the distance typed; everything else is refused."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def open_file_name(self, *a, **k):
        return str(self.path)

    def save_file_name(self, *a, **k):
        return None

    def ask_save_changes(self, name):
        return "discard"

    def ask_yes_no(self, *a):
        return False

    def ask_number(self, *a, **k):
        return 380.0

    def error(self, *a):
        print("error:", a, file=sys.stderr)

    def info(self, *a):
        pass


def settle(ms: int = 150) -> None:
    end = time.perf_counter() + ms / 1000
    while time.perf_counter() < end:
        QApplication.processEvents()
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)
        time.sleep(0.01)


def main() -> None:
    tmp = Path(tempfile.mkdtemp())
    svg = tmp / "press_frame.svg"
    svg.write_text(SVG)
    parts = build(None, dialogs=Answers(svg), settings_path=tmp / "s.ini", state_dir=tmp / "state",
                  offer_recovery=False)
    win, ctl = parts.window, parts.controller
    win.resize(1440, 900)
    win.move(0, 0)
    win.show()
    settle(600)
    win.actions["new"].trigger()
    view = win.canvas
    vp = view.viewport()
    view.snap_enabled = True

    def click(xy):
        p = view.mapFromScene(QPointF(*xy))
        QTest.mouseMove(vp, p)
        QTest.mouseClick(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, p)
        settle(60)

    win.actions["import_underlay"].trigger()          # File -> Import Underlay...; placing starts
    settle(300)
    u = ctl.scene.elements[-1]
    corners = u.placement.to_world([[20.0, -280.0], [400.0, -280.0]])
    click(tuple(corners[0]))                           # the outline's bottom corners: 380 mm apart
    click(tuple(corners[1]))
    u = ctl.scene.elements[-1]
    view.zoom_to_fit()
    settle(200)

    def w(x, y):                                       # a point of the drawing (SVG units) in the world
        return tuple(u.placement.to_world([[x, -y]])[0])

    view.toolbox.actions["ground"].trigger()
    click(w(80, 250))
    click(w(340, 250))
    view.toolbox.actions["crank"].trigger()
    click(w(80, 250))
    click(w(80, 190))
    view.toolbox.actions["rrr"].trigger()
    click(w(80, 190))
    click(w(340, 250))
    click(w(300, 110))
    view.toolbox.actions["select"].trigger()
    ctl.set_frame(ctl.sample_count() // 6)
    settle(400)
    subprocess.run(["import", "-window", "root", str(OUT / "underlay.png")], check=True)
    print("wrote", OUT / "underlay.png")
    parts.close()


if __name__ == "__main__":
    main()
