"""How long Open of a large scene blocks the GUI thread: all of it solved in place (before issue
20's GUI leftovers) against the background solve (now). A report, not a timed test.

It builds the whole app offscreen, writes a crank driving N RRR dyads (``tests/core/chains.py``;
N = 500: 1,002 joints) and opens it twice through File › Open:

- ``in place``: the heavy threshold raised so nothing is heavy (the old path): the GUI thread
  compiles, sweeps, diagnoses, classifies and then builds the docks before the event loop runs
  again;
- ``background``: the default: the GUI thread returns from Open at once, the worker solves (with
  the diagnostics and the summary the Diagnostics dock shows), and the GUI thread only lays out
  the docks and the canvas when the result lands.

It prints the GUI thread's blocked time in each (the longest stretch between two event-loop
turns, measured by a 0 ms timer) and their ratio, with the load average. Run from the repository
root::

    .venv/bin/python benchmarks/bench_open_large.py [N]
"""
from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "gui"), str(ROOT / "tests" / "core")]
os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")


def _open_blocked(n: int, heavy_seconds: float) -> tuple[float, float]:
    """(longest GUI-thread stretch without an event-loop turn, wall time to the document shown), s."""
    from app_fakes import FakeDialogs
    from chains import dyad_chain
    from PySide6.QtCore import QTimer
    from PySide6.QtWidgets import QApplication

    from mechsketch.core.io.scene_file import dumps_scene
    from mechsketch.core.model.scene import Scene
    from mechsketch.gui import controller as controller_module
    from mechsketch.gui.app import build

    controller_module.HEAVY_SECONDS = heavy_seconds
    state = Path(tempfile.mkdtemp())
    path = state / f"chain{n}.json"
    path.write_text(dumps_scene(Scene((dyad_chain(n),))))
    parts = build(dialogs=FakeDialogs(), settings_path=state / "s.ini", state_dir=state / "st", offer_recovery=False)
    w, c = parts.window, parts.controller
    w.show()
    app = QApplication.instance()
    for _ in range(20):
        app.processEvents()
    ticks = [time.perf_counter()]
    timer = QTimer()
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    timer.start(0)
    parts.dialogs.open_names.append(str(path))
    parts.dialogs.save_changes.append("discard")
    start = time.perf_counter()
    QTimer.singleShot(0, w.actions["open"].trigger)
    while c.scene.ids != ("chain",) or c.background.busy:
        app.processEvents()
        time.sleep(0.001)
    for _ in range(50):   # the docks' deferred redraws
        app.processEvents()
    shown = time.perf_counter() - start
    timer.stop()
    gaps = [b - a for a, b in zip(ticks, ticks[1:]) if a >= start - 0.01]
    parts.autosave.stop()
    parts.dialogs.save_changes.append("discard")
    w.close()
    return max(gaps, default=0.0), shown


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 500
    from mechsketch.gui.background import HEAVY_SECONDS

    blocked_old, shown_old = _open_blocked(n, 1e9)
    blocked_new, shown_new = _open_blocked(n, HEAVY_SECONDS)
    load = os.getloadavg()
    print(f"open a chain of {n} dyads ({2 * n + 2} joints); load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print(f"  in place:   GUI thread blocked {blocked_old:7.2f} s at most; shown after {shown_old:7.2f} s")
    print(f"  background: GUI thread blocked {blocked_new:7.2f} s at most; shown after {shown_new:7.2f} s")
    print(f"  longest block, background / in place: {blocked_new / blocked_old:.3f}")
    os._exit(0)


if __name__ == "__main__":
    main()
