"""Many variants of one linkage solved at once: :func:`solve_variants` and its :class:`Variants`.

``solve_variants(linkage, {"length:crank:A:B": array_D, ...}, samples=N, order=2)`` solves D
designs (the linkage with those values changed, see :mod:`.keys`) over one cycle of N samples,
chunk by chunk (:mod:`.budget`), and keeps per design and sample what the one-design
:class:`~mechsketch.core.solver.plan.Solution` gives: joint positions (D, N, 2) mm, velocities
mm/s and accelerations mm/s², link angles (D, N) rad, ω, α, ``valid`` and ``rates_valid``
(D, N); and per design: ``assembled`` (the design re-assembles at its drawn input; if not, why:
:meth:`Variants.failures`), ``full_cycle``, ``dead_point`` and ``min_transmission_angle`` (°).
"""
from __future__ import annotations

import concurrent.futures as cf
import math
import time
from typing import Callable, Iterable

import numpy as np

from ..errors import RequestError, UnknownIdError
from ..model.linkage import Linkage
from ..solver.plan import unwrap_finite
from ..solver.structure import MODAL_KINDS, GroupKind
from ..solver.tolerances import RATE_EPS, RATE_REL, TOGGLE_COND
from . import vec as V
from .bforces import BatchForces, chunk_forces
from .budget import check_kept, chunk_designs
from ..solver.branches import CANDIDATE
from .engine import BatchPlan, Constants, Inputs, Run
from .fused import Fused, fusable, transmission_extremes
from .geometry import Geometry, build_geometry
from .keys import design_values

EPS = float(np.finfo(float).eps)


def solve_chunk(bp: BatchPlan, values: dict, n: int, inp: Inputs, order: int
                ) -> tuple[Geometry, Constants, Run]:
    """Geometry, constants and kinematics of ``n`` designs (``values`` key -> (n,)) at the
    inputs ``inp``, each group kept on its smooth branch (:mod:`.engine`)."""
    geo = build_geometry(bp.linkage, bp.plan, values, n)
    K = bp.constants(geo)
    q = inp.row(inp.q)
    run = bp.run(K, q, inp.row(inp.qd), inp.row(inp.qdd), order)
    x, ring, x0 = bp.screen_inputs(inp)
    suspect = bp.screen(K, run if x is inp.q else None, x, ring, x0)
    suspect &= geo.ok
    if suspect.any():
        flips = bp.reference_flips(geo, np.flatnonzero(suspect), inp.q)
        if flips:
            run = bp.run(K, q, inp.row(inp.qd), inp.row(inp.qdd), order, flips=flips)
    return geo, K, run


def rates_valid(bp: BatchPlan, K: Constants, run: Run, valid: np.ndarray, order: int) -> np.ndarray:
    """(D, N) bool as :attr:`Solution.rates_valid`: valid, every group's velocity system
    conditioned (estimated relative error of the rates below RATE_REL), every rate finite."""
    if order < 1:
        return np.zeros(valid.shape, dtype=bool)
    ok = valid.copy()
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for step in bp.plan.steps:
            g = step.group
            if g.fixed:
                continue
            c = K.steps[g.name]
            cond = np.broadcast_to(run.outs[g.name].cond, ok.shape)
            if g.kind in MODAL_KINDS:
                cond = cond * cond
            ok &= RATE_EPS * EPS * (1.0 + c["coord"] / c["scale"]) <= RATE_REL * cond
        for st in run.states.values():
            rates = [st.v[0], st.v[1], st.w] + ([st.acc[0], st.acc[1], st.al] if order >= 2 else [])
            for r in rates:
                ok &= np.broadcast_to(np.isfinite(np.real(r)), ok.shape)
    return ok


def _unwrap_rows(a: np.ndarray) -> np.ndarray:
    """np.unwrap along the samples of each row, restarting after NaN gaps (as ``unwrap_finite``)."""
    fin = np.isfinite(a)
    whole = fin.all(axis=1)
    out = np.empty_like(a)
    if whole.any():
        out[whole] = np.unwrap(a[whole], axis=1)
    for d in np.flatnonzero(~whole):
        out[d] = unwrap_finite(a[d])
    return out


