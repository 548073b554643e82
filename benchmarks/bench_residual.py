"""``Solution.residual`` (issue 26 item 6: it is a third of ``diagnose()`` on a long chain) now
against a pass per link and per joint (the form it had: numpy over the samples, Python over the
links and joints, written out here), interleaved, best thread CPU of k, each on a fresh sweep
(the residual is kept per solution), with the two values compared bit for bit.

Cases at 3,600 samples: the six-bar example and 16 and 32 RRR dyads driven by a crank
(``tests/core/chains.py``).

Run::

    .venv/bin/python benchmarks/bench_residual.py [--runs 7]
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "core"))

import numpy as np  # noqa: E402

from chains import dyad_chain  # noqa: E402
from mechsketch.core import load_scene  # noqa: E402
from mechsketch.core.model.linkage import JointKind  # noqa: E402
from mechsketch.core.solver.plan import compile_plan  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

SAMPLES = 3600


def residual_per_joint(sol) -> float:
    """The residual one link and one joint at a time (numpy over the samples)."""
    lk, n, valid = sol.plan.linkage, len(sol), sol.valid
    worst = 0.0
    with np.errstate(invalid="ignore"):
        for k, st in sol._states.items():
            reach = max((abs(complex(*lk.joint(j).at) - st.a0) for j in lk.link(k).joints), default=0.0)
            r = np.abs(np.abs(np.broadcast_to(st.rot, (n,))) - 1.0) * reach
            worst = max(worst, float(np.nanmax(r[valid], initial=0.0)))
        for j in lk.joints:
            carriers = [c for c in lk.links_of(j.id) if c in sol._states]
            if len(carriers) < 2:
                continue
            p0 = complex(*j.at)
            pts = [np.broadcast_to(sol._states[c].point(p0), (n,)) for c in carriers]
            if j.kind is JointKind.R:
                r = max(np.nanmax(np.abs(p - pts[0])[valid], initial=0.0) for p in pts[1:])
            else:
                a = math.radians(j.axis_deg or 0.0)
                u = np.broadcast_to(sol._states[carriers[0]].rot, (n,)) * complex(math.cos(a), math.sin(a))
                r = np.nanmax(np.abs((u.conjugate() * (pts[1] - pts[0])).imag)[valid], initial=0.0)
            worst = max(worst, float(r))
    return worst


def cpu(fn) -> tuple[float, float]:
    c = time.thread_time()
    v = fn()
    return time.thread_time() - c, v


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7)
    args = ap.parse_args()
    cases = [("sixbar", load_scene(example_path("sixbar_moving_guide")).element("sixbar").with_samples(SAMPLES))]
    cases += [(f"chain{n}", dyad_chain(n, samples=SAMPLES)) for n in (16, 32)]
    for name, lk in cases:
        plan = compile_plan(lk)
        plan.sweep(order=2).residual()          # warm-up: branch points, the plan's layout
        ours, ref, same = [], [], True
        for _ in range(args.runs):              # interleaved, each on a fresh sweep
            t, v = cpu(plan.sweep(order=2).residual)
            ours.append(t)
            sol = plan.sweep(order=2)
            t, w = cpu(lambda: residual_per_joint(sol))
            ref.append(t)
            same = same and v == w
        ours_ms, ref_ms = min(ours) * 1e3, min(ref) * 1e3
        print(f"{name}: residual {ours_ms:.2f} ms, per-link/per-joint pass {ref_ms:.2f} ms, ratio "
              f"{ours_ms / ref_ms:.2f}; equal bit for bit: {same}; load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
