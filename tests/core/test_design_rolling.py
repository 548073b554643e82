"""Rolling levers with a prescribed slider law (issue 25, item 2), against independent references:

- recovering a known mechanism: the slider law of the example's slider circle (its synthesised
  S5(θ) as a table) gives back that circle as the lever element and the same slider profile;
- an independent integration (scipy's DOP853 on a pair-D ODE written here) and the relative
  instant centre P0 = P − S5'(θ)·n give both profiles; their arc lengths (scipy quad) equal the
  synthesis' to 1e-8 and each other (pure rolling);
- S5 reproduced physically: at each θ the designed profiles (the module's curves) are brought
  into tangent contact with the lever placed by the independent motion, solving for the slider's
  shift; it equals the law to 1e-8 mm;
- refusals (folding profiles, the wrong side) naming the change, and the change is enough;
- the CLI writes a scene that validates, exports (DXF read back), and reads back equal.
"""
from __future__ import annotations

import json
import math

import ezdxf
import numpy as np
import pytest
from scipy import integrate, optimize

from mechsketch.core import load_scene
from mechsketch.core.analyses.parts import check_parts
from mechsketch.core.analyses.parts.build import element_parts
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.cli import main
from mechsketch.core.design.design_report import DesignError
from mechsketch.core.design.rolling import design_rolling, requirements_of
from mechsketch.resources import example_path

PRESS = load_scene(example_path("rolling_lever_press")).elements[0]


def base_req(**law) -> dict:
    req = requirements_of(PRESS)
    req["slider_law"] = law
    return req


@pytest.fixture(scope="module")
def constant_design():
    return design_rolling(base_req(law="constant", travel=50.43))


