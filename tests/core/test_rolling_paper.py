"""The paper's compass construction beside the exact method: the table of the notes (default
scene) reproduced, the plateau of the literal construction (flaw C1), the N⁻² convergence of the
corrected construction and of the exact profile's discrete measures."""
from __future__ import annotations

import numpy as np
import pytest

import test_rolling_reference as ref
from mechsketch.core.analyses.rolling.report import summary
from mechsketch.core.analyses.rolling.synthesis import error_table, slip_report, synthesize

NS = (4, 16, 64, 512)

# notes, section C, "Results, default scene"
LITERAL_ARC = {4: 8.6e-2, 16: 5.4e-3, 64: 3.4e-4, 512: 5.3e-6}
LITERAL_SLIP = {4: 1.119, 16: 1.018, 64: 1.011, 512: 1.0107}
LITERAL_PHYSICAL = {4: 0.126, 16: 0.079, 64: 0.0731, 512: 0.0726}  # θ ∈ [0, −0.3]
CORRECTED_SLIP = {4: 5.9e-2, 16: 3.7e-3, 64: 2.3e-4, 512: 3.6e-6}
CORRECTED_PHYSICAL = {4: 6.9e-2, 16: 6.8e-3, 64: 4.8e-4}
EXACT_PHYSICAL = {4: 5.1e-2, 16: 3.9e-3, 64: 2.5e-4}


@pytest.fixture(scope="module")
def results():
    el = ref.element()
    out = {}
    for m in ("paper", "corrected", "exact"):
        for n in NS:
            res = synthesize(el, m, n, measures=False)
            out[m, n] = (res, slip_report(res, physical_range=(0.0, -0.3), refine=False))
    return out


@pytest.mark.parametrize("n", NS)
def test_literal_construction_reproduces_the_notes(results, n):
    _, rep = results["paper", n]
    assert abs(rep.points.arc_mismatch) == pytest.approx(LITERAL_ARC[n], rel=0.03)
    assert rep.points.kinematic_slip == pytest.approx(LITERAL_SLIP[n], abs=6e-4 if n < 512 else 6e-5)
    assert rep.physical.slip == pytest.approx(LITERAL_PHYSICAL[n], rel=0.01 if n > 4 else 0.003)
    assert rep.points.ic_offset == pytest.approx(10.1, abs=0.1)  # "its IC offset stays at 10.1 mm"
    assert rep.points.deviation == pytest.approx(2.2, abs=0.05)  # "deviates 2.2 mm from the exact centrode"


def test_literal_construction_levels_off(results):
    slips = [results["paper", n][1].points.kinematic_slip for n in NS]
    assert slips[-1] == pytest.approx(1.0107, abs=1e-4)
    assert slips[-1] / slips[-2] > 0.99  # 64 -> 512 points: no improvement
    assert slips[-1] / results["exact", 4][1].points.kinematic_slip > 10  # worse than the exact method at N = 4
    # relative: 2.3 % of the rolled length, and 0.35 % physically
    assert slips[-1] / 43.5558 == pytest.approx(0.023, abs=0.001)  # the centrode is 43.56 mm long
    phys = results["paper", 512][1].physical
    assert phys.rolled == pytest.approx(21, abs=0.3) and phys.ratio == pytest.approx(0.0035, abs=0.0001)


@pytest.mark.parametrize("n", NS)
def test_corrected_construction_reproduces_the_notes(results, n):
    _, rep = results["corrected", n]
    assert rep.points.kinematic_slip == pytest.approx(CORRECTED_SLIP[n], rel=0.05)
    assert rep.points.ic_offset < 1e-12  # its centres are instant centres
    if n in CORRECTED_PHYSICAL:
        assert rep.physical.slip == pytest.approx(CORRECTED_PHYSICAL[n], rel=0.05)


@pytest.mark.parametrize("n", (4, 16, 64))
def test_exact_points_on_a_spline_reproduce_the_notes_physical_slip(results, n):
    assert results["exact", n][1].physical.slip == pytest.approx(EXACT_PHYSICAL[n], rel=0.05)


