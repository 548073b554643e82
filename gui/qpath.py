"""QPainterPath from coordinate arrays, without pyqtgraph (issue 14: the canvas draws its first
frame before pyqtgraph, some 0.2 s to import, is loaded for the plots).

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
