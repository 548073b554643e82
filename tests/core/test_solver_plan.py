"""The plan/solution API: sweeps (start, direction, time), "model only what a scene needs",
link angles, NaN + valid where a group cannot be assembled, transmission angle, conditioning."""
from __future__ import annotations

import math

import numpy as np
import pytest

import linkage_builders as LB
import solution_checks as CK
from mechsketch.core import Linkage, load_scene
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


def example(name: str) -> Linkage:
    return load_scene(example_path(name)).elements[0]


# -- model only what a scene needs ---------------------------------------------------------------
def _counting(plan):
    """Wrap every step of ``plan`` so that the names of the groups run are recorded."""
    ran: list[str] = []
    for step in plan.steps:
        def run(states, order, flip=None, _f=step.run, _n=step.group.name):
            ran.append(_n)
            return _f(states, order, flip)
        step.run = run
    return ran


@pytest.mark.parametrize("joints,expected", [
    (["C"], ["RRR(coupler,rocker)"]),
    (["E"], ["RRP(rod,slider)"]),
    (["S"], ["RRP(rod,slider)"]),
    (["A", "B", "D"], []),
    (["C", "S"], ["RRR(coupler,rocker)", "RRP(rod,slider)"]),
    (None, ["RRR(coupler,rocker)", "RRP(rod,slider)"]),
])
def test_only_the_groups_the_requested_joints_depend_on_are_evaluated(joints, expected):
    lk = LB.two_dyads()
    plan = compile_plan(lk)
    ran = _counting(plan)
    x = np.linspace(0.0, 2 * math.pi, 50)
    sol = plan.evaluate(x, order=2, joints=joints)
    assert sorted(g.name for g in sol.groups) == sorted(expected)
    assert set(ran) == set(expected)  # (branch points are searched on the same groups only)
    full = compile_plan(lk).evaluate(x, order=2)
    for j in joints or lk.joint_ids:
        for f in ("position", "velocity", "acceleration"):
            assert np.array_equal(getattr(sol, f)(j), getattr(full, f)(j), equal_nan=True), (j, f)
    unsolved = {lk for g in full.groups if g.name not in expected for lk in (g.link_i, g.link_j)}
    for link in unsolved:
        with pytest.raises(KeyError, match="not solved"):
            sol.angle(link)


def test_dependencies_through_a_moving_guide_and_a_compound_hinge():
    six = compile_plan(example("sixbar_moving_guide"))
    assert [g.name for g in six.evaluate([0.3], joints=["C"]).groups] == ["RRR(coupler,rocker)"]
    # the block slides on the rocker: E needs the four-bar first
    assert [g.kind for g in six.evaluate([0.3], joints=["E"]).groups] == ["RRR", "RRP"]
    comp = compile_plan(LB.sixbar_compound())
    assert [g.kind for g in comp.evaluate([0.3], joints=["C"]).groups] == ["RRR"]
    assert [g.kind for g in comp.evaluate([0.3], joints=["S"]).groups] == ["RRR", "RRP"]
    with pytest.raises(KeyError, match="no joint"):
        comp.evaluate([0.3], joints=["nope"])


def test_public_one_line_api():
    scene = load_scene(example_path("slider_crank_offset"))
    sol = compile_plan(scene.element("slider_crank")).sweep(samples=90, order=2)
    assert len(sol) == 90 and sol.valid.all()
    for f, shape in (("position", (90, 2)), ("velocity", (90, 2)), ("acceleration", (90, 2))):
        assert getattr(sol, f)("C").shape == shape
    for f in ("angle", "omega", "alpha"):
        assert getattr(sol, f)("rod").shape == (90,)
    assert sol.input.shape == sol.valid.shape == (90,)
    part = compile_plan(scene.element("slider_crank")).sweep(samples=90, order=0, joints=["B"])
    assert part.groups == []
    assert np.array_equal(part.position("B"), sol.position("B"))