class _Extract:
    """What one chunk contributes to a :class:`Variants` (views of the chunk's run)."""

    def __init__(self, bp: BatchPlan, geo: Geometry, K: Constants, run: Run, inp: Inputs, order: int) -> None:
        self.bp, self.geo, self.K, self.run, self.inp, self.order = bp, geo, K, run, inp, order
        self.shape = (geo.n, np.size(inp.q))
        self.valid = run.valid & geo.ok[:, None]

    def _pair(self, p) -> np.ndarray:
        out = np.empty(self.shape + (2,))
        out[..., 0] = np.real(p[0])
        out[..., 1] = np.real(p[1])
        out[~self.valid] = np.nan
        return out

    def joint(self, j: str, what: int) -> np.ndarray:
        link = self.bp.plan.reporter[j]
        st = self.run.states.get(link)
        if st is None:
            raise UnknownIdError(f"joint {j!r} was not solved")
        p0 = self.K.at[j]
        p = st.point(j, p0) if what == 0 else st.vel(j, p0) if what == 1 else st.accel(j, p0)
        return self._pair(p)

    def angle(self, link: str) -> np.ndarray:
        lk = self.bp.linkage
        if link == lk.ground:
            rho = np.zeros(self.shape)
        elif link == lk.driver.link and not lk.driver.linear:
            rho = np.broadcast_to(self.inp.row(self.inp.q) - self.bp.plan.theta0, self.shape)
        else:
            c, s = self.run.states[link].cs
            rho = _unwrap_rows(np.arctan2(np.broadcast_to(np.real(s), self.shape),
                                          np.broadcast_to(np.real(c), self.shape)))
        a = rho + self.K.angle0.get(link, 0.0)
        return np.where(self.valid, a, np.nan)

    def rate(self, link: str, what: int) -> np.ndarray:
        st = self.run.states[link]
        v = st.w if what == 1 else st.al
        a = np.broadcast_to(np.real(np.asarray(v, dtype=complex if np.iscomplexobj(v) else float)), self.shape)
        return np.where(self.valid, a, np.nan)

    def singular(self) -> np.ndarray:
        out = np.zeros(self.shape, dtype=bool)
        for o in self.run.outs.values():
            if o.singular is not None:
                out |= np.broadcast_to(o.singular, self.shape)
        return out & self.geo.ok[:, None]

    def per_design(self) -> dict[str, np.ndarray]:
        """full_cycle, dead_point, min_transmission_angle (°) and rates_valid of the chunk."""
        sing = self.singular()
        full = (self.valid | sing).all(axis=1) & self.geo.ok
        low = np.zeros(self.geo.n, dtype=bool)
        mu_min = np.full(self.geo.n, np.inf)
        for step in self.bp.plan.steps:
            g = step.group
            out = self.run.outs[g.name]
            if not g.fixed:
                cond = np.where(self.valid, np.broadcast_to(np.real(out.cond), self.shape), np.inf)
                low |= cond.min(axis=1) < TOGGLE_COND
            if g.kind is GroupKind.RRR:
                rix, riy = out.si.arm(g.inner, self.K.at[g.inner])
                lx, ly = out.si.point(g.inner, self.K.at[g.inner])
                rjx, rjy = lx - out.sj.A[0], ly - out.sj.A[1]
                # the least μ (folded) is where the outer joints are nearest or farthest
                dx, dy = out.sj.A[0] - out.si.A[0], out.sj.A[1] - out.si.A[1]
                d2 = np.broadcast_to(np.real(dx * dx + dy * dy), self.shape)
                c = self.K.steps[g.name]
                mu = transmission_extremes(c["li"][:, 0], c["lj"][:, 0], np.where(self.valid, d2, np.inf).min(axis=1),
                                           np.where(self.valid, d2, -np.inf).max(axis=1))
                mu_min = np.minimum(mu_min, mu)
        has_rrr = any(s.group.kind is GroupKind.RRR for s in self.bp.plan.steps)
        mu_deg = (np.where(np.isfinite(mu_min) & self.geo.ok, np.degrees(mu_min), np.nan) if has_rrr else
                  np.full(self.geo.n, np.nan))
        return {"full_cycle": full, "dead_point": self.geo.ok & (~full | low | sing.any(axis=1)),
                "min_transmission_angle": mu_deg}


