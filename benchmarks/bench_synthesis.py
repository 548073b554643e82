"""Linkage synthesis (issue 22): speed and error of path, motion and function synthesis and of
the atlas, each printed beside the time of one ``mechsketch analyze --summary`` (a fresh process,
median of 5) measured in the same run, and the load average.

Sections (``--section``, default all but the atlas build):

- ``atlas``: build the atlas of each topology (``--designs``, default 1,000,000) from scratch in
  a temporary cache folder, in this process and on a Dask LocalCluster of ``--workers`` (default
  2) processes; time, designs drawn, disk size; the two builds compared bit for bit.
- ``atlas-speed``: the build's speed in designs per second, the studies engine (the default
  build, format v2) against the closed form of core/design/families.py (format v1), the same
  ``--speed-designs`` (default 50,000) designs of each topology in this process, alternated
  ``--repeat`` (default 2) times; the two atlases compared (same designs, descriptors).
- ``warm``: with the four-bar atlas loaded (``--designs``; built first if missing) and its tree
  made, the time (and this process's CPU time) to K = 10 candidates for the unreachable targets
  (each stage timed: retrieval, refinement, the solver's drive checks, validate's cut check).
- ``reachable``: a coupler curve of a known linkage of each topology, moved, turned and scaled,
  40 points: the recovered deviation relative to the target's size.
- ``exact``: 3- and 4-pose motion and 3-point function synthesis, the largest error of every
  candidate measured by the solver.
- ``unreachable``: the letter D, a foot path and the letter S (benchmarks/synthesis_de.py) with
  the four-bar: our best candidate's RMS point-to-curve distance against a 10-minute
  differential-evolution run recorded in benchmarks/synthesis_de_reference.json (``--run-de``
  runs it again and records it, ``--de-seconds`` to change its length).

Usage::

    .venv/bin/python benchmarks/bench_synthesis.py [--section warm,reachable,exact,unreachable,atlas,atlas-speed]
        [--designs 1000000] [--workers 2] [--run-de] [--de-seconds 600] [--speed-designs 50000] [--repeat 2]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

from synthesis_de import MIN_MU_DEG, differential_evolution_reference, measure, targets  # noqa: E402

from mechsketch.core.design import families as F  # noqa: E402
from mechsketch.core.design.atlas import build_atlas, closed_form_solver, forget_loaded, load_atlas  # noqa: E402
from mechsketch.core.design.atlas_store import atlas_folder, disk_bytes, save_atlas  # noqa: E402
from mechsketch.core.design.function import synthesize_function  # noqa: E402
from mechsketch.core.design.linkage_path import synthesize_path  # noqa: E402
from mechsketch.core.design.motion import synthesize_motion  # noqa: E402
from mechsketch.core.design.options import LinkageOptions  # noqa: E402
from mechsketch.core.design.targets import function_target, path_target, pose_target  # noqa: E402

REFERENCE = HERE / "synthesis_de_reference.json"
TOPS = ("fourbar", "slider_crank", "inverted_slider_crank", "sixbar")
#: every atlas (the path synthesis's "sixbar" uses all six six-bars)
ATLAS_TOPS = TOPS + ("watt_sixbar", "sixbar_slider", "watt_sixbar_slider", "sixbar_guide", "watt_sixbar_guide")


def load() -> str:
    a, b, c = os.getloadavg()
    return f"load {a:.2f} {b:.2f} {c:.2f}"


def analyze_summary_time() -> float:
    """Median wall time of ``mechsketch analyze fourbar_crank_rocker.json --summary``, fresh process."""
    exe = Path(sys.executable).with_name("mechsketch")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "mechsketch.core.cli"]
    scene = ROOT / "resources" / "examples" / "fourbar_crank_rocker.json"
    times = []
    for _ in range(6):
        t0 = time.perf_counter()
        subprocess.run(cmd + ["analyze", str(scene), "--summary"], capture_output=True, check=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times[1:])


def line(what: str, seconds: float, ref: float, extra: str = "") -> None:
    print(f"  {what}: {seconds:.3f} s = {seconds / ref:.1f} × analyze --summary{'; ' + extra if extra else ''} "
          f"[{load()}]", flush=True)


def section_atlas(designs: int, workers: int, ref: float, tops: tuple[str, ...] = ATLAS_TOPS) -> None:
    """Build each atlas in this process (and store it in the user cache folder, where the other
    sections read it), then again on a Dask LocalCluster of ``workers`` processes (compared
    with the first bit for bit, not stored). The in-process build's CPU seconds are printed
    too: on a loaded machine they, divided by the cores, bound what a quiet machine takes."""
    print(f"atlas build, {designs:,} designs per topology (the studies engine's batch kernels; numba resampling)")
    for top in tops:
        t0, c0 = time.perf_counter(), time.process_time()
        atlas = build_atlas(top, designs)
        one, cpu = time.perf_counter() - t0, time.process_time() - c0
        folder = atlas_folder(top, designs)
        save_atlas(atlas, folder)
        size = disk_bytes(folder)
        line(f"{top}: 1 process", one, ref, f"CPU {cpu:.1f} s ({cpu / designs * 1e6:.0f} CPU-s per 1e6 designs), "
             f"{atlas.meta['drawn']:,} drawn, {len(atlas):,} kept, "
             f"{size / 1e6:.1f} MB on disk ({folder})")
        if workers > 1:
            from distributed import Client, LocalCluster

            with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=None) as cl, \
                    Client(cl) as client:
                t0 = time.perf_counter()
                remote = build_atlas(top, designs, client=client)
                many = time.perf_counter() - t0
            same = all(np.array_equal(getattr(atlas, k), getattr(remote, k))
                       for k in ("shape", "points", "desc", "func", "turns", "mu"))
            line(f"{top}: Dask LocalCluster of {workers} processes", many, ref,
                 f"{one / many:.2f}× one process; bit-identical: {same}")


def section_atlas_speed(designs: int, repeat: int) -> None:
    """Designs per second of the atlas build: the studies engine (its fused compiled loop, the
    default from FUSED_DESIGNS designs on, and its numpy path) against the closed form."""
    from mechsketch.core.design.atlas_engine import engine_solver, fused_engine_solver

    solvers = (("engine fused", fused_engine_solver), ("engine numpy", engine_solver),
               ("closed form", closed_form_solver))
    print(f"atlas build speed, {designs:,} designs per topology, this process, alternated {repeat}×; compilation "
          "done before timing")
    for top in ATLAS_TOPS:
        for _, solver in solvers:
            build_atlas(top, 500, solver=solver, chunk=4096)      # numba compiled (and cached) before timing
        rates: dict[str, list[float]] = {name: [] for name, _ in solvers}
        built = {}
        for _ in range(repeat):
            for name, solver in solvers:
                t0 = time.perf_counter()
                built[name] = build_atlas(top, designs, solver=solver)
                rates[name].append(designs / (time.perf_counter() - t0))
        same = all(np.array_equal(getattr(built["engine fused"], k), getattr(built[name], k))
                   for name, _ in solvers for k in ("shape", "points", "desc", "func", "turns", "mu"))
        text = ", ".join(f"{name} {min(r):,.0f}-{max(r):,.0f}" for name, r in rates.items())
        ratio = [a / b for a, b in zip(rates["engine fused"], rates["closed form"])]
        ratio2 = [a / b for a, b in zip(rates["engine numpy"], rates["closed form"])]
        print(f"  {top}: designs/s {text}; engine fused / closed form {min(ratio):.2f}-{max(ratio):.2f}×, engine "
              f"numpy / closed form {min(ratio2):.2f}-{max(ratio2):.2f}×; the three atlases bit-identical: {same} "
              f"[{load()}]", flush=True)


def section_warm(designs: int, ref: float) -> None:
    print(f"warm atlas ({designs:,} designs per topology): K = 10 candidates, four-bar, μ ≥ {MIN_MU_DEG}°")
    t0 = time.perf_counter()
    atlas = load_atlas("fourbar", designs)
    t1 = time.perf_counter()
    atlas.tree()
    line("fourbar atlas read / tree made", t1 - t0, ref, f"tree {time.perf_counter() - t1:.2f} s")
    for name, (pts, closed) in targets().items():
        opts = LinkageOptions(candidates=10, min_transmission_deg=MIN_MU_DEG)
        t0, c0 = time.perf_counter(), time.process_time()
        res = synthesize_path(path_target(pts, closed), opts, "fourbar", atlas_designs=designs)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
        stages = ", ".join(f"{k} {v:.2f} s" for k, v in res.timings.items())
        line(f"{name}: {len(res.candidates)} candidates (solver-checked, validate's cut check passed)", dt, ref,
             f"CPU {cpu:.2f} s (what one quiet core takes); {stages}")


def _reachable(top: str) -> np.ndarray:
    x, sigma = {"fourbar": ([0, 0, 100, 0, 35, 110, 90, 60, 35.0], 1.0),
                "slider_crank": ([0, 0, 0.2, 15, 40, 130, 50, -30.0], 1.0),
                "inverted_slider_crank": ([0, 0, 100, 0, 45, 12, 40, 25.0], -1.0),
                "sixbar": ([0, 0, 100, 0, 13.35, 49.61, 84.37, 65.82, 35.68, 150.03, -51.48, 241.37, 129.35,
                            -34.70, -210.73], 1.0),
                # the six-bars with a slider (RRP) and a guided rocker (RPR) of tests/core/test_design_sixbar_dyads.py
                "sixbar_slider": ([0, 0, 100, 0, 13.35, 49.61, 84.37, 25.0, 35.68, 60.0, 20.0, 120.0,
                                   math.radians(100.0), -34.70, 40.0], 1.0),
                "sixbar_guide": ([0, 0, 100, 0, 13.35, 49.61, 84.37, 25.0, 35.68, 60.0, 20.0, 15.0, -34.70, 40.0],
                                 1.0)}[top]
    th = np.linspace(0.3, 0.3 + 2 * math.pi, 40, endpoint=False)
    P = F.evaluate(top, np.array([x]), th[None], sigma).P[0]
    P = 0.7 * np.exp(1.2j) * P + (300 - 50j)
    return np.stack([P.real, P.imag], axis=1)


def section_reachable(designs: int, ref: float) -> None:
    print("reachable targets (a known linkage's coupler curve moved, turned, scaled; 40 points); goal ≤ 1e-6")
    for top in TOPS + ("sixbar_slider", "sixbar_guide"):
        t = path_target(_reachable(top))
        t0 = time.perf_counter()
        opts = LinkageOptions(candidates=1, min_transmission_deg=20, max_size=12 if top.startswith("sixbar") else 5)
        res = synthesize_path(t, opts, top, atlas_designs=designs)
        c = res.candidates[0]
        line(f"{top}", time.perf_counter() - t0, ref, f"max deviation {c.deviation / t.size:.2e} of the size "
             f"({c.deviation:.2e} mm)")


def section_exact(ref: float) -> None:
    print("exact syntheses, largest error of every candidate measured by the solver; goal ≤ 1e-9")
    for poses in ([[0, 0, 0], [30, 10, 20], [50, 35, 45]], [[0, 0, 0], [30, 10, 20], [50, 35, 45], [55, 70, 80]]):
        t = pose_target(poses)
        t0 = time.perf_counter()
        res = synthesize_motion(t, LinkageOptions(candidates=5))
        worst = max(c.deviation / t.size for c in res.candidates)
        turn = max(c.angle_deviation for c in res.candidates)
        line(f"motion, {len(poses)} poses, {len(res.candidates)} candidates", time.perf_counter() - t0, ref,
             f"position {worst:.1e} of the size, angle {turn:.1e}°")
    for rows, unit, top in (([[0, 0], [40, 25], [90, 50]], "deg", "fourbar"),
                            ([[0, 0], [45, 20], [90, 45]], "mm", "slider_crank")):
        t = function_target(rows, unit)
        t0 = time.perf_counter()
        res = synthesize_function(t, LinkageOptions(candidates=5), top)
        worst = max(c.deviation for c in res.candidates)
        line(f"function, 3 points, {top}, {len(res.candidates)} candidates", time.perf_counter() - t0, ref,
             f"output {worst:.1e} {res.candidates[0].unit}")


def section_unreachable(designs: int, ref: float, run_de: bool, de_seconds: float) -> None:
    print(f"unreachable targets, four-bar, crank turning fully, μ ≥ {MIN_MU_DEG}°: RMS point-to-curve distance; "
          "goal ≤ 1.2 × differential evolution's")
    recorded = json.loads(REFERENCE.read_text()) if REFERENCE.exists() else {}
    for name, (pts, closed) in targets().items():
        if run_de or name not in recorded:
            print(f"  running differential evolution on {name} for {de_seconds:.0f} s ...", flush=True)
            de = differential_evolution_reference(pts, closed, de_seconds)
            de.update({"date": time.strftime("%Y-%m-%d %H:%M"), "load": load()})
            recorded[name] = de
            REFERENCE.write_text(json.dumps(recorded, indent=1))
        de = recorded[name]
        opts = LinkageOptions(candidates=3, min_transmission_deg=MIN_MU_DEG, full_turn=True)
        t0 = time.perf_counter()
        res = synthesize_path(path_target(pts, closed), opts, "fourbar", atlas_designs=designs)
        dt = time.perf_counter() - t0
        best = min((measure(c.params, c.sigma, pts, closed) for c in res.candidates), key=lambda r: r[0])
        line(f"{name}", dt, ref, f"ours RMS {best[0]:.3f} mm (max {best[1]:.3f}); DE {de['rms_mm']:.3f} mm "
             f"(max {de['max_mm']:.3f}) after {de['seconds']:.0f} s, {de['evaluations']:,} designs "
             f"[{de.get('load', '?')}]; ratio {best[0] / de['rms_mm']:.2f}")


def main() -> None:
    warnings.simplefilter("ignore", UserWarning)
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--section", default="exact,reachable,warm,unreachable")
    p.add_argument("--designs", type=int, default=1_000_000)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--run-de", action="store_true")
    p.add_argument("--de-seconds", type=float, default=600.0)
    p.add_argument("--speed-designs", type=int, default=50_000)
    p.add_argument("--repeat", type=int, default=2)
    a = p.parse_args()
    ref = analyze_summary_time()
    print(f"one `mechsketch analyze fourbar_crank_rocker.json --summary`: {ref:.3f} s (median of 5) [{load()}]")
    sections = a.section.split(",")
    if "atlas" in sections:
        section_atlas(a.designs, a.workers, ref)
    if "atlas-speed" in sections:
        section_atlas_speed(a.speed_designs, a.repeat)
    if "exact" in sections:
        section_exact(ref)
    if "reachable" in sections:
        section_reachable(a.designs, ref)
    if "warm" in sections:
        section_warm(a.designs, ref)
    if "unreachable" in sections:
        section_unreachable(a.designs, ref, a.run_de, a.de_seconds)
    forget_loaded()


if __name__ == "__main__":
    main()
