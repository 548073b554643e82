"""Plane vectors as (x, y) pairs of arrays, for D designs at once.

The studies work on many designs in one layout, so a point is not a Python ``complex`` but a pair
of arrays (float (D,) or (D, N); complex when the caller differentiates by complex step, see
:mod:`.linearised`). Every function here is built from +, −, ×, ÷ and √ only, so that it is
analytic in its inputs and a complex step through it gives exact first derivatives; comparisons
read the real part (:func:`re`).
"""
from __future__ import annotations

import numpy as np

Pair = tuple  # (x, y): arrays or floats


def re(x):
    """The real part of ``x`` (itself for real arrays and floats): what comparisons read."""
    return x.real if np.iscomplexobj(x) else x


def add(a: Pair, b: Pair) -> Pair:
    return a[0] + b[0], a[1] + b[1]


def sub(a: Pair, b: Pair) -> Pair:
    return a[0] - b[0], a[1] - b[1]


def scale(k, a: Pair) -> Pair:
    return k * a[0], k * a[1]


def mul(a: Pair, b: Pair) -> Pair:
    """a·b as complex numbers (a rotation of b by a, for |a| = 1)."""
    return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]


def cmul(a: Pair, b: Pair) -> Pair:
    """conj(a)·b: b turned back by a (for |a| = 1, the division b / a)."""
    return a[0] * b[0] + a[1] * b[1], a[0] * b[1] - a[1] * b[0]


def div(a: Pair, b: Pair) -> Pair:
    """a / b as complex numbers."""
    d = b[0] * b[0] + b[1] * b[1]
    return (a[0] * b[0] + a[1] * b[1]) / d, (a[1] * b[0] - a[0] * b[1]) / d


def norm(a: Pair):
    """|a| (√(x² + y²): analytic, unlike hypot)."""
    return np.sqrt(a[0] * a[0] + a[1] * a[1])


def unit(a: Pair) -> Pair:
    n = norm(a)
    return a[0] / n, a[1] / n


def cross(a: Pair, b: Pair):
    """z component of a × b."""
    return a[0] * b[1] - a[1] * b[0]


def dot(a: Pair, b: Pair):
    return a[0] * b[0] + a[1] * b[1]


def perp(a: Pair) -> Pair:
    """a turned by +90° (i·a)."""
    return -a[1], a[0]


def polar(r, deg) -> Pair:
    """r·(cos, sin) of ``deg`` degrees (complex ``deg`` too: a complex step through an angle key)."""
    a = np.asarray(deg) * (np.pi / 180.0)
    return r * np.cos(a), r * np.sin(a)


def of(z: complex, like=None) -> Pair:
    """A Python complex as a pair of floats (or of arrays shaped like ``like``)."""
    if like is None:
        return float(z.real), float(z.imag)
    return np.full(np.shape(like), z.real, dtype=np.result_type(like, float)), \
        np.full(np.shape(like), z.imag, dtype=np.result_type(like, float))


def where(mask, a: Pair, b: Pair) -> Pair:
    return np.where(mask, a[0], b[0]), np.where(mask, a[1], b[1])


__all__ = ["Pair", "add", "cmul", "cross", "div", "dot", "mul", "norm", "of", "perp", "polar", "re", "scale",
           "sub", "unit", "where"]
