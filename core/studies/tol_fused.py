"""A tolerance Monte Carlo's builds as one generated, compiled loop per linkage topology.

The reference path of :mod:`.tolerance` solves a block of builds with the batch engine — every
traced point written as a (B, N, 2) array, the masks and per-design flags made — and reduces the
arrays afterwards (:func:`.tol_kernels.reduce_point`). Here :mod:`.fused`'s generator writes the
plan's closed forms for positions only (order 0: no rates, no transmission angles, no flags), and
each build's traced points and link angles go to an (N, 2) scratch that stays in the CPU's cache
and is reduced at once by the per-build reducers of :mod:`.tol_kernels`
(:func:`~.tol_kernels.build_point`, :func:`~.tol_kernels.build_angle`): the same operations as
the reference, in the same order, so the same deviations, histograms and extremes.

Builds whose groups come within :data:`~mechsketch.core.solver.branches.CANDIDATE` of a toggle over
the cycle (a branch point is possible: the reference re-solves them on its numpy path, which
follows the branch) are not reduced here but flagged in ``redo``; :mod:`.tolerance` solves them
by the reference path. Builds that do not assemble at their drawn input fail at every sample the
nominal assembles (counted, never dropped). The kernel holds no Python object and releases the GIL:
threads over blocks (:mod:`.execute`) use every core.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from ..solver.branches import CANDIDATE
from ..solver.structure import MODAL_KINDS
from . import tol_kernels
from .engine import BatchPlan, Constants
from .fused import HEADER, _Gen, _module, columns


def _imports() -> str:
    """The generated module's import of the reducers, with a digest of their source: numba's cache
    of the kernel does not follow the functions it calls, so a change of theirs must change the
    kernel's source (and so its cache key)."""
    digest = hashlib.sha256(Path(tol_kernels.__file__).read_bytes()).hexdigest()[:16]
    return f"from mechsketch.core.studies.tol_kernels import build_angle, build_point  # tol_kernels {digest}\n\n"


class _TolGen(_Gen):
    """The source of one tolerance kernel (see the module docstring)."""

    def source(self) -> str:
        steps = self.groups()
        e = self.emit
        modal = [k for k, s in enumerate(steps) if s.group.kind in MODAL_KINDS]
        for k in modal:     # stored, and reduced after the samples' loop: a reduction in the loop
            e(f"gaps{k}[k] = g{k}gap if (g{k}ok | g{k}sing) else np.inf")   # keeps it from vectorising
        for i, (j, _w) in enumerate(self.joints):
            x, y = self.point(self.bp.plan.reporter[j], j)
            e(f"pj{i}[0, k, 0] = {x}; pj{i}[0, k, 1] = {y}")
        for i, (link, _w) in enumerate(self.links):
            c, s = self.st[link]["cs"]
            e(f"pl{i}[k] = math.atan2({s}, {c})")
        e("okk[k] = ok")
        scales = {k: self.c("step", steps[k].group.name, "scale") for k in modal}
        J, L = len(self.joints), len(self.links)
        jargs = "".join(f", nom{i}, nrm{i}, S{i}, T{i}, Q{i}, smax{i}, g{i}, lo{i}, wd{i}, hu{i}, hl{i}, ext{i}, mom{i}, "
                        f"fl{i}, dev{i}" for i in range(J))
        largs = "".join(f", lnom{i}, lt{i}, ldev{i}" for i in range(L))
        lines = [HEADER + _imports(), "@numba.njit(cache=True, nogil=True, error_model=\"numpy\")",
                 f"def kernel(C, A0, cq, sq, assembled, nvalid, r, redo{jargs}{largs}):",
                 "    D = C.shape[0]", "    N = cq.shape[0]", "    okk = np.zeros(N, dtype=np.bool_)",
                 "    na_ = np.empty(N)", "    mk = np.empty(N)", "    sg = np.empty((2, N))"]
        lines += [f"    pj{i} = np.zeros((1, N, 2))" for i in range(J)]
        lines += [f"    pl{i} = np.zeros(N)" for i in range(L)]
        lines += [f"    gaps{k} = np.empty(N)" for k in modal]
        lines += ["    for d in range(D):", "        redo[d] = False", "        if assembled[d]:"]
        ind = "            "
        lines += [f"{ind}K{i} = C[d, {i}]" for i in range(len(self.cols))]
        lines += [ind + ln for ln in self.pre]
        lines.append(f"{ind}for k in range(N):")
        lines += [ind + "    " + ln for ln in self.body]
        for k in modal:
            lines += [f"{ind}gmin{k} = np.inf", f"{ind}for k in range(N):", f"{ind}    gmin{k} = min(gmin{k}, gaps{k}[k])"]
        near = " or ".join(f"not (gmin{k} / {scales[k]} >= {CANDIDATE!r})" for k in modal) or "False"
        lines += [f"{ind}if {near}:", f"{ind}    redo[d] = True", f"{ind}    continue",
                  "        else:", "            okk[:] = False"]
        lines += [f"        build_point(d, pj{i}, okk, nom{i}, nrm{i}, nvalid, S{i}, T{i}, Q{i}, smax{i}, g{i}, r, lo{i}, "
                  f"wd{i}, hu{i}, hl{i}, ext{i}, mom{i}, fl{i}, dev{i}, na_, mk, sg)" for i in range(J)]
        lines += [f"        build_angle(d, pl{i}, A0[d, {i}], okk, lnom{i}, nvalid, lt{i}, r, ldev{i})" for i in range(L)]
        return "\n".join(lines) + "\n"


class TolFused:
    """The compiled tolerance kernel of one plan, traced joints and followed links."""

    def __init__(self, bp: BatchPlan, joints: tuple, links: tuple) -> None:
        steady = np.ndim(bp.plan.omega) == 0 and bp.linkage.driver.law.is_constant
        gen = _TolGen(bp, 0, tuple((j, 0) for j in joints), tuple((k, 0) for k in links), steady)
        self.source = gen.source()
        self.cols = list(gen.cols)
        self.bp, self.joints, self.links = bp, tuple(joints), tuple(links)
        self.kernel = _module(self.source)

    def columns(self, K: Constants) -> np.ndarray:
        """(D, columns) the per-design constants, as :meth:`.fused.Fused.columns`."""
        return columns(self.cols, K)

    def angle0(self, K: Constants) -> np.ndarray:
        """(D, links) each followed link's drawn angle, rad."""
        out = np.zeros((K.n, len(self.links)))
        for i, k in enumerate(self.links):
            out[:, i] = np.broadcast_to(K.angle0[k], (K.n, 1))[:, 0]
        return out


__all__ = ["TolFused"]
