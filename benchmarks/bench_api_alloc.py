"""The Python API against the app path, sweep by sweep from a fresh process (issue 26, item 3):
what ``core.runtime.tune_allocator()`` changes, measured as a ratio in the same run.

    .venv/bin/python benchmarks/bench_api_alloc.py [--Ns 3600,36000] [--sweeps 6] [--reps 8]

Each measurement is a new interpreter that does only ``Workspace.open(path)[id].compile()`` and
then ``sweep(N, order=2)`` ``--sweeps`` times (``--extract``: and reads every joint's position,
velocity and acceleration, as a user would), timing each sweep (thread CPU and wall) and counting
its minor page faults (``getrusage``). ``api``: a plain process (glibc's default malloc, as any
script that imports mechsketch); ``app``: the same after ``tune_allocator()`` (what the CLI and
the GUI launcher call first). The processes alternate api, app, api, app... (``--reps`` pairs per
case and N), so both see the same load; per sweep index the median over the processes is taken.

Printed per mechanism and N: the first sweep and the median of the later ones (ms), the page
faults per sweep, the ratio api / app of the first sweep and of the later ones, the load
average, and whether the target holds (api within 1.2x of app from the first sweep on).
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASES = [("four-bar", "fourbar_crank_rocker", "fourbar"),
         ("six-bar", "sixbar_moving_guide", "sixbar"),
         ("excavator", "excavator_arm", "arm")]
TARGET = 1.2


def child(mode: str, name: str, eid: str, n: int, sweeps: int, extract: bool) -> dict:
    """In a fresh process: ``sweeps`` sweeps; per sweep (thread CPU s, wall s, minor faults)."""
    if mode == "app":
        from mechsketch.core.runtime import tune_allocator

        tune_allocator()
    from mechsketch.core import Workspace

    plan = Workspace.open(ROOT / "resources" / "examples" / f"{name}.json")[eid].compile()
    joints = plan.linkage.joint_ids
    out = []
    for _ in range(sweeps):
        f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        c0, w0 = time.thread_time(), time.perf_counter()
        sol = plan.sweep(n, order=2)
        if extract:
            for j in joints:
                sol.position(j), sol.velocity(j), sol.acceleration(j)
        c1, w1 = time.thread_time(), time.perf_counter()
        out.append((c1 - c0, w1 - w0, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0))
        del sol
    return {"sweeps": out}


def run_child(mode: str, name: str, eid: str, n: int, sweeps: int, extract: bool) -> list:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--child", mode, name, eid, str(n), str(sweeps)]
    if extract:
        cmd.append("--extract")
    env = dict(os.environ)
    for k in ("MALLOC_TRIM_THRESHOLD_", "MALLOC_MMAP_THRESHOLD_", "MALLOC_TOP_PAD_", "MALLOC_ARENA_MAX"):
        env.pop(k, None)   # glibc's defaults, unless tune_allocator() changes them
    r = subprocess.run(cmd, capture_output=True, text=True, check=True, env=env, timeout=900)
    return json.loads(r.stdout.strip().splitlines()[-1])["sweeps"]


def loadavg() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--Ns", default="3600,36000")
    ap.add_argument("--sweeps", type=int, default=6)
    ap.add_argument("--reps", type=int, default=8,
                    help="process pairs (api, app) per case and N (a first sweep is one sample a process)")
    ap.add_argument("--extract", action="store_true", help="also read every joint's arrays after each sweep")
    ap.add_argument("--child", nargs=5, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        mode, name, eid, n, sweeps = a.child
        print(json.dumps(child(mode, name, eid, int(n), int(sweeps), a.extract)))
        return 0
    print(f"# bench_api_alloc  {time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime())}  load average {loadavg()}\n")
    print(f"fresh processes, {a.reps} pairs (api, app alternating) per row, {a.sweeps} order-2 sweeps each"
          f"{' + every joint read' if a.extract else ''}; medians over the processes; thread CPU ms "
          f"(wall ms); minor page faults per sweep\n")
    print("| mechanism | N | api: first | app: first | api: later | app: later | faults api first / later | "
          "faults app first / later | api / app first (CPU) | api / app later (CPU) | load | ≤ 1.2× |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    verdicts = []
    for label, name, eid in CASES:
        for n in [int(x) for x in a.Ns.split(",")]:
            runs = {"api": [], "app": []}
            for _ in range(a.reps):
                for mode in ("api", "app"):
                    runs[mode].append(run_child(mode, name, eid, n, a.sweeps, a.extract))
            stat = {}
            for mode, rs in runs.items():
                first = [r[0] for r in rs]
                later = [x for r in rs for x in r[1:]]
                stat[mode] = {"first": statistics.median(x[0] for x in first) * 1e3,
                              "first_wall": statistics.median(x[1] for x in first) * 1e3,
                              "later": statistics.median(x[0] for x in later) * 1e3,
                              "later_wall": statistics.median(x[1] for x in later) * 1e3,
                              "ffirst": statistics.median(x[2] for x in first),
                              "flater": statistics.median(x[2] for x in later)}
            s, t = stat["api"], stat["app"]
            r1, r2 = s["first"] / t["first"], s["later"] / t["later"]
            ok = r1 <= TARGET and r2 <= TARGET
            verdicts.append((label, n, r1, r2, ok))
            print(f"| {label} | {n:,} | {s['first']:.3f} ({s['first_wall']:.3f}) | {t['first']:.3f} "
                  f"({t['first_wall']:.3f}) | {s['later']:.3f} ({s['later_wall']:.3f}) | {t['later']:.3f} "
                  f"({t['later_wall']:.3f}) | {s['ffirst']:.0f} / {s['flater']:.0f} | {t['ffirst']:.0f} / "
                  f"{t['flater']:.0f} | {r1:.2f} | {r2:.2f} | {loadavg()} | {'yes' if ok else 'NO'} |", flush=True)
    print()
    for label, n, r1, r2, ok in verdicts:
        print(f"target api within {TARGET}x of app from the first sweep, {label} N = {n:,}: first {r1:.2f}x, "
              f"later {r2:.2f}x — {'met' if ok else 'MISSED'}")
    print(f"load average at the end: {loadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