# -- sweeps ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("rpm", [95.4929658551372, -30.0])
def test_sweep_starts_at_drawn_pose_and_follows_the_driver(rpm):
    lk = LB.fourbar(theta0=135.0, rpm=rpm)
    n = 72
    sol = compile_plan(lk).sweep(samples=n)
    sgn = math.copysign(1.0, rpm)
    assert sol.input[0] == pytest.approx(math.radians(135.0), abs=1e-15)
    assert np.allclose(np.diff(sol.input), sgn * 2 * math.pi / n, rtol=0, atol=1e-13)
    period = 60.0 / abs(rpm)
    assert np.allclose(sol.t, np.arange(n) * period / n, rtol=1e-14, atol=0)
    # the crank pin really turns that way: its angular velocity has the driver's sign
    assert np.all(np.sign(sol.omega("crank")) == sgn)
    B = sol.position("B")
    ang = np.unwrap(np.arctan2(B[:, 1], B[:, 0]))
    assert np.allclose(ang, sol.input, atol=1e-13)
    assert np.allclose(sol.velocity("B"), sgn * abs(lk.driver.omega) * 40.0 *
                       np.column_stack([-np.sin(sol.input), np.cos(sol.input)]), atol=1e-11)


def test_sweep_argument_errors():
    plan = compile_plan(LB.fourbar())
    with pytest.raises(ValueError, match="samples"):
        plan.sweep(samples=1)
    with pytest.raises(ValueError, match="order"):
        plan.evaluate([0.0], order=3)


def test_evaluate_shapes_and_time():
    plan = compile_plan(LB.fourbar())
    s = plan.evaluate(1.0, order=1)
    assert s.position("C").shape == (1, 2)
    x = [1.0, 1.5, 2.0]
    s = plan.evaluate(x, order=1, omega=2.0)
    assert np.allclose(s.t, [0.0, 0.25, 0.5])
    assert np.allclose(s.omega("crank"), 2.0)
    assert np.allclose(s.velocity("B"), 2.0 * 40.0 * np.column_stack([-np.sin(x), np.cos(x)]), atol=1e-12)


# -- link angles -----------------------------------------------------------------------------------
def test_link_angles_are_first_to_second_joint_and_unwrapped():
    lk = LB.fourbar(crank=60, coupler=110, rocker=100, ground=30, theta0=160, rpm=-45.0)  # drag link
    sol = compile_plan(lk).sweep(samples=360)
    for link in lk.moving_links:
        a, b = lk.link(link).joints[:2]
        d = sol.position(b) - sol.position(a)
        ang = sol.angle(link)
        assert np.allclose(np.angle(np.exp(1j * (ang - np.arctan2(d[:, 1], d[:, 0])))), 0, atol=1e-13)
        assert np.all(np.abs(np.diff(ang)) < 0.2)       # unwrapped
        assert abs(ang[0] - math.atan2(*(np.subtract(lk.joint(b).at, lk.joint(a).at)[::-1]))) < 1e-13
    # a drag link: every link turns once, clockwise, over the revolution
    for link in lk.moving_links:
        s = CK.link_rotation(sol, lk, link)
        turns = np.unwrap(np.angle(s))
        total = turns[-1] - turns[0] + (turns[1] - turns[0])
        assert total == pytest.approx(-2 * math.pi, abs=0.05)


def test_angle_of_a_block_whose_joints_coincide_is_its_rotation():
    lk = example("sixbar_moving_guide")   # block (E, Q): both at the same drawn point
    sol = compile_plan(lk).sweep(samples=120)
    assert np.allclose(sol.angle("block"), sol.angle("rocker") - sol.angle("rocker")[0], atol=1e-13)
    # the driver listed tip-first: its angle is input + π
    flipped = lk.with_link(lk.link("crank").__class__("crank", ("B", "A")))
    s2 = compile_plan(flipped).sweep(samples=120)
    assert np.allclose(np.angle(np.exp(1j * (s2.angle("crank") - s2.input - math.pi))), 0, atol=1e-13)
    assert np.allclose(np.diff(s2.angle("crank")), np.diff(s2.input), atol=1e-13)
    assert np.allclose(s2.position("E"), sol.position("E"), atol=1e-12)


def test_coupler_point_moves_with_its_link():
    lk = example("fourbar_crank_rocker")
    sol = compile_plan(lk).sweep(samples=90)
    E0, B0, C0 = (complex(*lk.joint(j).at) for j in "EBC")
    B, C, E = (CK._z(sol.position(j)) for j in "BCE")
    expect = B + (C - B) * (E0 - B0) / (C0 - B0)
    assert np.max(np.abs(E - expect)) < 1e-12
    assert np.allclose(sol.point("coupler", lk.joint("E").at), sol.position("E"), atol=0)