def test_convergence_orders():
    """Slopes of log(error) against log(N): −2 for the corrected construction and for the exact
    profile's discrete measures, about 0 for the literal construction (its plateau)."""
    ns = (16, 32, 64, 128, 256)
    rows = error_table(ref.element(), ns=ns, methods=("paper", "corrected", "exact"), repeat=1)

    def slope(method, attr):
        ys = [getattr(r, attr) for r in rows if r.method == method]
        return np.polyfit(np.log(ns), np.log(np.abs(ys)), 1)[0]

    assert slope("corrected", "kinematic_slip") == pytest.approx(-2.0, abs=0.05)
    assert slope("exact", "kinematic_slip") == pytest.approx(-2.0, abs=0.05)
    assert slope("exact", "arc_mismatch") == pytest.approx(-2.0, abs=0.05)
    assert slope("exact", "physical_slip") == pytest.approx(-2.0, abs=0.25)
    assert abs(slope("paper", "kinematic_slip")) < 0.01
    # the exact profile's points lie on the exact centrode whatever N; the paper's never do
    assert max(r.deviation for r in rows if r.method == "exact") < 1e-9
    assert min(r.deviation for r in rows if r.method == "paper") > 2.0
    assert max(r.continuous_slip for r in rows if r.method == "exact") < 1e-9


def test_pair_e_of_the_paper_construction_uses_its_own_poses(results):
    res, _ = results["paper", 64]
    # the paper's poses reach only θ ≈ −0.364 where the exact motion reaches the same lever arc
    # at −0.5926, so its slider travel falls short of the exact 50.44 mm
    assert res.theta[-1] == pytest.approx(-0.3637, abs=1e-3)
    assert res.S5[-1] < 40.0
    exact, _ = results["exact", 64]
    assert exact.S5[-1] == pytest.approx(50.4371, abs=1e-4)
    # S5 is the trapezoidal integral of k53 over the construction's θ_k
    trap = np.concatenate([[0], np.cumsum(0.5 * (res.k53[1:] + res.k53[:-1]) * np.diff(res.theta))])
    assert np.allclose(res.S5, trap, atol=1e-12)


def test_summary_says_plainly_that_the_paper_levels_off():
    res = synthesize(ref.element(method="paper", points=64))
    text = summary(res)
    assert "levels off" in text and "use method 'exact'" in text
    assert "1.011" in text  # its kinematic slip with N = 64
    res = synthesize(ref.element(method="corrected", points=64))
    assert "converges as N⁻²" in summary(res)


def test_constructions_close_to_the_end_of_the_working_range():
    """The literal construction cannot follow the lever to the rocker's tangency and says so; the
    corrected one can: its Newton iteration stops where its steps stall at round-off (the 2×2
    system is ill-conditioned there). It used to demand steps below 1e-15 rad and failed, e.g. at
    step 365 of 400 with the stroke ending 1e-6 rad before the tangency, 0.0125 rad before it."""
    from mechsketch.core.analyses.rolling.exact import working_range
    from mechsketch.core.analyses.rolling.geometry import LeverGeometry
    from mechsketch.core.errors import GeometryError

    lim = working_range(LeverGeometry.from_element(ref.element())).lower
    el = ref.element(stroke={"from": 0.0, "to": lim + 1e-7})
    with pytest.raises(GeometryError, match=r"the paper's construction fails at step 7\d of 100: the circle about P_7\d"):
        synthesize(el, "paper", 100, measures=False)
    near = ref.element(stroke={"from": 0.0, "to": lim + 1e-6})
    dev = [synthesize(near, "corrected", n).slip.points.deviation for n in (100, 200, 400)]
    assert dev[0] / dev[1] == pytest.approx(4.0, abs=0.1) and dev[1] / dev[2] == pytest.approx(4.0, abs=0.1)
    assert dev[2] < 1e-4  # mm from the exact centrode: N⁻² right up to the tangency
    assert synthesize(el, "exact", 100).slip.continuous.worst < 1e-9  # the exact method gets there
    # a stroke the paper's construction draws with N = 100 but not with 2N: the summary says so
    res = synthesize(ref.element(stroke={"from": 0.0, "to": -0.6993}), "paper", 100)
    assert res.slip.refined is None
    assert "note: with N = 200 points the paper's construction fails at step 200 of 200" in summary(res)
