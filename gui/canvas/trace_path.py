"""Traced paths thinned to what the screen can show (issue 26 item 1).

A coupler curve of 3,600 samples drawn a few hundred pixels wide has thousands of vertices a
pixel or less apart. Qt strokes a pen wider than one pixel vertex by vertex (a round join each),
so the paint time grows with the vertex count although nothing more can be seen. :func:`thin`
keeps only the vertices that change what is drawn by more than a fraction of a pixel:

- first, at most one vertex per ``step`` of arc length (``qpath.decimate``: the ends of every
  finite run and one NaN row between runs kept);
- then, along each run, a vertex is kept where the path has turned enough since the last one
  kept: a stretch of arc length s that turns by θ lies within about s·θ/8 of its chord, so the
  vertices are bucketed by the running sum of sqrt(θᵢ·sᵢ / (8·tol)) and the first of each
  bucket kept (with the run's ends): straight stretches collapse to their ends, a tight bend
  or a cusp keeps its vertices. ``tol`` is the deviation allowed, in the units of the points.

Array work over (N, 2); Qt-free (the canvas turns the result into a QPainterPath).
"""
from __future__ import annotations

import numpy as np

from ..qpath import decimate

#: the deviation a thinned trace may have from the full one, screen pixels
TOLERANCE_PX = 0.1


def _bend_keep(xy: np.ndarray, tol: float) -> np.ndarray:
    """(N,) bool: the vertices of one finite run (N, 2) that :func:`thin` keeps (see the module
    docstring); both ends always."""
    n = len(xy)
    keep = np.ones(n, dtype=bool)
    if n < 3:
        return keep
    d = np.diff(xy, axis=0)                       # (N-1, 2) segments
    s = np.hypot(d[:, 0], d[:, 1])                # their lengths
    ang = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.remainder(np.diff(ang) + np.pi, 2 * np.pi) - np.pi)   # (N-2,) at inner vertices
    # a vertex's share of the bend: its turn times the arc around it (half of each segment)
    share = np.sqrt(turn * 0.5 * (s[:-1] + s[1:]) / (8.0 * tol))
    bucket = np.floor(np.concatenate(([0.0], np.cumsum(share))))
    keep[1:-1] = bucket[1:] != bucket[:-1]
    return keep


def thin(xy: np.ndarray, step: float, tol: float) -> np.ndarray:
    """The vertices of the (N, 2) path ``xy`` (NaN rows break it) worth drawing at ``step`` (arc
    length, at most one vertex per step) and ``tol`` (deviation allowed), both in the units of
    ``xy``; ``tol`` <= 0: arc length only. Returns (M, 2), M <= N, a subset of the rows in order."""
    xy = decimate(xy, step)
    if tol <= 0 or len(xy) < 3:
        return xy
    fin = np.isfinite(xy).all(axis=1)
    keep = ~fin                                    # NaN rows (one between runs) stay
    edges = np.flatnonzero(np.diff(np.concatenate(([0], fin.view(np.int8), [0]))))
    for start, stop in zip(edges[0::2].tolist(), edges[1::2].tolist()):   # the runs [start, stop)
        keep[start:stop] = _bend_keep(xy[start:stop], tol)
    return xy[keep]
