"""Every example scene loads; every linkage in them solves, closes its loops, agrees with the
50-digit reference, and reproduces the textbook numbers it was built for (notes, section
"Suggested built-in example scenes")."""
from __future__ import annotations

import math

import numpy as np
import pytest

import linkage_builders as LB
import reference as R
import reference_drive as RD
import solution_checks as CK
from mechsketch.core import load_scene, validate_file
from mechsketch.core.cli import main
from mechsketch.core.solver.diagnostics import diagnose
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path, example_paths

PATHS = example_paths()


def linkages(path):
    return [e for e in load_scene(path).elements if e.type == "linkage"]


@pytest.mark.parametrize("path", PATHS, ids=lambda p: p.stem)
def test_example_loads(path):
    assert validate_file(path) == []
    scene = load_scene(path)
    assert scene.elements


LINKAGE_EXAMPLES = [(p, e.id) for p in PATHS for e in linkages(p)]


@pytest.mark.parametrize("path,eid", LINKAGE_EXAMPLES, ids=[f"{p.stem}:{e}" for p, e in LINKAGE_EXAMPLES])
def test_example_linkage_solves_accurately(path, eid, capsys):
    lk = load_scene(path).element(eid)
    sol = compile_plan(lk).sweep(samples=lk.samples, order=2)
    size = LB.size_of(lk)
    assert len(sol) == lk.samples
    assert sol.valid[0]
    if path.stem != "double_rocker":
        assert sol.valid.all()
    assert CK.closure_error(lk, sol) <= 1e-12 * size
    assert sol.residual() <= 1e-12 * size
    ok = np.flatnonzero(sol.valid)
    if lk.driver.kind == "crank" and lk.driver.law.is_constant:
        err = R.relative(R.compare(lk, sol, ok[:: max(1, len(ok) // 8)]))
        assert err["pos"] <= 1e-13 and err["ang"] <= 1e-13, err
        assert max(err[q] for q in ("vel", "acc", "omega", "alpha")) <= 1e-11, err
    else:   # any driver and law: the generic 50-digit reference (fewer samples: it is slower)
        err = RD.relative(RD.compare(lk, sol, ok[:: max(1, len(ok) // 3)]), size)
        assert err["pos"] <= 1e-13 and max(err["vel"], err["acc"]) <= 1e-11, err
    for g in sol.groups:
        s = CK.mode_signs(lk, sol, g)
        assert np.all(s[sol.valid] == s[0])
    assert main(["analyze", str(path), "--element", eid, "--samples", "24", "--csv", "-"]) == 0
    out = capsys.readouterr().out
    assert len(out.strip().splitlines()) == 25


def example(name):
    return load_scene(example_path(name)).elements[0]


def test_crank_rocker_numbers():
    """Crank 40, coupler 140, rocker 120, ground 160, ω1 = 10 rad/s, mode +1."""
    lk = example("fourbar_crank_rocker")
    at = {j.id: complex(*j.at) for j in lk.joints}
    assert abs(at["B"] - at["A"]) == pytest.approx(40, abs=1e-8)
    assert abs(at["C"] - at["B"]) == pytest.approx(140, abs=1e-8)
    assert abs(at["C"] - at["D"]) == pytest.approx(120, abs=1e-8)
    assert lk.driver.omega == pytest.approx(10.0, rel=1e-14)
    sol = compile_plan(lk).sweep(samples=360)
    assert diagnose(sol).groups[0][2] == 1.0
    # the rocker's limit positions: B on line AD, |BD| = coupler ∓ crank = 100 and 180
    phi_lo = math.degrees(math.acos((160 ** 2 + 120 ** 2 - 100 ** 2) / (2 * 160 * 120)))
    phi_hi = math.degrees(math.acos((160 ** 2 + 120 ** 2 - 180 ** 2) / (2 * 160 * 120)))
    fine = compile_plan(lk).evaluate(np.linspace(0, 2 * math.pi, 200001), order=0)
    rocker = np.degrees(fine.angle("rocker"))     # angle of D→C from +x = 180° − ∠CDA
    assert rocker.min() == pytest.approx(180 - phi_hi, abs=1e-6)
    assert rocker.max() == pytest.approx(180 - phi_lo, abs=1e-6)


def test_offset_slider_crank_stroke():
    """r = 40, L = 160, e = 20: stroke √((L+r)² − e²) − √((L−r)² − e²)."""
    lk = example("slider_crank_offset")
    x = compile_plan(lk).evaluate(np.linspace(0, 2 * math.pi, 400001), order=0).position("C")[:, 0]
    stroke = math.sqrt(200 ** 2 - 20 ** 2) - math.sqrt(120 ** 2 - 20 ** 2)
    assert x.max() - x.min() == pytest.approx(stroke, abs=1e-8)
    assert x.max() == pytest.approx(math.sqrt(200 ** 2 - 20 ** 2), abs=1e-9)
    sol = compile_plan(lk).sweep(samples=360)
    assert np.allclose(sol.position("C")[:, 1], 20.0, atol=1e-12)


def test_inverted_slider_crank_swing():
    """Crank 40 about A, rocker pivot C 100 away, slide axis through C: the rocker swings
    ±asin(40/100) about the line C→A."""
    lk = example("inverted_slider_crank")
    fine = compile_plan(lk).evaluate(np.linspace(0, 2 * math.pi, 400001), order=0)
    a = fine.angle("rocker")
    assert a.max() - a.min() == pytest.approx(2 * math.asin(0.4), abs=1e-8)


def test_sixbar_block_stays_on_the_rocker_guide():
    lk = example("sixbar_moving_guide")
    sol = compile_plan(lk).sweep(samples=720)
    D, C, E = (CK._z(sol.position(j)) for j in "DCE")
    q = lk.joint("Q")
    u = CK.link_rotation(sol, lk, "rocker") * LB.e(q.axis_deg)
    # E on the rocker's line through Q: cross(u, E − Q(t)) = 0
    Q = CK._z(sol.point("rocker", q.at))
    assert np.max(np.abs(CK.cross2_arr(u, E - Q))) < 1e-11
    assert np.allclose(np.abs(E - CK._z(sol.position("B"))), abs(complex(*lk.joint("E").at) - complex(*lk.joint("B").at)),
                       atol=1e-11)
