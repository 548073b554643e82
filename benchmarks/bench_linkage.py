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
"""
from __future__ import annotations

import argparse
import gc
import math
import os
import platform
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import mpmath
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from mechsketch.core.io.scene_file import load_scene  # noqa: E402
from mechsketch.core.model.linkage import Driver, Joint, JointKind, Link, Linkage  # noqa: E402
from mechsketch.core.solver.plan import TOGGLE_COND, compile_plan  # noqa: E402

from newton_baseline import NewtonBaseline  # noqa: E402
from reference_mp import MPReference  # noqa: E402

EXAMPLES = HERE.parent / "resources" / "examples"

#: targets of issue 2 §7 (order 2, N = 3,600)
TARGET_US = {"four-bar": 0.15, "six-bar (moving guide)": 0.30}
TARGET_POS, TARGET_DER, TARGET_SPEEDUP = 1e-13, 1e-12, 100.0
#: "away from toggles": every group's conditioning |sin| at least this
AWAY_COND = 1e-2
#: mechsketch error counts as "equal" to Newton's within this factor, or when both are at the
#: round-off level: below 10 ulps (10·2⁻⁵²) of the size / of the velocity or acceleration scale
EQUAL_FACTOR, EQUAL_FLOOR = 2.0, 10 * 2.0 ** -52


# ----------------------------------------------------------------------------------------------
# mechanisms
def example(name: str) -> Linkage:
    return load_scene(EXAMPLES / f"{name}.json").elements[0]


def near_change_point(delta_rel: float) -> tuple[Linkage, float]:
    """Grashof crank-rocker with s + l = p + q − δ, δ = delta_rel·(s + l).

    Frame A(0,0)–D(120,0), crank 40 drawn at 60°, coupler 100, rocker 60 + δ. At crank angle 180°
    (sample N/3 of every sweep) coupler and rocker are within a gap δ of collinear. Returns the
    linkage and δ as realised by the rounded drawn coordinates (computed in mpmath).
    """
    s, l, p = 40.0, 120.0, 100.0
    with mpmath.workdps(60):
        d = mpmath.mpf(delta_rel) * (s + l)
        q = mpmath.mpf(s) + l - p + d
        B = (s * math.cos(math.radians(60)), s * math.sin(math.radians(60)))
        Bm = mpmath.matrix([mpmath.mpf(B[0]), mpmath.mpf(B[1])])
        Dm = mpmath.matrix([mpmath.mpf(l), mpmath.mpf(0)])
        v = Dm - Bm
        dist = mpmath.norm(v)
        a = (p * p - q * q + dist * dist) / (2 * dist)
        h = mpmath.sqrt(p * p - a * a)
        e = v / dist
        C = Bm + a * e + h * mpmath.matrix([-e[1], e[0]])   # left of B→D: the upper assembly
        C = (float(C[0]), float(C[1]))
        real = (mpmath.hypot(mpmath.mpf(C[0]) - B[0], mpmath.mpf(C[1]) - B[1])
                + mpmath.hypot(mpmath.mpf(C[0]) - l, mpmath.mpf(C[1]))
                - mpmath.hypot(mpmath.mpf(B[0]), mpmath.mpf(B[1])) - l)
    R = JointKind.R
    lk = Linkage(
        id="near_change_point",
        joints=(Joint("A", R, (0.0, 0.0)), Joint("B", R, B), Joint("C", R, C), Joint("D", R, (l, 0.0))),
        links=(Link("ground", ("A", "D")), Link("crank", ("A", "B")), Link("coupler", ("B", "C")),
               Link("rocker", ("D", "C"))),
        ground="ground", driver=Driver("crank", "A", 60.0 * 10.0 / (2 * math.pi)), samples=360)
    return lk, float(real)


def size_of(lk: Linkage) -> float:
    pts = [j.at for j in lk.joints]
    return max(math.dist(a, b) for a in pts for b in pts)


# ----------------------------------------------------------------------------------------------
# timing
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
# reference and errors
@dataclass
class RefSet:
    """Reference at some sample indices, as double-double arrays (hi + lo) per joint."""

    idx: np.ndarray
    joints: list[str]
    hi: np.ndarray     # (3, n_ref, n_joints, 2): position, velocity, acceleration
    lo: np.ndarray
    cond: np.ndarray   # mechsketch conditioning (min over groups) at idx
    ms_branch_bad: int = 0      # poses where mechsketch's float answer led to another branch
    seeds_disagree: int = 0     # poses where the mechsketch and Newton seeds were far apart


class References:
    """mpmath reference poses of one mechanism, cached by the exact float driver angle."""

    def __init__(self, lk: Linkage):
        self.mp = MPReference(lk)
        self.sys = self.mp.system
        self.cache: dict[float, object] = {}
        self.size = size_of(lk)
        self.solves = 0
        self.seconds = 0.0
        with mpmath.workdps(self.mp.dps):
            th = mpmath.mpf(self.sys.drawn_theta())
            J = self._jac(th, [mpmath.mpf(v) for v in self.sys.seed_drawn()])
            self.sign0 = mpmath.sign(mpmath.det(J))

    def _jac(self, th, q):
        return mpmath.matrix(self.mp._ev(th, q)[1])

    def _detsign(self, pose):
        with mpmath.workdps(self.mp.dps):
            return mpmath.sign(mpmath.det(self._jac(pose.theta, pose.q)))

    def seeds_from_solution(self, sol, idx) -> np.ndarray:
        """mechsketch's float answer as q (n_idx, n) at the sample indices ``idx``."""
        cols = []
        for k, lid in enumerate(self.sys.unknown):
            p = sol.point(lid, self.sys.anchor[k])[idx]
            cols += [p[:, 0], p[:, 1], sol.rotation(lid)[idx]]
        return np.column_stack(cols)

    def build(self, sol, idx, newton_q: dict[int, np.ndarray] | None, joints) -> RefSet:
        """Reference at sample indices ``idx`` of ``sol`` (an order-2 mechsketch solution).

        The mpmath Newton starts from mechsketch's float answer; its assembly branch is checked
        independently: the sign of det(∂Φ/∂q) must be that of the drawn pose (it cannot change
        along a sweep that meets no singular pose). If not, it restarts from the Newton
        baseline's float answer.
        """
        t0 = time.perf_counter()
        n = len(idx)
        hi = np.zeros((3, n, len(joints), 2))
        lo = np.zeros_like(hi)
        cond = np.ones(n)
        groups = [g.name for g in sol.groups]
        bad = disagree = 0
        seeds = self.seeds_from_solution(sol, idx)
        for r, i in enumerate(idx):
            th = float(sol.input[i])
            if groups:
                cond[r] = min(float(sol.conditioning(g)[i]) for g in groups)
            pose = self.cache.get(th)
            if pose is None:
                seed = seeds[r].tolist() if sol.valid[i] else None
                alt = None if newton_q is None or i not in newton_q else list(newton_q[i])
                if alt is not None and seed is not None:
                    dif = max(abs(a - b) * (1.0 if (m % 3) < 2 else self.size)
                              for m, (a, b) in enumerate(zip(seed, alt)))
                    disagree += dif > 1e-6 * self.size
                pose = None
                if seed is not None:
                    try:
                        pose = self.mp.solve(th, seed, order=2)
                    except RuntimeError:
                        pose = None
                    if pose is not None and self._detsign(pose) != self.sign0:
                        pose = None
                    if pose is None:
                        bad += 1
                if pose is None and alt is not None:
                    pose = self.mp.solve(th, alt, order=2)
                    if self._detsign(pose) != self.sign0:
                        raise RuntimeError(f"no reference on the drawn branch at θ = {th!r}")
                if pose is None:
                    raise RuntimeError(f"no reference seed at θ = {th!r}")
                self.cache[th] = pose
                self.solves += 1
            for c, j in enumerate(joints):
                for w, vec in enumerate((pose.position(j), pose.velocity(j), pose.acceleration(j))):
                    for ax in (0, 1):
                        h = float(vec[ax])
                        hi[w, r, c, ax] = h
                        lo[w, r, c, ax] = float(vec[ax] - h)
        self.seconds += time.perf_counter() - t0
        return RefSet(np.asarray(idx), list(joints), hi, lo, cond, bad, disagree)