#: below this many design-samples the numpy path answers before a kernel could compile
FUSED_MIN = 2_000_000
#: designs per block of the fused path (its geometry is made a block at a time; the loop keeps
#: no temporaries, so a block's size costs only the block's results)
FUSED_BLOCK = 8192


def _fused(bp: BatchPlan, order: int, joints: list, links: list):
    """The fused kernel for this request, or None where the plan has no fused form."""
    if not fusable(bp):
        return None
    steady = np.ndim(bp.plan.omega) == 0 and bp.linkage.driver.law.is_constant
    return Fused(bp, order, tuple(joints), tuple(links), steady)


class _Sink:
    """Where the chunks' results go: the kept arrays of a :class:`Variants`."""

    def __init__(self, D: int, N: int, joints: list, links: list, summary: bool) -> None:
        self.D, self.N, self.summary = D, N, summary
        self.out_j = {key: np.empty((D, N, 2)) for key in joints}
        self.out_l = {key: np.empty((D, N)) for key in links}
        #: per design-sample: 1 valid, 2 rates valid, 4 singular (0 for designs not assembled)
        self.status = np.zeros((D, N), dtype=np.uint8) if summary else None
        self.flags = ({"assembled": np.zeros(D, dtype=bool), "full_cycle": np.zeros(D, dtype=bool),
                       "dead_point": np.zeros(D, dtype=bool), "min_transmission_angle": np.full(D, np.nan)}
                      if summary else {})
        self.reasons: list[str] = []
        self.reason = np.zeros(D, dtype=np.int32)
        self.amount = np.full(D, np.nan)

    def _geometry(self, idx: np.ndarray, geo: Geometry) -> None:
        if not self.summary:
            return
        self.flags["assembled"][idx] = geo.ok
        for r in np.unique(geo.reason[~geo.ok]):
            text = geo.reasons[int(r)]
            if text not in self.reasons:
                self.reasons.append(text)
            sel = ~geo.ok & (geo.reason == r)
            self.reason[idx[sel]] = self.reasons.index(text) + 1
            self.amount[idx[sel]] = geo.amount[sel]

    def numpy(self, idx: np.ndarray, ex: "_Extract", geo: Geometry) -> None:
        for (j, what), arr in self.out_j.items():
            arr[idx] = ex.joint(j, what)
        for (k, what), arr in self.out_l.items():
            arr[idx] = ex.angle(k) if what == 0 else ex.rate(k, what)
        if self.summary:
            rv = rates_valid(ex.bp, ex.K, ex.run, ex.valid, ex.order)
            self.status[idx] = ex.valid.view(np.uint8) | (rv.view(np.uint8) << 1) | (ex.singular().view(np.uint8) << 2)
            for key, v in ex.per_design().items():
                self.flags[key][idx] = v
        self._geometry(idx, geo)

    def fused(self, d0: int, d1: int, fz: Fused, bp: BatchPlan, chunk: dict, inp: Inputs) -> tuple:
        """Designs d0..d1 by the fused kernel (thread-safe: it writes only their rows); returns
        their indices and geometry (for :meth:`_geometry`, called in the chunks' order) and the
        designs to solve again on the numpy path (those near a toggle, where the branch screening
        decides)."""
        n = d1 - d0
        geo = build_geometry(bp.linkage, bp.plan, chunk, n)
        K = bp.constants(geo)
        q = np.asarray(inp.q, dtype=float)
        th = q - bp.plan.theta0
        full = lambda v: np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=float), q.shape))  # noqa: E731
        oj = [self.out_j[key][d0:d1] for key in fz.joints]
        ol = [np.empty((n, q.size, 2)) if w == 0 else self.out_l[(k, w)][d0:d1] for k, w in fz.links]
        status, red = fz(K, np.cos(th), np.sin(th), full(inp.qd), full(inp.qdd), oj, ol,
                         self.status[d0:d1] if self.summary else None)
        if not geo.ok.all():   # designs that do not assemble: nothing is valid
            status[~geo.ok] = 0
            for arr in oj + [a for a, (k, w) in zip(ol, fz.links) if w]:
                arr[~geo.ok] = np.nan
        valid = None if not ol else (status & 1).astype(bool)
        for (k, w), arr in zip(fz.links, ol):
            if w == 0:
                rho = _unwrap_rows(np.arctan2(arr[..., 1], arr[..., 0]))
                if k == bp.linkage.driver.link:
                    rho = np.broadcast_to(th, rho.shape)
                self.out_l[(k, 0)][d0:d1] = np.where(valid, rho + K.angle0[k], np.nan)
        idx = np.arange(d0, d1)
        steps = bp.plan.steps
        if self.summary:
            full_c = (red[:, 0] > 0) & geo.ok
            low = np.zeros(n, dtype=bool)
            mu = np.full(n, np.inf)
            for k, s in enumerate(steps):
                low |= red[:, 3 + 4 * k] < TOGGLE_COND
                if s.group.kind is GroupKind.RRR:
                    c = K.steps[s.group.name]
                    mu = np.minimum(mu, transmission_extremes(c["li"][:, 0], c["lj"][:, 0], red[:, 4 + 4 * k],
                                                              red[:, 5 + 4 * k]))
            self.flags["full_cycle"][d0:d1] = full_c
            self.flags["dead_point"][d0:d1] = geo.ok & (~full_c | low | (red[:, 1] > 0))
            self.flags["min_transmission_angle"][d0:d1] = np.where(np.isfinite(mu) & geo.ok, np.degrees(mu), np.nan)
        near = np.zeros(n, dtype=bool)
        for k, s in enumerate(steps):
            if s.group.kind in MODAL_KINDS:
                near |= ~(red[:, 2 + 4 * k] >= CANDIDATE)
        return idx, geo, idx[near & geo.ok]


