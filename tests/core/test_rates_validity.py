"""Rates have their own validity (issue 13, item 7): a sample can be assembled (``valid``, its
positions known) while its velocities and accelerations are not — at an exact toggle or change
point (the velocity system is singular: 0/0, or rounding noise such as ω = −4.4e16 rad/s where the
50-digit value is another 1e17), or where they overflow at extreme speed. ``Solution.rates_valid``
and the CSV column ``rates_valid`` say so; a field of a row flagged valid is never empty or
non-finite."""
from __future__ import annotations

import csv
import io
import json
import math

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core import load_scene
from mechsketch.core.cli import main
from mechsketch.core.cli.linkage_cmds import analysis_table
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path

RATE_FIELDS = (".vx", ".vy", ".ax", ".ay", ".omega", ".alpha")


def double_rocker_at_toggle(samples=3600, rpm=60.0):
    """Crank 60, frame 100, coupler 50, rocker 70, drawn with coupler and rocker in one line
    (|BD| = 120 = 50 + 70): the drawn pose is the toggle, to rounding."""
    a, d, b = 60.0, 100.0, 50.0
    th = math.acos((a * a + d * d - 120.0 ** 2) / (2 * a * d))
    B = a * complex(math.cos(th), math.sin(th))
    C = B + b * (d - B) / abs(d - B)
    return LB.build("dr", [("A", "R", (0.0, 0.0)), ("B", "R", LB.xy(B)), ("C", "R", LB.xy(C)), ("D", "R", (d, 0.0))],
                    {"ground": ["A", "D"], "crank": ["A", "B"], "coupler": ["B", "C"], "rocker": ["D", "C"]},
                    "ground", "crank", "A", rpm, samples)


def rows_of(table):
    text = table.to_csv()
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def check_rows(head, body):
    """Every field of a valid row is a finite number; every rate field of a rates-valid row too;
    rates_valid implies valid."""
    iv, ir = head.index("valid"), head.index("rates_valid")
    rate_cols = [k for k, h in enumerate(head) if h.endswith(RATE_FIELDS)]
    pos_cols = [k for k, h in enumerate(head) if k not in rate_cols and h not in ("valid", "rates_valid")]
    for r in body:
        assert r[iv] in ("0", "1") and r[ir] in ("0", "1")
        assert not (r[ir] == "1" and r[iv] == "0")
        if r[iv] == "1":
            assert all(r[k] != "" and math.isfinite(float(r[k])) for k in pos_cols), r
        if r[ir] == "1":
            assert all(r[k] != "" and math.isfinite(float(r[k])) for k in rate_cols), r
        else:
            assert all(r[k] == "" for k in rate_cols), r


def test_a_double_rocker_drawn_at_its_toggle_has_no_rates_there():
    lk = double_rocker_at_toggle()
    sol = compile_plan(lk).sweep(order=2)
    assert sol.valid[0] and not sol.rates_valid[0]
    # the 50-digit rocker speed at the drawn (float) pose is ~1e17 rad/s: no float rate is right
    with mpmath.workdps(50):
        at = {j.id: mpmath.mpc(*j.at) for j in lk.joints}
        rB, rC = at["B"] - at["A"], at["C"] - at["D"]
        cB = at["C"] - at["B"]
        w = 2 * mpmath.pi                                  # 60 rpm
        vB = 1j * w * rB
        # v_C = vB + i·w_c·cB = i·w_r·rC: solve the 2×2 for w_r
        det = mpmath.im(mpmath.conj(1j * rC) * (-1j * cB))
        w_r = mpmath.im(mpmath.conj(vB) * (-1j * cB)) / det
    assert abs(w_r) > 1e15
    head, body = rows_of(analysis_table(lk, sol))
    assert body[0][head.index("valid")] == "1" and body[0][head.index("rates_valid")] == "0"
    assert body[0][head.index("rocker.omega")] == ""
    check_rows(head, body)
    assert sol.rates_valid[sol.valid].sum() >= sol.valid.sum() - 2


def test_an_exact_change_point_sample_has_positions_but_no_rates():
    """A parallelogram drawn at 30° with 360 samples: samples 150 and 330 sit on the crossings,
    where the velocity system is exactly singular (ω = 0/0); the smooth branch's rates there are
    finite but the kernel cannot give them: the row is valid, its rates are not."""
    lk = LB.fourbar(crank=40.0, coupler=100.0, rocker=40.0, ground=100.0, theta0=30.0, samples=360)
    sol = compile_plan(lk).sweep(order=2)
    assert sol.valid.all()
    cond = sol.conditioning("RRR(coupler,rocker)")
    bad = ~sol.rates_valid
    assert set(np.flatnonzero(bad)) <= {149, 150, 151, 329, 330, 331} and bad[[150, 330]].all()
    assert (cond[bad] < 1e-4).all()
    head, body = rows_of(analysis_table(lk, sol))
    check_rows(head, body)
    # where rates are valid they are right: the rocker turns with the crank
    ok = sol.rates_valid
    assert np.allclose(sol.omega("rocker")[ok], sol.omega("crank")[ok], rtol=1e-9)


def test_rates_that_overflow_at_extreme_speed_are_not_valid():
    lk = LB.fourbar(samples=36, rpm=1e160)         # ω² overflows: accelerations are inf
    sol = compile_plan(lk).sweep(order=2)
    assert sol.valid.all() and not sol.rates_valid.any()
    head, body = rows_of(analysis_table(lk, sol))
    check_rows(head, body)
    assert all(r[head.index("valid")] == "1" and r[head.index("rates_valid")] == "0" for r in body)


@pytest.mark.parametrize("name", ["fourbar_crank_rocker", "double_rocker", "sixbar_moving_guide",
                                  "inverted_slider_crank", "slider_crank_offset"])
def test_the_examples_have_rates_wherever_they_are_valid(name, tmp_path, capsys):
    path = example_path(name)
    code = main(["analyze", str(path), "--samples", "720", "--csv", "-"])
    out, err = capsys.readouterr()
    assert code == 0, err
    head, body = rows_of_text(out)
    assert head[-2:] == ["valid", "rates_valid"]
    check_rows(head, body)
    lk = load_scene(path).elements[0]
    sol = compile_plan(lk).sweep(samples=720)
    assert (sol.rates_valid == sol.valid).all()


def rows_of_text(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def test_order_zero_has_no_rates():
    sol = compile_plan(LB.fourbar()).sweep(samples=8, order=0)
    assert not sol.rates_valid.any()


def test_csv_of_a_toggle_scene_through_the_cli(tmp_path, capsys):
    p = tmp_path / "dr.json"
    p.write_text(json.dumps(LB.scene_dict(double_rocker_at_toggle(samples=360))), encoding="utf-8")
    assert main(["analyze", str(p), "--csv", "-"]) == 0
    head, body = rows_of_text(capsys.readouterr().out)
    check_rows(head, body)
    assert body[0][head.index("rates_valid")] == "0"
