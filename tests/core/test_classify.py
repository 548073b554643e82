"""Classification in the diagnostics (issue 10 item 5): Grashof and the four-bar's type, the
slider-crank's kind, and each output's stroke and time ratio against closed forms (the textbook
limit positions: links collinear, a guide tangent to the crank circle, the law of cosines)."""
from __future__ import annotations

import cmath
import math

import pytest

import drive_builders as DB
import linkage_builders as LB
from mechsketch.core.analyses.classify import classification, fourbar_type, output_motions
from mechsketch.core.solver.plan import compile_plan


def lines_of(lk, samples=360):
    plan = compile_plan(lk)
    return classification(lk, plan, plan.sweep(samples))


def motion(lk, link, samples=360):
    plan = compile_plan(lk)
    return next(m for m in output_motions(lk, plan, plan.sweep(samples)) if m.link == link)


@pytest.mark.parametrize("lengths,cls,kind", [
    ((160, 40, 140, 120), "Grashof", "crank-rocker"),
    ((30, 60, 70, 80), "Grashof", "double crank"),
    ((100, 80, 30, 110), "Grashof", "double rocker"),
    ((100, 80, 110, 30), "Grashof", "rocker-crank"),
    ((110, 90, 95, 85), "non-Grashof", "triple rocker"),
    ((100, 40, 100, 40), "change point", "crank-rocker with change points"),
    ((120, 40, 150, 70), "change point", "crank-rocker with change points"),
])
def test_four_bar_types_follow_grashof_and_the_shortest_link(lengths, cls, kind):
    c, k = fourbar_type(*lengths)
    assert c.startswith(cls) and k.startswith(kind)


def test_a_crank_rocker_swings_and_returns_as_its_limit_positions_say():
    """Limit positions: crank and coupler in line, |AC| = b ± a; the crank angles between them
    give the time ratio at constant speed."""
    a, b, c, d = 40.0, 140.0, 120.0, 160.0
    text = "\n".join(lines_of(LB.fourbar()))
    assert "Grashof (s + l = 200 < p + q = 260 mm); crank-rocker" in text

    def limit(r):   # C where |AC| = r, C above AD; crank along ±AC
        x = (r * r + d * d - c * c) / (2 * d)
        return complex(x, math.sqrt(r * r - x * x))
    Cx, Cf = limit(b + a), limit(b - a)
    rocker = lambda C: cmath.phase(C - d)   # noqa: E731
    swing = math.degrees(rocker(Cf) - rocker(Cx))
    m = motion(LB.fourbar(), "rocker")
    assert math.degrees(m.travel) == pytest.approx(swing, abs=1e-9)
    assert f"swings {swing:.4f}°" in text
    th_ext, th_fold = cmath.phase(Cx), cmath.phase(Cf) + math.pi   # crank at the extended / folded limit
    out = (th_ext - th_fold) % (2 * math.pi)     # rocker angle grows from folded to extended? check both
    ratio = m.time_ratio
    assert min(ratio, 1 / ratio) == pytest.approx(min(out, 2 * math.pi - out) / max(out, 2 * math.pi - out),
                                                  abs=1e-7)
    assert m.t_out + m.t_back == pytest.approx(60 / 95.4929658551372, rel=1e-15)


def test_an_offset_slider_crank_has_the_textbook_stroke_and_quick_return():
    r, l, e = 40.0, 160.0, 20.0
    text = "\n".join(lines_of(LB.slider_crank(crank=r, rod=l, offset=e)))
    assert "slider-crank: offset (e = 20 mm)" in text and "the crank turns fully" in text
    stroke = math.sqrt((l + r) ** 2 - e * e) - math.sqrt((l - r) ** 2 - e * e)
    m = motion(LB.slider_crank(crank=r, rod=l, offset=e), "slider")
    assert m.travel == pytest.approx(stroke, abs=1e-9)
    alpha = math.asin(e / (l - r)) - math.asin(e / (l + r))
    ratio = m.time_ratio
    assert max(ratio, 1 / ratio) == pytest.approx((math.pi + alpha) / (math.pi - alpha), abs=1e-7)
    centric = "\n".join(lines_of(LB.slider_crank(crank=r, rod=l, offset=0.0)))
    assert "slider-crank: centric" in centric
    assert motion(LB.slider_crank(crank=r, rod=l, offset=0.0), "slider").time_ratio == pytest.approx(1.0, abs=1e-7)


def test_an_inverted_slider_crank_guide_swings_and_returns_quickly():
    r, dist = 40.0, 100.0
    text = "\n".join(lines_of(LB.inverted_slider_crank(crank=r, ground=dist)))
    assert "the guide swings" in text
    m = motion(LB.inverted_slider_crank(crank=r, ground=dist), "rocker")
    assert m.travel == pytest.approx(2 * math.asin(r / dist), abs=1e-9)
    short = 2 * math.acos(r / dist)   # crank angle between the two tangent positions, near side
    ratio = m.time_ratio
    assert max(ratio, 1 / ratio) == pytest.approx((2 * math.pi - short) / short, abs=1e-7)


def test_an_actuator_arm_states_its_stroke_and_its_boom_swing():
    lk = DB.excavator()
    text = "\n".join(lines_of(lk))
    assert "input: cylinder between two pivots ('barrel' on 'P'), stroke 850 to 1250 mm (400 mm), law cycloidal" in text
    c1, c2 = complex(800, -550), complex(1200, 350)
    a, b = abs(c1), abs(c2)
    gamma = [math.acos((a * a + b * b - L * L) / (2 * a * b)) for L in (850.0, 1250.0)]
    m = motion(lk, "boom")
    assert m.travel == pytest.approx(gamma[1] - gamma[0], abs=1e-9)
    assert m.t_out == pytest.approx(5.0, abs=1e-4) and m.time_ratio == pytest.approx(1.0, abs=1e-4)


def test_the_summary_carries_the_classification():
    from mechsketch.core import Workspace
    from mechsketch.resources import example_path
    text = Workspace.open(example_path("double_rocker"))["double_rocker"].summary()
    assert "non-Grashof" in text and "triple rocker" in text
    text = Workspace.open(example_path("excavator_arm"))["arm"].summary()
    assert "drawn input 984.8858 mm" in text and "reachable: the whole stroke, 850 to 1250 mm" in text
