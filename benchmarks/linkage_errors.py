"""Reference and errors for the linkage benchmark: the 50-digit reference poses of one mechanism
(:mod:`reference_mp`, cached, its assembly branch checked), and the error measures of an answer
against them.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import mpmath
import numpy as np

from mechsketch.core.model.linkage import Linkage

from linkage_cases import size_of
from reference_mp import MPReference

#: "away from toggles": every group's conditioning |sin| at least this
AWAY_COND = 1e-2


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
