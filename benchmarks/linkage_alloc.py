"""The allocator diagnostic of the linkage benchmark: the order-2 sweeps timed in fresh processes
(``bench_linkage.py --alloc-probe default|tuned``), with glibc's default malloc and with
``mallopt`` keeping freed memory, counting page faults per call.
"""
from __future__ import annotations

import sys
from pathlib import Path

from mechsketch.core.solver.plan import compile_plan

from linkage_cases import example
from linkage_timing import best_of, ms_solve

#: the script whose hidden ``--alloc-probe`` option runs :func:`probe_main` in a fresh process
BENCH = Path(__file__).resolve().parent / "bench_linkage.py"


def allocator_probe(mechs, Ns, reps_for) -> list[tuple]:
    """Best µs/sample and minor page faults per call of the order-2 sweep + extraction."""
    import resource

    out = []
    for name, lk in mechs:
        plan = compile_plan(lk)
        joints = list(lk.joint_ids)
        for N in Ns:
            ms_solve(plan, N, 2, joints)
            reps = reps_for(N)
            f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
            sec = best_of(lambda: ms_solve(plan, N, 2, joints), 0.0, min_k=reps, max_k=reps)[0]
            f1 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
            out.append((name, N, sec / N * 1e6, (f1 - f0) / reps))
    return out


def run_probe(mode: str, quick: bool):
    """allocator_probe in a fresh process (the allocator's state depends on the process' history:
    after large arrays glibc raises its own thresholds)."""
    import json
    import subprocess

    cmd = [sys.executable, str(BENCH), "--alloc-probe", mode] + (["--quick"] if quick else [])
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=300, check=True)
        return [tuple(x) for x in json.loads(r.stdout.strip().splitlines()[-1])]
    except (subprocess.SubprocessError, ValueError, IndexError, OSError):
        return None


def probe_main(mode: str, quick: bool) -> int:
    import json

    if mode == "tuned" and not tune_glibc_malloc():
        return 1
    mechs = [("four-bar", example("fourbar_crank_rocker")),
             ("six-bar (moving guide)", example("sixbar_moving_guide"))]
    Ns = [3600] if quick else [3600, 36000]
    res = allocator_probe(mechs, Ns, lambda N: (20 if quick else 60) if N <= 3600 else 15)
    print(json.dumps(res))
    return 0


def tune_glibc_malloc() -> bool:
    """Keep freed memory in the process (no trimming, no per-array mmap): glibc's mallopt."""
    import ctypes
    import ctypes.util

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3
        return bool(libc.mallopt(M_MMAP_THRESHOLD, 64 << 20)) and bool(libc.mallopt(M_TRIM_THRESHOLD, 512 << 20))
    except (OSError, AttributeError):
        return False
