"""The batch engine (core/studies) against the one-design path, design by design.

Every design of a batch is compared with ``compile_plan(design).sweep(N, order)`` of the same
design (its drawn geometry from the batch's re-assembly, :func:`design_linkage`): positions,
velocities, accelerations of every joint, angles and rates of every link, the validity masks.
Hard cases on purpose: every group kind (RRR, RRP, RPR, PRP, RPP, guides on moving links, fixed
groups), every driver (crank, slider, cylinder) and motion law, parallelograms through their
change points (branch points), toggles and assembly limits, guides that pass through parallel,
extreme ratios, and designs that do not assemble. The re-assembly itself is compared with
:func:`set_dimension` applied key by key, and pivot and coupler-point edits with an independent
construction.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import drive_builders as DB
import linkage_builders as LB
from mechsketch.core.errors import EditError, RequestError
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.dimensions import set_dimension
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.studies.geometry import build_geometry, design_linkage
from mechsketch.core.studies.keys import variables
from mechsketch.core.studies.variants import solve_variants
from mechsketch.core.workspace import Workspace
from test_fixed_groups import CASES as FIXED_CASES

EXAMPLES = "resources/examples"


def example(name: str, element: str):
    return Workspace.open(f"{EXAMPLES}/{name}.json").element(element)


def size(lk) -> float:
    return max(abs(complex(*j.at)) for j in lk.joints) + LB.size_of(lk)


def rounding(sol, w: int) -> np.ndarray:
    """(N,) the one-design path's own relative rounding error of a quantity of derivative order
    ``w`` at each sample, 8·eps·(1 + coordinates/size)/cond^(w+1) over its groups (the estimate
    behind ``Solution.rates_valid``): large only within rounding of a toggle or of parallel guides."""
    eps = np.finfo(float).eps
    est = np.zeros(len(sol))
    with np.errstate(divide="ignore", invalid="ignore"):
        for step in sol.plan.steps:
            if step.group.fixed:
                continue
            c = np.abs(np.broadcast_to(sol.conditioning(step.group.name), est.shape))
            est = np.maximum(est, 8 * eps * (1 + step.coord / step.scale) / c ** (w + 1))
    return np.where(np.isfinite(est), est, np.inf)


def compare(lk, b, d: int, samples: int, order: int, tol: float = 1e-12) -> float:
    """Design ``d`` of batch ``b`` against the one-design sweep; returns the worst relative error.

    Each quantity agrees to ``tol`` of its size (positions: the mechanism's size; rates: their
    largest magnitude over the cycle) at every sample, or — at samples within rounding of a
    toggle or of parallel guides, where the one-design path itself is only as accurate as its
    conditioning allows — to 100 times that path's own rounding estimate (:func:`rounding`)."""
    geo = build_geometry(lk, b.plan.plan, {k: v[d:d + 1] for k, v in b.values.items()}, 1)
    assert geo.ok[0] == b.assembled[d]
    if not geo.ok[0]:
        assert not b.valid[d].any() and np.isnan(b.position(lk.joint_ids[0])[d]).all()
        return 0.0
    one = design_linkage(geo, 0)
    sol = compile_plan(one).sweep(samples, order)
    assert np.array_equal(sol.valid, b.valid[d]), f"design {d}: valid differs"
    assert np.array_equal(sol.singular, b.singular[d])
    if order:
        assert np.array_equal(sol.rates_valid, b.rates_valid[d]), f"design {d}: rates_valid differs"
    v, rv = sol.valid, sol.rates_valid
    s = size(one)
    allow = [np.maximum(tol, 100 * rounding(sol, w)) for w in range(order + 1)]
    worst = 0.0

    def check(got, ref, mask, scale, w, what):
        nonlocal worst
        if not mask.any():
            return
        err = np.abs(got[mask] - ref[mask]) / scale
        err = err.max(axis=-1) if err.ndim > 1 else err
        assert (err <= allow[w][mask]).all(), f"design {d} {what}: {err.max():.2e}"
        worst = max(worst, float(err[allow[w][mask] <= tol].max(initial=0.0)))

    for j in lk.joint_ids:
        got = b.position(j)[d]
        assert np.isnan(got[~v]).all()
        check(got, sol.position(j), v, s, 0, f"{j} position")
        for w, fn, bf in ((1, sol.velocity, b.velocity), (2, sol.acceleration, b.acceleration)):
            if order >= w and rv.any():
                ref = fn(j)
                check(bf(j)[d], ref, rv, float(np.max(np.abs(ref[rv]))) + s * 1e-300, w, f"{j} rate {w}")
    for k in lk.moving_links:
        check(b.angle(k)[d], sol.angle(k), v, 1.0, 0, f"{k} angle")
        for w, fn, bf in ((1, sol.omega, b.omega), (2, sol.alpha, b.alpha)):
            if order >= w and rv.any():
                ref = fn(k)
                check(bf(k)[d], ref, rv, float(np.max(np.abs(ref[rv]))) + 1e-300, w, f"{k} rate {w}")
    assert worst <= tol
    return worst


