"""Linkage solver: speed against error (a report, not a test).

    .venv/bin/python benchmarks/bench_linkage.py [--quick] [--out DIR]

For a four-bar, an offset slider-crank, a six-bar with a moving guide and a near-change-point
four-bar, at N = 360 … 360,000 driver samples, positions only (order 0) and with velocities and
accelerations (order 2), it measures in the same run:

* mechsketch: ``plan.sweep(N, order)`` plus extraction of every joint's (N, 2) position (and
  velocity, acceleration) arrays, best of k ``time.perf_counter`` runs, µs per sample;
* the generic baseline: Newton on the same loop equations, pose by pose, warm-started
  (:mod:`newton_baseline`); for N above a limit it runs on a subset (arcs of consecutive samples
  ending at the reference poses) and its per-sample time is extrapolated: the table says so;
* pylinkage (four-bar), if installed;
* errors against a 50-digit mpmath solution of the loop equations (:mod:`reference_mp`) at a
  subsample of evenly spaced poses (plus the pose nearest a toggle).

Error measures: position |Δp| / size (size: the largest distance between two drawn joints);
velocity |Δv| / max|v_ref| and acceleration |Δa| / max|a_ref| (maxima over the reference poses and
joints of that mechanism; over the poses away from toggles for the "away" columns); each the
maximum over the reference poses and all joints.

Writes benchmarks/out/linkage.md (the report printed to stdout), linkage_speed_error.png (time
against error) and linkage_near_toggle.png (error against the toggle gap).

This file runs the benchmark; its parts: :mod:`linkage_cases` (the mechanisms),
:mod:`linkage_timing` (best-of-k timing, the Newton baseline's blocks), :mod:`linkage_errors`
(reference poses and error measures), :mod:`linkage_sections` (each measured section),
:mod:`linkage_alloc` (the fresh-process allocator probe), :mod:`linkage_report` (the markdown
report and the targets) and :mod:`linkage_plots` (the figures).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from mechsketch.core.solver.plan import compile_plan  # noqa: E402

from linkage_alloc import probe_main, run_probe  # noqa: E402
from linkage_cases import example, near_change_point  # noqa: E402
from linkage_errors import References  # noqa: E402
from linkage_plots import plot  # noqa: E402
from linkage_report import render  # noqa: E402
from linkage_sections import (Row, bench_mechanism, near_toggle_scan, pylinkage_section,  # noqa: E402
                              subset_section)
from linkage_timing import Interleaved, best_of  # noqa: E402
from newton_baseline import NewtonBaseline  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="N = 360, 3,600 only; fewer reference poses")
    ap.add_argument("--out", default=str(HERE / "out"), help="output folder (default benchmarks/out)")
    ap.add_argument("--alloc-probe", choices=["default", "tuned"], help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.alloc_probe:
        return probe_main(args.alloc_probe, args.quick)

    class cfg:  # noqa: N801
        quick = args.quick
        Ns = [360, 3600] if args.quick else [360, 3600, 36000, 360000]
        n_ref = 12 if args.quick else 60
        n_ref_scan = 6 if args.quick else 24
        newton_full_limit = 3600 if args.quick else 36000
        arc = 360
        newton_tol = 1e-10
        timing_budget = 2.0 if args.quick else 25.0   # interleaved best-of-k window, seconds
        newton_reps = 2 if args.quick else 3
        deltas = [1e-4, 1e-6, 1e-8] if args.quick else [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
        scan_N = 3600

    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    load0 = os.getloadavg()

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    mechs = [
        ("four-bar", example("fourbar_crank_rocker")),
        ("slider-crank (offset)", example("slider_crank_offset")),
        ("six-bar (moving guide)", example("sixbar_moving_guide")),
    ]
    ncp, ncp_delta = near_change_point(1e-6)
    log(f"linkage benchmark ({'quick' if cfg.quick else 'full'}): N = {cfg.Ns}")
    rows: list[Row] = []
    refs_by = {}
    timer = Interleaved()
    for name, lk in mechs + [("near-change-point four-bar", ncp)]:
        refs_by[name] = References(lk)
        rows += bench_mechanism(name, lk, cfg.Ns, cfg, refs_by[name], timer, log)
    log("pylinkage …")
    py_rows, py_note = pylinkage_section(mechs[0][1], cfg.Ns, cfg,
                                         [r for r in rows if r.mech == "four-bar"], refs_by["four-bar"],
                                         timer, log)
    sub_res, subset, steps_all, steps_sub = subset_section(
        mechs[2][1], [3600] if cfg.quick else [3600, 36000], cfg, timer)
    log(f"timing mechsketch, pylinkage and the subset solves, interleaved, {cfg.timing_budget:g} s …")
    cfg.rounds = timer.run(cfg.timing_budget)
    cfg.kmin, cfg.kmax = [min(timer.k.values())], [max(timer.k.values())]
    for r in rows:
        key = ("ms", r.mech, r.N, r.order)
        r.ms_us, r.ms_k = timer.best[key] / r.N * 1e6, timer.k[key]
        log(f"  {r.mech:28s} N={r.N:<7d} order {r.order}: mechsketch {r.ms_us:.3f} µs/sample "
            f"(best of {r.ms_k}), Newton {r.nt.us:.1f} µs: {r.speedup:,.0f}×")
    for p in py_rows or []:
        p[2] = timer.best[p[2]] / p[0] * 1e6
        p[4] = p[4].ms_us
    sub_rows = sub_res()
    # allocator diagnostic (last timing of the run: mallopt cannot be undone)
    alloc = None
    if sys.platform.startswith("linux"):
        log("allocator probe (fresh processes) …")
        before = run_probe("default", cfg.quick)
        after = run_probe("tuned", cfg.quick)
        if before and after:
            alloc = list(zip(before, after))
    log("near-toggle scan …")
    scan = near_toggle_scan(cfg.deltas, cfg.scan_N, cfg, log)
    # scipy.optimize.root side note (four-bar, N = 360, positions)
    nb_root = NewtonBaseline(mechs[0][1], tol=cfg.newton_tol, method="root")
    inp = compile_plan(mechs[0][1]).sweep(360, order=0).input
    t_root = best_of(lambda: nb_root.run(inp, 0), 0.0, min_k=3, max_k=3)[0] / 360 * 1e6
    nt360 = next(r.nt.us for r in rows if r.mech == "four-bar" and r.N == 360 and r.order == 0)
    elapsed = time.perf_counter() - t_start
    load1 = os.getloadavg()

    report = render(rows, py_rows, py_note, sub_rows, subset, steps_all, steps_sub, scan, cfg,
                    ncp_delta, refs_by, (t_root, nt360), elapsed, load0, load1, alloc)
    (out_dir / "linkage.md").write_text(report)
    print(report)
    try:
        plot(rows, py_rows, scan, out_dir)
    except ImportError as exc:
        log(f"no plot: {exc} (pip install matplotlib, the 'bench' extra)")
    log(f"wrote {out_dir / 'linkage.md'}, {out_dir / 'linkage_speed_error.png'}, "
        f"{out_dir / 'linkage_near_toggle.png'} in {elapsed:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