@dataclass
class Err:
    pos: float
    vel: float = math.nan
    acc: float = math.nan
    pos_away: float = math.nan
    vel_away: float = math.nan
    acc_away: float = math.nan
    per_sample: np.ndarray | None = None   # (3, n_ref) normalised errors


def errors(ref: RefSet, arrays: list[np.ndarray | None], size: float) -> Err:
    """arrays: [P, V, A] each (n_ref, n_joints, 2) at the reference samples (V, A may be None).

    Positions are divided by the size. Velocities and accelerations by the largest reference
    magnitude over the samples considered (all of them, or only those away from toggles, so that a
    spike at a toggle does not shrink the errors elsewhere); ``per_sample`` holds, per sample, the
    worst joint's error over that sample's own largest magnitude (the local relative error).
    """
    n = len(ref.idx)
    per = np.full((3, n), np.nan)
    out = [math.nan] * 6
    away = ref.cond >= AWAY_COND
    for w, X in enumerate(arrays):
        if X is None:
            continue
        d = (X - ref.hi[w]) - ref.lo[w]
        e = np.max(np.hypot(d[..., 0], d[..., 1]), axis=1)                  # (n,) absolute
        mag = (np.full(n, size) if w == 0 else
               np.max(np.hypot(ref.hi[w][..., 0], ref.hi[w][..., 1]), axis=1))
        per[w] = e / mag
        out[w] = float(np.max(e) / np.max(mag))
        if away.any():
            out[3 + w] = float(np.max(e[away]) / np.max(mag[away]))
    return Err(*out, per_sample=per)


def gather(arrs_by_joint: dict[str, tuple], joints, rows) -> list[np.ndarray | None]:
    out = []
    for w in range(3):
        if arrs_by_joint[joints[0]][w] is None:
            out.append(None)
            continue
        out.append(np.stack([arrs_by_joint[j][w][rows] for j in joints], axis=1))
    return out


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