class Variants:
    """D designs of one linkage solved over one cycle (see the module docstring). Arrays are
    (D, N) or (D, N, 2), NaN where a design is not assembled at a sample; per design (D,)."""

    def __init__(self, bp: BatchPlan, values: dict, n: int, inp: Inputs, order: int) -> None:
        self.plan, self.values, self.n, self.order = bp, values, n, order
        self._inp = inp
        self._joints: dict[tuple[str, int], np.ndarray] = {}
        self._links: dict[tuple[str, int], np.ndarray] = {}
        self.seconds = 0.0
        #: the fused compiled loop where the plan has one: True always, False never (the numpy
        #: reference), None from FUSED_MIN design-samples on (below, numpy answers before a
        #: kernel could compile)
        self.fast: bool | None = None
        #: threads over the fused path's chunks (its kernel releases the GIL); the same numbers
        #: whatever their number
        self.workers = 1

    # -- the cycle -------------------------------------------------------------------------
    @property
    def input(self) -> np.ndarray:
        """(N,) the driver's input at each sample (rad or mm), as ``Solution.input``."""
        return self._inp.q

    @property
    def t(self) -> np.ndarray:
        """(N,) time of each sample, s."""
        return self._inp.t

    def __len__(self) -> int:
        return self.n

    # -- per design and sample -------------------------------------------------------------
    def position(self, joint: str) -> np.ndarray:
        """(D, N, 2) position of ``joint``, mm."""
        return self._get_joint(joint, 0)

    def velocity(self, joint: str) -> np.ndarray:
        """(D, N, 2) velocity of ``joint``, mm/s."""
        self._need(1, "velocity")
        return self._get_joint(joint, 1)

    def acceleration(self, joint: str) -> np.ndarray:
        """(D, N, 2) acceleration of ``joint``, mm/s²."""
        self._need(2, "acceleration")
        return self._get_joint(joint, 2)

    def angle(self, link: str) -> np.ndarray:
        """(D, N) angle of the link's first-to-second joint vector, rad, unwrapped (as
        ``Solution.angle``)."""
        return self._get_link(link, 0)

    def omega(self, link: str) -> np.ndarray:
        """(D, N) angular velocity, rad/s."""
        self._need(1, "omega")
        return self._get_link(link, 1)

    def alpha(self, link: str) -> np.ndarray:
        """(D, N) angular acceleration, rad/s²."""
        self._need(2, "alpha")
        return self._get_link(link, 2)

    def _need(self, order: int, what: str) -> None:
        if self.order < order:
            raise RequestError(f"{what} needs solve_variants(..., order={order}) or more (this one has order "
                               f"{self.order})")

    def _get_joint(self, joint: str, what: int) -> np.ndarray:
        if joint not in self.plan.linkage.joint_ids:
            raise UnknownIdError(f"linkage {self.plan.linkage.id!r} has no joint {joint!r}")
        if (joint, what) not in self._joints:
            self._compute([(joint, what)], [])
        return self._joints[(joint, what)]

    def _get_link(self, link: str, what: int) -> np.ndarray:
        if link not in self.plan.linkage.link_ids:
            raise UnknownIdError(f"linkage {self.plan.linkage.id!r} has no link {link!r}")
        if (link, what) not in self._links:
            self._compute([], [(link, what)])
        return self._links[(link, what)]

    def _compute(self, joints: list, links: list, summary: bool = False,
                 progress: Callable[[float], object] | None = None) -> None:
        """Solve every chunk and keep ``joints`` [(id, 0|1|2)], ``links`` [(id, 0|1|2)] and, with
        ``summary``, the per-design flags and the (D, N) masks."""
        start = time.perf_counter()
        D, N = self.n, np.size(self._inp.q)
        kept = 8.0 * N * (2 * len(joints) + len(links)) + (3.0 * N + 32 if summary else 0.0)
        check_kept(kept * D, f"solving {D:,} designs × {N:,} samples",
                   "ask for fewer joints (joints=[...]), fewer samples or designs, or run a study (mechsketch study), "
                   "which keeps only each design's metrics")
        sink = _Sink(D, N, joints, links, summary)
        lk = self.plan.linkage
        auto = self.fast is None and D * N >= FUSED_MIN
        fz = _fused(self.plan, self.order, joints, links) if (self.fast or auto) else None
        step = chunk_designs(N, len(lk.joints) + len(lk.links), D, kept)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            self._chunks(sink, fz, step, progress)
        self._joints.update(sink.out_j)
        self._links.update(sink.out_l)
        if summary:
            self._status, self._flags, self._masks = sink.status, sink.flags, {}
            self._reasons, self._reason, self._amount = ["assembled"] + sink.reasons, sink.reason, sink.amount
        self.seconds += time.perf_counter() - start

    def _chunks(self, sink: "_Sink", fz, step: int, progress) -> None:
        D = self.n
        if fz is not None:
            step = max(step, min(D, FUSED_BLOCK))
        starts = range(0, D, step)
        if fz is None:
            for d0 in starts:
                d1 = min(D, d0 + step)
                chunk = {k: v[d0:d1] for k, v in self.values.items()}
                geo, K, run = solve_chunk(self.plan, chunk, d1 - d0, self._inp, self.order)
                sink.numpy(np.arange(d0, d1), _Extract(self.plan, geo, K, run, self._inp, self.order), geo)
                if progress is not None:
                    progress(d1 / D)
            return

        def one(d0: int) -> tuple:
            d1 = min(D, d0 + step)
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):   # per thread
                return sink.fused(d0, d1, fz, self.plan, {k: v[d0:d1] for k, v in self.values.items()}, self._inp)

        if self.workers > 1 and len(starts) > 1:     # the kernel releases the GIL: chunks on threads
            with cf.ThreadPoolExecutor(max_workers=self.workers) as pool:
                self._finish(sink, zip(starts, pool.map(one, starts)), step, progress)
        else:
            self._finish(sink, ((d0, one(d0)) for d0 in starts), step, progress)

    def _finish(self, sink: "_Sink", done, step: int, progress) -> None:
        """The fused chunks' failures recorded and their designs near a toggle solved again on the
        numpy path, in the chunks' order (the same reasons' numbering whatever the threads)."""
        D, N = self.n, np.size(self._inp.q)
        lk = self.plan.linkage
        per = len(lk.joints) + len(lk.links)
        for d0, (idx, geo, redo) in done:
            sink._geometry(idx, geo)
            for lo in range(0, redo.size, max(1, chunk_designs(N, per, redo.size))):
                sub_idx = redo[lo:lo + chunk_designs(N, per, redo.size)]
                sub = {k: v[sub_idx] for k, v in self.values.items()}
                geo2, K, run = solve_chunk(self.plan, sub, sub_idx.size, self._inp, self.order)
                sink.numpy(sub_idx, _Extract(self.plan, geo2, K, run, self._inp, self.order), geo2)
            if progress is not None:
                progress(min(D, d0 + step) / D)

    # -- masks and per-design results --------------------------------------------------------
    def _mask(self, name: str, bit: int) -> np.ndarray:
        m = self._masks.get(name)
        if m is None:
            m = self._masks[name] = (self._status & bit).astype(bool)
        return m

    @property
    def valid(self) -> np.ndarray:
        """(D, N) bool: the design is assembled at the sample (as ``Solution.valid``)."""
        return self._mask("valid", 1)

    @property
    def rates_valid(self) -> np.ndarray:
        """(D, N) bool: velocities and accelerations given (as ``Solution.rates_valid``)."""
        return self._mask("rates_valid", 2)

    @property
    def singular(self) -> np.ndarray:
        """(D, N) bool: a group assembles but its pose is undetermined there."""
        return self._mask("singular", 4)

    @property
    def assembled(self) -> np.ndarray:
        """(D,) bool: the design re-assembles at its drawn input (else :meth:`message` says why)."""
        return self._flags["assembled"]

    @property
    def full_cycle(self) -> np.ndarray:
        """(D,) bool: assembled at every sample of the cycle (a crank turns fully; an actuator
        runs its whole stroke)."""
        return self._flags["full_cycle"]

    @property
    def dead_point(self) -> np.ndarray:
        """(D,) bool: an assembled design with a dead point in its cycle (an assembly limit, a
        toggle with conditioning below 1e-3 at some sample, a singular sample)."""
        return self._flags["dead_point"]

    @property
    def min_transmission_angle(self) -> np.ndarray:
        """(D,) degrees: the smallest transmission angle of the RRR groups over the assembled
        samples, folded to [0°, 90°] (min(μ, 180° − μ)); NaN without an RRR group or assembled sample."""
        return self._flags["min_transmission_angle"]

    def message(self, d: int) -> str:
        """Why design ``d`` does not assemble at its drawn input ("" if it does)."""
        r = int(self._reason[d])
        if r == 0:
            return ""
        a = self._amount[d]
        return self._reasons[r] + (f" (by {a:.6g})" if math.isfinite(a) else "")

    def forces(self) -> BatchForces:
        """The kinetostatics of every design over the cycle (driving effort, pin forces, shaking;
        :class:`~.bforces.BatchForces`), solved again chunk by chunk at order 2 on the numpy path."""
        lk = self.plan.linkage
        D, N = self.n, np.size(self._inp.q)
        pins = [(j.id, b) for j in lk.joints if j.kind.value == "R" for b in lk.links_of(j.id)[1:]]
        check_kept(D * N * 8.0 * (4 + 2 * len(pins)), f"the forces of {D:,} designs × {N:,} samples",
                   "ask for fewer designs or samples, or run a study, which keeps only each design's metrics")
        eff, sm = np.full((D, N), np.nan), np.full((D, N), np.nan)
        sf = np.full((D, N, 2), np.nan)
        pin = {j: {} for j, _ in pins}
        for j, b in pins:
            pin[j][b] = np.full((D, N, 2), np.nan)
        valid = np.zeros((D, N), dtype=bool)
        step = chunk_designs(N, len(lk.joints) + len(lk.links), D)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            for d0 in range(0, D, step):
                d1 = min(D, d0 + step)
                chunk = {k: v[d0:d1] for k, v in self.values.items()}
                geo, K, run = solve_chunk(self.plan, chunk, d1 - d0, self._inp, 2)
                ok = run.valid & geo.ok[:, None]
                r = chunk_forces(self.plan, K, run, chunk, ok)
                eff[d0:d1], sm[d0:d1], valid[d0:d1] = r["effort"], r["shaking_moment"], r["valid"]
                sf[d0:d1, :, 0], sf[d0:d1, :, 1] = r["shaking_force"].real, r["shaking_force"].imag
                for j, by in r["pins"].items():
                    for b, f in by.items():
                        pin[j][b][d0:d1, :, 0], pin[j][b][d0:d1, :, 1] = f.real, f.imag
        return BatchForces("torque" if self.plan.kind == "crank" else "force", eff, pin, sf, sm, valid)

    def failures(self) -> dict[str, int]:
        """How many designs do not assemble, per reason."""
        codes, counts = np.unique(self._reason[self._reason > 0], return_counts=True)
        return {self._reasons[int(c)]: int(k) for c, k in zip(codes, counts)}


