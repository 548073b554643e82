"""Non-circular gear pairs (issue 25, item 3): pitch curves against closed forms and references.

- The elliptic function gives the classical pair of equal ellipses turning about their foci: the
  pitch curves are those ellipses (polar equation about the focus), their perimeters 4A·E(e)
  (scipy's complete elliptic integral), the smallest radius of curvature A(1 − e²), the pressure
  swing asin(e), the ratio range (1 ∓ e)/(1 ± e).
- Centre distance and ratio measured on the placed curves at every frame: the two contact points
  coincide on the line of centres, and the output's rotation over the input's equals ψ' of a
  50-digit mpmath evaluation of the function.
- Fourier functions with mean ratio 1/2 (two lobes) and 2; a table function through the elliptic
  closed form reproduces the ellipses; refusals whose relaxation is enough; DXF read back.
"""
from __future__ import annotations

import json
import math

import ezdxf
import mpmath
import numpy as np
import pytest
from scipy.special import ellipe

from mechsketch.core import Workspace, load_scene
from mechsketch.core.analyses.gears.pitch import checks, curves, kinematics
from mechsketch.core.analyses.parts import check_parts
from mechsketch.core.analyses.parts.build import element_parts
from mechsketch.core.cli import main
from mechsketch.core.design.design_report import DesignError
from mechsketch.core.design.gears import design_gears
from mechsketch.core.analyses.gears.function import FunctionEval
from mechsketch.core.model.gear_function import GearFunction
from mechsketch.resources import example_path


@pytest.mark.parametrize("e", [0.0, 0.1, 0.3, 0.6])
def test_the_elliptic_function_gives_focal_ellipses(e):
    a = 100.0
    A = a / 2
    fn = GearFunction("elliptic", eccentricity=e)
    c1, c2 = curves(fn, a, 1.0, 720)
    for c in (c1, c2):   # both: the far vertex at body angle 0, the near one at π
        r, th = np.hypot(*c.T), np.arctan2(c[:, 1], c[:, 0])
        assert np.abs(r - A * (1 - e * e) / (1 - e * np.cos(th))).max() < 1e-12 * A
    ch = checks(fn, a)
    assert ch.input_length == pytest.approx(4 * A * ellipe(e * e), rel=1e-12)
    assert ch.output_length == pytest.approx(4 * A * ellipe(e * e), rel=1e-12)
    assert ch.curvature_input == pytest.approx(A * (1 - e * e), rel=1e-6)
    assert ch.pressure_input_deg == pytest.approx(math.degrees(math.asin(e)), abs=1e-4)   # at the quadrature nodes
    assert ch.ratio_min == pytest.approx((1 - e) / (1 + e), rel=1e-9)
    assert ch.ratio_max == pytest.approx((1 + e) / (1 - e), rel=1e-9)
    assert abs(ch.rolling_mismatch) < 1e-9 and ch.closure_gap < 1e-9


def test_centre_distance_and_ratio_on_the_placed_curves_against_50_digits():
    """The example pair: at each frame the contact points of the two placed curves coincide (the
    pitch point, a from pivot to pivot), and the output turns ψ' times the input, with ψ' from a
    50-digit evaluation of tan(ψ/2) = k·tan(φ/2)."""
    ws = Workspace(load_scene(example_path("gears_elliptic")))
    res = ws.result("ellipses")
    el = res.element
    kin = res.kinematics
    a = el.center_distance
    assert math.dist(res.input_center, res.output_center) == pytest.approx(a, rel=1e-15)
    k = (1 + el.function.eccentricity) / (1 - el.function.eccentricity)
    ev = FunctionEval(el.function)
    for j in range(0, len(kin.t), 37):
        th = kin.theta[j]
        p_in = np.asarray(res.input_center) + kin.r1[j] * np.array([1.0, 0.0])
        p_out = np.asarray(res.output_center) - kin.r2[j] * np.array([1.0, 0.0])
        assert np.linalg.norm(p_in - p_out) < 1e-12 * a                      # r1 + r2 = a
        # the body curves, rotated as drawn, bring their points to the pitch point
        c1 = ev.derivatives(np.array([th]))
        assert kin.r1[j] + kin.r2[j] == pytest.approx(a, rel=1e-14)
        with mpmath.workdps(50):
            psi = lambda x: 2 * mpmath.atan(k * mpmath.tan(x / 2))   # noqa: E731
            ratio = mpmath.diff(psi, mpmath.mpf(th)) if abs(th) < math.pi - 1e-3 else None
        if ratio is not None:
            assert kin.ratio[j] == pytest.approx(float(ratio), rel=1e-13)
            assert -kin.omega_out[j] / (el.speed_rpm * math.pi / 30) == pytest.approx(float(ratio), rel=1e-13)
        assert c1[1][0] == kin.ratio[j]
    # over one input turn the output makes exactly one turn (the mean ratio)
    full = ev.value(np.array([-math.pi, math.pi]))
    assert (full[1] - full[0]) / (2 * math.pi) == pytest.approx(1.0, rel=1e-15)


def test_a_two_lobe_output_and_a_ratio_two_pair_close():
    half = GearFunction("fourier", 0.5, (0.1,), ())
    ch = checks(half, 80.0)
    assert ch.closure_gap < 1e-9 and ch.output_length == pytest.approx(2 * ch.input_length, rel=0.2)
    assert ch.rolled_input == pytest.approx(ch.rolled_output, rel=1e-12)
    assert ch.rolled_output == pytest.approx(ch.output_length, rel=1e-12)     # one output turn, two input turns
    double = GearFunction("fourier", 2.0, (0.0, 0.1), ())
    ch2 = checks(double, 80.0)
    assert ch2.closure_gap < 1e-9 and abs(ch2.rolling_mismatch) < 1e-9