# ----------------------------------------------------------------------------------------------
# pylinkage
def pylinkage_fourbar(lk: Linkage, N: int):
    """A pylinkage model of the example four-bar (A, D frame; B crank; C RRR; E coupler point)."""
    import pylinkage as pl

    at = {j.id: j.at for j in lk.joints}
    plan = compile_plan(lk)
    sgn = 1.0 if lk.driver.omega >= 0 else -1.0
    d = sgn * 2 * math.pi / N
    O1 = pl.Ground(*at["A"], name="A")
    O2 = pl.Ground(*at["D"], name="D")
    cr = pl.Crank(O1, radius=math.dist(at["A"], at["B"]), angular_velocity=d,
                  initial_angle=plan.theta0 - d, name="B")  # its first output is sample 0
    rr = pl.RRRDyad(cr.output, O2, distance1=math.dist(at["B"], at["C"]),
                    distance2=math.dist(at["D"], at["C"]), x=at["C"][0], y=at["C"][1], name="C")
    ang = (math.atan2(at["E"][1] - at["B"][1], at["E"][0] - at["B"][0])
           - math.atan2(at["C"][1] - at["B"][1], at["C"][0] - at["B"][0]))
    fx = pl.FixedDyad(cr.output, rr, distance=math.dist(at["B"], at["E"]), angle=ang, name="E")
    L = pl.Linkage([O1, O2, cr, rr, fx])
    L.set_input_velocity(cr, omega=lk.driver.omega)
    return L, L.get_coords(), ["A", "D", "B", "C", "E"]


# ----------------------------------------------------------------------------------------------
@dataclass
class Row:
    mech: str
    N: int
    order: int
    ms_us: float
    ms_k: int
    ms_err: Err
    nt: NewtonResult | None
    ref: RefSet
    extra: dict = field(default_factory=dict)

    @property
    def speedup(self):
        return self.nt.us / self.ms_us if self.nt else math.nan


def fmt(x, spec=".1e"):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "—"
    return format(x, spec)


def fus(x):
    if x is None or math.isnan(x):
        return "—"
    return f"{x:.3f}" if x < 10 else f"{x:.1f}" if x < 1000 else f"{x:.0f}"


def equal_or_better(ms: float, nt: float) -> bool:
    if math.isnan(ms):
        return True
    if math.isnan(nt):
        return False
    return ms <= max(EQUAL_FACTOR * nt, EQUAL_FLOOR)


def bench_mechanism(name, lk, Ns, cfg, refs: References, timer: Interleaved, log) -> list[Row]:
    plan = compile_plan(lk)
    nb = NewtonBaseline(lk, tol=cfg.newton_tol)
    joints = list(lk.joint_ids)
    size = refs.size
    rows: list[Row] = []
    prev = None
    for N in Ns:
        sol2 = plan.sweep(N, order=2)
        inputs = sol2.input
        idx = np.unique(np.round(np.linspace(0, N, cfg.n_ref, endpoint=False)).astype(int))
        conds = np.min([sol2.conditioning(g.name) for g in sol2.groups], axis=0)
        worst = int(np.nanargmin(conds))
        if conds[worst] < AWAY_COND:  # near a toggle: always include the closest sample
            idx = np.unique(np.append(idx, worst))
        # Newton, positions (its answers seed the reference where mechsketch's cannot)
        nt0, nsub0 = run_newton(nb, inputs, 0, idx, cfg.newton_full_limit, prev, cfg.arc,
                                cfg.newton_reps)
        if nt0.q_full is not None:
            prev = (inputs, nt0.q_full)
        ref = refs.build(sol2, idx, nt0.q_at, joints)
        nt0.err = errors(ref, gather(nsub0, joints, slice(None)), size)
        nt0.jumps = int(np.sum(nt0.err.per_sample[0] > 1e-6))
        for order in (0, 2):
            sol, _ = ms_solve(plan, N, order, joints)
            timer.add(("ms", name, N, order), timed(lambda N=N, order=order: ms_solve(plan, N, order, joints)))
            arr = {j: (sol.position(j)[idx],
                       sol.velocity(j)[idx] if order == 2 else None,
                       sol.acceleration(j)[idx] if order == 2 else None) for j in joints}
            err = errors(ref, gather(arr, joints, slice(None)), size)
            if order == 0:
                nt = nt0
            else:
                nt, nsub = run_newton(nb, inputs, 2, idx, cfg.newton_full_limit, prev, cfg.arc,
                                      cfg.newton_reps)
                nt.err = errors(ref, gather(nsub, joints, slice(None)), size)
                nt.jumps = int(np.sum(nt.err.per_sample[0] > 1e-6))
            row = Row(name, N, order, math.nan, 0, err, nt, ref)
            row.extra["min_cond"] = float(conds[worst])
            if nt.full is not None:
                # whole-sweep check: samples where Newton is not on mechsketch's branch (mechsketch
                # is checked against the reference's drawn branch at every reference pose)
                far = np.zeros(N, dtype=bool)
                for j in joints:
                    far |= np.hypot(*(nt.full[j][0] - sol2.position(j)).T) > 1e-6 * size
                nt.sweep_jumps = int(far.sum())
                nt.full = None
            rows.append(row)
            log(f"  {name:28s} N={N:<7d} order {order}: mechsketch "
                f"(pos {fmt(err.pos)}, vel {fmt(err.vel)}, acc {fmt(err.acc)}); Newton {nt.us:.1f} µs "
                f"[{nt.mode}] (pos {fmt(nt.err.pos)}, vel {fmt(nt.err.vel)}, acc {fmt(nt.err.acc)})")
    return rows


