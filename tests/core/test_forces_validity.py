"""Forces only where the kinematics with its rates is valid, each force column with an error
estimate of its own (issue 20, item 2).

The repro ``forces_near_dead_point.json`` (a loaded double rocker 1e-14 rad before its limit at
one sample): ``analyze --forces`` printed a driving torque of 1.8e25 N·m in a row whose
``rates_valid`` was 0, and that row became the summary's peak. Now such rows have no forces
(``forces_valid`` 0, empty fields), the peaks are taken over the valid rows, and every column's
``.err`` estimate (from the conditioning of the group solves) bounds its difference from the
50-digit equilibrium of the whole mechanism (:mod:`forces_reference`), well-conditioned and at
the samples nearest the dead point."""
from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import replace

import numpy as np
import pytest

import linkage_builders as LB
from forces_reference import MpKin, equilibrium
from mechsketch.core import Workspace
from mechsketch.core.analyses.forces.kinetostatics import linkage_forces
from mechsketch.core.analyses.forces.report import force_columns
from mechsketch.core.cli import main
from mechsketch.core.model.loads import LinkMass, Torque
from mechsketch.core.solver.plan import compile_plan
from reference import MpReference
from test_forces import loaded

REPRO = "/work/shared/cases/s3/forces_near_dead_point.json"


def _rows(capsys, *argv):
    assert main(["analyze", *argv]) == 0
    out = capsys.readouterr().out
    rows = list(csv.reader(io.StringIO(out)))
    return rows[0], rows[1:]


def test_no_forces_where_the_rates_are_not_valid(capsys):
    head, rows = _rows(capsys, REPRO, "--forces", "--csv", "-")
    rv, fv, tq = head.index("rates_valid"), head.index("forces_valid"), head.index("driver.torque")
    force_cols = list(range(tq, fv))        # driver.torque ... shaking.M: the force columns
    bad = [r for r in rows if r[rv] == "0"]
    assert any(r[head.index("valid")] == "1" for r in bad)     # the row 1e-14 before the limit
    for r in rows:
        assert r[fv] == ("1" if r[rv] == "1" else "0")
        if r[fv] == "0":
            assert all(r[i] == "" for i in force_cols) and r[tq] == ""
        else:
            assert all(math.isfinite(float(r[i])) for i in force_cols)
            assert all(r[head.index(f"{head[i]}.err")] != "" for i in force_cols)
    torques = [abs(float(r[tq])) for r in rows if r[fv] == "1"]
    assert max(torques) < 1e4            # the valid rows near the limit: ~1,158 N·m, not 1.8e25
    assert main(["analyze", REPRO, "--forces", "--summary"]) == 0
    text = capsys.readouterr().out
    peak = float(re.search(r"driving torque \(input\): peak (\S+) N·m", text).group(1))
    assert abs(peak) == pytest.approx(max(torques), rel=1e-5)
    assert "e+25" not in text and "forces_valid 0" in text


def test_the_force_columns_and_their_error_columns(capsys):
    head, rows = _rows(capsys, "resources/examples/fourbar_loaded.json", "--forces", "--csv", "-")
    forces = head[head.index("driver.torque"):head.index("forces_valid")]
    assert head[head.index("forces_valid") + 1:] == [f"{c}.err" for c in forces]
    assert all(r[head.index("forces_valid")] == "1" for r in rows)


def _actual(lk, res, kin, k) -> dict[str, float]:
    """|core − 50-digit equilibrium| per column at sample k (N or N·m)."""
    e = equilibrium(lk, kin)
    out = {res.driver.column: abs(res.driver.values[k] - float(e["T"]))}
    cols = force_columns(res)
    for (j, b), (fx, fy) in e["pins"].items():
        m = list(res.pins[j]).index(b)
        prefix = j if m == 0 else f"{j}[{b}]"
        out[f"{prefix}.Fx"] = abs(cols[f"{prefix}.Fx"][k] - float(fx))
        out[f"{prefix}.Fy"] = abs(cols[f"{prefix}.Fy"][k] - float(fy))
    for j, (N, C) in e["slides"].items():
        out[f"slide.{j}.normal"] = abs(res.slides[j].normal[k] - float(N))
        out[f"slide.{j}.moment"] = abs(res.slides[j].moment[k] - float(C))
    sx, sy, sm = (float(v) for v in e["shaking"])
    out["shaking.Fx"] = abs(res.shaking_force[k][0] - sx)
    out["shaking.Fy"] = abs(res.shaking_force[k][1] - sy)
    out["shaking.M"] = abs(res.shaking_moment[k] - sm)
    return out


def _check_bounds(lk, res, sol, samples) -> list[tuple[float, float]]:
    """Assert each column's estimate bounds its error at ``samples``; (error, estimate) pairs of the
    driving effort."""
    ref = MpReference(lk)
    pairs = []
    for k in samples:
        assert res.valid[k]
        kin = MpKin(ref, sol, k)
        for col, err in _actual(lk, res, kin, k).items():
            est = res.errors[col][k]
            assert err <= est, (k, col, err, est)
        pairs.append((_actual(lk, res, kin, k)[res.driver.column], res.errors[res.driver.column][k]))
    return pairs


