"""The input grid of a plan's constant-speed sweeps of N samples, kept between sweeps.

Every sweep of N samples of a crank at its constant speed has the same inputs, so the same crank
rotation (cos, sin), and the same motion of the crank's points (arm, position, velocity and
acceleration at the plan's speed). :class:`SweepGrid` keeps them, per plan and sample count
(:meth:`~.plan.Plan.sweep`): the inputs and cos/sin are made with the grid, the crank's points are
taken from the crank state of the second sweep of order 2 that computed them
(:meth:`SweepGrid.harvest`), so that a size swept once costs what it did without the grid. Later
sweeps start their crank state from them (:meth:`~.link_state.LinkState.share_points`) instead of
computing them again: the same functions on the same inputs, so the same bits.

Everything kept is read-only (``flags.writeable = False``): solutions share these arrays inside
their link states, and what :class:`~.solution.Solution` hands out (``position``, ``velocity``,
``acceleration``, ``input``) is always a new array.
"""
from __future__ import annotations

import math

import numpy as np

from . import kernels as K
from .link_state import LinkState


def _freeze(*arrays) -> None:
    for a in arrays:
        if isinstance(a, np.ndarray):
            a.flags.writeable = False


class SweepGrid:
    """``inputs`` (N,) rad, the sample numbers ``k`` (N,), the crank's ``cs`` (cos, sin) of the
    offsets from its drawn angle (None for a drive other than a plain crank); once harvested,
    ``points`` {drawn position: [arm, point, velocity, acceleration]} and ``rates``
    {drawn position: [velocity, acceleration]} of the crank's joints other than its pivot ((x, y)
    pairs of float (N,) arrays; mm, mm/s, mm/s²) and ``finite`` (every crank position is
    finite)."""

    __slots__ = ("inputs", "k", "cs", "points", "rates", "finite", "_drawn", "_full")

    def __init__(self, n: int, omega: float, theta0: float, crank_drawn: list[complex] | None) -> None:
        # rows of one buffer, made read-only at once (views taken after that are read-only too)
        buf = np.empty((2 if crank_drawn is None else 4, n))
        k, inputs = buf[0], buf[1]
        k[:] = np.arange(n, dtype=float)   # the same values as int k times a float (exact below 2**53)
        sgn = 1.0 if omega >= 0 else -1.0
        np.multiply(sgn * (2.0 * math.pi / n), k, out=inputs)
        inputs += theta0                # θ0 + sgn·(2π/N)·k, in place
        if crank_drawn is not None:     # as K.crank_cs: cos and sin of inputs − θ0
            th = inputs - theta0
            np.cos(th, out=buf[2])
            np.sin(th, out=buf[3])
        buf.flags.writeable = False
        self.inputs, self.k = buf[1], buf[0]
        self.cs = None if crank_drawn is None else (buf[2], buf[3])
        self.points = self.rates = None
        self.finite = False
        self._drawn = crank_drawn
        self._full = 0             # order-2 sweeps on this grid before its points were kept

    def share(self, st: LinkState) -> None:
        """Start the crank state ``st`` of a sweep on this grid from the kept motion, if any."""
        if self.points is not None:
            st.share_points(self.points, self.rates)
            st.finite = self.finite

    def harvest(self, st: LinkState | None, order: int) -> None:
        """Keep the motion of the crank's points that ``st``, the crank state of a sweep of
        ``order`` on this grid, computed (made here if it did not: the same methods); after the
        second sweep of order 2 (the rates are those of the plan's constant speed), so that a
        size swept once pays nothing for it (making arrays read-only costs ~1 µs each)."""
        if st is None or order < 2 or self.points is not None or self._drawn is None:
            return
        self._full += 1
        if self._full < 2:
            return
        points, rates = {}, {}
        for p0 in self._drawn:
            if p0 == st.a0:         # the pivot: scalars, made as they are at every solve
                continue
            arm = st.arm_xy(p0)
            at, vel, acc = st.point_xy(p0), st.vel_at(p0, arm), st.acc_at(p0, arm)
            points[p0], rates[p0] = [arm, at, vel, acc], [vel, acc]
            _freeze(*arm, *at, *vel, *acc)
        self.rates = rates
        # every position pivot + R·(cos, sin)·offset is finite: the inputs are (an arange), so
        # cos and sin are, and the drawn offsets are far from overflow
        self.finite = math.isfinite(abs(st.a0)) and all(abs(p0 - st.a0) < 1e300 for p0 in self._drawn)
        self.points = points       # last: a grid with points is complete


__all__ = ["SweepGrid"]