def subset_section(lk: Linkage, Ns, cfg, timer: Interleaved):
    """'Model only what a scene needs': the crank-pin-side joints vs all joints, six-bar."""
    plan = compile_plan(lk)
    alljoints = list(lk.joint_ids)
    subset = ["A", "B", "C", "D"]   # the loop closed through the crank pin B: one RRR group
    steps_all, steps_sub = len(plan.steps_for(None)), len(plan.steps_for(subset))
    keys = []
    for N in Ns:
        for order in (0, 2):
            timer.add(("all", N, order), timed(lambda N=N, order=order: ms_solve(plan, N, order, alljoints)))
            timer.add(("sub", N, order), timed(lambda N=N, order=order: ms_solve(plan, N, order, subset,
                                                                                  want=subset)))
            keys.append((N, order))

    def results():
        out = []
        for N, order in keys:
            ta, ts = timer.best[("all", N, order)], timer.best[("sub", N, order)]
            out.append((N, order, ta / N * 1e6, ts / N * 1e6, ta / ts))
        return out
    return results, subset, steps_all, steps_sub


def pylinkage_section(lk: Linkage, Ns, cfg, ms_rows: list[Row], refs: References,
                      timer: Interleaved, log):
    try:
        import importlib.metadata as md

        import pylinkage  # noqa: F401
        from pylinkage._numba_compat import HAS_NUMBA
        version = md.version("pylinkage")
    except Exception as exc:  # noqa: BLE001
        return None, f"not installed ({type(exc).__name__})"
    size = refs.size
    out = []
    for N in Ns:
        L, c0, comps = pylinkage_fourbar(lk, N)
        L.step_fast(iterations=4)                     # JIT warm-up (numba caches on disk)
        L.set_coords(c0)
        L.step_fast_with_kinematics(iterations=4)
        for order in (0, 2):
            ms = next(r for r in ms_rows if r.N == N and r.order == order)
            ref = ms.ref

            def go(L=L, c0=c0, N=N, order=order):
                L.set_coords(c0)              # back to the drawn pose (not timed)
                t0 = time.perf_counter()
                if order == 0:
                    L.step_fast(iterations=N)
                else:
                    L.step_fast_with_kinematics(iterations=N)
                return time.perf_counter() - t0

            L.set_coords(c0)
            P, V, A = ((L.step_fast(iterations=N), None, None) if order == 0
                       else L.step_fast_with_kinematics(iterations=N))
            timer.add(("py", N, order), go)
            joints = ref.joints
            arrs = []
            for X in (P, V, A):
                if X is None:
                    arrs.append(None)
                    continue
                arrs.append(np.stack([X[ref.idx, comps.index(j)] for j in joints], axis=1))
            err = errors(ref, arrs, size)
            b = joints.index("B")
            d = (arrs[0][:, b] - ref.hi[0][:, b]) - ref.lo[0][:, b]
            crank_pin = float(np.max(np.hypot(d[:, 0], d[:, 1]))) / size
            out.append([N, order, ("py", N, order), err, ms, crank_pin])
            log(f"  pylinkage N={N} order {order}: pos {fmt(err.pos)}, "
                f"vel {fmt(err.vel)}, acc {fmt(err.acc)}")
    jit = "numba JIT" if HAS_NUMBA else "pure Python (numba not installed)"
    return out, f"pylinkage {version}, `Linkage.step_fast` / `step_fast_with_kinematics` ({jit})"


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

    cmd = [sys.executable, str(Path(__file__).resolve()), "--alloc-probe", mode] + (["--quick"] if quick else [])
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


def near_toggle_scan(deltas, N, cfg, log):
    """Errors at the pose nearest the toggle against the gap δ (order 2)."""
    out = []
    for dr in deltas:
        lk, dreal = near_change_point(dr)
        refs = References(lk)
        size = refs.size
        plan = compile_plan(lk)
        joints = list(lk.joint_ids)
        sol = plan.sweep(N, order=2)
        conds = np.min([sol.conditioning(g.name) for g in sol.groups], axis=0)
        worst = int(np.nanargmin(conds))
        idx = np.unique(np.append(np.round(np.linspace(0, N, cfg.n_ref_scan, endpoint=False)).astype(int),
                                  [worst - 1, worst, worst + 1]))
        nb = NewtonBaseline(lk, tol=cfg.newton_tol)
        run = nb.run(sol.input, 2)
        J = nb.joints(run)
        q_at = {int(i): run.q[i] for i in idx}
        ref = refs.build(sol, idx, q_at, joints)
        arr = {j: (sol.position(j)[idx], sol.velocity(j)[idx], sol.acceleration(j)[idx]) for j in joints}
        e_ms = errors(ref, gather(arr, joints, slice(None)), size)
        e_nt = errors(ref, gather({j: tuple(a[idx] for a in J[j]) for j in joints}, joints, slice(None)), size)
        r = int(np.flatnonzero(ref.idx == worst)[0])
        out.append(dict(delta_rel=dreal / size, delta=dreal, cond=float(conds[worst]),
                        ms=e_ms.per_sample[:, r], nt=e_nt.per_sample[:, r],
                        ms_away=(e_ms.pos_away, e_ms.vel_away, e_ms.acc_away),
                        nt_jumps=int(np.sum(e_nt.per_sample[0] > 1e-6)),
                        ms_bad=ref.ms_branch_bad))
        log(f"  δ/size={dreal / size:.1e}: sin μ={conds[worst]:.1e} mechsketch at toggle "
            f"pos {e_ms.per_sample[0, r]:.1e} vel {e_ms.per_sample[1, r]:.1e} acc {e_ms.per_sample[2, r]:.1e}")
    return out


