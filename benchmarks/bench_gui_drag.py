"""Responsiveness of a live drag in the whole app: mouse move to repainted canvas, at 3,600 samples.

A report, not a timed test. It builds the whole desktop app (``mechsketch.gui.app.build``: main
window, canvas, scrub bar, animation player, docks as a user first sees them), opens one scene
and drags one joint with real mouse events on the canvas viewport in small steps along a circle:

- ``sixbar``: joint C of the six-bar example (RRR + RRP on a moving guide), C and E traced
  (target: median <= 5 ms per move);
- ``chain16`` / ``chain32``: a crank driving 16 / 32 RRR dyads (``tests/core/chains.py``), joint
  P1 dragged, which every dyad downstream depends on (the worst case for the incremental
  re-sweep: all groups run again), the last joint traced (target for 32 dyads: <= 16 ms).

Each step is timed from the mouse-move event to the end of a synchronous repaint of the
viewport and the events that follow (wall clock), and its GUI-thread CPU time
(``time.thread_time``) is split into

- solve: ``Workspace.result_of`` (compile, branch points, sweep), with the branch-point search
  alone shown apart;
- diagnostics: every ``diagnose`` call made during the step (the canvas' dead-point marks, the
  scrub bar, the diagnostics panel when it is shown);
- canvas update: the rest of the mouse-move handling (tool, controller signals, items, panels);
- paint: the canvas' paint event (the one repaint of the viewport the event loop makes of the
  items' updates; timed by an event filter, :class:`CanvasPaintTimer`);
- pending events: the rest of what the event loop runs (``processEvents()``, until the canvas
  has painted) before the next move: panels redrawn a few times a second during a drag (see
  ``gui/panels/lazy.py``) and painted;

and the release: mouse release -> the diagnostics panel (deferred during the drag) refreshed and
painted (its first paint event after the refresh), and then everything else the release left
pending run, split into the output classification (``classify.output_motions``: the outputs'
strokes and time ratios), ``diagnose``, the diagnostics panel's refresh, the canvas' sync and the
solve; ``--classify-reference`` times the release with the classification as it was before
issue 14 (tests/core/classify_reference.py).

Issue 26's targets are ratios to baselines measured in the same run, printed with the load average:
item 1, the GUI-thread CPU per move (median; the mean too) against ``Workspace.preview`` + result
of the same moves alone; item 6, the GUI-thread CPU from the release to the diagnostics panel
painted against the element's full solve at the same samples (a fresh workspace's result). CPU
time stays meaningful when other processes share the machine (wall-clock times grow with the load
average). Beside the speed it prints the error: the solution the app shows at the last move, and
after the release, against a fresh full solve of the same linkage (max |Δposition| over every
joint and sample, mm; 0 means bit for bit), whether the branch offsets match a fresh search, and
whether the summary after the release is a fresh workspace's.

Run::

    QT_QPA_PLATFORM=offscreen python benchmarks/bench_gui_drag.py [--cases sixbar chain16 chain32]
        [--samples 3600] [--moves 300] [--hide-diagnostics] [--classify-reference] [--json out.json]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import statistics
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "core"))

import numpy as np  # noqa: E402
from PySide6.QtCore import QEvent, QObject, QPointF, QRectF, Qt  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402

from chains import dyad_chain  # noqa: E402
from mechsketch.core import ReplaceElement, Scene, load_scene  # noqa: E402
from mechsketch.core.analyses import classify as classify_mod  # noqa: E402
from mechsketch.core.solver import plan as plan_mod  # noqa: E402
from mechsketch.core.solver.plan import compile_plan  # noqa: E402
from mechsketch.core.workspace import results as results_mod  # noqa: E402
from mechsketch.core.workspace.workspace import Workspace  # noqa: E402
from mechsketch.gui.app import build  # noqa: E402
from mechsketch.gui.canvas.view import CanvasView  # noqa: E402
from mechsketch.gui.panels.diagnostics import DiagnosticsPanel  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

TARGET_MS = {"sixbar": 5.0, "chain16": 16.0, "chain32": 16.0}


class Timers:
    """GUI-thread CPU seconds (``time.thread_time``) spent in a few wrapped functions since the
    last ``reset`` (CPU, not wall clock: other processes on a loaded machine do not count)."""

    def __init__(self) -> None:
        self.acc: dict[str, float] = defaultdict(float)
        self.calls: dict[str, int] = defaultdict(int)
        self.ends: dict[str, tuple[float, float]] = {}
        self._depth: dict[str, int] = defaultdict(int)

    def wrap(self, owner, name: str, key: str) -> None:
        fn = getattr(owner, name)

        def timed(*a, **kw):
            if self._depth[key]:          # re-entrant: count the outermost call only
                return fn(*a, **kw)
            self._depth[key] += 1
            t0 = time.thread_time()
            try:
                return fn(*a, **kw)
            finally:
                t1 = time.thread_time()
                self.acc[key] += t1 - t0
                self.ends[key] = (t1, time.perf_counter())
                self.calls[key] += 1
                self._depth[key] -= 1

        setattr(owner, name, timed)

    def reset(self) -> None:
        self.acc.clear()
        self.calls.clear()
        self.ends.clear()

    def last_end(self, key: str) -> tuple[float, float] | None:
        """(GUI-thread CPU s, wall s) at the end of the last call of ``key`` since the reset."""
        return self.ends.get(key)


class PaintWatch(QObject):
    """Records (GUI-thread CPU s, wall s) at each paint event of a widget."""

    def __init__(self, widget) -> None:
        super().__init__()
        self.widget = widget
        self.paints: list[tuple[float, float]] = []
        widget.installEventFilter(self)

    def eventFilter(self, obj, ev) -> bool:  # noqa: N802 - Qt API
        if ev.type() == QEvent.Type.Paint:
            self.paints.append((time.thread_time(), time.perf_counter()))
        return False

    def painted_after(self, when: tuple[float, float] | None) -> tuple[float, float] | None:
        """The first paint after ``when`` (a ``Timers.last_end``), if any."""
        if when is None:
            return None
        return next((p for p in self.paints if p[1] >= when[1]), None)

    def stop(self) -> None:
        self.widget.removeEventFilter(self)


class CanvasPaintTimer(QObject):
    """Times the canvas' paint events (GUI-thread CPU): an event filter on its viewport that runs
    the view's own handling of each paint event itself (``viewportEvent``), timed, and consumes
    it (nothing is patched: a test process keeps its classes as they are)."""

    def __init__(self, view) -> None:
        super().__init__()
        self.view = view
        self.count = 0
        self.cpu = 0.0
        view.viewport().installEventFilter(self)

    def eventFilter(self, obj, ev) -> bool:  # noqa: N802 - Qt API
        if ev.type() != QEvent.Type.Paint:
            return False
        c0 = time.thread_time()
        try:
            self.view.viewportEvent(ev)
        finally:
            self.cpu += time.thread_time() - c0
            self.count += 1
        return True

    def stop(self) -> None:
        self.view.viewport().removeEventFilter(self)


def case_scene(case: str, samples: int) -> tuple[Scene, str, str, list[str], float]:
    """(scene, element id, dragged joint, traced joints, drag radius mm)."""
    if case == "sixbar":
        six = load_scene(example_path("sixbar_moving_guide")).element("sixbar").with_samples(samples)
        return Scene((six,)), "sixbar", "C", ["C", "E"], 6.0
    n = int(case.removeprefix("chain"))
    return Scene((dyad_chain(n, samples=samples),)), "chain", "P1", [f"P{n}"], 6.0


def max_position_error(a, b, joint_ids) -> float:
    """max |Δposition| (mm) over every joint and sample; NaN where both are NaN counts as equal."""
    worst = 0.0
    for j in joint_ids:
        pa, pb = np.asarray(a.position(j)), np.asarray(b.position(j))
        same_nan = np.isnan(pa) & np.isnan(pb)
        d = np.where(same_nan, 0.0, np.abs(pa - pb))
        worst = max(worst, float(np.max(d, initial=0.0)) if not np.isnan(d).any() else math.inf)
    return worst


def untimed(summary: str) -> str:
    """A summary without its solve time (the only line that differs between equal results)."""
    return re.sub(r" in [0-9.]+ ms \([0-9.]+ µs per pose\)", "", summary)


def branches_equal(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def drag_path(joint_at, radius: float, moves: int) -> list[tuple[float, float]]:
    """The dragged joint's positions, warm-up (20) included: small steps along a circle."""
    out = []
    for k in range(moves + 20):
        a = 2 * math.pi * k / 60.0
        out.append((joint_at[0] + radius * (math.cos(a) - 1.0), joint_at[1] + radius * math.sin(a)))
    return out


