"""The measured sections of the linkage benchmark: one mechanism against Newton at every N and
order, the subset solve, pylinkage, and the error scan against the toggle gap.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver.plan import compile_plan

from linkage_cases import near_change_point, pylinkage_fourbar
from linkage_errors import AWAY_COND, Err, References, RefSet, errors, gather
from linkage_report import fmt
from linkage_timing import Interleaved, NewtonResult, ms_solve, run_newton, timed
from newton_baseline import NewtonBaseline


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
