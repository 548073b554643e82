"""Arithmetic on sample arrays or scalars that skips the passes a scalar 0, 1 or −1 would make.

The kernels (:mod:`.kernels`) compute with (x, y) pairs whose components are float (N,) arrays
or, for a constant (the frame, a guide along an axis), Python floats: these helpers leave out the
array passes that would add a scalar zero or multiply by ±1 or 0 (the same values either way).
"""
from __future__ import annotations

import numpy as np

__all__ = ["_add", "_full", "_minus", "_pair", "_sc", "_sub"]


def _full(v, shape):
    """``v`` as an array of ``shape`` if it is a scalar (rates of a slider keep the samples' shape)."""
    if shape and (not isinstance(v, np.ndarray) or v.ndim == 0):
        out = np.empty(shape)
        out.fill(v)
        return out
    return v


def _pair(x, y, shape) -> tuple:
    """(x, y) with at least one component of ``shape``: a constant component of a vector that
    varies stays a scalar (a guide along an axis), a constant vector becomes arrays."""
    if isinstance(x, np.ndarray) and x.ndim or isinstance(y, np.ndarray) and y.ndim:
        return x, y
    return _full(x, shape), _full(y, shape)


def _sc(a, x):
    """a·x, without the pass for a scalar ``a`` of 1, −1 or 0 (a guide along an axis; 0 gives the
    scalar 0.0, which :func:`_add` and :func:`_sub` then skip)."""
    if isinstance(a, float):
        if a == 1.0:
            return x
        if a == 0.0:
            return 0.0
        if a == -1.0:
            return -x
    return a * x


def _add(a, b):
    """a + b, skipping a scalar zero term."""
    if isinstance(b, float) and b == 0.0:
        return a
    if isinstance(a, float) and a == 0.0:
        return b
    return a + b


def _sub(a, b):
    """a − b, skipping a scalar zero term."""
    if isinstance(b, float) and b == 0.0:
        return a
    if isinstance(a, float) and a == 0.0:
        return -b
    return a - b


def _minus(a: tuple, b: tuple) -> tuple:
    """(x, y) of a − b, without passes when ``b`` is a pair of scalar zeros."""
    bx, by = b
    if isinstance(bx, float) and isinstance(by, float) and bx == 0.0 and by == 0.0:
        return a
    return a[0] - bx, a[1] - by
