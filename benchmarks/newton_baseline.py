"""Generic baseline: Newton's method on the linkage's loop equations, pose by pose (float64, scipy).

The equations are those of :mod:`reference_mp` (reference-point coordinates, one (x, y, ρ) per
moving link, the driver prescribed), evaluated in float with an analytic Jacobian. This is the
usual generic approach of a multibody or sketch solver that knows nothing of Assur groups:

* positions: at each driver sample, Newton iterations q ← q − J⁻¹Φ from the previous sample's
  answer (warm start; the first sample starts from the drawn pose), LU by scipy's LAPACK wrappers (``scipy.linalg.lapack.dgesv``, the
  cheapest scipy entry point for a small dense system), until
  the step is below ``tol`` (relative to the mechanism size; angles are scaled by the size);
* velocities and accelerations (order 2): the differentiated constraints J q̇ = −Φ̇(q̇ = 0) and
  J q̈ = −Φ̈(q̈ = 0) with their quadratic velocity terms, solved with one LU of J at the converged
  pose (analytic, not finite differences);
* extraction: all joints' points from the link poses, vectorised over the samples.

``method="root"`` uses ``scipy.optimize.root`` (MINPACK hybrd with the analytic Jacobian) per pose
instead of the hand Newton loop; it is slower and is only reported as a side note.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize as sopt
from scipy.linalg import lapack

from mechsketch.core.model.linkage import Linkage

try:
    from .reference_mp import LoopSystem
except ImportError:  # run as a script from benchmarks/
    from reference_mp import LoopSystem


@dataclass
class NewtonRun:
    """Link poses at the samples: columns of q (n, N) and, for order 2, q̇, q̈."""

    inputs: np.ndarray
    q: np.ndarray
    qd: np.ndarray | None
    qdd: np.ndarray | None
    iterations: int
    failed: int


class NewtonBaseline:
    def __init__(self, linkage: Linkage, tol: float = 1e-10, max_iter: int = 30,
                 method: str = "newton"):
        self.system = LoopSystem(linkage)
        s = self.system
        pts = [j.at for j in linkage.joints]
        self.size = max(math.dist(a, b) for a in pts for b in pts)
        self.tol = tol
        self.max_iter = max_iter
        self.method = method
        self.theta0 = s.drawn_theta()
        self.scale = np.array([1.0, 1.0, self.size] * (s.n // 3))

    def _eval(self, theta, q, **kw):
        return self.system.evaluate(float, math.cos, math.sin, math.pi, self.theta0, theta, q, **kw)

    def _newton(self, theta: float, q: list[float]) -> tuple[list[float], int, bool]:
        lim = self.tol * self.size
        scale = self.scale
        dgesv = lapack.dgesv
        for it in range(1, self.max_iter + 1):
            phi, J, _, _ = self._eval(theta, q)
            _, _, dq, info = dgesv(np.array(J), np.array(phi))
            if info:
                break
            q = [a - b for a, b in zip(q, dq.tolist())]
            step = float(np.max(np.abs(dq) * scale))
            if step <= lim:
                return q, it, True
            if not math.isfinite(step):
                break
        return q, self.max_iter, False

    def _root(self, theta: float, q: list[float]) -> tuple[list[float], int, bool]:
        def fun(x):
            phi, J, _, _ = self._eval(theta, x.tolist())
            return np.array(phi), np.array(J)

        r = sopt.root(fun, np.array(q), jac=True, method="hybr",
                      options={"xtol": self.tol})
        return r.x.tolist(), int(r.nfev), bool(r.success)

    def run(self, inputs, order: int = 0, q_start=None) -> NewtonRun:
        """Solve at the driver angles ``inputs`` in sequence (each from the previous answer)."""
        inputs = np.asarray(inputs, dtype=float)
        N, n = inputs.shape[0], self.system.n
        Q = np.empty((N, n))
        Qd = np.empty((N, n)) if order >= 1 else None
        Qdd = np.empty((N, n)) if order >= 2 else None
        q = list(self.system.seed_drawn() if q_start is None else q_start)
        solve = self._root if self.method == "root" else self._newton
        w = self.system.omega
        zero = [0.0] * n
        getrf, getrs = lapack.dgetrf, lapack.dgetrs
        total = failed = 0
        for k, th in enumerate(inputs.tolist()):
            q, it, ok = solve(th, q)
            total += it
            failed += not ok
            Q[k] = q
            if order >= 1:
                _, J, phid, _ = self._eval(th, q, qd=zero, qdd=zero, omega=w, rates=True)
                lu, piv, _ = getrf(np.array(J))
                qd, _ = getrs(lu, piv, np.array(phid))
                qd = -qd
                Qd[k] = qd
                if order >= 2:
                    _, _, _, phidd = self._eval(th, q, qd=qd.tolist(), qdd=zero, omega=w,
                                                jac=False, rates=True)
                    Qdd[k] = -getrs(lu, piv, np.array(phidd))[0]
        return NewtonRun(inputs, Q, Qd, Qdd, total, failed)

    def joints(self, run: NewtonRun, names=None) -> dict[str, tuple]:
        """{joint: (P, V, A)} as (N, 2) arrays (V, A None below order 1, 2), vectorised."""
        cols = lambda a: None if a is None else list(a.T)  # noqa: E731
        out = self.system.joints(float, np.cos, np.sin, math.pi, self.theta0, run.inputs,
                                 cols(run.q), cols(run.qd), cols(run.qdd), self.system.omega,
                                 0.0, names)
        N = run.inputs.shape[0]

        def xy(v):
            a = np.empty((N, 2))
            a[:, 0], a[:, 1] = v
            return a

        res = {}
        for j, (P, V, A) in out.items():
            res[j] = (xy(P), None if run.qd is None else xy(V), None if run.qdd is None else xy(A))
        return res
