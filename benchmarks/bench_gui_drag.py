"""Responsiveness of a live drag: mouse move to repainted canvas, six-bar at 3,600 samples per cycle.

A report, not a timed test. It shows the six-bar example (RRR + RRP on a moving guide) in a
CanvasView, traces two joints, presses on joint C and moves the mouse in small steps along a
circle. Each step is timed from the mouse-move event to the end of a synchronous repaint of the
viewport; the step includes the whole-cycle re-solve (compile + 3,600-sample sweep + diagnostics)
through ``controller.preview``, the canvas update and the paint. It prints the median (target
<= 16 ms), 90th percentile and worst step, split into solve / canvas update / paint, and the CPU
time the GUI thread spent per step (``time.thread_time``), which stays meaningful when other
processes share the machine (wall-clock times then grow with the load average, shown too).

Run::

    QT_QPA_PLATFORM=offscreen python benchmarks/bench_gui_drag.py [--samples 3600] [--moves 300]
    python benchmarks/bench_gui_drag.py --json out.json    # under a real display (xcb) too
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import sys
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6.QtCore import QPointF, Qt  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402
from PySide6.QtWidgets import QApplication  # noqa: E402

from mechsketch.core import load_scene  # noqa: E402
from mechsketch.core.model.edits import ReplaceElement  # noqa: E402
from mechsketch.gui.canvas.view import CanvasView  # noqa: E402
from mechsketch.gui.controller import SceneController  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

TARGET_MS = 16.0


def run(samples: int, moves: int, radius: float, size: tuple[int, int]) -> dict:
    app = QApplication.instance() or QApplication(sys.argv[:1])
    scene = load_scene(example_path("sixbar_moving_guide"))
    six = scene.element("sixbar")
    ctl = SceneController(scene)
    ctl.push(ReplaceElement(six.with_samples(samples), "samples"))
    ctl.undo_stack.clear()
    view = CanvasView(ctl)
    view.resize(*size)
    view.show()
    QTest.qWaitForWindowExposed(view)
    view.zoom_to_fit()
    view.set_traced("sixbar", "C", True)
    view.set_traced("sixbar", "E", True)
    vp = view.viewport()
    app.processEvents()

    joint_at = ctl.scene.element("sixbar").joint("C").at
    at = lambda xy: view.mapFromScene(QPointF(*xy))  # noqa: E731
    QTest.mouseMove(vp, at(joint_at))
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(joint_at))
    total, solve, update, paint, cpu = [], [], [], [], []
    for k in range(moves + 20):
        a = 2 * math.pi * k / 60.0
        p = (joint_at[0] + radius * (math.cos(a) - 1.0), joint_at[1] + radius * math.sin(a))
        c0 = time.thread_time()
        t0 = time.perf_counter()
        QTest.mouseMove(vp, at(p))
        t1 = time.perf_counter()
        vp.repaint()
        t2 = time.perf_counter()
        c1 = time.thread_time()
        if k < 20:          # warm-up
            continue
        res = ctl.result("sixbar")
        total.append((t2 - t0) * 1e3)
        solve.append(res.seconds * 1e3)
        update.append((t1 - t0) * 1e3 - res.seconds * 1e3)
        paint.append((t2 - t1) * 1e3)
        cpu.append((c1 - c0) * 1e3)
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(p))
    n_cmd = ctl.undo_stack.count()
    sol = ctl.result("sixbar").solution
    view.close()

    def stats(xs: list[float]) -> dict:
        xs = sorted(xs)
        return {"median": statistics.median(xs), "p90": xs[int(0.9 * (len(xs) - 1))], "max": xs[-1]}

    return {
        "platform": QApplication.platformName(), "python": platform.python_version(),
        "samples": len(sol), "moves": moves, "viewport": [vp.width(), vp.height()],
        "undo_commands_after_release": n_cmd,
        "total_ms": stats(total), "solve_ms": stats(solve), "canvas_update_ms": stats(update),
        "paint_ms": stats(paint), "gui_thread_cpu_ms": stats(cpu), "target_ms": TARGET_MS,
        "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        "cpus": os.cpu_count(),
        "meets_target": statistics.median(total) <= TARGET_MS,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=3600)
    ap.add_argument("--moves", type=int, default=300)
    ap.add_argument("--radius", type=float, default=6.0, help="mm, the circle the mouse follows")
    ap.add_argument("--size", type=int, nargs=2, default=(1200, 800))
    ap.add_argument("--json", help="also write the report here")
    args = ap.parse_args(argv)
    rep = run(args.samples, args.moves, args.radius, tuple(args.size))
    print(f"drag of joint C, six-bar, {rep['samples']} samples per cycle, {rep['moves']} mouse moves, "
          f"platform {rep['platform']}, viewport {rep['viewport'][0]}x{rep['viewport'][1]}")
    for key, name in (("total_ms", "mouse move -> repainted canvas"), ("solve_ms", "  whole-cycle re-solve"),
                      ("canvas_update_ms", "  canvas update (tool, items)"), ("paint_ms", "  paint"),
                      ("gui_thread_cpu_ms", "GUI-thread CPU time per move")):
        s = rep[key]
        print(f"{name:34s} median {s['median']:7.2f} ms   p90 {s['p90']:7.2f} ms   max {s['max']:7.2f} ms")
    print(f"target: median <= {TARGET_MS:.0f} ms -> {'met' if rep['meets_target'] else 'NOT met'}; "
          f"undo commands after release: {rep['undo_commands_after_release']}; "
          f"load average {rep['load_average']} on {rep['cpus']} CPUs")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(rep, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
