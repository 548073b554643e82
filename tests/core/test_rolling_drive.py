"""Crank synthesis of the rolling lever and the whole mechanism driven from the crank."""
from __future__ import annotations

import math

import numpy as np
import pytest

import test_rolling_reference as ref
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.errors import GeometryError


@pytest.fixture(scope="module")
def press():
    return synthesize(ref.element(), measures=False)


def _coupler_path(d, theta):
    geo = ref.Geo(d)
    a, _ = ref.scipy_reference(d, theta)
    return geo.lever(a, theta, np.array(d["drive"]["coupler_point"], float))


def test_crank_and_coupler_lengths(press):
    C = _coupler_path(ref.PRESS, np.array([0.0, -0.5926]))
    d = np.linalg.norm(C - np.array(ref.PRESS["drive"]["crank_pivot"]), axis=1)
    drv = press.drive
    assert drv.crank == pytest.approx(0.5 * abs(d[1] - d[0]), abs=1e-9)
    assert drv.coupler == pytest.approx(0.5 * (d[1] + d[0]), abs=1e-9)
    assert drv.crank == pytest.approx(29.0783, abs=1e-4) and drv.coupler == pytest.approx(149.4942, abs=1e-4)
    assert (drv.theta_folded, drv.theta_extended) == (0.0, -0.5926)  # d grows over this stroke
    assert math.degrees(drv.forward_angle) + 360 - math.degrees(drv.forward_angle) == pytest.approx(360)


def test_dead_centres_are_collinear(press):
    drv = press.drive
    fr = drv.frames(np.array([drv.phi_folded, drv.phi_extended]))
    A, B, C = fr.A, fr.B, fr.C
    # folded: B on the far side of A from C; extended: B between A and C
    assert np.linalg.norm(C[0] - A[0]) == pytest.approx(drv.coupler - drv.crank, abs=1e-9)
    assert np.linalg.norm(C[1] - A[1]) == pytest.approx(drv.coupler + drv.crank, abs=1e-9)
    for k in range(2):
        u, v = B[k] - A[k], C[k] - A[k]
        assert abs(u[0] * v[1] - u[1] * v[0]) < 1e-9 * np.linalg.norm(u) * np.linalg.norm(v)
    assert fr.theta == pytest.approx([0.0, -0.5926], abs=1e-9)


def test_whole_mechanism_runs_from_the_crank(press):
    drv = press.drive
    phi = drv.phi_folded + np.linspace(0.0, 2 * math.pi, 721)
    fr = drv.frames(phi)
    assert np.allclose(np.linalg.norm(fr.B - fr.A, axis=1), drv.crank, atol=1e-12)
    assert fr.coupler_residual < 1e-6  # |B − C| = coupler
    assert np.abs(np.linalg.norm(fr.B - fr.C, axis=1) - drv.coupler).max() < 1e-6
    assert np.all(fr.theta <= 1e-12) and np.all(fr.theta >= -0.5926 - 1e-12)
    fwd = phi <= drv.phi_extended
    assert np.all(np.diff(fr.theta[fwd]) <= 1e-12) and np.all(np.diff(fr.theta[~fwd]) >= -1e-12)
    # the rocker keeps its length, the lever contact stays on the exact frame profile
    assert np.allclose(np.linalg.norm(fr.F - fr.G, axis=1), press.geom.ell, atol=1e-9)
    a_ref, s_ref = ref.scipy_reference(ref.PRESS, np.sort(fr.theta[fwd])[::-1])
    _, P, _, _, _, _ = ref.Geo(ref.PRESS).contact(a_ref, np.sort(fr.theta[fwd])[::-1])
    assert np.abs(P[::-1] - fr.P[fwd][np.argsort(fr.theta[fwd])]).max() < 1e-8
    assert fr.S5.max() == pytest.approx(50.4371, abs=1e-4)


def test_inclined_example_drive():
    from mechsketch.core import load_scene
    from mechsketch.resources import example_path

    el = load_scene(example_path("rolling_lever_inclined")).element("inclined")
    res = synthesize(el, measures=False)
    C = _coupler_path(el.to_dict(), np.array([0.0, el.stroke.end]))
    d = np.linalg.norm(C - np.array(el.drive.crank_pivot), axis=1)
    assert res.drive.crank == pytest.approx(0.5 * abs(d[1] - d[0]), abs=1e-9)
    assert res.drive.coupler == pytest.approx(0.5 * (d[0] + d[1]), abs=1e-9)


def test_crank_pivot_that_cannot_drive_the_stroke_is_refused():
    th = np.array([0.0, -0.3, -0.3 - 1e-6])[1:]
    C = _coupler_path(ref.PRESS, th)
    tangent = (C[1] - C[0]) / np.linalg.norm(C[1] - C[0])
    A = C[0] + 80.0 * np.array([-tangent[1], tangent[0]])  # d(θ) is smallest at mid-stroke
    el = ref.element(drive={"crank_pivot": list(A), "coupler_point": [30, 40]})
    with pytest.raises(GeometryError, match=r"not monotone over the stroke \(it turns at θ ≈ -0\.(29|30)\d*.*d ≈ 80 mm"):
        synthesize(el, measures=False)
