"""``mechsketch validate`` against ``mechsketch analyze --summary`` on long linkages (issue 20, item 7;
a report, not a test).

Target: validate ≤ 1.5× analyze --summary, end to end, for a 32-dyad chain and a linkage of about
1,000 joints (the chain of ``tests/core/chains.py`` with 500 dyads: 1,002 joints, 1,001 links).
Each chain is measured three times: with the default plate sizes (its plates cannot be cut:
validate builds and checks every part and lists them as warnings), with a ``drawing`` block that
makes it cut-ready (boss radius 3 mm, bores Ø2 mm: every part passes, so every check runs to the
end, necks included; the chain's links are congruent, so most checks are taken from the first
congruent part) and cut-ready with every moving joint moved by up to ±3 mm at random (seed 1), so
no two links are alike and every part is checked on its own.

Each case runs the ``mechsketch`` console script in fresh processes, validate and analyze
interleaved, and prints the median CPU time of the child (user + system; the wall time beside it)
and the ratio, with the load average before and after. Error: in-process, the thinnest web of
every part of the cut-ready chains against its closed form (boss radius − bore radius = 2 mm:
every plate is a stadium or the rounded hull of its bosses, so the web is the bore's ligament).

Usage::

    .venv/bin/python benchmarks/bench_validate.py [--runs 5] [--sizes 32,500]
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "core"))

from chains import dyad_chain  # noqa: E402

from mechsketch.core.io.scene_file import save_scene  # noqa: E402
from mechsketch.core.model.drawing import LinkageDrawing  # noqa: E402
from mechsketch.core.model.scene import Scene  # noqa: E402

TARGET = 1.5
CUT_READY = LinkageDrawing(boss_radius=3.0, bore_diameter=2.0)


def jittered(lk, seed: int = 1):
    """``lk`` with every joint but the frame's moved by up to ±3 mm: no two links congruent."""
    import numpy as np

    rng = np.random.default_rng(seed)
    ground = set(lk.link(lk.ground).joints)
    moves = {j.id: (j.at[0] + rng.uniform(-3, 3), j.at[1] + rng.uniform(-3, 3)) for j in lk.joints
             if j.id not in ground and j.id != "P0"}
    return lk.with_joints_moved(moves)


def _script() -> list[str]:
    exe = Path(sys.executable).with_name("mechsketch")
    if exe.exists():
        return [str(exe)]
    return [sys.executable, "-c", "import sys; from mechsketch.gui.launcher import main; sys.exit(main())"]


def run_once(cmd: list[str]) -> tuple[float, float, str]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=1800)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{out.stdout}\n{out.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out.stdout


def web_errors(scene_path: Path) -> tuple[int, float]:
    """Parts checked and the largest |web − 2 mm| of a cut-ready chain (in-process)."""
    from mechsketch.core import load_scene
    from mechsketch.core.analyses.parts import check_parts
    from mechsketch.core.analyses.parts.build import PartOptions, element_parts
    from mechsketch.core.solver.plan import compile_plan

    lk = load_scene(scene_path).elements[0]
    ps = element_parts(lk, PartOptions(), compile_plan(lk))
    checks = check_parts(ps.parts, 1.0)
    assert all(c.ok for c in checks), [c.problems for c in checks if not c.ok][:3]
    return len(checks), max(abs(c.web - 2.0) for c in checks)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--sizes", default="32,500", help="dyads per chain (500: 1,002 joints)")
    args = ap.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}; {args.runs} runs per command")
    print("| case | joints | validate CPU s (wall) | analyze --summary CPU s (wall) | ratio (CPU) | target | validate says |")
    print("|---|---|---|---|---|---|---|")
    errors = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            for label, drawing, jitter in (("default sizes", None, False), ("cut-ready", CUT_READY, False),
                                           ("cut-ready, no two links alike", CUT_READY, True)):
                lk = dyad_chain(n)
                if drawing is not None:
                    lk = replace(lk, drawing=drawing)
                if jitter:
                    lk = jittered(lk)
                path = Path(tmp) / f"chain{n}_{'cut' if drawing else 'default'}{'_j' if jitter else ''}.json"
                save_scene(Scene((lk,)), path)
                v, a, said = [], [], ""
                run_once(_script() + ["validate", str(path)])   # warm the bytecode cache
                for _ in range(args.runs):
                    wall, cpu, out = run_once(_script() + ["validate", str(path)])
                    v.append((cpu, wall))
                    said = f"{sum('part ' in ln for ln in out.splitlines())} part warnings" if "warnings" in out else "ok"
                    wall, cpu, _ = run_once(_script() + ["analyze", str(path), "--summary"])
                    a.append((cpu, wall))
                vc, vw = statistics.median(c for c, _ in v), statistics.median(w for _, w in v)
                ac, aw = statistics.median(c for c, _ in a), statistics.median(w for _, w in a)
                ratio = vc / ac
                print(f"| chain{n}, {label} | {len(lk.joints):,} | {vc:.2f} ({vw:.2f}) | {ac:.2f} ({aw:.2f}) | "
                      f"{ratio:.2f}× | {'met' if ratio <= TARGET else 'MISSED'} (≤ {TARGET}×) | {said} |")
                if drawing is not None and not jitter:
                    errors.append((n, *web_errors(path)))
    print()
    for n, parts, err in errors:
        print(f"chain{n} cut-ready: {parts} parts checked, thinnest web vs closed form 2 mm: max |Δ| = {err:.2e} mm")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
