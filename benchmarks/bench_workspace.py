"""Workspace: the cost of one drag-preview move does not depend on what else the scene holds.

Drags joint C of the six-bar example (3,600 samples per cycle) around a small circle, once with
the six-bar alone and once in a scene that also holds an untouched chain of 32 RRR dyads (also
3,600 samples), and prints the median cost per move of both and their ratio (target ≤ 1.2×):

- core: ``Workspace.preview`` + ``Workspace.result`` (the incremental re-sweep);
- app: a real mouse move on the offscreen canvas through the controller to the repainted viewport
  (1200 x 800 px looking at the six-bar, the same zoom in both scenes; the chain's first dyads are
  in view; grid snapping off so that every move is a new position).

Beside the speed it prints the error: the previewed solution against a full solve of the same
linkage (max |difference| over every joint's position, velocity and acceleration; 0 means bit for
bit) and its loop-closure residual; and the solves one undo and one redo run after the release
(target: at most one element).

    QT_QPA_PLATFORM=offscreen .venv/bin/python benchmarks/bench_workspace.py [--moves 200]
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "core"))

import numpy as np  # noqa: E402
from PySide6.QtCore import QPointF, QRectF, Qt  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402
from PySide6.QtWidgets import QApplication  # noqa: E402

from chains import dyad_chain  # noqa: E402
from mechsketch.core import MoveJoint, Scene, load_scene  # noqa: E402
from mechsketch.core.solver.plan import compile_plan  # noqa: E402
from mechsketch.core.workspace import Workspace  # noqa: E402
from mechsketch.gui.canvas.view import CanvasView  # noqa: E402
from mechsketch.gui.controller import SceneController  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

SAMPLES = 3600
RADIUS = 6.0   # mm: the circle the dragged joint follows


def scenes() -> dict[str, Scene]:
    six = load_scene(example_path("sixbar_moving_guide")).element("sixbar").with_samples(SAMPLES)
    chain = dyad_chain(32, samples=SAMPLES)
    return {"six-bar alone": Scene((six,)), "six-bar + 32-dyad chain": Scene((six, chain))}


def path(c0: tuple[float, float], k: int) -> tuple[float, float]:
    a = 2 * math.pi * k / 60.0
    return (c0[0] + RADIUS * (math.cos(a) - 1.0), c0[1] + RADIUS * math.sin(a))


def max_error(a, b, linkage) -> float:
    worst = 0.0
    for j in linkage.joint_ids:
        for fa, fb in ((a.position, b.position), (a.velocity, b.velocity), (a.acceleration, b.acceleration)):
            d = np.abs(fa(j) - fb(j))
            worst = max(worst, float(np.nanmax(d, initial=0.0)))
    return worst


def core_moves(scene: Scene, moves: int) -> dict:
    ws = Workspace(scene)
    for eid in scene.ids:
        ws.result(eid)
    c0 = ws.element("sixbar").joint("C").at
    ws.begin_preview()
    times = []
    for k in range(moves + 10):
        t0 = time.perf_counter()
        ws.preview(MoveJoint("sixbar", "C", path(c0, k)))
        res = ws.result("sixbar")
        dt = time.perf_counter() - t0
        if k >= 10:
            times.append(dt * 1e3)
    full = compile_plan(ws.element("sixbar")).sweep(samples=SAMPLES, order=2)
    err = max_error(res.solution, full, ws.element("sixbar"))
    ws.end_preview(notify=False)
    ws.apply(MoveJoint("sixbar", "C", path(c0, moves + 9)))
    ws.result("sixbar")                                        # the release solves the final value
    before = sum(v for key, v in ws.stats.items() if key.startswith("solve:"))
    inverse = ws.apply(MoveJoint("sixbar", "C", c0))           # what undo applies
    for eid in scene.ids:
        ws.result(eid)
    after_undo = sum(v for key, v in ws.stats.items() if key.startswith("solve:"))
    ws.apply(inverse)
    for eid in scene.ids:
        ws.result(eid)
    after_redo = sum(v for key, v in ws.stats.items() if key.startswith("solve:"))
    return {"median_ms": statistics.median(times), "incremental": ws.stats["incremental"],
            "error": err, "residual": res.solution.residual(),
            "undo_solves": after_undo - before, "redo_solves": after_redo - after_undo}


def app_moves(scene: Scene, moves: int) -> dict:
    app = QApplication.instance() or QApplication(sys.argv[:1])
    ctl = SceneController(scene)
    view = CanvasView(ctl)
    view.resize(1200, 800)
    view.show()
    QTest.qWaitForWindowExposed(view)
    view.zoom_to_rect(QRectF(-60.0, -60.0, 320.0, 260.0))   # the six-bar, the same zoom in both scenes
    view.snap_action.trigger()   # snapping off: every mouse move is a new position
    vp = view.viewport()
    app.processEvents()
    # the drag follows the six-bar on screen, whatever the zoom the chain asks for
    c0 = ctl.scene.element("sixbar").joint("C").at
    at = lambda xy: view.mapFromScene(QPointF(*xy))  # noqa: E731
    QTest.mouseMove(vp, at(c0))
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(c0))
    times, update = [], []
    for k in range(moves + 10):
        t0 = time.perf_counter()
        QTest.mouseMove(vp, at(path(c0, k)))
        t1 = time.perf_counter()
        vp.repaint()
        dt = time.perf_counter() - t0
        if k >= 10:
            times.append(dt * 1e3)
            update.append((t1 - t0) * 1e3)
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(path(c0, moves + 9)))
    n0 = sum(v for key, v in ctl.workspace.stats.items() if key.startswith("solve:"))
    ctl.undo_stack.undo()
    n1 = sum(v for key, v in ctl.workspace.stats.items() if key.startswith("solve:"))
    view.close()
    return {"median_ms": statistics.median(times), "solve_and_update_ms": statistics.median(update),
            "paint_ms": statistics.median(times) - statistics.median(update),
            "undo_commands": ctl.undo_stack.count(),
            "undo_solves": n1 - n0}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--moves", type=int, default=200)
    args = ap.parse_args(argv)
    print(f"drag of six-bar joint C, {SAMPLES} samples per cycle, {args.moves} moves; "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    for layer, fn in (("core (Workspace.preview + result)", core_moves), ("app (mouse move -> repaint)", app_moves)):
        reps = {name: fn(scene, args.moves) for name, scene in scenes().items()}
        alone, both = reps["six-bar alone"], reps["six-bar + 32-dyad chain"]
        ratio = both["median_ms"] / alone["median_ms"]
        print(f"\n{layer}")
        for name, rep in reps.items():
            extra = ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                              for k, v in rep.items() if k != "median_ms")
            print(f"  {name:26s} median {rep['median_ms']:7.3f} ms per move   ({extra})")
        print(f"  ratio with / without the chain: {ratio:.2f}x  (target <= 1.2x: {'met' if ratio <= 1.2 else 'MISSED'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
