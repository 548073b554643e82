"""The outputs' strokes and time ratios (``classify.output_motions``, issue 14): CPU time now
against the function as it was (one whole-linkage solve per golden-section step and search, kept
in ``tests/core/classify_reference.py``), interleaved, best of k, with the error beside it.

Cases at 3,600 samples per cycle: the six-bar example (one output), the V-engine (two sliders),
16 and 32 RRR dyads driven by a crank (``tests/core/chains.py``: 16 / 32 rockers). Error: the
largest difference of the outputs' least and greatest values (rad or mm) and of the time from
least to greatest (s) from the old function, and of the extremes from a dense sampling of the
whole cycle (200,000 inputs: its own error is curvature × spacing² / 8, ~1e-10 of the value).

Run::

    .venv/bin/python benchmarks/bench_classify.py [--runs 5] [--reference-runs 2] [--json out.json]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "core"))

import numpy as np  # noqa: E402

from chains import dyad_chain  # noqa: E402
from classify_reference import output_motions_reference  # noqa: E402
from mechsketch.core import load_scene  # noqa: E402
from mechsketch.core.analyses.classify import output_motions  # noqa: E402
from mechsketch.core.solver.motion_law import at_times  # noqa: E402
from mechsketch.core.solver.plan import compile_plan  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

SAMPLES = 3600
DENSE = 200_000


def cases():
    yield "sixbar", load_scene(example_path("sixbar_moving_guide")).element("sixbar").with_samples(SAMPLES)
    yield "v_engine", load_scene(example_path("v_engine")).element("vengine").with_samples(SAMPLES)
    for n in (16, 32):
        yield f"chain{n}", dyad_chain(n, samples=SAMPLES)


def cpu(fn) -> float:
    c = time.thread_time()
    fn()
    return time.thread_time() - c


def dense_extremes(lk, plan, m) -> tuple[float, float]:
    """The output's least and greatest value over DENSE inputs of the cycle."""
    drv = lk.driver
    T = drv.period
    t = np.arange(DENSE) * (T / DENSE)
    q = (at_times(drv, plan.theta0, t).q if drv.linear or not drv.law.is_constant
         else plan.theta0 + math.copysign(1.0, drv.speed_rpm) * 2 * math.pi * t / T)
    sol = plan.evaluate(q, order=0)
    if m.kind == "rocker":
        y = sol.angle(m.link)
    else:
        j = lk.joint(m.joint)
        a = math.radians(j.axis_deg or 0.0)
        y = sol.point(m.link, j.at) @ np.array([math.cos(a), math.sin(a)])
    return float(np.min(y)), float(np.max(y))


def run(name, lk, runs: int, ref_runs: int) -> dict:
    plan = compile_plan(lk)
    sol = plan.sweep(order=2)
    output_motions(lk, plan, sol)    # warm-up: branch points, caches
    new_t, ref_t = [], []
    for k in range(max(runs, ref_runs)):       # interleaved A/B
        if k < runs:
            new_t.append(cpu(lambda: output_motions(lk, plan, sol)))
        if k < ref_runs:
            ref_t.append(cpu(lambda: output_motions_reference(lk, plan, sol)))
    new, ref = output_motions(lk, plan, sol), output_motions_reference(lk, plan, sol)
    d_val = d_t = d_dense = 0.0
    for m, r in zip(new, ref, strict=True):
        if m.note or r.note:
            continue
        d_val = max(d_val, abs(m.low - r.low), abs(m.high - r.high))
        d_t = max(d_t, abs(m.t_out - r.t_out), abs(m.t_back - r.t_back))
        lo, hi = dense_extremes(lk, plan, m)
        d_dense = max(d_dense, abs(m.low - lo), abs(m.high - hi))
    return {"case": name, "outputs": len(new), "groups": len(plan.steps), "samples": len(sol),
            "new_ms_best": min(new_t) * 1e3, "new_ms_median": float(np.median(new_t)) * 1e3,
            "reference_ms_best": min(ref_t) * 1e3, "speedup": min(ref_t) / min(new_t),
            "max_diff_extreme_vs_reference": d_val, "max_diff_time_vs_reference_s": d_t,
            "max_diff_extreme_vs_dense": d_dense, "period_s": lk.driver.period}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--reference-runs", type=int, default=2)
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    reps = []
    print(f"output_motions, {SAMPLES} samples per cycle; thread CPU, best of {args.runs} (old function: best of "
          f"{args.reference_runs}), interleaved")
    print(f"{'case':9s} {'outputs':>7s} {'groups':>6s} {'now ms':>8s} {'median':>8s} {'before ms':>10s} {'x':>6s}  "
          f"{'|Δextreme| vs before':>21s} {'|Δt| vs before s':>17s} {'|Δextreme| vs dense':>20s}")
    for name, lk in cases():
        r = run(name, lk, args.runs, args.reference_runs)
        reps.append(r)
        print(f"{name:9s} {r['outputs']:7d} {r['groups']:6d} {r['new_ms_best']:8.1f} {r['new_ms_median']:8.1f} "
              f"{r['reference_ms_best']:10.1f} {r['speedup']:6.1f}  {r['max_diff_extreme_vs_reference']:21.3g} "
              f"{r['max_diff_time_vs_reference_s']:17.3g} {r['max_diff_extreme_vs_dense']:20.3g}")
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(reps, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