def solve_variants(linkage: Linkage, values: dict, samples: int | None = None, order: int = 2,
                   joints: Iterable[str] | None = None, links: Iterable[str] | None = None,
                   progress: Callable[[float], object] | None = None, fast: bool | None = None,
                   workers: int = 1) -> Variants:
    """Solve the designs of ``linkage`` given by ``values`` (key -> scalar or array (D,); see
    :mod:`.keys`) over one cycle of ``samples`` samples (default the linkage's) to derivative
    ``order`` 0-2. ``joints``/``links``: what to keep (default every joint and moving link; the
    others are solved again when first read). RequestError for unknown keys, values that are not
    finite numbers, or results over the memory budget. ``fast``: True the fused compiled loop
    (where the plan has one), False the numpy reference path (the same bits; tests compare
    them), None the loop from :data:`FUSED_MIN` design-samples on. ``workers``: threads over the
    fused loop's chunks of :data:`FUSED_BLOCK` designs (the same numbers whatever their number)."""
    if order not in (0, 1, 2):
        raise RequestError(f"order must be 0, 1 or 2, got {order}")
    vals, n = design_values(linkage, values)
    bp = BatchPlan(linkage)
    inp = bp.inputs(samples or linkage.samples)
    b = Variants(bp, vals, n, inp, order)
    b.fast = fast
    b.workers = max(1, int(workers))
    js = list(linkage.joint_ids if joints is None else joints)
    ls = list(linkage.moving_links if links is None else links)
    for j in js:
        if j not in linkage.joint_ids:
            raise UnknownIdError(f"linkage {linkage.id!r} has no joint {j!r}")
    for k in ls:
        if k not in linkage.link_ids:
            raise UnknownIdError(f"linkage {linkage.id!r} has no link {k!r}")
    b._compute([(j, w) for j in js for w in range(order + 1)], [(k, w) for k in ls for w in range(order + 1)],
               summary=True, progress=progress)
    return b


__all__ = ["Variants", "rates_valid", "solve_chunk", "solve_variants"]
