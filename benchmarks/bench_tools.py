"""Cost of the canvas tools' live work: a handle drag of a Geneva drive and of a rolling lever, and
the animation export. A report, not a timed test.

For each element a handle is dragged in small steps through the real canvas (mouse events to a
shown CanvasView); each step is timed from the mouse-move event to the end of a synchronous
repaint, and the re-analysis inside it (``controller.preview`` -> workspace) separately. The
rolling lever's previews skip the slip report (the release computes it once): both costs are
printed. Then one cycle of the Geneva example is exported as a GIF: render time per frame (GUI
thread) and the whole export (worker encoding included). Errors: the preview's result equals a
fresh solve of the same element (max difference printed, expected 0).

Run::

    QT_QPA_PLATFORM=offscreen .venv/bin/python benchmarks/bench_tools.py [--moves 40]
"""
from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import numpy as np  # noqa: E402
from PySide6.QtCore import QPointF, QRectF, Qt  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402
from PySide6.QtWidgets import QApplication  # noqa: E402

from mechsketch.core import load_scene  # noqa: E402
from mechsketch.core.workspace.results import solve_geneva, solve_rolling  # noqa: E402
from mechsketch.gui.animation_export import AnimationExporter  # noqa: E402
from mechsketch.gui.canvas.view import CanvasView  # noqa: E402
from mechsketch.gui.controller import SceneController  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402


def drag(view, ctl, eid: str, handle: str, path: list[tuple[float, float]]) -> tuple[list[float], list[float]]:
    """Drag ``handle`` of ``eid`` along ``path`` (mm); per step: (total ms, re-analysis ms)."""
    vp = view.viewport()
    h = next(h for h in view.extras.handles.handles() if h.name == handle and h.element == eid)
    at = lambda xy: view.mapFromScene(QPointF(*xy))  # noqa: E731
    QTest.mouseMove(vp, at(h.at))
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(h.at))
    solve_ms: list[float] = []
    orig = ctl.preview

    def timed(edit):
        t = time.perf_counter()
        ok = orig(edit)
        ctl.element_result(eid)
        solve_ms.append((time.perf_counter() - t) * 1e3)
        return ok

    ctl.preview = timed
    total = []
    for xy in path:
        t = time.perf_counter()
        QTest.mouseMove(vp, at(xy))
        vp.repaint()
        total.append((time.perf_counter() - t) * 1e3)
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(path[-1]))
    ctl.preview = orig
    return total[1:], solve_ms[1:]


def report(name: str, total: list[float], solve: list[float]) -> None:
    print(f"| {name} | {len(total)} | {statistics.median(total):.1f} | {np.percentile(total, 90):.1f} | "
          f"{statistics.median(solve):.1f} |")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--moves", type=int, default=40)
    args = ap.parse_args()
    app = QApplication.instance() or QApplication([])
    print("| drag | steps | median ms / step | p90 ms | re-analysis median ms |")
    print("|---|---|---|---|---|")
    for name, example, eid, handle, path in (
            ("Geneva z=6 wheel centre (3,600 samples)", "geneva_z6", "indexer", "wheel",
             [(100 + 0.5 * k, 0.2 * k) for k in range(args.moves)]),
            ("rolling lever pivot G (exact, N = 200)", "rolling_lever_press", "press", "pivot",
             [(-150 + 0.25 * k, -40 - 0.1 * k) for k in range(args.moves)])):
        ctl = SceneController(load_scene(example_path(example)))
        view = CanvasView(ctl)
        view.resize(900, 700)
        view.show()
        view.snap_enabled = False
        view.zoom_to_rect(QRectF(-200, -150, 400, 300))
        ctl.set_selection([(eid, "element", eid)])
        total, solve = drag(view, ctl, eid, handle, path)
        report(name, total, solve)
        el = ctl.scene.element(eid)
        res = ctl.element_result(eid)
        fresh = solve_geneva(el) if example.startswith("geneva") else solve_rolling(el)
        if example.startswith("geneva"):
            err = float(np.max(np.abs(res.wheel_rotation - fresh.wheel_rotation)))
        else:
            err = float(np.max(np.abs(res.frames.P - fresh.frames.P)))
        print(f"|   after release: result vs a fresh solve, max difference {err:.1e} | | | | |")
        t = time.perf_counter()
        solve_rolling(el, measures=True) if not example.startswith("geneva") else None
        if not example.startswith("geneva"):
            print(f"|   full rolling solve with the slip report: {(time.perf_counter() - t) * 1e3:.1f} ms | | | | |")
        view.close()

    ctl = SceneController(load_scene(example_path("geneva_z6")))
    view = CanvasView(ctl)
    view.resize(900, 700)
    view.show()
    ex = AnimationExporter(view, ctl)
    done: list[str] = []
    ex.finished.connect(done.append)
    t0 = time.perf_counter()
    render = []
    for k in range(0, ctl.sample_count(), ctl.sample_count() // 20):
        t = time.perf_counter()
        ex._size = (720, 560)
        ex.render(k)
        render.append((time.perf_counter() - t) * 1e3)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        ex.start(str(Path(tmp) / "a.gif"), frames=48)
        while not done:
            app.processEvents()
            time.sleep(0.002)
        whole = time.perf_counter() - t0
        size = (Path(tmp) / "a.gif").stat().st_size
    print(f"\nanimation export: render {statistics.median(render):.1f} ms per 720 x 560 frame (GUI thread); "
          f"48-frame GIF in {whole:.2f} s, {size / 1024:.0f} KiB")


if __name__ == "__main__":
    main()
