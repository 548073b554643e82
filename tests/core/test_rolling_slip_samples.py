"""Per-sample slip of a rolling-lever synthesis (``SlipReport.samples``), the arrays the slip plots
draw: they end at the summary's figures and agree with independent integrations and sums."""
from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

import test_rolling_reference as ref
from mechsketch.core.analyses.rolling import exact as rx
from mechsketch.core.analyses.rolling.geometry import pose_state
from mechsketch.core.analyses.rolling.geometry import LeverGeometry
from mechsketch.core.analyses.rolling.slip import continuous_measures, continuous_slip
from mechsketch.core.analyses.rolling.report import summary
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.workspace import Workspace
from mechsketch.core.model.scene import Scene


@pytest.fixture(scope="module")
def exact():
    return synthesize(ref.element(), "exact", 200)


def test_exact_method_samples_are_the_computed_motions_slip_ending_at_the_summary_figure(exact):
    rep = exact.slip
    s = rep.samples
    assert s.source == "continuous"
    assert np.array_equal(s.theta, exact.theta)
    assert s.slip_d[0] == 0.0 and s.slip_e[0] == 0.0
    # to the last bit: the plot's end is the number the summary prints
    assert s.slip_d[-1] == rep.continuous.slip_d and s.slip_e[-1] == rep.continuous.slip_e
    assert np.all(np.diff(s.slip_d) >= 0.0) and np.all(np.diff(s.slip_e) >= 0.0)
    # the numbers: chords of 201 points give 3.8e-5 mm, the motion itself slides < 1e-9 mm
    assert rep.points.kinematic_slip > 1e-5
    assert s.slip_d[-1] < 1e-9 and f"{rep.continuous.slip_d:.2e}" in summary(exact)


def _bad_path(geom, end=-0.5926, n=2001):
    """A motion integrated with ℓ 0.1 % off (it slides about 1e-3 mm): a visible slip to accumulate."""
    th = np.linspace(0.0, end, n)
    a = np.empty_like(th)
    a[0] = geom.alpha0
    s = np.zeros_like(th)
    for i in range(n - 1):
        st_ = pose_state(geom, a[i:i + 1], th[i:i + 1])
        a[i + 1] = a[i] + (th[i + 1] - th[i]) * (1.0 - st_.g[0] / (geom.ell * 1.001))
        s[i + 1] = s[i] + (th[i + 1] - th[i]) * st_.k53[0]
    return th, a, s


def test_accumulated_slip_at_each_sample_equals_an_independent_integration_to_that_sample():
    geom = LeverGeometry.from_element(ref.element())
    path = rx.ExactPath(geom, *_bad_path(geom), 0.0, 0)
    grid = np.linspace(0.0, -0.5926, 38)   # between mesh nodes (where the computed motion may jump)
    total, samples = continuous_slip(path, 0.0, -0.5926, grid)
    assert samples.slip_d[-1] == total.slip_d and total.slip_d > 1e-4
    for k in (5, 17, 30):
        alone = continuous_measures(path, 0.0, float(grid[k]))
        assert samples.slip_d[k] == pytest.approx(alone.slip_d, rel=1e-9, abs=1e-15)
        assert samples.slip_e[k] == pytest.approx(alone.slip_e, rel=1e-9, abs=1e-15)
    # a stroke run upwards accumulates from its own start
    up_total, up = continuous_slip(path, -0.5926, 0.0, grid[::-1])
    assert up.slip_d[-1] == pytest.approx(up_total.slip_d, rel=1e-12)
    assert up.slip_d[10] == pytest.approx(continuous_measures(path, -0.5926, float(grid[::-1][10])).slip_d, rel=1e-9)


@pytest.mark.parametrize("method", ["paper", "corrected"])
def test_constructions_accumulate_the_kinematic_slip_of_their_points(method):
    res = synthesize(ref.element(), method, 24)
    s = res.slip.samples
    assert s.source == "points" and np.array_equal(s.theta, res.theta)
    assert s.slip_d[-1] == pytest.approx(res.slip.points.kinematic_slip, rel=1e-13)
    assert s.slip_e[-1] == pytest.approx(res.slip.points.kinematic_slip_e, rel=1e-13)
    # independent: complex arithmetic, one interval at a time, from the definition (notes, C)
    g = res.geom
    f = complex(*g.f)
    want = [0.0]
    for k in range(len(res.theta) - 1):
        um = 0.5 * (res.u1[k] + res.u1[k + 1])
        m = complex(*g.c1) + g.R1 * cmath.exp(1j * um)
        x1 = complex(*res.F[k + 1]) + cmath.exp(1j * res.theta[k + 1]) * (m - f)
        x0 = complex(*res.F[k]) + cmath.exp(1j * res.theta[k]) * (m - f)
        want.append(want[-1] + abs(x1 - x0))
    np.testing.assert_allclose(s.slip_d, want, rtol=1e-12, atol=1e-15)


def test_the_workspace_result_hands_out_the_cores_arrays_and_no_slip_of_its_own():
    from mechsketch.core.workspace import results

    assert not hasattr(results, "cumulative_slip")
    ws = Workspace(Scene((ref.element(),)))
    res = ws.result(ref.element().id)
    assert res.slip_samples is res.synthesis.slip.samples
    fr = res.frames
    # the contact angles per frame put the contact on the lever circle at P (lever frame -> ground)
    g = res.synthesis.geom
    k = 77
    lever_pt = complex(*g.c1) + g.R1 * cmath.exp(1j * fr.u1[k])
    ground = complex(*fr.F[k]) + cmath.exp(1j * fr.theta[k]) * (lever_pt - complex(*g.f))
    assert abs(ground - complex(*fr.P[k])) < 1e-9
    slider_pt = complex(*g.c2) + g.R2 * cmath.exp(1j * fr.u2[k])
    ground = complex(*fr.F[k]) + cmath.exp(1j * fr.theta[k]) * (slider_pt - complex(*g.f))
    assert abs(ground - complex(*fr.P0[k])) < 1e-9
    assert math.isfinite(res.slip_samples.slip_d[-1])