def random_designs(lk, D: int, rel: float, seed: int, count: int = 4) -> dict:
    rng = np.random.default_rng(seed)
    keys = [v for v in variables(lk).values() if v.geometric]
    pick = rng.choice(len(keys), size=min(count, len(keys)), replace=False)
    out = {}
    for i in sorted(pick):
        v = keys[i]
        out[v.key] = v.nominal + rng.normal(size=D) * (rel * abs(v.nominal) + rel * 5)
    return out


CASES = {
    "fourbar": lambda: example("fourbar_crank_rocker", "fourbar"),
    "double_rocker": lambda: example("double_rocker", "double_rocker"),
    "sixbar_moving_guide": lambda: example("sixbar_moving_guide", "sixbar"),
    "slider_crank": lambda: example("slider_crank_offset", "slider_crank"),
    "inverted_slider_crank": lambda: example("inverted_slider_crank", "inverted_slider_crank"),
    "excavator_cylinder": lambda: example("excavator_arm", "arm"),
    "vengine_cycloidal": lambda: DB.vengine(kind="cycloidal"),
    "crank_point_table": lambda: DB.crank_with_point(kind="modified_trapezoid"),
    "prp": LB.prp_linkage,
    "rpp_yoke": LB.scotch_yoke,
    "rrp_on_crank": LB.crank_guided,
    "stephenson": LB.sixbar_stephenson,
    "rpr_on_moving": LB.rpr_on_moving_links,
    "rrp_on_coupler": LB.rrp_guide_on_coupler,
    "eight_bar": LB.eight_bar,
    "slider_driven": DB.pushed_crank,
    "cylinder_slider": DB.cylinder_slider,
    "fixed_groups": FIXED_CASES["fourbar_chain"],
    "fixed_rpr_on_pivot": FIXED_CASES["rpr_on_pivot"],
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_kind_driver_and_law_matches_the_one_design_path(case):
    lk = CASES[case]()
    vals = random_designs(lk, 4, 0.01, seed=len(case))
    b = solve_variants(lk, vals, samples=40, order=2, fast=False)
    for d in range(4):
        compare(lk, b, d, 40, 2)


def test_parallelogram_change_points_keep_each_design_on_its_branch():
    """Crank = rocker and coupler = ground: the change points at 0° and 180° of the crank are
    branch points (the samples hit them exactly); designs a hair off have none."""
    lk = LB.fourbar(crank=40.0, coupler=160.0, rocker=40.0, ground=160.0, theta0=60.0)
    vals = {"length:crank:A:B": np.array([40.0, 40.0, 39.0, 40.0 + 1e-9, 41.0]),
            "length:rocker:D:C": np.array([40.0, 40.5, 39.0, 40.0, 41.0])}
    b = solve_variants(lk, vals, samples=360, order=2, fast=False)
    branches = [compile_plan(design_linkage(build_geometry(lk, b.plan.plan, {k: v[d:d + 1] for k, v in vals.items()},
                                                           1), 0)).branch_points()["RRR(coupler,rocker)"].size
                for d in range(5)]
    assert branches == [2, 0, 2, 0, 2]
    for d in range(5):
        compare(lk, b, d, 360, 2, tol=1e-14)
        geo = build_geometry(lk, b.plan.plan, {k: v[d:d + 1] for k, v in vals.items()}, 1)
        sol = compile_plan(design_linkage(geo, 0)).sweep(360, 2)
        for j in lk.joint_ids:    # the same bits, at the change points too
            assert np.array_equal(sol.position(j), b.position(j)[d], equal_nan=True)
            assert np.array_equal(sol.velocity(j)[sol.rates_valid], b.velocity(j)[d][sol.rates_valid])
    # the parallelogram stays a parallelogram: C − B = D − A at every sample
    C, B = b.position("C")[0], b.position("B")[0]
    assert np.max(np.abs((C - B) - [160.0, 0.0])) < 1e-12 * 160


def test_toggles_limits_and_extreme_ratios():
    """A double rocker (assembly limits inside the cycle), a Grashof-equal crank-rocker touching
    its toggle (s + l = p + q), a crank 1e-3 of the frame, and a linkage a million mm away."""
    cases = [
        (example("double_rocker", "double_rocker"), {"length:input:A:B": np.array([90.0, 95.0, 60.0])}),
        (LB.fourbar(crank=40.0, coupler=140.0, rocker=120.0, ground=160.0),
         {"length:crank:A:B": np.array([40.0, 60.0, 100.0])}),   # 100 + 160 = 140 + 120: s + l = p + q
        (LB.fourbar(crank=0.16, coupler=160.0, rocker=159.9, ground=160.0),
         {"length:crank:A:B": np.array([0.16, 0.1, 0.05])}),
        (LB.fourbar(origin=complex(1e6, -2e6), rot=33.0), {"length:coupler:B:C": np.array([140.0, 139.0, 141.0])}),
    ]
    for lk, vals in cases:
        b = solve_variants(lk, vals, samples=90, order=2, fast=False)
        for d in range(3):
            compare(lk, b, d, 90, 2)


def test_guides_passing_through_parallel():
    """PRP and RPP groups whose two slide axes turn through parallel during the cycle (no
    intersection, then one far away), with the axes varied near parallel in the drawing too."""
    prp = LB.prp_linkage(xi=100.0)
    b = solve_variants(prp, {"axis:ground:Q2": np.array([100.0, 40.0 + 1e-3, 40.0 + 0.05])}, samples=72, order=2,
                       fast=False)
    assert (~b.valid).any()
    for d in range(3):
        compare(prp, b, d, 72, 2)
    yoke = LB.scotch_yoke()
    b = solve_variants(yoke, {"axis:yoke:Qg": np.array([-90.0, -0.05, -1e-4])}, samples=72, order=2, fast=False)
    for d in range(3):
        compare(yoke, b, d, 72, 2)


def test_designs_that_do_not_assemble_are_counted_with_the_one_design_reason():
    lk = example("fourbar_crank_rocker", "fourbar")
    vals = {"length:rocker:D:C": np.array([120.0, 3.0, 125.0, 500.0]), "length:crank:A:B": np.array([40.0, 40.0, -1.0, 40.0])}
    b = solve_variants(lk, vals, samples=36, order=1, fast=False)
    assert b.assembled.tolist() == [True, False, False, False]
    assert sum(b.failures().values()) == 3
    for d in (1, 3):   # the one-design edit refuses the same group
        with pytest.raises(EditError) as exc:
            set_dimension(lk, "length:rocker:D:C", float(vals["length:rocker:D:C"][d]))
        assert "RRR(coupler,rocker)" in str(exc.value) and "RRR(coupler,rocker)" in b.message(d)
    assert "must be positive" in b.message(2)
    assert np.isnan(b.position("E")[1:]).all() and not b.valid[1:].any() and not b.full_cycle[1:].any()
    assert np.isnan(b.min_transmission_angle[1:]).all()


def test_reassembly_agrees_with_set_dimension_key_by_key():
    for lk in (example("sixbar_moving_guide", "sixbar"), LB.sixbar_stephenson(), example("excavator_arm", "arm"),
               LB.rrp_guide_on_coupler()):
        rng = np.random.default_rng(7)
        dims = [v for v in variables(lk).values() if v.kind == "dimension"]
        keys = [dims[i] for i in rng.choice(len(dims), 3, replace=False)]
        ref = lk
        vals = {}
        for v in keys:
            x = v.nominal * (1.0 + 0.004) if v.unit == "mm" else v.nominal + 0.5
            ref = set_dimension(ref, v.key, x)
            vals[v.key] = np.array([x])
        geo = build_geometry(lk, compile_plan(lk), vals, 1)
        assert geo.ok[0]
        s = size(lk)
        for j in lk.joints:
            assert abs(geo.point(j.id, 0) - complex(*ref.joint(j.id).at)) <= 1e-12 * s, (lk.id, j.id)


def test_pivot_and_coupler_point_edits_against_an_independent_construction():
    lk = example("fourbar_crank_rocker", "fourbar")
    j = {x.id: complex(*x.at) for x in lk.joints}
    newD = complex(166.0, 7.5)
    vals = {"x:D": np.array([newD.real]), "y:D": np.array([newD.imag]),
            "point:coupler:E:x": np.array([30.0]), "point:coupler:E:y": np.array([55.0])}
    geo = build_geometry(lk, compile_plan(lk), vals, 1)
    # independent: B keeps its crank angle, C closes B–C and D–C in the drawn mode, E in the coupler frame
    A, B = j["A"], j["B"]
    li, lj = abs(j["C"] - B), abs(j["C"] - j["D"])
    C = LB.circle_meet(B, li, newD, lj, 1 if LB.cross2(j["D"] - B, j["C"] - B) >= 0 else -1)
    E = B + complex(30.0, 55.0) * (C - B) / abs(C - B)
    for name, want in (("A", A), ("B", B), ("C", C), ("D", newD), ("E", E)):
        assert abs(geo.point(name, 0) - want) < 1e-12 * 200, name
    b = solve_variants(lk, vals, samples=60, order=2, fast=False)
    compare(lk, b, 0, 60, 2)


def test_fused_loop_is_the_numpy_reference_bit_for_bit():
    """The compiled loops (four-bar, six-bar with a guide on the rocker) against the numpy path:
    the same bits for every joint, link, mask and per-design flag, with designs at toggles, near
    the parallelogram's change points (handed to the numpy path) and not assembling."""
    for lk, extra in ((example("fourbar_crank_rocker", "fourbar"), {"length:rocker:D:C": [120, 60, 20, 400]}),
                      (example("sixbar_moving_guide", "sixbar"), {"length:rod2:B:E": [118.0, 110, 90, 20]})):
        rng = np.random.default_rng(3)
        D = 16
        vals = {"length:crank:A:B": 40 + rng.normal(size=D) * 4, "length:coupler:B:C": 140 + rng.normal(size=D) * 3}
        k = next(iter(extra))
        vals[k] = np.concatenate([extra[k], np.full(D - 4, float(extra[k][0]))])
        vals["length:crank:A:B"][:2] = [40.0, 41.0]
        a = solve_variants(lk, vals, samples=72, order=2, fast=False)
        f = solve_variants(lk, vals, samples=72, order=2, fast=True)
        for j in lk.joint_ids:
            for fn in ("position", "velocity", "acceleration"):
                assert np.array_equal(getattr(a, fn)(j), getattr(f, fn)(j), equal_nan=True), (lk.id, j, fn)
        for link in lk.moving_links:
            for fn in ("angle", "omega", "alpha"):
                assert np.array_equal(getattr(a, fn)(link), getattr(f, fn)(link), equal_nan=True), (link, fn)
        for m in ("valid", "rates_valid", "singular", "assembled", "full_cycle", "dead_point"):
            assert np.array_equal(getattr(a, m), getattr(f, m)), m
        assert np.array_equal(a.min_transmission_angle, f.min_transmission_angle, equal_nan=True)
        assert not a.assembled.all() and not a.full_cycle.all()


def test_per_design_flags_against_the_diagnostics():
    lk = example("fourbar_crank_rocker", "fourbar")
    vals = {"length:crank:A:B": np.array([40.0, 60.0, 75.0]), "length:rocker:D:C": np.array([120.0, 120.0, 100.0])}
    b = solve_variants(lk, vals, samples=360, order=0, fast=False)
    for d in range(3):
        geo = build_geometry(lk, b.plan.plan, {k: v[d:d + 1] for k, v in vals.items()}, 1)
        sol = compile_plan(design_linkage(geo, 0)).sweep(360, 0)
        diag = diagnose(sol)
        assert b.full_cycle[d] == diag.full_turn
        mu = np.degrees(sol.transmission_angle("RRR(coupler,rocker)"))
        want = np.nanmin(np.minimum(mu, 180.0 - mu))
        assert abs(b.min_transmission_angle[d] - want) < 1e-9
        assert b.dead_point[d] == (not diag.full_turn or bool(diag.dead_points))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(5.0, 120.0), st.floats(60.0, 220.0), st.floats(40.0, 200.0),
                          st.floats(80.0, 200.0)), min_size=3, max_size=3))