# -- infeasible samples ------------------------------------------------------------------------------
def test_double_rocker_gap_is_nan_and_invalid_exactly_where_it_cannot_assemble():
    lk = example("double_rocker")
    sol = compile_plan(lk).sweep(samples=720)
    at = {j.id: complex(*j.at) for j in lk.joints}
    r, g = abs(at["B"] - at["A"]), abs(at["D"] - at["A"])
    reach = abs(at["C"] - at["B"]) + abs(at["C"] - at["D"])
    lim = math.acos((r * r + g * g - reach * reach) / (2 * r * g))
    expect = np.abs(np.angle(np.exp(1j * sol.input))) < lim
    assert np.array_equal(sol.valid, expect)
    bad = ~sol.valid
    assert bad.sum() > 100
    for j in ("B", "C"):
        for f in ("position", "velocity", "acceleration"):
            arr = getattr(sol, f)(j)
            assert np.isnan(arr[bad]).all() and np.isfinite(arr[~bad]).all(), (j, f)
    for link in ("coupler", "output"):
        for f in ("angle", "omega", "alpha"):
            arr = getattr(sol, f)(link)
            assert np.isnan(arr[bad]).all() and np.isfinite(arr[~bad]).all(), (link, f)
    assert CK.closure_error(lk, sol) < 1e-12
    assert np.isfinite(sol.residual()) and sol.residual() < 1e-12


def test_slider_crank_that_cannot_turn_fully():
    lk = LB.slider_crank(crank=40.0, rod=30.0, offset=20.0, theta0=10.0)
    sol = compile_plan(lk).sweep(samples=720)
    # B_y − e must stay within ±rod: sin θ ∈ [(e − rod)/r, (e + rod)/r] = [−0.25, 1.25]
    expect = np.sin(sol.input) >= -0.25
    assert np.array_equal(sol.valid, expect)
    assert np.isnan(sol.position("S")[~expect]).all()


# -- transmission angle and conditioning ------------------------------------------------------------
def test_transmission_angle_and_conditioning_of_the_crank_rocker():
    lk = example("fourbar_crank_rocker")
    sol = compile_plan(lk).sweep(samples=360)
    g = sol.groups[0].name
    mu = sol.transmission_angle(g)
    B, C, D = (CK._z(sol.position(j)) for j in "BCD")
    expect = np.abs(np.angle((B - C) / (D - C)))
    assert np.allclose(mu, expect, atol=1e-13)
    assert np.allclose(sol.conditioning(g), np.sin(mu), atol=1e-13)
    # extremes at θ = 0 and π (both sampled): cos μ = (b² + c² − (d ∓ a)²) / 2bc
    lo = math.degrees(math.acos((140 ** 2 + 120 ** 2 - 120 ** 2) / (2 * 140 * 120)))
    hi = math.degrees(math.acos((140 ** 2 + 120 ** 2 - 200 ** 2) / (2 * 140 * 120)))
    assert np.degrees(mu.min()) == pytest.approx(lo, abs=1e-6)
    assert np.degrees(mu.max()) == pytest.approx(hi, abs=1e-6)
    with pytest.raises(ValueError, match="RRR"):
        s2 = compile_plan(example("slider_crank_offset")).sweep(samples=10)
        s2.transmission_angle(s2.groups[0].name)