def preview_baseline(scene: Scene, eid: str, joint: str, radius: float, moves: int) -> list[float]:
    """Issue 26 item 1's baseline: the core re-solve of the same moves alone — ``Workspace.preview``
    of the linkage with the joint moved, then its result (what the controller asks for) — GUI-thread
    CPU ms per move, warm-up dropped."""
    ws = Workspace(scene)
    lk = ws.scene.element(eid)
    ws.result(eid)
    ws.begin_preview()
    out = []
    for k, p in enumerate(drag_path(lk.joint(joint).at, radius, moves)):
        c0 = time.thread_time()
        ws.preview(ReplaceElement(lk.with_joint_moved(joint, p)))
        ws.result(eid)
        c1 = time.thread_time()
        if k >= 20:
            out.append((c1 - c0) * 1e3)
    ws.end_preview(notify=False)
    return out


def full_solve_baseline(scene: Scene, eid: str, repeat: int = 5) -> float:
    """Issue 26 item 6's baseline: the element's full solve at the same samples (a fresh
    workspace's result: compile, branch points, sweep), median GUI-thread CPU ms."""
    times = []
    for _ in range(repeat):
        ws = Workspace(scene)
        c0 = time.thread_time()
        ws.result(eid)
        times.append((time.thread_time() - c0) * 1e3)
    return statistics.median(times)