def test_random_four_bars(designs):
    lk = example("fourbar_crank_rocker", "fourbar")
    arr = np.array(designs)
    vals = {"length:crank:A:B": arr[:, 0], "length:coupler:B:C": arr[:, 1], "length:rocker:D:C": arr[:, 2],
            "length:ground:A:D": arr[:, 3]}
    b = solve_variants(lk, vals, samples=24, order=2, fast=False)
    for d in range(3):
        compare(lk, b, d, 24, 2)


def test_bad_requests_name_the_entry(monkeypatch):
    lk = example("fourbar_crank_rocker", "fourbar")
    with pytest.raises(RequestError, match="length:crank:A:Z"):
        solve_variants(lk, {"length:crank:A:Z": [1.0]}, samples=8)
    with pytest.raises(RequestError, match="design 1"):
        solve_variants(lk, {"length:crank:A:B": [40.0, math.nan]}, samples=8)
    with pytest.raises(RequestError, match="same number"):
        solve_variants(lk, {"length:crank:A:B": [40.0, 41.0], "length:rocker:D:C": [1.0, 2.0, 3.0]}, samples=8)
    monkeypatch.setenv("MECHSKETCH_MEMORY_MB", "5")
    with pytest.raises(RequestError, match="MECHSKETCH_MEMORY_MB"):
        solve_variants(lk, {"length:crank:A:B": np.full(2000, 40.0)}, samples=360)


