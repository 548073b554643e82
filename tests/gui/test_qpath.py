"""gui/qpath.finite_path draws what pyqtgraph's arrayToQPath(connect="finite") draws."""
from __future__ import annotations

import numpy as np
import pytest
from pyqtgraph import arrayToQPath

from mechsketch.gui.qpath import finite_path


def _segments(path) -> set[tuple[float, float, float, float]]:
    """The drawn straight segments of a path (zero-length ones dropped)."""
    out, last = set(), None
    for k in range(path.elementCount()):
        e = path.elementAt(k)
        if e.isLineTo() and last is not None and (e.x, e.y) != last:
            out.add((*last, e.x, e.y))
        last = (e.x, e.y)
    return out


def test_all_finite_is_element_for_element_pyqtgraphs():
    t = np.linspace(0, 2 * np.pi, 361)
    x, y = 30 * np.cos(t) + 1e-3 * t, 20 * np.sin(3 * t)
    ours, ref = finite_path(x, y), arrayToQPath(x, y, connect="finite")
    assert ours.elementCount() == ref.elementCount() == 361
    for k in range(361):
        a, b = ours.elementAt(k), ref.elementAt(k)
        assert (a.type, a.x, a.y) == (b.type, b.x, b.y)
    assert ours.elementAt(0).isMoveTo() and ours.elementAt(5).isLineTo()


@pytest.mark.parametrize("seed", range(6))
def test_gaps_draw_the_same_segments(seed):
    rng = np.random.default_rng(seed)
    n = 200
    x, y = rng.standard_normal(n), rng.standard_normal(n)
    bad = rng.random(n) < [0.01, 0.05, 0.3, 0.6, 0.9, 0.02][seed]
    x[bad & (rng.random(n) < 0.5)] = np.nan
    y[bad] = [np.inf, -np.inf, np.nan][seed % 3]
    ours = finite_path(x, y)
    assert _segments(ours) == _segments(arrayToQPath(x, y, connect="finite"))
    fin = np.isfinite(x) & np.isfinite(y)
    expected = {(x[k], y[k], x[k + 1], y[k + 1]) for k in range(n - 1) if fin[k] and fin[k + 1]}
    assert _segments(ours) == expected
    assert all(np.isfinite([ours.elementAt(k).x, ours.elementAt(k).y]).all() for k in range(ours.elementCount()))


def test_empty_and_all_nan():
    assert finite_path(np.zeros(0), np.zeros(0)).elementCount() == 0
    assert finite_path(np.full(4, np.nan), np.zeros(4)).elementCount() == 0
    one = finite_path(np.array([np.nan, 2.0]), np.array([0.0, 3.0]))
    assert one.elementCount() == 1 and one.elementAt(0).isMoveTo() and (one.elementAt(0).x, one.elementAt(0).y) == (2.0, 3.0)
