"""Retake the README screenshots of the drawing tools from the real window (not a test).

Run under a virtual X server, from the repository root::

    xvfb-run -s "-screen 0 1440x900x24" .venv/bin/python docs/screenshots/take_tools.py

It starts the app, chooses File -> New and then draws as a user would, with mouse clicks and keys
sent to the canvas: a Geneva drive (Geneva tool), a rolling lever (rolling-lever tool), a six-bar
with a PRP group (ground, crank, RRR and PRP tools); it switches the overlays and the centrodes
view on from the View menu, exports a GIF with File -> Export Animation, and captures the X
screen with ImageMagick's ``import -window root`` after each step.
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PySide6.QtCore import QEvent, QPointF, QRectF, Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QApplication

from mechsketch.gui.app import build

OUT = Path(__file__).resolve().parent


class Answers:
    """A dialog service answering the export's file question; everything else is refused."""

    def __init__(self) -> None:
        self.names: list[str] = []

    def save_file_name(self, *a, **k):
        return self.names.pop(0) if self.names else None

    def open_file_name(self, *a, **k):
        return None

    def ask_save_changes(self, name):
        return "discard"

    def ask_yes_no(self, *a):
        return False

    def error(self, *a):
        print("error:", a, file=sys.stderr)

    def info(self, *a):
        pass


def settle(ms: int = 150) -> None:
    """Let Qt work for ``ms`` (the app's event loop is not running: deferred deletes too)."""
    end = time.perf_counter() + ms / 1000
    while time.perf_counter() < end:
        QApplication.processEvents()
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)
        time.sleep(0.01)


def main() -> None:
    tmp = Path(tempfile.mkdtemp())
    dialogs = Answers()
    parts = build(None, dialogs=dialogs, settings_path=tmp / "s.ini", state_dir=tmp / "state", offer_recovery=False)
    win, ctl = parts.window, parts.controller
    win.resize(1440, 900)
    win.move(0, 0)
    win.show()
    settle(600)
    win.actions["new"].trigger()
    view = win.canvas
    vp = view.viewport()
    view.snap_enabled = True

    def at(xy):
        return view.mapFromScene(QPointF(*xy))

    def click(xy):
        QTest.mouseMove(vp, at(xy))
        QTest.mouseClick(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(xy))
        settle(40)

    def move(xy):
        QTest.mouseMove(vp, at(xy))
        settle(60)

    def tool(name):
        view.toolbox.actions[name].trigger()

    def shot(name):
        settle(300)
        subprocess.run(["import", "-window", "root", str(OUT / name)], check=True)
        print("wrote", OUT / name)

    # -- a Geneva drive: two clicks, keys for the slots; handles and the Geneva overlay ----------
    view.zoom_to_rect(QRectF(-110, -120, 330, 240))
    tool("geneva")
    click((0, 0))
    move((100, 0))
    QTest.keyClick(vp, Qt.Key.Key_6)
    move((100, 0))
    shot("tool_geneva_placing.png")
    click((100, 0))
    view.extras.actions["geneva"].trigger()
    tool("select")
    eid = ctl.scene.ids[-1]
    res = ctl.element_result(eid)
    k = int(np.nanargmax(res.contact.Rn)) if res.contact is not None else 0
    ctl.set_frame(round(k * ctl.sample_count() / res.n_frames) - 40)
    shot("tool_geneva.png")

    # -- a rolling lever: seven clicks, then one handle dragged --------------------------------
    ctl.set_selection([])
    off = (0.0, 400.0)
    pts = [(0, 0), (50, 0), (60, -20), (-150, -40), (20, 0), (100, 0), (60, 0)]
    pts = [(x + off[0], y + off[1]) for x, y in pts]
    view.zoom_to_rect(QRectF(-190 + off[0], -120 + off[1], 330, 230))
    tool("rolling")
    for p in pts[:6]:
        click(p)
    move((75 + off[0], 25 + off[1]))
    shot("tool_rolling_placing.png")
    click(pts[6])
    tool("select")
    lever = ctl.scene.ids[-1]
    ctl.set_frame(ctl.sample_count() // 5)
    shot("tool_rolling.png")

    # -- a six-bar with a PRP group: ground, crank, RRR, PRP ------------------------------------
    ctl.set_selection([])
    o = (600.0, 0.0)
    view.zoom_to_rect(QRectF(-80 + o[0], -60 + o[1], 320, 260))
    tool("ground")
    click((0 + o[0], 0 + o[1]))
    click((160 + o[0], 0 + o[1]))
    tool("crank")
    click((0 + o[0], 0 + o[1]))
    click((20 + o[0], 40 + o[1]))
    tool("rrr")
    click((20 + o[0], 40 + o[1]))
    click((160 + o[0], 0 + o[1]))
    click((130 + o[0], 110 + o[1]))
    tool("prp")
    click((145 + o[0], 55 + o[1]))
    click((100 + o[0], 150 + o[1]))
    move((10 + o[0], 150 + o[1]))
    shot("tool_prp_placing.png")
    click((0 + o[0], 150 + o[1]))
    tool("select")
    six = [lk.id for lk in ctl.linkages()][-1]
    ctl.set_selection([(six, "joint", "E"), (six, "joint", "D")])
    extras = view.extras.actions
    extras["vectors"].trigger()
    extras["transmission"].trigger()
    ctl.set_frame(60)
    shot("tool_prp_sixbar.png")
    extras["vectors"].trigger()

    # -- the coupler's centrodes, rolling --------------------------------------------------------
    ctl.set_selection([(six, "link", "link1")])
    extras["centrodes"].trigger()
    extras["centres"].trigger()
    view.zoom_to_rect(QRectF(-260 + o[0], -200 + o[1], 700, 520))
    ctl.set_frame(100)
    shot("centrodes.png")

    # -- File -> Export Animation (GIF) ---------------------------------------------------------
    gif = OUT / "sixbar_centrodes.gif"
    dialogs.names.append(str(gif))
    done = []
    win.canvas_menus.exporter.finished.connect(done.append)
    win.resize(900, 640)
    settle(300)
    win.canvas_menus.actions["export_animation"].trigger()
    while not done:
        settle(100)
    print(done[0])
    del lever
    parts.close()


if __name__ == "__main__":
    main()