def test_threads_over_the_fused_chunks_give_the_same_bits(monkeypatch):
    """workers=2 runs the fused loop's chunks on two threads: every array, mask, flag and failure
    reason the same bits as one thread, designs that do not assemble (two reasons) and designs near
    the toggle (solved again on the numpy path) spread over several chunks."""
    from mechsketch.core.studies.variants import FUSED_BLOCK

    lk = Workspace.open(f"{EXAMPLES}/fourbar_crank_rocker.json").element("fourbar")
    D = 2 * FUSED_BLOCK + 77
    rng = np.random.default_rng(4)
    crank = 40.0 + rng.normal(size=D) * 6.0
    crank[::997] = 500.0                       # cannot close
    rocker = 120.0 + rng.normal(size=D) * 2.0
    rocker[5::1013] = -3.0                      # not a length
    rocker[7::50] = 60.2                        # coupler + rocker just above the largest reach: a toggle
    vals = {"length:crank:A:B": crank, "length:rocker:D:C": rocker}
    kw = dict(samples=24, order=2, joints=["E", "C"], links=["rocker"], fast=True)
    import mechsketch.core.studies.variants as V
    redone, solve = [], V.solve_chunk
    monkeypatch.setattr(V, "solve_chunk", lambda bp, values, n, *r: redone.append(n) or solve(bp, values, n, *r))
    a, b = solve_variants(lk, vals, workers=1, **kw), solve_variants(lk, vals, workers=2, **kw)
    assert sum(redone) > 0                     # the numpy path took the designs near the toggle
    assert (~a.assembled).sum() > 20 and len(a.failures()) >= 2
    for f in ("position", "velocity", "acceleration"):
        for j in ("E", "C"):
            assert np.array_equal(getattr(a, f)(j), getattr(b, f)(j), equal_nan=True), (f, j)
    assert np.array_equal(a.angle("rocker"), b.angle("rocker"), equal_nan=True)
    for m in ("valid", "rates_valid", "assembled", "full_cycle", "dead_point", "min_transmission_angle"):
        assert np.array_equal(np.asarray(getattr(a, m)), np.asarray(getattr(b, m)), equal_nan=True), m
    assert a.failures() == b.failures()
    assert [a.message(d) for d in range(0, D, 997)] == [b.message(d) for d in range(0, D, 997)]
