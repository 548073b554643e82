"""Timing for the linkage benchmark: best-of-k and interleaved best-of-k runs, what is timed for
mechsketch (sweep plus extraction), and the Newton baseline timed in short blocks, over the whole
sweep or over arcs ending at the reference poses.
"""
from __future__ import annotations

import gc
import math
import time
from dataclasses import dataclass

import numpy as np

from linkage_errors import Err
from newton_baseline import NewtonBaseline


def best_of(fn, budget: float, min_k: int = 3, max_k: int = 500):
    """Best wall time of fn() over k runs (cyclic GC off while timing; arrays are freed by
    reference counting anyway); returns (seconds, k, result)."""
    best, k, total, res = math.inf, 0, 0.0, None
    gc.disable()
    try:
        while k < min_k or (total < budget and k < max_k):
            res = None
            t0 = time.perf_counter()
            res = fn()
            dt = time.perf_counter() - t0
            best, total, k = min(best, dt), total + dt, k + 1
    finally:
        gc.enable()
    return best, k, res


class Interleaved:
    """Best-of-k timing of many jobs, interleaved: each round runs every job a few times back to
    back (about ``slice_s`` worth of runs, at least once), rounds repeat until the budget is
    spent. Under intermittent load from other processes, each job's best then comes from the whole
    window, not from one burst. A job is ``fn() -> seconds`` (it times its own measured part)."""

    def __init__(self):
        self.jobs: dict = {}
        self.best: dict = {}
        self.k: dict = {}

    def add(self, key, fn):
        self.jobs[key] = fn
        self.best[key], self.k[key] = math.inf, 0

    def run(self, budget: float, min_rounds: int = 5, slice_s: float = 0.02) -> int:
        t0, rounds = time.perf_counter(), 0
        gc.disable()
        try:
            while rounds < min_rounds or time.perf_counter() - t0 < budget:
                for key, fn in self.jobs.items():
                    reps = 1 if self.k[key] == 0 else max(1, min(50, int(slice_s / self.best[key])))
                    for _ in range(reps):
                        self.best[key] = min(self.best[key], fn())
                        self.k[key] += 1
                rounds += 1
        finally:
            gc.enable()
        return rounds


def timed(fn):
    def job():
        t0 = time.perf_counter()
        fn()
        return time.perf_counter() - t0
    return job


def ms_solve(plan, N: int, order: int, joints, want=None):
    """What is timed for mechsketch: solve and extract every requested joint's arrays."""
    sol = plan.sweep(N, order=order, joints=want)
    out = [sol.position(j) for j in joints]
    if order == 2:
        out += [sol.velocity(j) for j in joints]
        out += [sol.acceleration(j) for j in joints]
    return sol, out


# ----------------------------------------------------------------------------------------------
# Newton baseline: full run or arcs
@dataclass
class NewtonResult:
    us: float
    err: Err | None
    samples: int          # samples actually solved (timed)
    mode: str             # "full" or "subset …"
    q_at: dict            # sample index -> q (float) at reference samples
    q_full: np.ndarray | None
    iters: float
    failed: int
    jumps: int = 0        # reference poses where Newton is on another assembly branch
    full: dict | None = None   # full run: {joint: (P, V, A)} over all samples (freed after use)
    sweep_jumps: int | None = None  # samples (full runs) where Newton left mechsketch's branch


#: Newton is timed in blocks this short (~1–3 ms) so that a best-of-k can dodge preemption by
#: other processes, like mechsketch's sub-millisecond runs can
NEWTON_TIMING_BLOCK = 32


def _newton_blocks(nb: NewtonBaseline, inputs, order: int, blocks, reps: int):
    """Run Newton over ``blocks`` [(sample indices, seed q or None = continue from the previous
    block's last answer)]. Each block is cut into pieces of NEWTON_TIMING_BLOCK samples, each piece
    run ``reps`` times from the same start (the runs are deterministic); time = Σ of the pieces'
    best runs, plus the best of ``reps`` vectorised extractions. Returns (seconds, NewtonRun over
    the concatenated samples, joints dict)."""
    from newton_baseline import NewtonRun

    total, runs, q = 0.0, [], None
    gc.disable()
    try:
        for seg, seed in blocks:
            q = list(seed) if seed is not None else q
            for p in range(0, len(seg), NEWTON_TIMING_BLOCK):
                piece = inputs[seg[p:p + NEWTON_TIMING_BLOCK]]
                best = math.inf
                for _ in range(reps):
                    t0 = time.perf_counter()
                    run = nb.run(piece, order, q_start=q)
                    best = min(best, time.perf_counter() - t0)
                total += best
                runs.append(run)
                q = list(run.q[-1])
        cat = lambda name: None if getattr(runs[0], name) is None else np.concatenate(  # noqa: E731
            [getattr(x, name) for x in runs])
        big = NewtonRun(np.concatenate([x.inputs for x in runs]), cat("q"), cat("qd"), cat("qdd"),
                        sum(x.iterations for x in runs), sum(x.failed for x in runs))
        best = math.inf
        for _ in range(reps):
            t0 = time.perf_counter()
            J = nb.joints(big)
            best = min(best, time.perf_counter() - t0)
    finally:
        gc.enable()
    return total + best, big, J


def run_newton(nb: NewtonBaseline, inputs: np.ndarray, order: int, ref_idx: np.ndarray,
               full_limit: int, prev: tuple[np.ndarray, np.ndarray] | None, arc: int,
               reps: int) -> tuple[NewtonResult, dict]:
    """Time the Newton baseline (best of ``reps`` per block of ≤ ``arc`` samples).

    N ≤ full_limit: the whole sweep, from the drawn pose, in consecutive blocks (one continuation).
    Otherwise a subset: arcs of ``arc`` consecutive samples ending at each reference sample, each
    started from the previous (10× coarser) full run's answer at the sample just before the arc.
    """
    N = len(inputs)
    if N <= full_limit:
        cuts = list(range(0, N, arc)) + [N]
        blocks = [(np.arange(a, b), nb.system.seed_drawn() if a == 0 else None)
                  for a, b in zip(cuts[:-1], cuts[1:])]
        sec, run, J = _newton_blocks(nb, inputs, order, blocks, reps)
        sub = {j: tuple(None if a is None else a[ref_idx] for a in J[j]) for j in J}
        q_at = {int(i): run.q[i] for i in ref_idx}
        return NewtonResult(sec / N * 1e6, None, N, "full sweep", q_at,
                            run.q, run.iterations / N, run.failed, full=J), sub
    prev_inputs, prev_q = prev
    ratio = N // len(prev_inputs)
    blocks = []
    for r in ref_idx:
        start = int(r) - arc + 1
        blocks.append((np.arange(start, int(r) + 1) % N, prev_q[(start // ratio) % len(prev_inputs)]))
    sec, run, J = _newton_blocks(nb, inputs, order, blocks, reps)
    ends = np.arange(1, len(blocks) + 1) * arc - 1
    sub = {j: tuple(None if a is None else a[ends] for a in J[j]) for j in J}
    q_at = {int(i): run.q[e] for i, e in zip(ref_idx, ends)}
    n = len(run.inputs)
    return NewtonResult(sec / n * 1e6, None, n,
                        f"subset: {len(blocks)} arcs × {arc} samples, extrapolated",
                        q_at, None, run.iterations / n, run.failed), sub