def slope(xs, ys):
    xs, ys = np.log10(np.asarray(xs)), np.log10(np.maximum(np.asarray(ys), 1e-300))
    return float(np.polyfit(xs, ys, 1)[0])


# ----------------------------------------------------------------------------------------------
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


# ----------------------------------------------------------------------------------------------
def render(rows, py_rows, py_note, sub_rows, subset, steps_all, steps_sub, scan, cfg, ncp_delta,
           refs_by, root_note, elapsed, load0, load1, alloc=None) -> str:
    L = []
    add = L.append
    import numpy
    import scipy

    add("# Linkage solver: speed against error\n")
    add(f"{'Quick run' if cfg.quick else 'Full run'} on {platform.machine()} × {os.cpu_count()} CPUs, "
        f"Python {platform.python_version()}, numpy {numpy.__version__}, scipy {scipy.__version__}, "
        f"mpmath {mpmath.__version__}. Load average {load0[0]:.2f} at start, {load1[0]:.2f} at end "
        f"(other processes on this 2-core machine slow the timings; every timing is a best of k, "
        f"which removes preemption but not shared-cache contention: judge targets on a quiet "
        f"machine, load ≲ 1). Whole run {elapsed:.0f} s.\n")
    add("- **µs/sample**: best of k `time.perf_counter` runs of `plan.sweep(N, order)` plus extraction "
        "of every joint's (N, 2) position array (and velocity and acceleration arrays for order 2); "
        f"compile excluded. The mechsketch, pylinkage and subset timings are interleaved (round robin, "
        f"{cfg.rounds} rounds over {cfg.timing_budget:g} s, each configuration run ~20 ms per round; "
        f"k = {min(cfg.kmin)}…{max(cfg.kmax)} runs each) so that a burst of other work cannot spoil "
        "one configuration's best.")
    add(f"- **Errors** against a {refs_by['four-bar'].mp.dps}-digit mpmath solution of the loop equations "
        f"(`benchmarks/reference_mp.py`, a generic multibody formulation, checked against `mpmath.diff`), "
        f"at {cfg.n_ref} evenly spaced poses per N (plus the pose nearest a toggle for the near-change-point "
        "mechanism). pos = max |Δp| / size (size: largest distance between two drawn joints); "
        "vel = max |Δv| / max |v_ref|; acc = max |Δa| / max |a_ref|; maxima over those poses and all joints "
        "(for the \"away\" columns, over the poses away from toggles only).")
    add(f"- **Newton**: the same loop equations, pose by pose, warm-started from the previous pose, "
        f"analytic Jacobian, LAPACK `dgesv` via scipy, step tolerance {cfg.newton_tol:g}·size; "
        "velocities and accelerations from the differentiated constraints (J q̇ = −Φ̇, J q̈ = −Φ̈ with the "
        "quadratic terms; not finite differences), one LU per pose; joint extraction vectorised. "
        f"Timed in pieces of {NEWTON_TIMING_BLOCK} consecutive samples (1–3 ms, short enough to dodge "
        f"preemption like mechsketch's runs), each piece run {cfg.newton_reps} times from the same start "
        "and its best kept: the same best-of-k as mechsketch, if anything in Newton's favour. "
        f"Above N = {cfg.newton_full_limit:,} it runs on a subset (arcs of {cfg.arc} "
        "consecutive samples ending at each reference pose, started from the previous N's Newton answer) "
        "and its per-sample time is extrapolated: see the `Newton run` column.")
    add(f"- `scipy.optimize.root` (hybr, analytic Jacobian) per pose instead of the hand Newton: "
        f"{root_note[0]:.0f} µs/sample vs {root_note[1]:.0f} µs (four-bar, N = 360, positions); "
        "the table uses the faster hand Newton, so the speed-ups are not inflated by it.")
    add(f"- **speed-up** = Newton µs / mechsketch µs. \"Equal or better error\": mechsketch ≤ "
        f"{EQUAL_FACTOR:g} × Newton's, or both at the round-off level (≤ 10 ulps = {EQUAL_FLOOR:.1e}).\n")

    def table(sel, near=False):
        head = ["mechanism", "N", "order", "mechsketch µs/sample", "pos err/size", "vel rel err",
                "acc rel err"]
        if near:
            head += ["away: pos / vel / acc"]
        head += ["Newton µs/sample", "Newton pos", "Newton vel", "Newton acc"]
        if near:
            head += ["Newton away: pos / vel / acc", "Newton off-branch (ref poses / whole sweep)"]
        head += ["speed-up", "Newton run"]
        add("| " + " | ".join(head) + " |")
        add("|" + "|".join(["---"] * len(head)) + "|")
        for r in sel:
            e, n = r.ms_err, r.nt
            cells = [r.mech, f"{r.N:,}", str(r.order), fus(r.ms_us), fmt(e.pos), fmt(e.vel), fmt(e.acc)]
            if near:
                cells += [f"{fmt(e.pos_away)} / {fmt(e.vel_away)} / {fmt(e.acc_away)}"]
            cells += [fus(n.us), fmt(n.err.pos), fmt(n.err.vel), fmt(n.err.acc)]
            if near:
                sw = "n/a (subset)" if n.sweep_jumps is None else str(n.sweep_jumps)
                cells += [f"{fmt(n.err.pos_away)} / {fmt(n.err.vel_away)} / {fmt(n.err.acc_away)}",
                          f"{n.jumps} / {sw}"]
            cells += [f"{r.speedup:,.0f}×", n.mode]
            add("| " + " | ".join(cells) + " |")
        add("")

    main_rows = [r for r in rows if r.mech != "near-change-point four-bar"]
    near_rows = [r for r in rows if r.mech == "near-change-point four-bar"]
    add("## Results\n")
    table(main_rows)

    add("## Near-change-point four-bar\n")
    size = refs_by["near-change-point four-bar"].size
    mc = near_rows[0].extra["min_cond"]
    add(f"Frame 120, crank 40, coupler 100, rocker 60 + δ: s + l = p + q − δ with δ = {ncp_delta:.3e} mm "
        f"= {ncp_delta / size:.1e} of the size ({size:.1f} mm), as realised by the rounded drawn "
        f"coordinates. At crank angle 180° (sample N/3, always a reference pose) the coupler and rocker "
        f"are {mc:.1e} (sin μ) from collinear. \"away\" = samples where every group's conditioning "
        f"|sin μ| ≥ {AWAY_COND:g}; the toggle sample itself is in the \"all\" columns.\n")
    table(near_rows, near=True)

    add("### Error against the toggle gap (N = 3,600, order 2, at the sample nearest the toggle)\n")
    add("Velocity and acceleration errors here are local: over the largest |v_ref|, |a_ref| of that "
        "sample's joints.\n")
    add("| δ / size | sin μ at toggle | mechsketch pos err/size | vel rel err | acc rel err | "
        "mechsketch away (pos / vel / acc) | Newton pos | Newton vel | Newton acc | Newton branch jumps |")
    add("|---|---|---|---|---|---|---|---|---|---|")
    for s in scan:
        add(f"| {s['delta_rel']:.1e} | {s['cond']:.1e} | {fmt(s['ms'][0])} | {fmt(s['ms'][1])} | "
            f"{fmt(s['ms'][2])} | {fmt(s['ms_away'][0])} / {fmt(s['ms_away'][1])} / {fmt(s['ms_away'][2])} | "
            f"{fmt(s['nt'][0])} | {fmt(s['nt'][1])} | {fmt(s['nt'][2])} | {s['nt_jumps']} |")
    add("")
    fit = [s for s in scan if s["delta_rel"] <= 1e-4]
    if len(fit) >= 2:
        dl = [s["delta_rel"] for s in fit]
        sl = lambda key, w: slope(dl, [s[key][w] for s in fit])  # noqa: E731
        p_cond = slope(dl, [s["cond"] for s in fit])
        add(f"Scaling (least-squares slopes in log-log over δ/size ≤ 1e-4): sin μ at the toggle ∝ "
            f"δ^{p_cond:.2f}. Error at the toggle sample: mechsketch ∝ δ^{sl('ms', 0):.2f} (position), "
            f"δ^{sl('ms', 1):.2f} (velocity), δ^{sl('ms', 2):.2f} (acceleration); Newton ∝ "
            f"δ^{sl('nt', 0):.2f}, δ^{sl('nt', 1):.2f}, δ^{sl('nt', 2):.2f}. So positions and velocities "
            "lose about ε/sin μ (δ^-1/2) and accelerations ε/sin² μ (δ^-1): that is the conditioning of "
            "the problem itself (a length or coordinate perturbed by ε·size moves the inner joint by "
            "~ε·size/sin μ), and the generic Newton, which never forms a length, shows the same slopes "
            "within a small constant factor. Away from the toggle (every group's |sin μ| ≥ "
            f"{AWAY_COND:g}) the errors stay small for every δ.\n")
        eps = 2.0 ** -52
        cp = max(s["ms"][0] * s["cond"] for s in fit) / eps
        cv = max(s["ms"][1] * s["cond"] for s in fit) / eps
        ca = max(s["ms"][2] * s["cond"] ** 2 for s in fit) / eps
        add(f"Fitted worst constants: position error/size ≈ {cp:.1f}·ε/sin μ, velocity ≈ {cv:.1f}·ε/sin μ, "
            f"acceleration ≈ {ca:.1f}·ε/sin² μ (ε = 2⁻⁵²). So the targets hold where sin μ ≥ "
            f"{cp * eps / TARGET_POS:.0e} (position ≤ {TARGET_POS:g}), ≥ {cv * eps / TARGET_DER:.0e} "
            f"(velocity ≤ {TARGET_DER:g}) and ≥ {math.sqrt(ca * eps / TARGET_DER):.0e} (acceleration ≤ "
            f"{TARGET_DER:g}): \"away from toggles\" means |sin μ| ≳ "
            f"{math.sqrt(ca * eps / TARGET_DER):.0e} for accelerations; the core's toggle flag "
            f"(TOGGLE_COND = {TOGGLE_COND:g}) covers positions and velocities.\n")

    if py_rows is None:
        add(f"## pylinkage\n\npylinkage: {py_note}.\n")
    else:
        add("## pylinkage (four-bar, same run)\n")
        add(f"{py_note}. Timed like mechsketch (best of k), "
            "JIT compilation excluded; its result is already one (N, 5, 2) array of all joints. pylinkage advances its crank by atan2(last position) + Δθ at "
            "every step, so its crank angle drifts like a random walk; the crank-pin column is that "
            "drift alone (B's position error / size).\n")
        add("| N | order | pylinkage µs/sample | pos err/size | of which crank pin B | vel rel err | "
            "acc rel err | mechsketch µs/sample | pylinkage / mechsketch time |")
        add("|---|---|---|---|---|---|---|---|---|")
        for N, order, us, e, ms_us, cp in py_rows:
            add(f"| {N:,} | {order} | {fus(us)} | {fmt(e.pos)} | {fmt(cp)} | {fmt(e.vel)} | {fmt(e.acc)} | "
                f"{fus(ms_us)} | {us / ms_us:,.1f}× |")
        add("")

    add("## Model only what a scene needs (six-bar)\n")
    add(f"`plan.sweep(N, order, joints={subset})` runs {steps_sub} of the {steps_all} groups "
        "(the crank-pin-side loop: the RRR group through the crank pin B) and extracts those joints; "
        "\"all\" solves and extracts every joint.\n")
    add("| N | order | all joints µs/sample | crank-pin-side subset µs/sample | all / subset |")
    add("|---|---|---|---|---|")
    for N, order, ta, ts, ratio in sub_rows:
        add(f"| {N:,} | {order} | {fus(ta)} | {fus(ts)} | {ratio:.2f}× |")
    add("")

    if alloc:
        add("## Memory allocator (diagnostic)\n")
        add("Every sweep allocates its temporaries afresh. With glibc's defaults, freed memory above "
            "128 kB is given back to the kernel (heap trimming; larger arrays are mmap-ed one by one), "
            "so the next sweep page-faults it in again. glibc raises those thresholds by itself only "
            "after it has freed large mmap-ed arrays, so the tables above, timed in this long-running "
            "process, depend on what it did before (in a full run its N = 360,000 sweeps have raised "
            "them). Measured in fresh processes, with glibc's defaults "
            "and with `mallopt(M_MMAP_THRESHOLD, 64 MiB)` + `mallopt(M_TRIM_THRESHOLD, 512 MiB)` at "
            "start (order 2, sweep + extraction, best of k):\n")
        add("| mechanism | N | default µs/sample | page faults per call | tuned malloc µs/sample | "
            "page faults per call | default / tuned |")
        add("|---|---|---|---|---|---|---|")
        for (name, N, t0, f0), (_, _, t1, f1) in alloc:
            add(f"| {name} | {N:,} | {fus(t0)} | {f0:,.0f} | {fus(t1)} | {f1:,.0f} | {t0 / t1:.2f}× |")
        add("")

    # targets
    add("## Targets (issue 2 §7)\n")
    missed = []
    probe = {}
    for (name, N, t0, f0), (_, _, t1, f1) in alloc or []:
        probe[(name, N)] = (t0, f0, t1, f1)
    mark = lambda ok: "met" if ok else "MISSED"  # noqa: E731
    for mech, tgt in TARGET_US.items():
        r = next(r for r in rows if r.mech == mech and r.N == 3600 and r.order == 2)
        ok = r.ms_us <= tgt
        line = (f"- {mech}, order 2, N = 3,600 (target ≤ {tgt} µs/sample): {r.ms_us:.3f} in this benchmark "
                f"process — **{mark(ok)}**")
        if not ok:
            missed.append(f"{mech} speed")
        if (mech, 3600) in probe:
            t0, f0, t1, f1 = probe[(mech, 3600)]
            line += (f"; fresh process, glibc's default allocator: {t0:.3f} ({f0:,.0f} page faults per call) — "
                     f"**{mark(t0 <= tgt)}**; fresh process, allocator keeping its memory: {t1:.3f} — "
                     f"**{mark(t1 <= tgt)}**")
            if t0 > tgt:
                missed.append(f"{mech} speed in a fresh process with glibc's default allocator")
            if t1 > tgt and ok:
                missed.append(f"{mech} speed in a fresh process even with the allocator tuned")
        add(line)
    benign = main_rows
    pos = max(r.ms_err.pos for r in benign)
    der = max(max(r.ms_err.vel, r.ms_err.acc) for r in benign if r.order == 2)
    away_pos = max(r.ms_err.pos_away for r in near_rows)
    away_der = max(max(r.ms_err.vel_away, r.ms_err.acc_away) for r in near_rows if r.order == 2)
    ok_pos = max(pos, away_pos) <= TARGET_POS
    ok_der = max(der, away_der) <= TARGET_DER
    add(f"- position error ≤ {TARGET_POS:g} of the size (all rows; near-change-point away from the toggle): "
        f"worst {max(pos, away_pos):.1e} — **{'met' if ok_pos else 'MISSED'}**")
    add(f"- velocity/acceleration error ≤ {TARGET_DER:g} relative away from toggles: worst "
        f"{max(der, away_der):.1e} — **{'met' if ok_der else 'MISSED'}**")
    if not ok_pos:
        missed.append("position error")
    if not ok_der:
        missed.append("velocity/acceleration error")
    def verdict(r):
        near = r in near_rows
        pick = lambda e, w: getattr(e, w + ("_away" if near else ""))  # noqa: E731
        ws = ["pos"] + (["vel", "acc"] if r.order == 2 else [])
        worse = [w for w in ws if not equal_or_better(pick(r.ms_err, w), pick(r.nt.err, w))]
        return r.speedup >= TARGET_SPEEDUP and not worse, worse

    at_target = [r for r in rows if r.N == 3600 and r.order == 2]
    bad = []
    for r in at_target:
        ok, worse = verdict(r)
        if not ok:
            bad.append(f"{r.mech}: {r.speedup:,.0f}×" + (f", {'/'.join(worse)} error worse than Newton"
                                                           if worse else ""))
    sp = ", ".join(f"{r.mech} {r.speedup:,.0f}×" for r in at_target)
    add(f"- ≥ {TARGET_SPEEDUP:.0f}× faster than Newton at equal or better error (order 2, N = 3,600; "
        f"near-change-point errors compared away from the toggle): {sp} — "
        f"**{'met' if not bad else 'MISSED'}**" + ("" if not bad else ": " + "; ".join(bad)))
    if bad:
        missed.append("speed-up/error vs Newton")
    others = []
    for r in rows:
        if r in at_target:
            continue
        ok, worse = verdict(r)
        if not ok:
            others.append(f"{r.mech} N={r.N:,} order {r.order}: {r.speedup:,.0f}×"
                          + (f", {'/'.join(worse)} error worse" if worse else ""))
    add("  - other rows (information, not the target's condition): "
        + ("all ≥ 100× at equal or better error" if not others else "below 100× or worse error: "
           + "; ".join(others) + ". At N = 360 mechsketch's fixed per-call cost (Python dispatch of "
           "the kernels and of the per-joint extraction, ~50–150 µs a call) dominates"))
    branch = sum(r.ref.ms_branch_bad for r in rows)
    add(f"- mechsketch on the drawn assembly branch at every reference pose: "
        f"{'yes' if branch == 0 else f'NO ({branch} poses)'}")
    add("")
    add("Missed targets: " + (", ".join(missed) if missed else "none") + ".\n")
    add("Reference cost: " + ", ".join(f"{k} {v.solves} poses in {v.seconds:.1f} s" for k, v in refs_by.items())
        + ".\n")
    return "\n".join(L)


