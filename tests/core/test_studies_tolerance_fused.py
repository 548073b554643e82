"""The fused tolerance kernel (core/studies/tol_fused.py) against the reference path (the batch
engine's numpy arrays reduced by tol_kernels.reduce_point): per build the same deviation of every
traced point and link angle (to 1e-12 of the mechanism's size), the same histograms (envelopes),
moments, failures, whatever the topology — a four-bar, a slider-crank, a six-bar with a guide on a
moving link — and near a toggle and with builds that do not assemble (counted, never dropped)."""
from __future__ import annotations

import numpy as np
import pytest

from mechsketch.core.studies import tolerance as T
from mechsketch.core.studies.tolerance import tolerance
from mechsketch.core.workspace import Workspace

EX = "resources/examples/"
CASES = {
    "fourbar": (EX + "fourbar_crank_rocker.json", "fourbar", ["E", "C"], ["crank", "coupler", "rocker"],
                {"length:crank:A:B": {"normal": 0.0167}, "length:coupler:B:C": {"uniform": 0.05},
                 "clearance": {"B": "H7/g6", "C": "H8/f7"}}),
    "slider_crank": (EX + "slider_crank_offset.json", "slider_crank", ["B", "C"], ["crank", "rod", "slider"],
                     {"length:crank:A:B": {"normal": 0.02}, "length:rod:B:C": {"uniform": 0.04},
                      "clearance": {"B": "H7/g6", "C": "H7/f7"}}),
    "sixbar": (EX + "sixbar_moving_guide.json", "sixbar", ["E"], ["rocker", "rod2"],
               {"length:crank:A:B": {"normal": 0.0167}, "length:rocker:D:C": {"uniform": 0.05},
                "length:rod2:B:E": {"normal": 0.03}, "clearance": {"B": "H7/g6", "C": "H8/f7", "E": "H7/h6"}}),
}
#: the four-bar near its toggle: the rocker shortened to ~62 mm, coupler + rocker just above the
#: largest crank-pin-to-pivot distance (200 mm) — builds within 2 % of the toggle go to the numpy
#: path, some cannot reach it and fail there
TOGGLE = {"length:rocker:D:C": {"normal": 1.2, "bias": -58.0}, "length:crank:A:B": {"normal": 0.05},
          "clearance": {"B": "H7/g6"}}
#: builds whose rocker is so far off that many cannot be assembled at their drawn input at all
BROKEN = {"length:rocker:D:C": {"normal": 80.0}, "clearance": {"C": "H8/f7"}}


def _size(lk) -> float:
    return max(abs(c) for j in lk.joints for c in j.at)


def _compare(lk, spec, joints, links, builds=2 * T.BLOCK + 300, samples=72, seed=3):
    a = tolerance(lk, spec, builds=builds, samples=samples, seed=seed, joints=joints, links=links, fast=True)
    b = tolerance(lk, spec, builds=builds, samples=samples, seed=seed, joints=joints, links=links, fast=False)
    tol = 1e-12 * _size(lk)
    for j in joints:
        da, db = a.deviation(j), b.deviation(j)
        assert np.array_equal(np.isfinite(da), np.isfinite(db)), j
        fin = np.isfinite(db)
        assert np.max(np.abs(da[fin] - db[fin]), initial=0.0) <= tol, j
        for q in (0.005, 0.5, 0.99):
            assert np.allclose(a.envelope(j, q), b.envelope(j, q), rtol=0, atol=tol, equal_nan=True), (j, q)
        assert np.allclose(a.sigma(j), b.sigma(j), rtol=1e-9, atol=tol, equal_nan=True), j
        assert np.array_equal(a._acc[j]["fails"], b._acc[j]["fails"])
    for k in links:
        da, db = a.angle_deviation(k), b.angle_deviation(k)
        assert np.array_equal(np.isfinite(da), np.isfinite(db)), k
        fin = np.isfinite(db)
        assert np.max(np.abs(da[fin] - db[fin]), initial=0.0) <= 1e-9, k      # degrees
    assert a.failed == b.failed
    assert np.array_equal(a.assembled, b.assembled)
    return a, b


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_fused_kernel_gives_the_reference_deviations(case):
    path, eid, joints, links, spec = CASES[case]
    lk = Workspace.open(path).element(eid)
    a, _b = _compare(lk, spec, joints, links)
    assert a.failed == 0
    assert np.all(a.deviation(joints[0]) > 0)


def test_near_a_toggle_and_with_builds_that_fail_on_the_way(monkeypatch):
    path, eid, joints, links, _spec = CASES["fourbar"]
    lk = Workspace.open(path).element(eid)
    redone = []
    reference = T._reference

    def spy(ctx, values, plays, n, out, idx=None):
        if idx is not None:
            redone.append(idx.size)
        return reference(ctx, values, plays, n, out, idx)

    monkeypatch.setattr(T, "_reference", spy)
    a, _b = _compare(lk, TOGGLE, joints, links)
    assert sum(redone) > 0                      # some builds were near the toggle: the numpy path
    assert 0 < a.failed < a.builds              # some cannot pass the toggle's sample: counted
    assert a.assembled.all()


def test_builds_that_do_not_assemble_at_all_are_counted():
    path, eid, joints, links, _spec = CASES["fourbar"]
    lk = Workspace.open(path).element(eid)
    a, _b = _compare(lk, BROKEN, joints, links, builds=T.BLOCK + 50)
    assert (~a.assembled).sum() > 0
    assert a.failed >= (~a.assembled).sum()
    assert np.all(np.isinf(a.deviation("E")[~a.assembled]))


def test_the_same_numbers_whatever_the_threads():
    path, eid, joints, links, spec = CASES["sixbar"]
    lk = Workspace.open(path).element(eid)
    kw = dict(builds=3 * T.BLOCK + 7, samples=48, seed=5, joints=joints, links=links, fast=True)
    a, b = tolerance(lk, spec, workers=1, **kw), tolerance(lk, spec, workers=2, **kw)
    assert np.array_equal(a.deviation("E"), b.deviation("E"))
    assert np.array_equal(a.angle_deviation("rod2"), b.angle_deviation("rod2"))
    assert np.array_equal(a.envelope("E", 0.99), b.envelope("E", 0.99), equal_nan=True)
    assert np.array_equal(a.sigma("E"), b.sigma("E"), equal_nan=True)