def test_error_estimates_bound_the_error_near_the_dead_point():
    """The repro's linkage solved at inputs 1e-3 down to 1e-9 rad inside its limit (conditioning
    from ~0.03 down to ~3e-5) and at well-conditioned samples: where the rates are valid every
    column's error against the 50-digit equilibrium is within its estimate, and the estimate
    grows as the conditioning falls; where they are not, there are no forces."""
    ws = Workspace.open(REPRO)
    lk = ws.element("dr1em14")
    plan = ws.plan("dr1em14")
    lim = max(p.input for p in ws.result("dr1em14").diagnostics.dead_points)    # +128.04°, a limit
    assert plan.evaluate(np.array([lim + 1e-9]), order=0).valid[0] == False    # noqa: E712
    x = np.array([lim - d for d in (1e-3, 1e-5, 1e-7, 1e-9, 1e-11)] + [0.3, 1.2])
    sol = plan.evaluate(x, order=2)
    res = linkage_forces(plan, sol)
    cond = res.conditioning["RRR(coupler,output)"]
    assert np.array_equal(res.valid, sol.rates_valid) and not res.valid.all() and res.valid.sum() >= 4
    assert np.isnan(res.driver.values[~res.valid]).all()
    ok = list(np.flatnonzero(res.valid))
    _check_bounds(lk, res, sol, ok)
    col = res.driver.column
    rel = res.errors[col][ok] / np.abs(res.driver.values[ok])
    assert cond[ok[len(ok) - 3]] < 1e-3                     # the last valid input near the limit
    assert rel[len(ok) - 3] > 1e3 * min(rel[-2:])          # ~1/conditioning² (the kinematics' part)
    assert max(rel[-2:]) < 1e-12


def _near_dead(lk, samples=720):
    """A four-bar whose transmission angle nearly closes (conditioning ~1e-3 at some samples)."""
    plan = compile_plan(lk)
    sol = plan.sweep(samples)
    return plan, sol, linkage_forces(plan, sol)


@pytest.mark.parametrize("base", [LB.fourbar(), LB.slider_crank(), LB.sixbar_guide(), LB.prp_linkage(),
                                  LB.scotch_yoke(), LB.inverted_slider_crank()], ids=lambda lk: lk.id)
def test_error_estimates_bound_the_error_of_every_group_kind(base):
    lk = loaded(base)
    plan = compile_plan(lk)
    sol = plan.sweep(72)
    res = linkage_forces(plan, sol)
    ks = [k for k in (0, 17, 40, 63) if res.valid[k]]
    pairs = _check_bounds(lk, res, sol, ks)
    for err, est in pairs:        # not absurdly loose where it is well conditioned
        assert est < 1e-11 * (1.0 + np.nanmax(np.abs(res.driver.values)))


def test_error_estimate_at_a_tight_transmission_angle():
    lk = LB.fourbar(crank=40.0, coupler=60.0, rocker=120.0, ground=140.0)
    lk = replace(lk, masses=tuple(LinkMass(k, 0.5) for k in lk.moving_links), loads=(Torque("T", "rocker", -2.0),))
    plan, sol, res = _near_dead(lk)
    cond = res.conditioning[res.groups[0].name]
    k = int(np.nanargmin(np.where(res.valid, cond, np.nan)))
    assert cond[k] < 0.1
    near = [j for j in (k, (k + 1) % len(res), (k - 1) % len(res), (k + 360) % len(res)) if res.valid[j]]
    assert len(near) >= 2
    _check_bounds(lk, res, sol, near)


def test_forces_valid_is_rates_valid_for_every_loaded_example():
    import glob

    for path in sorted(glob.glob("resources/examples/*.json")):
        ws = Workspace.open(path)
        for el in ws.scene.elements:
            if getattr(el, "type", "") != "linkage" or not el.has_dynamics:
                continue
            res, sol = ws.forces(el.id), ws.solve(el.id)
            assert np.array_equal(res.valid, sol.rates_valid & np.isfinite(res.driver.values))
            for name, v in force_columns(res).items():
                assert np.isfinite(v[res.valid]).all() and np.isnan(v[~res.valid]).all()
                e = res.errors[name]
                assert np.isfinite(e[res.valid]).all() and (e[res.valid] >= 0).all()


def test_rates_valid_without_a_pass_equals_the_full_check(monkeypatch):
    """``rates_valid`` is ``valid`` with no pass over the samples where the kernels' conditioning
    floors and the quiet extraction prove it (issue 26: the forces read it every time); it equals
    the check over every sample, for every example at N = 8, 360 and 3,600 and the s3 repros."""
    import glob

    from mechsketch.core.solver.solution import Solution

    paths = sorted(glob.glob("resources/examples/*.json")) + [REPRO, "/work/shared/cases/s3/prp_near_parallel_guides.json"]
    fast_hits = 0
    for path in paths:
        ws = Workspace.open(path)
        for el in ws.scene.elements:
            if getattr(el, "type", "") != "linkage":
                continue
            plan = ws.plan(el.id)
            for n in (8, 360, 3600):
                fast = plan.sweep(n, order=2)
                fast_hits += fast._rates_bounded()
                got = fast.rates_valid
                full = plan.sweep(n, order=2)
                with monkeypatch.context() as m:
                    m.setattr(Solution, "_rates_bounded", lambda self: False)
                    want = full.rates_valid
                assert np.array_equal(got, want), (path, n)
    assert fast_hits > 10          # the fast path is taken (every well-conditioned example)
