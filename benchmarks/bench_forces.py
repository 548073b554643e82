"""Kinetostatics: the cost of forces on top of the kinematics, against their error.

For a loaded four-bar (the example ``fourbar_loaded``: masses, gravity, a force, a torque, a
spring, a damper; its bearing friction timed apart), a loaded slider-crank and a loaded six-bar
with a moving guide (masses on every link, gravity, a torque on the output), and the excavator
arm driven by a cylinder on a cycloidal stroke (its driving force, N), at N = 360, 3,600 and
36,000 samples, prints:

- kinematics alone: ``plan.sweep(N)`` at order 2 (what the forces need);
- kinematics + forces: the sweep and ``linkage_forces`` (driving torque, every joint reaction,
  shaking force and moment: what ``analyze --forces`` writes), and the ratio to the kinematics
  alone (target ≤ 2× at N = 3,600);
- the power-balance check (computed on first access of ``result.power``) and the friction
  iteration, timed apart;
- the error: the worst relative power-balance residual over the cycle, and the largest
  difference from the independent whole-mechanism linear solve (tests/core/forces_reference.py)
  at 12 samples, relative to the largest force there.

Times are the best of interleaved runs (the kinematics and the forces alternate, so both see the
same allocator state and load), as thread CPU time (``time.thread_time``: time the machine's other
processes take from this one does not count; their cache traffic and page faults still do); the
load average is printed beside each verdict. The power check alone is wall time.

    .venv/bin/python benchmarks/bench_forces.py [--budget 3]
"""
from __future__ import annotations

import argparse
import gc
import math
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "core"))

import numpy as np  # noqa: E402

from forces_reference import FloatKin, equilibrium  # noqa: E402
from mechsketch.core import load_scene  # noqa: E402
from mechsketch.core.analyses.forces.kinetostatics import linkage_forces  # noqa: E402
from mechsketch.core.model.loads import LinkMass, Torque  # noqa: E402
from mechsketch.core.solver.plan import compile_plan  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

TARGET = 2.0


def loaded(name: str, eid: str, output: str):
    """An example with masses on every moving link, gravity and a torque on ``output``."""
    lk = load_scene(example_path(name)).element(eid)
    masses = tuple(LinkMass(k, 0.2 + 0.15 * i) for i, k in enumerate(lk.moving_links))
    return replace(lk, masses=masses, gravity=(0.0, -9.81), loads=(Torque("load", output, -2.0),))


def cases():
    four = load_scene(example_path("fourbar_loaded")).element("loaded_fourbar")
    return [("four-bar (example fourbar_loaded)", replace(four, friction=()), four),
            ("slider-crank (masses, gravity, torque)", loaded("slider_crank_offset", "slider_crank", "slider"), None),
            ("six-bar, moving guide (masses, gravity, torque)", loaded("sixbar_moving_guide", "sixbar", "block"), None),
            ("cylinder arm, driving force (example excavator_arm: masses, gravity, torque)",
             loaded("excavator_arm", "arm", "stick"), None)]


def interleaved(jobs: dict, budget: float) -> dict:
    """Best seconds of each job, running them in turn until ``budget`` seconds are spent."""
    best = {k: math.inf for k in jobs}
    gc.disable()
    try:
        end = time.perf_counter() + budget
        rounds = 0
        while rounds < 5 or time.perf_counter() < end:
            for name, fn in jobs.items():
                t0 = time.thread_time()
                fn()
                best[name] = min(best[name], time.thread_time() - t0)
            rounds += 1
    finally:
        gc.enable()
    return best


def loadavg() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def linear_solve_error(lk, sol, res, count: int = 12) -> float:
    worst = 0.0
    for k in np.linspace(0, len(sol) - 1, count).astype(int):
        if not res.valid[k]:
            continue
        e = equilibrium(lk, FloatKin(sol, int(k)))
        scale = max([abs(e["T"])] + [math.hypot(*f) for f in e["pins"].values()])
        d = abs(res.driver.values[k] - e["T"])
        for (j, b), f in e["pins"].items():
            d = max(d, float(np.hypot(*(res.pins[j][b][k] - np.array(f)))))
        worst = max(worst, d / scale)
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=float, default=3.0, help="seconds of timing per case and N")
    args = ap.parse_args()
    print(f"load average {loadavg()} (2-core machine: above ~1 the timings are noisy); thread CPU ms, "
          f"best of interleaved runs\n")
    print("| mechanism | N | kinematics ms | + forces ms | ratio | power check ms | friction ms (passes) "
          "| power residual | vs linear solve | load |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    verdicts = []
    for name, lk, with_friction in cases():
        plan = compile_plan(lk)
        for n in (360, 3600, 36000):
            sol = plan.sweep(n)
            res = linkage_forces(plan, sol)

            def both():
                s = plan.sweep(n)
                linkage_forces(plan, s)

            def power():
                r = linkage_forces(plan, sol)
                t0 = time.perf_counter()
                _ = r.power
                return time.perf_counter() - t0

            jobs = {"kin": lambda: plan.sweep(n), "both": both}
            best = interleaved(jobs, args.budget * (0.5 if n != 3600 else 1.0))
            t_power = min(power() for _ in range(20))
            fr_text = "—"
            if with_friction is not None:
                fplan = compile_plan(with_friction)
                fsol = fplan.sweep(n)
                fres = linkage_forces(fplan, fsol)
                t_f = interleaved({"f": lambda: linkage_forces(fplan, fsol)}, 0.5)["f"]
                fr_text = f"{t_f * 1e3:.3f} ({fres.friction.iterations}; residual {fres.friction.power.worst:.1e})"
            ratio = best["both"] / best["kin"]
            err = linear_solve_error(lk, sol, res)
            print(f"| {name} | {n:,} | {best['kin'] * 1e3:.3f} | {best['both'] * 1e3:.3f} | {ratio:.2f}× | "
                  f"{t_power * 1e3:.3f} | {fr_text} | {res.power.worst:.1e} | {err:.1e} | {loadavg()} |", flush=True)
            if n == 3600:
                verdicts.append((name, ratio, best["kin"], best["both"], loadavg()))
    print()
    for name, ratio, kin, both, load in verdicts:
        print(f"target kinematics + forces ≤ {TARGET:g}× kinematics at N = 3,600, {name}: kinematics "
              f"{kin * 1e3:.3f} ms (baseline), + forces {both * 1e3:.3f} ms (ours), {ratio:.2f}×; load {load} — "
              f"{'met' if ratio <= TARGET else 'MISSED'}")
    print(f"load average at the end {loadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