def run(case: str, samples: int, moves: int, size: tuple[int, int], hide_diagnostics: bool,
        timers: Timers | None = None) -> dict:
    timers = timers or Timers()
    scene, eid, joint, traced, radius = case_scene(case, samples)
    state = tempfile.mkdtemp(prefix="mechsketch-bench-")
    parts = build(state_dir=state, settings_path=os.path.join(state, "settings.ini"), offer_recovery=False)
    app, ctl, win = parts.app, parts.controller, parts.window
    ctl.reset(scene)
    win.resize(*size)
    win.show()
    QTest.qWaitForWindowExposed(win)
    if hide_diagnostics:
        win.docks["diagnostics"].hide()
    view = win.canvas
    view.snap_enabled = False   # every mouse move is a new position
    for j in traced:
        view.set_traced(eid, j, True)
    lk = ctl.scene.element(eid)
    if case == "sixbar":
        view.zoom_to_fit()
    else:   # the first dyads fill the view (a 6 mm circle is a few pixels when the whole chain is)
        view.zoom_to_rect(QRectF(-60.0, -60.0, 420.0, 220.0))
    vp = view.viewport()
    app.processEvents()
    painter = CanvasPaintTimer(view)
    diag_shown = win.diagnostics.isVisible()

    joint_at = lk.joint(joint).at
    at = lambda xy: view.mapFromScene(QPointF(*xy))  # noqa: E731
    QTest.mouseMove(vp, at(joint_at))
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(joint_at))
    cols = defaultdict(list)
    unchanged = 0
    p = joint_at
    for k, p in enumerate(drag_path(joint_at, radius, moves)):
        before = ctl.result(eid)
        timers.reset()
        c0 = time.thread_time()
        t0 = time.perf_counter()
        QTest.mouseMove(vp, at(p))
        cm = time.thread_time()
        # what the event loop runs before the next move: the canvas' one repaint (Qt coalesces the
        # items' updates into it) and the panels' deferred redraws (a forced repaint() here would
        # paint the canvas twice per move: the scene's own queued update paints it again)
        n_paint, paint0 = painter.count, painter.cpu
        app.processEvents()
        while painter.count == n_paint and time.perf_counter() - t0 < 5.0:
            app.processEvents()
        t3 = time.perf_counter()
        c1 = time.thread_time()
        if k < 20:          # warm-up
            continue
        unchanged += ctl.result(eid) is before
        solve, branch, diag = (timers.acc.get(key, 0.0) * 1e3 for key in ("solve", "branch", "diagnose"))
        cols["total"].append((t3 - t0) * 1e3)
        cols["solve"].append(solve)
        cols["branch"].append(branch)
        cols["diagnostics"].append(diag)
        cols["canvas_update"].append((cm - c0) * 1e3 - solve - diag)
        cols["canvas_paints"].append(painter.count - n_paint)
        paint = (painter.cpu - paint0) * 1e3
        cols["paint"].append(paint)
        cols["events"].append((c1 - cm) * 1e3 - paint)
        cols["cpu"].append((c1 - c0) * 1e3)
    # the error: what the app shows at the last move against a fresh full solve of that linkage
    shown = ctl.result(eid)
    fresh = compile_plan(ctl.scene.element(eid))
    full = fresh.sweep(samples=samples, order=2)
    err_drag = max_position_error(shown.solution, full, lk.joint_ids)
    br_drag = branches_equal(shown.plan.branch_points(), fresh.branch_points())
    # the release: mouse release -> the diagnostics panel (deferred during the drag) redrawn
    panel = win.diagnostics
    stale_before = bool(getattr(panel, "_stale", False))
    watch = PaintWatch(panel.text.viewport()) if diag_shown else None
    timers.reset()
    c0 = time.thread_time()
    t0 = time.perf_counter()
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, at(p))
    # the panel refreshes within the release's handling (or later, were it deferred): its first
    # paint after the refresh (timed when main() wrapped it; else after the release) shows the text
    refreshed = lambda: timers.last_end("diagnostics_panel") or (c0, t0)  # noqa: E731
    while diag_shown and (panel._stale or not watch.painted_after(refreshed())) and time.perf_counter() - t0 < 20.0:
        app.processEvents()
    shown_at = watch.painted_after(refreshed()) if diag_shown else None
    app.processEvents()
    t1 = time.perf_counter()
    c1 = time.thread_time()
    painter.stop()
    release = {"wall": (t1 - t0) * 1e3, "cpu": (c1 - c0) * 1e3,
               **{key: timers.acc.get(key, 0.0) * 1e3
                  for key in ("classify", "diagnose", "solve", "diagnostics_panel", "canvas_sync")},
               "panel_cpu": (shown_at[0] - c0) * 1e3 if shown_at else math.nan,
               "panel_wall": (shown_at[1] - t0) * 1e3 if shown_at else math.nan,
               "panel_refreshed": diag_shown and stale_before and not panel._stale and shown_at is not None}
    if watch is not None:
        watch.stop()
    released = ctl.result(eid)
    ws = Workspace(ctl.scene)
    ref = ws.result(eid)
    err_release = max_position_error(released.solution, ref.solution, lk.joint_ids)
    diag_equal = untimed(released.summary()) == untimed(ref.summary())
    n_cmd = ctl.undo_stack.count()
    ctl.undo_stack.setClean()   # no 'save changes?' question on close
    parts.close()
    # the baselines, in the same run: the core re-solve of the same moves, the full solve
    preview = preview_baseline(scene, eid, joint, radius, moves)
    full_ms = full_solve_baseline(ctl.scene, eid)

    def stats(xs: list[float]) -> dict:
        xs = sorted(xs)
        return {"median": statistics.median(xs), "mean": statistics.fmean(xs), "p90": xs[int(0.9 * (len(xs) - 1))],
                "max": xs[-1]}

    return {
        "case": case, "platform": parts.app.platformName(), "python": platform.python_version(),
        "samples": len(full), "groups": len(fresh.steps), "moves": moves,
        "viewport": [vp.width(), vp.height()], "diagnostics_panel_shown": diag_shown,
        "moves_without_change": unchanged, "undo_commands_after_release": n_cmd,
        **{f"{key}_ms": stats(v) for key, v in cols.items()},
        "error_drag_mm": err_drag, "error_release_mm": err_release, "branches_equal_fresh": br_drag,
        "summary_equal_fresh_after_release": diag_equal, "release_ms": release,
        "preview_baseline_ms": stats(preview), "full_solve_ms": full_ms,
        "drag_ratio": statistics.median(cols["cpu"]) / statistics.median(preview),
        "drag_mean_ratio": statistics.fmean(cols["cpu"]) / statistics.fmean(preview),
        "release_ratio": release["panel_cpu"] / full_ms,
        "release_all_ratio": release["cpu"] / full_ms,
        "target_ms": TARGET_MS.get(case, 16.0),
        "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else None, "cpus": os.cpu_count(),
        "meets_target": statistics.median(cols["total"]) <= TARGET_MS.get(case, 16.0),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", default=["sixbar", "chain16", "chain32"])
    ap.add_argument("--samples", type=int, default=3600)
    ap.add_argument("--moves", type=int, default=200)
    ap.add_argument("--size", type=int, nargs=2, default=(1400, 900), help="main window, px")
    ap.add_argument("--hide-diagnostics", action="store_true", help="close the diagnostics dock first")
    ap.add_argument("--classify-reference", action="store_true",
                    help="the outputs' classification as before issue 14 (one solve per golden step and search)")
    ap.add_argument("--json", help="also write the reports here")
    args = ap.parse_args(argv)
    if args.classify_reference:
        from classify_reference import output_motions_reference
        classify_mod.output_motions = output_motions_reference
    timers = Timers()
    timers.wrap(Workspace, "result_of", "solve")
    timers.wrap(plan_mod, "find_branch_points", "branch")
    timers.wrap(results_mod, "diagnose", "diagnose")
    timers.wrap(classify_mod, "output_motions", "classify")
    timers.wrap(DiagnosticsPanel, "refresh", "diagnostics_panel")
    timers.wrap(CanvasView, "_sync", "canvas_sync")
    reps = []
    for case in args.cases:
        rep = run(case, args.samples, args.moves, tuple(args.size), args.hide_diagnostics, timers)
        reps.append(rep)
        print(f"\n{case}: drag, {rep['groups']} groups, {rep['samples']} samples per cycle, {rep['moves']} mouse "
              f"moves, whole app on {rep['platform']}, viewport {rep['viewport'][0]}x{rep['viewport'][1]}, "
              f"diagnostics panel {'shown' if rep['diagnostics_panel_shown'] else 'hidden'}")
        for key, name in (("total_ms", "mouse move -> repainted canvas, wall"),
                          ("cpu_ms", "GUI-thread CPU time per move"), ("solve_ms", "  solve (result_of)"),
                          ("branch_ms", "    of which branch points"), ("diagnostics_ms", "  diagnostics"),
                          ("canvas_update_ms", "  canvas update (rest)"), ("paint_ms", "  paint"),
                          ("events_ms", "  pending events (deferred redraws)")):
            s = rep[key]
            print(f"{name:36s} median {s['median']:7.2f} ms   mean {s['mean']:7.2f} ms   p90 {s['p90']:7.2f} ms   "
                  f"max {s['max']:7.2f} ms")
        print(f"canvas paints per move: median {rep['canvas_paints_ms']['median']:.0f}, max "
              f"{rep['canvas_paints_ms']['max']:.0f}")
        print(f"target: median <= {rep['target_ms']:.0f} ms -> {'met' if rep['meets_target'] else 'NOT met'}; "
              f"moves that changed nothing: {rep['moves_without_change']}; "
              f"undo commands after release: {rep['undo_commands_after_release']}")
        r = rep["release_ms"]
        print(f"release -> diagnostics panel painted: {r['panel_wall']:.1f} ms wall, {r['panel_cpu']:.1f} ms "
              f"GUI-thread CPU; everything the release made pending run: {r['wall']:.1f} ms wall, {r['cpu']:.1f} ms "
              f"CPU; panel refreshed: {r['panel_refreshed']}")
        print(f"  GUI-thread CPU of: classification {r['classify']:.1f} ms "
              f"({'before issue 14' if args.classify_reference else 'vectorised'}), diagnose() {r['diagnose']:.1f} ms, "
              f"diagnostics panel refresh {r['diagnostics_panel']:.1f} ms (classification included), "
              f"canvas sync {r['canvas_sync']:.1f} ms (diagnose included), solve {r['solve']:.1f} ms")
        d = rep["preview_baseline_ms"]["median"]
        print(f"issue 26 item 1, drag: ours {rep['cpu_ms']['median']:.2f} ms GUI-thread CPU per move, baseline "
              f"Workspace.preview + result alone {d:.2f} ms, ratio {rep['drag_ratio']:.2f} (target <= 2.5: "
              f"{'met' if rep['drag_ratio'] <= 2.5 else 'NOT met'}); means {rep['cpu_ms']['mean']:.2f} / "
              f"{rep['preview_baseline_ms']['mean']:.2f} ms, ratio {rep['drag_mean_ratio']:.2f}; load {rep['load_average']:.2f}")
        print(f"issue 26 item 6, release: ours {r['panel_cpu']:.1f} ms GUI-thread CPU to the diagnostics panel "
              f"painted, baseline the full solve {rep['full_solve_ms']:.1f} ms, ratio {rep['release_ratio']:.2f} "
              f"(target <= 4: {'met' if rep['release_ratio'] <= 4 else 'NOT met'}); everything pending run "
              f"{r['cpu']:.1f} ms, ratio {rep['release_all_ratio']:.2f}; load {rep['load_average']:.2f}")
        print(f"error: drag vs fresh full solve max |dpos| {rep['error_drag_mm']:.3g} mm "
              f"(branch offsets equal: {rep['branches_equal_fresh']}); after release {rep['error_release_mm']:.3g} mm "
              f"(summary equal to a fresh workspace's: {rep['summary_equal_fresh_after_release']}); "
              f"load average {rep['load_average']:.2f} on {rep['cpus']} CPUs")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(reps, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