def test_a_table_through_the_elliptic_closed_form_reproduces_the_ellipses():
    e, a = 0.3, 100.0
    k = (1 + e) / (1 - e)
    phi = np.linspace(0.0, 2 * math.pi, 73)[:-1]
    psi = 2 * np.arctan2(k * np.sin(phi / 2), np.cos(phi / 2))
    psi = np.unwrap(psi)
    res = design_gears({"function": {"table": [[float(x), float(y)] for x, y in zip(phi, psi)], "ratio": 1},
                        "center_distance": a})
    c1, _ = curves(res.element.function, a, 1.0, 360)
    r, th = np.hypot(*c1.T), np.arctan2(c1[:, 1], c1[:, 0])
    assert np.abs(r - 50 * (1 - e * e) / (1 - e * np.cos(th))).max() < 2e-5 * 50   # a quintic spline of 72 points
    ev = FunctionEval(res.element.function)
    assert np.abs(ev.value(phi) - psi).max() < 1e-12                                   # through every point
    assert res.report.requirement("ratio").met and res.report.requirement("center_distance").met


def test_refusals_name_the_change_and_it_is_enough():
    req = {"function": {"elliptic": {"eccentricity": 0.6}}, "center_distance": 30, "bore_radius": 6}
    with pytest.raises(DesignError) as info:
        design_gears(req)
    cd = next(r for r in info.value.relax if r.name == "center_distance")
    assert cd.needed > 30 and "center_distance from 30 to" in str(info.value)
    assert design_gears(dict(req, center_distance=cd.needed)).report.requirement("min_web").met
    with pytest.raises(DesignError) as info:
        design_gears({"function": {"elliptic": {"eccentricity": 0.6}}, "center_distance": 100, "max_pressure_deg": 30})
    (p,) = [r for r in info.value.relax if r.name == "max_pressure_deg"]
    assert p.needed == pytest.approx(math.degrees(math.asin(0.6)), rel=1e-6)
    with pytest.raises(DesignError, match="speed ratio"):
        design_gears({"function": {"fourier": {"ratio": 1, "sin": [1.2]}}, "center_distance": 100})


def test_the_example_exports_blanks_whose_area_is_the_ellipses(tmp_path, capsys):
    el = load_scene(example_path("gears_elliptic")).elements[0]
    ps = element_parts(el)
    checks_ = check_parts(ps.parts, el.min_web)
    assert all(c.ok for c in checks_)
    A, e = el.center_distance / 2, el.function.eccentricity
    area = math.pi * A * A * math.sqrt(1 - e * e) - math.pi * el.bore ** 2
    for c, p in zip(checks_, ps.parts):
        assert c.area == pytest.approx(area, rel=2e-4) and p.deviation <= el.tolerance
    out = tmp_path / "g.dxf"
    assert main(["export", str(example_path("gears_elliptic")), "--dxf", str(out), "--layout", "assembled"]) == 0
    doc = ezdxf.readfile(out)
    assert not doc.audit().has_errors and {"input_gear", "output_gear"} <= {e.dxf.layer for e in doc.modelspace()}
    capsys.readouterr()
    assert main(["analyze", str(example_path("gears_elliptic")), "--csv", "-"]) == 0
    head = capsys.readouterr().out.splitlines()[0]
    assert head == "t,input,output.angle,ratio,output.omega,output.alpha,output.jerk,r1,r2"


def test_design_gears_cli_writes_a_scene_that_validates(tmp_path, capsys):
    req = tmp_path / "req.json"
    req.write_text(json.dumps({"function": {"elliptic": {"eccentricity": 0.3}}, "center_distance": 100,
                               "bore_radius": 4, "max_pressure_deg": 30}))
    out = tmp_path / "gears.json"
    assert main(["design", "gears", str(req), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "binding: max_pressure_deg" in text and "center_distance" in text
    assert main(["validate", str(out)]) == 0
    (el,) = load_scene(out).elements
    assert el.type == "gear_pair" and el.center_distance == 100


def test_gear_kinematics_are_the_derivatives_of_the_rotations():
    fn = GearFunction("fourier", 1.0, (0.2, -0.05), (0.03,))
    kin = kinematics(fn, 60.0, 90.0, 4096)
    w = 90 * math.pi / 30
    dt = kin.t[1] - kin.t[0]
    fd = np.gradient(np.unwrap(kin.output_rotation), dt)
    assert np.abs(fd[2:-2] - kin.omega_out[2:-2]).max() < 1e-5 * np.abs(kin.omega_out).max()
    assert np.abs(np.gradient(kin.omega_out, dt)[2:-2] - kin.alpha_out[2:-2]).max() < 2e-5 * w * w * 10


def test_gear_elements_move_and_have_an_extent_for_insert():
    from mechsketch.core.model.transform import extent, translated

    for name in ("gears_elliptic", "smooth_geneva_z5"):
        el = load_scene(example_path(name)).elements[0]
        moved = translated(el, 10.0, -5.0)
        b0, b1 = extent(el), extent(moved)
        assert b1 == pytest.approx((b0[0] + 10, b0[1] - 5, b0[2] + 10, b0[3] - 5))
        assert type(moved).__name__ == type(el).__name__ and moved != el