class Reference:
    """The pair-D motion α(θ) integrated independently, and the pair-E curves of a law (mm, rad)."""

    def __init__(self, el, s5, ds5, theta_end: float) -> None:
        self.G = np.asarray(el.rocker_pivot, float)
        self.f = np.asarray(el.pin, float)
        self.c1 = np.asarray(el.lever_circle.center, float)
        self.R1 = el.lever_circle.radius
        self.ell = float(np.linalg.norm(self.f - self.G))
        a0 = math.atan2(*(self.f - self.G)[::-1])
        axis = math.radians(el.slider_axis_deg)
        self.ds = np.array([math.cos(axis), math.sin(axis)])
        self.n = np.array([-self.ds[1], self.ds[0]])
        self.s5, self.ds5 = s5, ds5
        sol = integrate.solve_ivp(lambda t, y: [1.0 - self.g(y[0], t) / self.ell], (0.0, theta_end), [a0],
                                  method="DOP853", rtol=1e-13, atol=1e-15, dense_output=True)
        self.alpha = lambda t: float(sol.sol(t)[0])

    def g(self, a: float, t: float) -> float:
        """Distance from G along the rocker line to the near intersection with the moved lever circle."""
        e = np.array([math.cos(a), math.sin(a)])
        F = self.G + self.ell * e
        c = F + self.rot(t, self.c1 - self.f)
        w = c - self.G
        b = w @ e
        return b - math.sqrt(b * b - (w @ w - self.R1 ** 2))

    @staticmethod
    def rot(t: float, v: np.ndarray) -> np.ndarray:
        return np.array([math.cos(t) * v[0] - math.sin(t) * v[1], math.sin(t) * v[0] + math.cos(t) * v[1]])

    def pose(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        a = self.alpha(t)
        e = np.array([math.cos(a), math.sin(a)])
        return self.G + self.ell * e, self.G + self.g(a, t) * e     # F, P

    def lever_curve(self, t: float) -> np.ndarray:
        F, P = self.pose(t)
        p0 = P - self.ds5(t) * self.n
        return self.rot(-t, p0 - F) + self.f

    def slider_curve(self, t: float) -> np.ndarray:
        _, P = self.pose(t)
        return P - self.ds5(t) * self.n - (self.s5(t) - self.s5(0.0)) * self.ds

    def length(self, curve, t0: float, t1: float) -> float:
        def speed(t):
            h = 1e-5
            return np.linalg.norm((curve(t - 2 * h) - 8 * curve(t - h) + 8 * curve(t + h) - curve(t + 2 * h)) / (12 * h))
        return integrate.quad(speed, min(t0, t1) + 3e-5, max(t0, t1) - 3e-5, epsabs=0, epsrel=1e-11, limit=200)[0] \
            + 6e-5 * 0.5 * (speed(min(t0, t1) + 3e-5) + speed(max(t0, t1) - 3e-5))


def test_the_law_of_the_slider_circle_gives_back_the_circle_and_its_profile():
    """Recover a known mechanism: the example's own S5(θ) (its circle synthesis, 201 points) as a
    table law: the lever element lies on the slider circle, the slider profile is the circle's."""
    circle = synthesize(PRESS, measures=False)
    table = [[float(t), float(s)] for t, s in zip(circle.theta, circle.S5)]
    res = design_rolling(base_req(table=table))
    syn = res.synthesis
    lev = syn.lever_e_points
    sc = PRESS.slider_circle
    assert np.abs(np.hypot(*(lev - np.asarray(sc.center)).T) - sc.radius).max() < 1e-8
    assert np.abs(syn.Q - circle.Q).max() < 1e-8 and np.abs(syn.S5 - circle.S5).max() < 1e-10
    assert res.report.requirement("s5_tolerance").value < 1e-9
    assert all(r.met for r in res.report.requirements)


def test_profiles_arc_lengths_and_s5_against_an_independent_integration(constant_design):
    el, syn = constant_design.element, constant_design.synthesis
    travel, span = 50.43, el.stroke.span
    ref = Reference(el, lambda t: travel * t / span, lambda t: travel / span, el.stroke.end)
    t0, t1 = el.stroke.start, el.stroke.end
    length_l = ref.length(ref.lever_curve, t0, t1)
    length_s = ref.length(ref.slider_curve, t0, t1)
    assert length_l == pytest.approx(length_s, rel=1e-9)                  # pure rolling, independently
    cont = syn.slip.continuous
    assert cont.length_lever_e == pytest.approx(length_l, rel=1e-8)
    assert cont.length_slider == pytest.approx(length_s, rel=1e-8)
    rep = constant_design.report
    assert rep.requirement("rolling_tolerance").value == pytest.approx(abs(cont.length_lever_e - cont.length_slider))
    # the curves themselves, pointwise
    for t in np.linspace(t0, t1, 7):
        lev, _ = syn.lever_profile_e()[0](np.array([t])), None
        assert np.linalg.norm(lev[0] - ref.lever_curve(t)) < 1e-8
        assert np.linalg.norm(syn.slider_profile()[0](np.array([t]))[0] - ref.slider_curve(t)) < 1e-8


def test_the_designed_profiles_in_contact_reproduce_s5(constant_design):
    """Place the lever by the independent motion and its designed element Π30 against the designed
    slider profile Π50: the shift of the slider at which they touch (equal points, parallel
    tangents) is the law's S5, to 1e-8 mm."""
    el, syn = constant_design.element, constant_design.synthesis
    travel, span = 50.43, el.stroke.span
    ref = Reference(el, lambda t: travel * t / span, lambda t: travel / span, el.stroke.end)
    lever, _, _ = syn.lever_profile_e()
    slider, _, _ = syn.slider_profile()
    ds = ref.ds

    def at(curve, s):
        return curve(np.array([s]))[0]

    def tangent(curve, s):
        return (at(curve, s + 1e-6) - at(curve, s - 1e-6)) / 2e-6

    for t in np.linspace(-0.05, -0.55, 6):
        F, _ = ref.pose(t)

        def world(s):
            return F + ref.rot(t, at(lever, s) - ref.f)

        def eqs(v):
            s_l, s_s, shift = v
            gap = world(s_l) - (at(slider, s_s) + shift * ds)
            tl, ts = ref.rot(t, tangent(lever, s_l)), tangent(slider, s_s)
            return [gap[0], gap[1], (tl[0] * ts[1] - tl[1] * ts[0]) / (np.linalg.norm(tl) * np.linalg.norm(ts))]

        sol = optimize.fsolve(eqs, [t + 0.01, t - 0.01, travel * t / span + 0.3], xtol=1e-13, full_output=True)
        s_l, s_s, shift = sol[0]
        assert np.abs(eqs(sol[0])).max() < 1e-9                                 # they touch, tangent
        assert abs(s_l - t) < 1e-5 and abs(s_s - t) < 1e-5   # at the points of the same θ
        assert shift == pytest.approx(travel * t / span, abs=1e-8)


def test_a_law_whose_lever_element_cannot_be_cut_is_refused_naming_the_plates():
    """S5 = 50u + 100u³ (u the stroke fraction): k53 reaches 590 mm/rad, the lever element runs far
    out along the normal and the lever plate through it cannot be cut: refused, naming min_web."""
    u = np.linspace(0.0, 1.0, 9)
    table = [[float(x * -0.5926), float(50 * x + 100 * x ** 3)] for x in u]
    with pytest.raises(DesignError) as info:
        design_rolling(base_req(table=table))
    assert "min_web" in str(info.value) and "thinnest web of the plates" in str(info.value)


def test_a_law_reversing_the_slider_is_refused_naming_the_working_side():
    """A table whose spline makes k53 change sign puts the contact on both sides of P."""
    table = [[0.0, 0.0], [-0.2, 20.0], [-0.4, 25.0], [-0.5926, 80.0]]
    with pytest.raises(DesignError) as info:
        design_rolling(base_req(table=table))
    assert "working_side" in str(info.value)
    assert not any(r.name == "slider_side" for r in info.value.relax)   # flipping the side cannot help


def test_a_law_at_rest_at_its_ends_is_refused_with_the_reason():
    with pytest.raises(DesignError, match="at rest at a stroke end"):
        design_rolling(base_req(law="cycloidal", travel=50))


def test_the_wrong_side_is_refused_naming_slider_side_and_the_flip_works():
    with pytest.raises(DesignError) as info:
        design_rolling(base_req(law="constant", travel=-50.43))
    (flip,) = [r for r in info.value.relax if r.name == "slider_side"]
    assert flip.needed == -1 and "slider_side from 1 to -1" in str(info.value) and "%" not in flip.text()
    req = base_req(law="constant", travel=-50.43)
    req["slider_side"] = -1
    assert design_rolling(req).report.requirement("working_side").met


def test_a_stroke_beyond_the_working_range_names_the_range():
    req = base_req(law="constant", travel=60)
    req["stroke"] = {"from": 0.0, "to": -0.9}
    with pytest.raises(DesignError, match="Reachable range"):
        design_rolling(req)


def test_cli_writes_a_scene_that_validates_exports_and_reads_back(tmp_path, capsys, constant_design):
    req = tmp_path / "req.json"
    req.write_text(json.dumps(base_req(law="constant", travel=50.43)))
    out = tmp_path / "lever.json"
    assert main(["design", "rolling", str(req), "--out", str(out), "--id", "press"]) == 0
    text = capsys.readouterr().out
    assert "pure rolling" in text and "S5 reproduced" in text and "binding" in text
    (el,) = load_scene(out).elements
    assert el.id == "press" and el.slider_law is not None and el.slider_circle is None
    assert el.slider_law == constant_design.element.slider_law and el.stroke == constant_design.element.stroke
    assert main(["validate", str(out)]) == 0
    assert main(["synthesize", str(out), "--summary"]) == 0
    summary = capsys.readouterr().out
    assert "slider law S5(θ): constant, travel 50.43 mm" in summary and "pure rolling" in summary
    dxf = tmp_path / "lever.dxf"
    assert main(["export", str(out), "--dxf", str(dxf)]) == 0
    doc = ezdxf.readfile(dxf)
    assert not doc.audit().has_errors
    assert {"frame", "lever", "slider"} <= {e.dxf.layer for e in doc.modelspace()}
    checks = check_parts(element_parts(el).parts, 1.0)
    assert all(c.ok for c in checks)


def test_malformed_requests_list_every_problem():
    with pytest.raises(DesignError) as info:
        design_rolling({"pin": [0, 0], "colour": 1})
    msg = str(info.value)
    assert "unknown key 'colour'" in msg and "slider_law is required" in msg
    req = base_req(table=[[0.0, 0.0], [-0.1, 1.0], [-0.1, 2.0], [-0.5926, 5.0]])
    with pytest.raises(DesignError, match="strictly increasing or decreasing"):
        design_rolling(req)
    req = base_req(law="constant", travel=10)
    req["slider_circle"] = {"center": [0, 0], "radius": 5}
    with pytest.raises(DesignError, match="no slider_circle"):
        design_rolling(req)