@pytest.mark.parametrize("case", ["slider", "inverted", "prp", "yoke"])
def test_conditioning_of_other_kinds_is_the_sine_between_the_velocity_columns(case):
    lk = {"slider": lambda: LB.slider_crank(xi=150.0, pin=2 + 3j), "inverted": lambda: LB.inverted_slider_crank(offset=7.0),
          "prp": lambda: LB.prp_linkage(), "yoke": lambda: LB.scotch_yoke(slot=120.0, guide=200.0)}[case]()
    sol = compile_plan(lk).sweep(samples=90)
    g = sol.groups[0]
    c = sol.conditioning(g.name)
    ok = sol.valid
    if g.kind == "RRP":    # |cos(φ_rod − ξ)|
        rod = CK._z(sol.position(g.inner)) - CK._z(sol.position(g.outer_i))
        u = CK.link_rotation(sol, lk, g.link_j) * LB.e(lk.joint(g.outer_j).axis_deg)
        expect = np.abs((np.conj(u) * rod).real) / np.abs(rod)
    elif g.kind == "RPR":  # |σ| (along-axis part of M − H) over the drawn size max(|M0 − H0|, |offset|)
        d = CK._z(sol.position(g.outer_i)) - CK._z(sol.position(g.outer_j))
        u = CK.link_rotation(sol, lk, g.link_j) * LB.e(lk.joint(g.inner).axis_deg)
        d0 = complex(*lk.joint(g.outer_i).at) - complex(*lk.joint(g.outer_j).at)
        off = (np.conj(LB.e(lk.joint(g.inner).axis_deg)) * d0).imag
        expect = np.minimum(np.abs((np.conj(u) * d).real) / max(abs(d0), abs(off)), 1.0)
    else:                  # |sin| between the two slide axes
        first = (g.known_i, g.outer_i) if g.kind == "PRP" else (g.link_j, g.inner)
        ua = CK.link_rotation(sol, lk, first[0]) * LB.e(lk.joint(first[1]).axis_deg)
        ub = CK.link_rotation(sol, lk, g.known_j) * LB.e(lk.joint(g.outer_j).axis_deg)
        expect = np.abs(CK.cross2_arr(ua, ub))
    assert np.allclose(np.broadcast_to(c, expect.shape)[ok], expect[ok], atol=1e-13)


def test_compile_plan_twice_gives_the_same_plan():
    lk = LB.fourbar()
    a, b = compile_plan(lk), compile_plan(lk)
    x = np.linspace(0, 6, 7)
    assert np.array_equal(a.evaluate(x).position("C"), b.evaluate(x).position("C"))
    assert a.mobility == 1


@pytest.mark.parametrize("case", ["outer joints coincide", "overflowing coordinates"])
def test_valid_samples_are_finite(case):
    """A sample marked valid has finite positions: where a kernel's arithmetic breaks down (the
    RRR's outer joints exactly coincident: direction 0/0; lengths of 1e154 mm: squares overflow),
    the sample is reported as not assembled rather than as a valid NaN pose."""
    if case == "outer joints coincide":   # crank = ground: drawn with the crank pin B exactly on D
        lk = LB.build("rhombus", [("A", "R", (0.0, 0.0)), ("B", "R", (60.0, 0.0)), ("C", "R", (90.0, 51.9615242)),
                                 ("D", "R", (60.0, 0.0))],
                     {"ground": ["A", "D"], "crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
                     "ground", "crank", "A")
        sol = compile_plan(lk).evaluate(np.array([0.0, 0.5]), order=2)
        assert list(sol.valid) == [False, True]
    else:
        from dataclasses import replace
        lk = LB.fourbar()
        lk = replace(lk, joints=tuple(j.moved((j.at[0] * 1e154, j.at[1] * 1e154)) for j in lk.joints))
        sol = compile_plan(lk).sweep(samples=12)
    for j in lk.joint_ids:
        assert np.isfinite(sol.position(j)[sol.valid]).all(), j
    for g in sol.groups:
        assert not (sol.feasible(g.name) & ~sol.valid).any()
    assert np.isnan(sol.position("C")[~sol.valid]).all()


def test_residual_sees_a_stretched_link(monkeypatch):
    """The reported loop-closure residual must notice a kernel that keeps the joints shared but
    gets a link's length wrong: the inner point L moved consistently for both links (as a broken
    kernel computing a wrong L would), so only the links' rigidity shows it."""
    from mechsketch.core.solver import kernels

    lk = LB.fourbar()
    m0, h0, l0 = (complex(*lk.joint(j).at) for j in "BDC")
    real = kernels.rrr

    def stretched(*a, **k):
        out = real(*a, **k)
        M, H = out.state_i.A, out.state_j.A
        L = M + (1 + 1e-6) * out.state_i.rot * (l0 - m0)      # coupler 1 ppm too long
        out.state_i.rot = (L - M) / (l0 - m0)
        out.state_j.rot = (L - H) / (l0 - h0)
        return out
    monkeypatch.setattr(kernels, "rrr", stretched)
    sol = compile_plan(lk).sweep(samples=36)
    assert CK.closure_error(lk, sol) > 1e-4            # 140 mm · 1e-6
    assert sol.residual() > 1e-4
