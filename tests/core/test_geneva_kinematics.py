"""Geneva kinematics against the notes' table (z = 3…12), independent geometry (the roller centre
seen from the wheel centre), finite differences, and the step of the acceleration at entry/exit."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mechsketch.core.analyses.geneva.kinematics import accel_ratio, jerk_ratio, peak_accel, velocity_ratio
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.model.geneva import Drawing, Geneva

W1 = 10.0
RPM = W1 * 30 / math.pi

# seeds/NOTES.md, "Textbook Geneva kinematics": z, λ, 2φ0 (°), t_motion/T, i_max, φ at max |ε| (°),
# ε̃_max, entry jump tan(π/z), j̃(0)
TABLE = [
    (3, 0.86603, 60.0, 0.1667, 6.46410, 4.76, 31.39243, 1.73205, -672),
    (4, 0.70711, 90.0, 0.2500, 2.41421, 11.46, 5.40698, 1.00000, -48.04),
    (5, 0.58779, 108.0, 0.3000, 1.42592, 17.57, 2.29883, 0.72654, -13.32),
    (6, 0.50000, 120.0, 0.3333, 1.00000, 22.90, 1.34964, 0.57735, -6),
    (7, 0.43388, 128.6, 0.3571, 0.76642, 27.55, 0.92840, 0.48157, -3.429),
    (8, 0.38268, 135.0, 0.3750, 0.61991, 31.64, 0.69976, 0.41421, -2.249),
    (9, 0.34202, 140.0, 0.3889, 0.51980, 35.26, 0.55908, 0.36397, -1.611),
    (10, 0.30902, 144.0, 0.4000, 0.44721, 38.49, 0.46484, 0.32492, -1.226),
    (11, 0.28173, 147.3, 0.4091, 0.39224, 41.39, 0.39772, 0.29363, -0.9745),
    (12, 0.25882, 150.0, 0.4167, 0.34920, 44.00, 0.34765, 0.26795, -0.8002),
]


def drive(z: int, rpm: float = RPM, **kw) -> Geneva:
    return Geneva("g", z, 100.0, 8.0, speed_rpm=rpm, drawing=Drawing(wheel_bore_radius=1.0), **kw)


@pytest.mark.parametrize("row", TABLE, ids=[f"z{r[0]}" for r in TABLE])
def test_notes_table(row):
    z, lam, eng, motion, i_max, phi_m, eps, jump, j0 = row
    k = kinematics(drive(z), 3600)
    assert round(k.lam, 5) == lam
    assert round(math.degrees(2 * k.phi0), 1) == eng
    assert round(k.motion_fraction, 4) == motion and k.dwell_fraction == pytest.approx(1 - k.motion_fraction)
    assert round(k.i_max, 5) == i_max
    assert round(math.degrees(k.phi_peak), 2) == phi_m
    assert round(k.accel_peak_ratio, 5) == eps
    assert k.accel_peak == pytest.approx(eps * W1 ** 2, abs=1e-5 * W1 ** 2)
    assert round(k.jump / W1 ** 2, 5) == jump
    decimals = len(str(j0).split(".")[1]) if "." in str(j0) else 0
    assert k.jerk_centre / W1 ** 3 == pytest.approx(j0, abs=0.5 * 10.0 ** -decimals)


@pytest.mark.parametrize("z", range(3, 13))
def test_closed_forms_against_finite_differences_and_a_dense_search(z):
    lam = math.sin(math.pi / z)
    phi0 = math.pi / 2 - math.pi / z
    phi = np.linspace(-phi0 * 0.999, phi0 * 0.999, 401)
    h = 1e-5
    theta = lambda p: np.arctan2(lam * np.sin(p), 1 - lam * np.cos(p))  # noqa: E731
    fd1 = (theta(phi + h) - theta(phi - h)) / (2 * h)
    fd2 = (velocity_ratio(phi + h, lam) - velocity_ratio(phi - h, lam)) / (2 * h)
    fd3 = (accel_ratio(phi + h, lam) - accel_ratio(phi - h, lam)) / (2 * h)
    scale = [np.abs(f).max() for f in (fd1, fd2, fd3)]
    assert np.abs(velocity_ratio(phi, lam) - fd1).max() < 1e-8 * scale[0]
    assert np.abs(accel_ratio(phi, lam) - fd2).max() < 1e-7 * scale[1]
    assert np.abs(jerk_ratio(phi, lam) - fd3).max() < 1e-6 * scale[2]
    # the peak of |ε̃| by brute force over a fine grid, against the closed-form root
    dense = np.linspace(0, phi0, 2_000_001)
    k = int(np.argmax(np.abs(accel_ratio(dense, lam))))
    phi_m, eps_max = peak_accel(lam)
    assert phi_m == pytest.approx(dense[k], abs=2e-6)
    assert eps_max == pytest.approx(abs(accel_ratio(dense[k], lam)), rel=1e-12)
    assert phi_m < phi0
    # radial entry: no velocity shock, acceleration step tan(π/z)
    assert velocity_ratio(phi0, lam) == pytest.approx(0, abs=1e-15)
    assert accel_ratio(-phi0, lam) == pytest.approx(math.tan(math.pi / z), rel=1e-13)
    assert jerk_ratio(0.0, lam) == pytest.approx(-lam * (1 + lam) / (1 - lam) ** 3, rel=1e-13)


@pytest.mark.parametrize("z,n,direction,rpm", [(3, 7200, 0.0, RPM), (6, 3600, 35.0, RPM), (8, 4000, -120.0, -RPM),
                                               (12, 3601, 90.0, 2 * RPM)])
def test_sampled_table_against_independent_geometry_and_finite_differences(z, n, direction, rpm):
    el = drive(z, rpm, wheel_direction_deg=direction, crank_center=(12.0, -7.0))
    k = kinematics(el, n)
    assert len(k.phi) == n and np.all(np.diff(k.t) > 0) and k.t[0] == 0.0
    assert k.t[-1] == pytest.approx(k.period * (n - 1) / n)
    # the wheel's slot 0 points from the wheel centre at the roller centre while engaged
    crank = math.radians(direction) + k.phi
    roller = np.c_[12.0 + el.crank_radius * np.cos(crank), -7.0 + el.crank_radius * np.sin(crank)]
    o2 = np.array(el.wheel_center)
    slot_dir = np.arctan2(roller[:, 1] - o2[1], roller[:, 0] - o2[0])
    expect = np.angle(np.exp(1j * (slot_dir - math.radians(direction) - math.pi)))
    e = k.engaged
    assert np.abs(k.wheel_angle[e] - expect[e]).max() < 1e-12
    assert np.all(np.abs(k.wheel_angle[~e]) == pytest.approx(math.pi / z))
    # dwell share of the samples
    assert e.mean() == pytest.approx(k.motion_fraction, abs=2.0 / n)
    # derivatives by central differences in time, inside the engagement
    dt = k.t[1] - k.t[0]
    inner = np.nonzero(e)[0][2:-2]
    for f, df, dd in ((k.wheel_angle, k.omega, None), (k.omega, k.alpha, None), (k.alpha, k.jerk, None)):
        fd = (f[inner + 1] - f[inner - 1]) / (2 * dt)
        assert np.abs(fd - df[inner]).max() < 2e-3 * np.abs(df[inner]).max()
    # the wheel turns opposite to the crank
    assert np.all(np.sign(k.omega[inner]) == -np.sign(rpm))


def test_acceleration_is_a_step_at_entry_and_exit_never_interpolated():
    el = drive(6)
    k = kinematics(el, 3600)  # φ0 = 60° falls on a sample
    jump = math.tan(math.pi / 6) * el.omega1 ** 2
    first, last = np.nonzero(k.engaged)[0][[0, -1]]
    assert k.phi[first] == pytest.approx(-k.phi0, abs=1e-12) and k.phi[last] == pytest.approx(k.phi0, abs=1e-12)
    assert k.alpha[first - 1] == 0.0 and k.alpha[first] == pytest.approx(-jump, rel=1e-12)
    assert k.alpha[last] == pytest.approx(jump, rel=1e-12) and k.alpha[last + 1] == 0.0
    assert k.jump == pytest.approx(jump, rel=1e-15)
    p, a = k.alpha_with_jumps()
    at_entry = a[np.isclose(p, -k.phi0, atol=1e-12)]
    at_exit = a[np.isclose(p, k.phi0, atol=1e-12)]
    assert list(at_entry) == pytest.approx([0.0, -jump]) and list(at_exit) == pytest.approx([jump, 0.0])
    assert np.all(np.diff(p) >= 0) and len(p) == len(k.phi) + 2


def test_clockwise_crank_mirrors_the_motion():
    n = 1000
    ccw, cw = kinematics(drive(5), n), kinematics(drive(5, -RPM), n)
    assert cw.phi[0] == math.pi and cw.phi[1] < cw.phi[0]  # time order: the crank angle decreases
    assert np.array_equal(cw.engaged, ccw.engaged)
    # mirror image about the line of centres, sample by sample
    for a, b in ((cw.wheel_angle, ccw.wheel_angle), (cw.omega, ccw.omega), (cw.alpha, ccw.alpha),
                 (cw.jerk, ccw.jerk)):
        assert np.allclose(a, -b, rtol=1e-13, atol=1e-12)
    # at the same crank angle: the same wheel position and acceleration, the opposite velocity
    k = np.arange(1, n)
    j = n - k
    assert np.allclose(cw.phi[k], ccw.phi[j], atol=1e-13)
    assert np.allclose(cw.wheel_angle[k], ccw.wheel_angle[j], atol=1e-12)
    assert np.allclose(cw.omega[k], -ccw.omega[j], atol=1e-9)
    assert np.allclose(cw.alpha[k], ccw.alpha[j], atol=1e-8)
    assert np.any(cw.omega > 0)  # a clockwise crank turns the wheel counter-clockwise
    entry = cw.phases[1]
    assert entry.name == "indexing" and entry.phi_start == pytest.approx(cw.phi0)
    assert cw.phases[0].t_end == pytest.approx(ccw.phases[0].t_end)


def test_peak_acceleration_falls_with_z_as_in_the_example_scenes():
    eps = [kinematics(drive(z), 3600).accel_peak_ratio for z in (4, 6, 8)]
    assert [round(e, 2) for e in eps] == [5.41, 1.35, 0.70]
