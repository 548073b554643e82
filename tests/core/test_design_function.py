"""Function synthesis (core/design/freudenstein.py, function.py) against closed forms.

Freudenstein's linear solve is checked against the textbook closed-form output of a known
four-bar (the half-angle solution of A·cos ψ + B·sin ψ = C) and slider-crank: from exact pairs
it returns the known lengths. Every synthesised candidate is driven by the product's solver and
its output compared with the pairs; a function sampled from a known linkage with more pairs
than Freudenstein takes must be recovered exactly by the least squares.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from mechsketch.core.design import freudenstein as FR
from mechsketch.core.design.function import synthesize_function
from mechsketch.core.design.options import LinkageOptions
from mechsketch.core.design.targets import DesignError, function_target
from mechsketch.core.io.scene_file import element_problems
from mechsketch.core.solver.plan import compile_plan


def fourbar_psi(phi, a, b, c, d, branch=1.0):
    """Rocker angle of a four-bar (pivots (0,0), (d,0)) by the half-angle closed form."""
    A = 2 * c * (d - a * np.cos(phi))
    B = -2 * a * c * np.sin(phi)
    C = b * b - a * a - c * c - d * d + 2 * a * d * np.cos(phi)
    return 2 * np.arctan2(B + branch * np.sqrt(A * A + B * B - C * C), A + C)


def test_closed_form_reference_closes_the_loop():
    phi = np.linspace(0, 2 * math.pi, 50)
    a, b, c, d = 30.0, 90.0, 80.0, 100.0
    psi = fourbar_psi(phi, a, b, c, d)
    B = a * np.exp(1j * phi)
    C = d + c * np.exp(1j * psi)
    assert np.max(np.abs(np.abs(C - B) - b)) < 1e-12 * b


@pytest.mark.parametrize("a,b,c,d", [(30, 90, 80, 100), (45, 120, 70, 100), (20, 60, 55, 50)])
def test_freudenstein_recovers_a_known_fourbar(a, b, c, d):
    phi = np.radians([20.0, 75.0, 140.0])[None, :]
    psi = fourbar_psi(phi, a, b, c, d)
    x, sigma, th = FR.fourbar(phi, psi, float(d))
    assert np.allclose(x[0, 4:7], [a, b, c], rtol=1e-10)
    out = FR.outputs("fourbar", x, sigma, th)
    assert np.max(np.abs(np.angle(np.exp(1j * (out - psi))))) < 1e-10


def test_freudenstein_recovers_a_known_slider_crank():
    a, b, h = 35.0, 110.0, 12.0
    phi = np.radians([10.0, 80.0, 170.0])[None, :]
    s = a * np.cos(phi) + np.sqrt(b * b - (h - a * np.sin(phi)) ** 2)
    x, sigma, th = FR.slider_crank(phi, s)
    assert np.allclose([x[0, 3], x[0, 4], x[0, 5]], [h, a, b], rtol=1e-10)
    assert np.max(np.abs(FR.outputs("slider_crank", x, sigma, th) - s)) < 1e-10 * b


def _solver_outputs(cand, target):
    lk = cand.linkage
    sgn = 1.0 if lk.driver.speed_rpm > 0 else -1.0
    th0 = math.atan2(lk.joint("B").at[1] - lk.joint("A").at[1], lk.joint("B").at[0] - lk.joint("A").at[0])
    plan = compile_plan(lk)
    sol = plan.evaluate(th0 + target.inputs_rad, order=0)     # the pairs' inputs, from the drawn pose
    assert sol.valid.all()
    if target.angular:
        got = sol.angle("output")
        err = np.angle(np.exp(1j * ((got - got[0]) - target.outputs)))
    else:
        x = sol.position("C")[:, 0]
        err = (x - x[0]) - target.outputs
    span = plan.evaluate(th0 + np.linspace(0, target.inputs_rad[-1], 500), order=0)
    assert span.valid.all()
    assert sgn * target.inputs_rad[-1] > 0          # the crank turns the way the inputs go
    assert not element_problems(lk)
    return np.max(np.abs(err))


@pytest.mark.parametrize("rows,unit,topology", [
    ([[0, 0], [40, 25], [90, 50]], "deg", "fourbar"),
    ([[0, 0], [-30, 10], [-100, 35]], "deg", "fourbar"),
    ([[0, 0], [45, 20], [90, 45]], "mm", "slider_crank"),
])
def test_three_precision_points_exact(rows, unit, topology):
    t = function_target(rows, unit)
    res = synthesize_function(t, LinkageOptions(candidates=2), topology)
    assert res.candidates
    for c in res.candidates:
        err = _solver_outputs(c, t)
        tol = math.radians(1e-9) if unit == "deg" else 1e-9
        assert err <= tol
        assert c.deviation <= (1e-9 if unit == "deg" else 1e-9)
        assert "output" in c.linkage.link_ids and "P" not in c.linkage.joint_ids


def test_least_squares_recovers_a_known_function():
    a, b, c, d = 30.0, 90.0, 80.0, 100.0
    phi = np.radians(np.linspace(20, 160, 8)) + 0.3
    psi = fourbar_psi(phi, a, b, c, d)
    rows = np.stack([np.degrees(phi - phi[0]), np.degrees(np.unwrap(psi) - psi[0])], axis=1)
    t = function_target(rows, "deg")
    res = synthesize_function(t, LinkageOptions(candidates=1, min_transmission_deg=20), "fourbar", size=d, atlas=False)
    best = res.candidates[0]
    assert _solver_outputs(best, t) <= math.radians(1e-8)


def test_function_refusals():
    with pytest.raises(DesignError, match="at least 3"):
        function_target([[0, 0], [10, 5]])
    with pytest.raises(DesignError, match="same input"):
        function_target([[0, 0], [10, 5], [10, 7]])
    with pytest.raises(DesignError, match="increase"):
        function_target([[0, 0], [10, 5], [5, 7]])
    with pytest.raises(DesignError, match="never changes"):
        function_target([[0, 3], [10, 3], [20, 3]])
    with pytest.raises(DesignError, match="output_mm"):
        synthesize_function(function_target([[0, 0], [10, 5], [20, 7]], "deg"), topology="slider_crank")
