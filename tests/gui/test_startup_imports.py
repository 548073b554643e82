"""GUI start-up (issue 14): the first frame imports no heavy library it does not draw with, and
the plots dock made after it is the same panel as before. Not timed: fresh processes are checked
through ``sys.modules``; benchmarks/bench_gui_startup.py reports the time."""
from __future__ import annotations

import json
import os
import subprocess
import sys

from app_fakes import FakeDialogs
from PySide6.QtWidgets import QToolButton

from mechsketch.gui.main_window import LazyDock

HEAVY = ("pyqtgraph", "shapely", "ezdxf", "jsonschema", "imageio", "scipy", "matplotlib")

PROBE = r"""
import json, os, sys, tempfile, time
from mechsketch.gui.app import build
from PySide6.QtCore import QEvent, QEventLoop, QObject

class FirstPaint(QObject):
    seen = False
    heavy = None
    def eventFilter(self, obj, event):
        if not self.seen and event.type() == QEvent.Type.Paint:
            self.seen = True
            self.heavy = sorted({m.split(".")[0] for m in sys.modules} & set(HEAVY))
        return False

HEAVY = json.loads(sys.argv[1])
state = tempfile.mkdtemp()
parts = build(state_dir=state, settings_path=os.path.join(state, "settings.ini"))
probe = FirstPaint()
parts.app.installEventFilter(probe)
after_build = sorted({m.split(".")[0] for m in sys.modules} & set(HEAVY))
parts.window.show()
limit = time.monotonic() + 60
while not probe.seen and time.monotonic() < limit:
    parts.app.processEvents(QEventLoop.ProcessEventsFlag.WaitForMoreEvents)
dock = parts.window.docks["plots"]
pending_at_paint = dock.pending
while dock.pending and time.monotonic() < limit:
    parts.app.processEvents(QEventLoop.ProcessEventsFlag.WaitForMoreEvents)
print(json.dumps({"after_build": after_build, "at_first_paint": probe.heavy, "pending_at_paint": pending_at_paint,
                  "pending_later": dock.pending, "panel": type(dock.widget()).__name__,
                  "curves": len(parts.window.plots.curves), "later": sorted({m.split(".")[0] for m in sys.modules} & set(HEAVY))}))
parts.autosave.stop()
os._exit(0)
"""


def test_first_frame_imports_no_heavy_library_and_the_plots_follow():
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    out = subprocess.run([sys.executable, "-c", PROBE, json.dumps(HEAVY)], capture_output=True, text=True,
                         timeout=120, env=env)
    assert out.returncode == 0, out.stderr
    got = json.loads(out.stdout.strip().splitlines()[-1])
    assert got["after_build"] == [] and got["at_first_paint"] == [], got
    assert got["pending_at_paint"] is True          # the plots were not made before the first frame
    assert got["pending_later"] is False and got["panel"] == "PlotsPanel"
    assert got["curves"] > 0                        # the default example's plots are drawn
    assert got["later"] == ["pyqtgraph"]             # and only then is pyqtgraph loaded


def test_plots_made_on_demand_before_the_window_is_shown(qtbot, tmp_path):
    from mechsketch.gui.app import build

    parts = build(dialogs=FakeDialogs(), settings_path=tmp_path / "s.ini", state_dir=tmp_path / "st",
                  offer_recovery=False)
    qtbot.addWidget(parts.window)
    dock = parts.window.docks["plots"]
    assert isinstance(dock, LazyDock) and dock.pending
    plots = parts.window.plots                     # asked for: made now, and put in the dock
    assert not dock.pending and dock.widget() is plots and parts.window.plots is plots
    assert "fourbar" in plots.title.text()
    actions = {b.defaultAction() for b in plots.findChildren(QToolButton)}
    assert {parts.window.actions["export_png"], parts.window.actions["export_csv"]} <= actions
    parts.autosave.stop()
    parts.window.close()


def test_plots_made_after_the_first_paint_when_shown(qtbot, tmp_path):
    from mechsketch.gui.app import build

    parts = build(dialogs=FakeDialogs(), settings_path=tmp_path / "s.ini", state_dir=tmp_path / "st",
                  offer_recovery=False)
    qtbot.addWidget(parts.window)
    dock = parts.window.docks["plots"]
    assert dock.pending
    parts.window.show()
    qtbot.waitUntil(lambda: not dock.pending, timeout=20000)   # no one asked: the first paint made it
    assert type(dock.widget()).__name__ == "PlotsPanel" and dock.widget().isVisible() is True
    parts.autosave.stop()
    parts.window.close()


def test_stand_in_asks_for_the_plots_panels_size(qtbot, tmp_path):
    """The first layout is the one the real panel gets: same size hints."""
    from PySide6.QtWidgets import QDockWidget

    from mechsketch.gui.app import build

    parts = build(dialogs=FakeDialogs(), settings_path=tmp_path / "s.ini", state_dir=tmp_path / "st",
                  offer_recovery=False)
    qtbot.addWidget(parts.window)
    dock = parts.window.docks["plots"]
    stand_in = QDockWidget.widget(dock)             # what the dock holds now, not made on demand
    assert dock.pending and type(stand_in).__name__ == "_FirstPaint"
    plots = parts.window.plots
    assert (stand_in.sizeHint(), stand_in.minimumSizeHint()) == (plots.sizeHint(), plots.minimumSizeHint())
    parts.autosave.stop()
    parts.window.close()


def test_canvas_fits_as_with_the_plots_made_before_the_window_shows(qtbot, tmp_path):
    """The canvas zooms to fit at its first show: with the plots made after the first frame it
    must land on the same view as when they exist from the start (they did before issue 14)."""
    from mechsketch.gui.app import build

    views = []
    for eager in (True, False):
        parts = build(dialogs=FakeDialogs(), settings_path=tmp_path / f"{eager}.ini",
                      state_dir=tmp_path / f"st{eager}", offer_recovery=False)
        qtbot.addWidget(parts.window)
        if eager:
            parts.window.plots
        parts.window.show()
        dock = parts.window.docks["plots"]
        qtbot.waitUntil(lambda: not dock.pending, timeout=20000)
        qtbot.waitUntil(lambda: parts.window.docks["plots"].width() < 500, timeout=20000)   # size_docks ran
        canvas = parts.window.canvas
        centre = canvas.mapToScene(canvas.viewport().rect().center())
        views.append((canvas.transform().m11(), round(centre.x(), 6), round(centre.y(), 6),
                      canvas.viewport().width(), dock.width()))
        parts.autosave.stop()
        parts.window.close()
    assert views[0] == views[1]
    assert views[0][0] > 0
