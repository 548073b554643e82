"""Any input link, linear actuators, motion laws and dimension edits: speed against error (a
report, not a test).

    .venv/bin/python benchmarks/bench_drivers.py [--runs 5]

For a V-engine crank with two pins, a four-bar whose crank carries a traced point (modified
trapezoid law), an excavator arm lifted by a cylinder (cycloidal stroke), a cylinder pushing a
slider (harmonic) and a slider driven along a fixed guide, it prints µs per sample of
``plan.sweep(N, order=2)`` plus every joint's position, velocity and acceleration arrays (best of
``--runs``), at N = 360, 3,600 and 36,000, beside the same sweep of a constant-speed binary-crank
four-bar (the baseline the crank kernels were tuned on); and the error against the generic
50-digit reference of ``tests/core/reference_drive.py`` (constraint equations with the driver's
own equation, Newton in mpmath; rates by 80-digit differences) at 6 samples: position over the
mechanism's size, velocity and acceleration over the largest reference value.

Then the cost of a dimension edit (``set_dimension``: re-assembly at the drawn input plus the
check that the result compiles) on the four-bar, a Stephenson six-bar and the excavator arm, and
of the motion laws alone (``cycle`` at N = 36,000).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "core"))

import drive_builders as DB  # noqa: E402
import linkage_builders as LB  # noqa: E402
import reference_drive as RD  # noqa: E402
from mechsketch.core.solver.dimensions import set_dimension  # noqa: E402
from mechsketch.core.solver.motion_law import cycle  # noqa: E402
from mechsketch.core.solver.plan import compile_plan  # noqa: E402

CASES = {
    "four-bar, binary crank (baseline)": lambda: LB.fourbar(),
    "V-engine, crank with two pins": lambda: DB.vengine(),
    "crank with a traced point, modified trapezoid": lambda: DB.crank_with_point(kind="modified_trapezoid"),
    "excavator arm, cylinder, cycloidal": lambda: DB.excavator(),
    "cylinder pushing a slider, harmonic": lambda: DB.cylinder_slider(),
    "slider on a fixed guide, harmonic": lambda: DB.pushed_crank(),
}
SAMPLES = (360, 3600, 36000)


def best(fn, runs: int) -> float:
    out = []
    for _ in range(runs):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return min(out)


def sweep_all(plan, lk, n: int) -> None:
    sol = plan.sweep(n, order=2)
    for j in lk.joint_ids:
        sol.position(j), sol.velocity(j), sol.acceleration(j)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} (a shared machine: rerun when quiet before judging)\n")
    print("| mechanism | groups | " + " | ".join(f"µs/sample N={n:,}" for n in SAMPLES)
          + " | pos err | vel err | acc err |")
    print("|---|---|" + "---|" * (len(SAMPLES) + 3))
    for name, make in CASES.items():
        lk = make()
        plan = compile_plan(lk)
        times = [best(lambda n=n: sweep_all(plan, lk, n), args.runs if n < 36000 else max(2, args.runs // 2)) / n * 1e6
                 for n in SAMPLES]
        sol = plan.sweep(360, order=2)
        ok = np.flatnonzero(sol.valid)
        if name.endswith("(baseline)") or ok.size == 0:
            errs = ["—", "—", "—"]
        else:
            e = RD.relative(RD.compare(lk, sol, ok[:: max(1, ok.size // 6)]), LB.size_of(lk))
            errs = [f"{e['pos']:.1e}", f"{e['vel']:.1e}", f"{e['acc']:.1e}"]
        print(f"| {name} | {len(plan.steps)} | " + " | ".join(f"{t:.3f}" for t in times) + " | " + " | ".join(errs)
              + " |")
    print("\n| dimension edit | ms per edit |")
    print("|---|---|")
    for name, lk, key, value in (("four-bar: crank length", LB.fourbar(), "length:crank:A:B", 45.0),
                                 ("Stephenson six-bar: coupler side B–E", LB.sixbar_stephenson(), "length:coupler:B:E", 70.0),
                                 ("excavator arm: boom O–E", DB.excavator(), "length:boom:O:E", 2700.0)):
        print(f"| {name} | {best(lambda: set_dimension(lk, key, value), args.runs) * 1e3:.3f} |")
    print("\n| motion law, N = 36,000 | µs per sample |")
    print("|---|---|")
    for law in ("cycloidal", "harmonic", "modified_trapezoid"):
        drv = DB.excavator(kind=law).driver
        print(f"| {law} (actuator) | {best(lambda: cycle(drv, 0.0, 36000), args.runs) / 36000 * 1e6:.4f} |")
    drv = DB.crank_with_point().driver
    from dataclasses import replace
    from mechsketch.core.model.drivers import LawKind, MotionLaw
    table = replace(drv, law=MotionLaw(LawKind.TABLE, ((0, 0), (0.2, 50), (0.5, 200), (0.8, 300), (1, 360))))
    print(f"| table, 4 knots (crank) | {best(lambda: cycle(table, 0.0, 36000), args.runs) / 36000 * 1e6:.4f} |")


if __name__ == "__main__":
    main()