def plot(rows, py_rows, scan, out_dir: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    markers = {"four-bar": "o", "slider-crank (offset)": "s", "six-bar (moving guide)": "^",
               "near-change-point four-bar": "D"}
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharex=True)
    for ax, order in zip(axes, (0, 2)):
        for mech, mk in markers.items():
            sel = [r for r in rows if r.mech == mech and r.order == order]
            if not sel:
                continue
            e_ms = [r.ms_err.pos if order == 0 else max(r.ms_err.pos, r.ms_err.vel, r.ms_err.acc) for r in sel]
            e_nt = [r.nt.err.pos if order == 0 else max(r.nt.err.pos, r.nt.err.vel, r.nt.err.acc) for r in sel]
            ax.plot([r.ms_us for r in sel], e_ms, mk + "-", color="C0", label=f"mechsketch: {mech}")
            ax.plot([r.nt.us for r in sel], e_nt, mk + "--", color="C3", mfc="none",
                    label=f"Newton: {mech}")
            for r, e in zip(sel, e_ms):
                ax.annotate(f"{r.N:,}", (r.ms_us, e), fontsize=6, xytext=(3, 3), textcoords="offset points")
        if py_rows:
            sel = [p for p in py_rows if p[1] == order]
            e = [p[3].pos if order == 0 else max(p[3].pos, p[3].vel, p[3].acc) for p in sel]
            ax.plot([p[2] for p in sel], e, "x:", color="C2", label="pylinkage: four-bar")
        ax.axhline(1e-13 if order == 0 else 1e-12, color="grey", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("µs per sample (log)")
        ax.set_ylabel("max position error / size" if order == 0 else
                      "max of position/size, velocity and acceleration relative errors")
        ax.set_title("positions only" if order == 0 else "with velocities and accelerations")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=6, loc="best")
    fig.suptitle("Linkage solving: time per sample against error (50-digit reference); "
                 "labels: N; dotted: error targets")
    fig.tight_layout()
    fig.savefig(out_dir / "linkage_speed_error.png", dpi=130)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    d = [s["delta_rel"] for s in scan]
    for w, (lab, c) in enumerate((("position / size", "C0"), ("velocity rel.", "C1"), ("acceleration rel.", "C2"))):
        ax.plot(d, [s["ms"][w] for s in scan], "o-", color=c, label=f"mechsketch {lab}")
        ax.plot(d, [s["nt"][w] for s in scan], "s--", color=c, mfc="none", label=f"Newton {lab}")
    ax.plot(d, [s["cond"] for s in scan], "k:", label="sin μ at toggle")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("δ / size (gap to the change point)")
    ax.set_ylabel("error at the sample nearest the toggle")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Near-change-point four-bar, N = 3,600")
    fig.tight_layout()
    fig.savefig(out_dir / "linkage_near_toggle.png", dpi=130)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
