"""Traced paths thinned to the screen (gui/canvas/trace_path.thin, issue 26 item 1): the thinned
polyline stays within a fraction of a pixel of every sample, keeps its runs, ends and cusps, has
far fewer vertices, and paints the same pixels as the path the canvas drew before."""
from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtGui import QColor, QImage, QPainter, QTransform

from mechsketch.core import load_scene
from mechsketch.core.workspace.workspace import Workspace
from mechsketch.gui.canvas import items as I
from mechsketch.gui.canvas.trace_path import TOLERANCE_PX, thin
from mechsketch.gui.qpath import xy_path
from mechsketch.resources import example_path


def deviation(dense: np.ndarray, poly: np.ndarray) -> float:
    """Greatest distance from a finite point of ``dense`` (N, 2) to the polyline ``poly`` (M, 2)."""
    p = dense[np.isfinite(dense).all(axis=1)]
    a, b = poly[:-1], poly[1:]
    ab = b - a
    l2 = np.maximum((ab ** 2).sum(axis=1), 1e-300)
    t = np.clip(((p[:, None, :] - a[None]) * ab[None]).sum(axis=2) / l2[None], 0.0, 1.0)
    q = a[None] + t[..., None] * ab[None]
    return float(np.hypot(*(p[:, None, :] - q).transpose(2, 0, 1)).min(axis=1).max())


@pytest.mark.parametrize("radius_px", [5.0, 40.0, 400.0])
def test_a_circle_stays_within_the_tolerance_of_its_samples(radius_px):
    th = np.linspace(0.0, 2 * np.pi, 3601)
    xy = np.column_stack([radius_px * np.cos(th), radius_px * np.sin(th)])
    out = thin(xy, 1.5, TOLERANCE_PX)
    assert deviation(xy, out) <= 2.5 * TOLERANCE_PX
    # every kept vertex is a sample, in order; the ends are kept
    idx = [int(np.flatnonzero((xy == v).all(axis=1))[0]) for v in out]
    assert idx == sorted(idx) and idx[0] == 0 and idx[-1] == 3600
    # the chord of a circle within tol of its arc spans sqrt(8·r·tol): so many vertices, not more than twice
    chords = 2 * np.pi * radius_px / np.sqrt(8 * radius_px * TOLERANCE_PX)
    assert len(out) <= 2 * chords + 3
    assert len(out) < len(thin(xy, 1.5, 0.0)) or radius_px < 10


def test_a_straight_stretch_collapses_to_its_ends_and_a_cusp_keeps_its_tip():
    t = np.linspace(-np.pi, 3 * np.pi, 4001)   # a cycloid: cusps at t = 0 and 2π (px)
    xy = np.column_stack([30 * (t - np.sin(t)), 30 * (1 - np.cos(t))])
    out = thin(xy, 1.5, TOLERANCE_PX)
    assert deviation(xy, out) <= 2.5 * TOLERANCE_PX
    for tip in (0.0, 60 * np.pi):
        assert np.min(np.hypot(out[:, 0] - tip, out[:, 1])) <= 2.5 * TOLERANCE_PX
    line = np.column_stack([np.linspace(0, 500, 1000), np.linspace(0, 200, 1000)])
    assert np.array_equal(thin(line, 1.5, TOLERANCE_PX), line[[0, -1]])


def test_runs_broken_by_nan_stay_apart_with_their_ends():
    th = np.linspace(0.0, 2 * np.pi, 1000)
    xy = np.column_stack([100 * np.cos(th), 60 * np.sin(th)])
    xy[300:340] = np.nan
    xy[700] = np.nan
    out = thin(xy, 1.5, TOLERANCE_PX)
    bad = ~np.isfinite(out).all(axis=1)
    assert not bad[0] and not bad[-1]
    runs = [r for r in np.split(out, np.flatnonzero(bad)) if len(r)]
    runs = [r[np.isfinite(r).all(axis=1)] for r in runs]
    runs = [r for r in runs if len(r)]
    assert [len(r) > 1 for r in runs] == [True, True, True]
    for ref, run in zip((xy[:300], xy[340:700], xy[701:]), runs):
        assert np.array_equal(run[0], ref[0]) and np.array_equal(run[-1], ref[-1])
        assert deviation(ref, run) <= 2.5 * TOLERANCE_PX


def _render(path, transform: QTransform, w: int, h: int) -> np.ndarray:
    img = QImage(w, h, QImage.Format.Format_ARGB32_Premultiplied)
    img.fill(QColor("white"))
    p = QPainter(img)
    p.setRenderHint(QPainter.RenderHint.Antialiasing, True)
    p.setTransform(transform)
    p.setPen(I._pen(I.TRACE, 1.6))
    p.drawPath(path)
    p.end()
    a = np.frombuffer(img.constBits(), np.uint8).reshape(h, img.bytesPerLine() // 4, 4)[:, :w, :3]
    return 255 - a.min(axis=2).astype(int)     # ink: 0 white .. 255 full


@pytest.mark.parametrize("name,joint", [("sixbar_moving_guide", "C"), ("fourbar_crank_rocker", "E"),
                                        ("excavator_arm", "K"), ("inverted_slider_crank", "T")])
@pytest.mark.parametrize("span_px", [80, 600])
def test_the_canvas_trace_paints_the_pixels_it_painted_before(qapp, name, joint, span_px):
    scene = load_scene(example_path(name))
    lk = next(e for e in scene.elements if joint in getattr(e, "joint_ids", ()))
    sol = Workspace(type(scene)((lk.with_samples(3600),))).result(lk.id).solution
    xy = np.asarray(sol.position(joint))
    fin = xy[np.isfinite(xy).all(axis=1)]
    s = span_px / max(np.ptp(fin[:, 0]), np.ptp(fin[:, 1]))
    px = 1.0 / s
    tr = QTransform(s, 0, 0, -s, 20 - fin[:, 0].min() * s, 20 + fin[:, 1].max() * s)
    before = xy_path(xy, close=True, step=I.TRACE_STEP_PX * px)   # what TraceItem drew before issue 26
    after = I._trace(xy, I.TRACE_STEP_PX * px, TOLERANCE_PX * px)
    assert after.elementCount() * 3 < before.elementCount()
    a, b = _render(before, tr, span_px + 40, span_px + 40), _render(after, tr, span_px + 40, span_px + 40)
    # the same pixels inked: whatever one paints at half strength or more, the other paints too,
    # and no pixel's ink moves by more than a sub-pixel shift of an edge can make (0.4 px)
    assert not ((a >= 128) & (b == 0)).any() and not ((b >= 128) & (a == 0)).any()
    assert np.abs(a - b).max() <= 100
    assert abs(int(a.sum()) - int(b.sum())) <= 0.02 * a.sum()
