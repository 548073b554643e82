"""QPainterPath from coordinate arrays, without pyqtgraph (issue 14: the canvas draws its first
frame before pyqtgraph, some 0.2 s to import, is loaded for the plots).

:func:`xy_path` makes the canvas's traced paths from (N, 2) arrays, thinned by :func:`decimate`.

:func:`finite_path` draws what pyqtgraph's ``arrayToQPath(x, y, connect="finite")`` draws, made
the same way: each run of finite points is copied with numpy straight into the memory of a
QPolygonF (no Python object per point) and added to the path as one subpath.
"""
from __future__ import annotations

import numpy as np
import shiboken6
from PySide6.QtGui import QPainterPath, QPolygonF


def _polygon(x: np.ndarray, y: np.ndarray) -> QPolygonF:
    """A QPolygonF holding the points (x[k], y[k]), filled through its buffer."""
    n = len(x)
    poly = QPolygonF()
    poly.resize(n)
    buf = np.frombuffer(shiboken6.VoidPtr(poly.data(), n * 16, True), dtype=np.float64).reshape(n, 2)
    buf[:, 0] = x
    buf[:, 1] = y
    return poly


def finite_path(x: np.ndarray, y: np.ndarray) -> QPainterPath:
    """A polyline through the points (x[k], y[k]) (N,) each, broken where a point is not finite
    (NaN or ±inf): such points are left out and each run of finite points is its own subpath."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    path = QPainterPath()
    if len(x) == 0:
        return path
    finite = np.isfinite(x) & np.isfinite(y)
    if finite.all():
        path.addPolygon(_polygon(x, y))
        return path
    edges = np.flatnonzero(np.diff(np.concatenate(([0], finite.view(np.int8), [0]))))
    for start, stop in zip(edges[0::2].tolist(), edges[1::2].tolist()):   # the runs [start, stop)
        path.addPolygon(_polygon(x[start:stop], y[start:stop]))
    return path


def decimate(xy: np.ndarray, step: float) -> np.ndarray:
    """Drop points of an (N, 2) path closer than ``step`` (mm, along the path) to the last kept
    one; the ends of every finite run and one NaN row between runs are kept."""
    n = len(xy)
    if n < 3 or step <= 0:
        return xy
    fin = np.isfinite(xy).all(axis=1)
    with np.errstate(invalid="ignore"):
        d = np.hypot(*np.diff(xy, axis=0).T)
    s = np.concatenate(([0.0], np.cumsum(np.where(np.isfinite(d), d, 0.0))))
    bucket = np.floor(s / step)
    keep = np.ones(n, dtype=bool)
    keep[1:] = bucket[1:] != bucket[:-1]
    change = fin[1:] != fin[:-1]
    keep[1:] |= change
    keep[:-1] |= change
    keep[0] = keep[-1] = True
    keep &= fin | np.concatenate(([True], change)) | np.concatenate((change, [True]))
    return xy[keep]


def xy_path(xy: np.ndarray, close: bool = False, step: float = 0.0) -> QPainterPath:
    """A QPainterPath through the (N, 2) points (decimated to ``step`` mm); NaN rows break it."""
    if close and np.isfinite(xy).all() and len(xy) > 2:
        xy = np.vstack([xy, xy[:1]])
    xy = decimate(xy, step)
    return finite_path(xy[:, 0], xy[:, 1])
