"""Forward-mode derivatives on numpy arrays: a value and its gradient with respect to K seeds.

The synthesis evaluates a linkage's loop closure in closed form (:mod:`.families`) and needs the
exact derivatives of every point with respect to the design's parameters and the crank angle, to
refine a design by least squares. Each :class:`Dual` carries ``v`` (any shape S, float or
complex) and ``d`` (shape S + (K,)): ``d[..., k]`` is ∂v/∂seed_k. Products, quotients, square
roots and e^{iθ} follow the chain rule; broadcasting follows numpy's on ``v`` (``d`` gets the
trailing K axis). The derivatives are those of the same closed forms, so they are exact to
rounding (tests compare them with central differences).
"""
from __future__ import annotations

import numpy as np


class Dual:
    """A value ``v`` (shape S) and its derivatives ``d`` (shape S + (K,))."""

    __slots__ = ("v", "d")
    __array_ufunc__ = None   # numpy defers to our operators (ndarray * Dual -> Dual.__rmul__)

    def __init__(self, v, d) -> None:
        self.v = v
        self.d = d

    # -- construction ---------------------------------------------------------------------
    @staticmethod
    def seed(v: np.ndarray, k: int, nseeds: int) -> "Dual":
        """The independent variable number ``k`` of ``nseeds`` with values ``v``."""
        v = np.asarray(v, dtype=float)
        d = np.zeros(v.shape + (nseeds,))
        d[..., k] = 1.0
        return Dual(v, d)

    @staticmethod
    def const(v) -> "Dual":
        return Dual(np.asarray(v), np.zeros(np.shape(v) + (1,)))

    # -- arithmetic -----------------------------------------------------------------------
    def __add__(self, o) -> "Dual":
        if isinstance(o, Dual):
            return Dual(self.v + o.v, self.d + o.d)
        return Dual(self.v + o, self.d)

    __radd__ = __add__

    def __neg__(self) -> "Dual":
        return Dual(-self.v, -self.d)

    def __sub__(self, o) -> "Dual":
        if isinstance(o, Dual):
            return Dual(self.v - o.v, self.d - o.d)
        return Dual(self.v - o, self.d)

    def __rsub__(self, o) -> "Dual":
        return Dual(o - self.v, -self.d)

    def __mul__(self, o) -> "Dual":
        if isinstance(o, Dual):
            return Dual(self.v * o.v, self.d * o.v[..., None] + self.v[..., None] * o.d)
        o = np.asarray(o)
        return Dual(self.v * o, self.d * o[..., None])

    __rmul__ = __mul__

    def inv(self) -> "Dual":
        r = 1.0 / self.v
        return Dual(r, -self.d * (r * r)[..., None])

    def __truediv__(self, o) -> "Dual":
        if isinstance(o, Dual):
            return self * o.inv()
        o = np.asarray(o)
        return Dual(self.v / o, self.d / o[..., None])

    def __rtruediv__(self, o) -> "Dual":
        return self.inv() * o

    # -- functions ------------------------------------------------------------------------
    def conj(self) -> "Dual":
        return Dual(np.conj(self.v), np.conj(self.d))

    @property
    def real(self) -> "Dual":
        return Dual(np.real(self.v), np.real(self.d))

    @property
    def imag(self) -> "Dual":
        return Dual(np.imag(self.v), np.imag(self.d))

    def sqrt(self) -> "Dual":
        """Square root of a real value (NaN where it is negative)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            s = np.sqrt(self.v)
            return Dual(s, self.d * (0.5 / s)[..., None])

    def abs(self) -> "Dual":
        """|v| of a real value."""
        sg = np.sign(self.v)
        return Dual(np.abs(self.v), self.d * sg[..., None])

    def abs2(self) -> "Dual":
        """|z|² of a complex value (real)."""
        return Dual(np.abs(self.v) ** 2, 2.0 * np.real(np.conj(self.v)[..., None] * self.d))

    def expi(self) -> "Dual":
        """e^{i·v} of a real value."""
        e = np.exp(1j * self.v)
        return Dual(e, 1j * e[..., None] * self.d)

    def angle(self) -> "Dual":
        """arg(z) of a complex value, rad (its derivative Im(dz/z))."""
        return Dual(np.angle(self.v), np.imag(self.d / self.v[..., None]))


def cross(a: Dual, b: Dual) -> Dual:
    """z-component of a × b for complex-encoded vectors: Im(conj(a)·b)."""
    return (a.conj() * b).imag


def dot(a: Dual, b: Dual) -> Dual:
    """a · b for complex-encoded vectors: Re(conj(a)·b)."""
    return (a.conj() * b).real


__all__ = ["Dual", "cross", "dot"]
