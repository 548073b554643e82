"""The outputs' extremes refined by all golden-section searches at once (issue 14): the same
results as the search one output and one input at a time (the function as it was, kept in
classify_reference.py), on every example linkage and on dyad chains, and the same extremes as a
dense sampling of the whole cycle (an independent reference)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chains import dyad_chain
from classify_reference import output_motions_reference
from mechsketch.core import load_scene
from mechsketch.core.analyses.classify import GOLDEN, _golden_min_all, output_motions
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.solver.branches import golden_min
from mechsketch.core.solver.motion_law import at_times
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_paths


def _examples() -> list[tuple[str, Linkage]]:
    out = []
    for p in example_paths():
        out += [(f"{p.stem}/{el.id}", el) for el in load_scene(p).elements if isinstance(el, Linkage)]
    return out


CASES = _examples() + [(f"chain{n}", dyad_chain(n, samples=s)) for n, s in ((1, 360), (3, 90), (8, 90), (16, 60))]


def test_every_example_linkage_is_covered():
    names = [n for n, _ in CASES]
    assert len(names) >= 12 and any(n.startswith("excavator_arm") for n in names)   # an actuator, cycloidal law
    assert any(n.startswith("v_engine") for n in names)                                  # sliders


@pytest.mark.parametrize("lookahead", [1, 2, 3, 4, 7])
def test_the_searches_at_once_take_the_same_steps_as_one_search_at_a_time(lookahead):
    """Functions with known minima, some searches going left and some right at each step, one
    returning NaN (golden_min then always keeps the right part): iterates equal bit for bit, with
    any number of steps solved per call (7 does not divide the 60 steps)."""
    fs = [lambda x: (x - 0.3) ** 2, lambda x: math.cos(x), lambda x: -math.sin(3 * x) + 0.1 * x,
          lambda x: abs(x - 1.7) ** 1.5, lambda x: math.nan]
    a = np.array([0.0, 2.0, -0.2, 1.0, 0.0])
    b = np.array([1.0, 4.5, 1.3, 2.0, 1.0])
    m = len(fs)
    calls = []

    def f(t):
        calls.append(len(t))
        return np.array([fs[j % m](float(v)) for j, v in enumerate(t)])
    x, fx = _golden_min_all(f, a, b, GOLDEN, lookahead)
    assert len(calls) == 2 + math.ceil(GOLDEN / lookahead)
    for i, f in enumerate(fs):
        xi, fi = golden_min(f, float(a[i]), float(b[i]), GOLDEN)
        assert x[i] == xi and (fx[i] == fi or (math.isnan(fi) and math.isnan(fx[i])))
    assert x[0] == pytest.approx(0.3, abs=1e-8)
    assert x[1] == pytest.approx(math.pi, abs=5e-8)   # cos is flat there: sqrt(eps) resolution
    assert x[3] == pytest.approx(1.7, abs=1e-8)


@pytest.mark.parametrize("name,lk", CASES, ids=[n for n, _ in CASES])
def test_output_motions_equal_the_search_one_input_at_a_time(name, lk):
    plan = compile_plan(lk)
    sol = plan.sweep(order=2)
    new, ref = output_motions(lk, plan, sol), output_motions_reference(lk, plan, sol)
    assert [(m.link, m.kind, m.joint, m.note) for m in new] == [(m.link, m.kind, m.joint, m.note) for m in ref]
    dt = lk.driver.period / len(sol)
    for m, r in zip(new, ref):
        if r.note:
            assert math.isnan(m.low) and m.t_out is None
            continue
        scale = max(1.0, abs(r.low), abs(r.high))
        # the same iterates; a last-bit difference of a value (a slider's dot product) may turn
        # one comparison, after which both searches still end within the flatness of the extreme
        assert abs(m.low - r.low) <= 1e-13 * scale and abs(m.high - r.high) <= 1e-13 * scale
        assert abs(m.t_out - r.t_out) <= 1e-6 * dt and abs(m.t_back - r.t_back) <= 1e-6 * dt


def _dense(lk, plan, link: str, kind: str, joint: str, m: int) -> tuple[np.ndarray, np.ndarray]:
    """The output over the whole cycle at m times (s) t = kT/m, unwrapped: (t, value)."""
    drv = lk.driver
    T = drv.period
    t = np.arange(m) * (T / m)
    if drv.linear or not drv.law.is_constant:
        q = at_times(drv, plan.theta0, t).q
    else:
        q = plan.theta0 + math.copysign(1.0, drv.speed_rpm) * 2 * math.pi * t / T
    sol = plan.evaluate(q, order=0)
    if kind == "rocker":
        return t, sol.angle(link)
    j = lk.joint(joint)
    u = np.array([math.cos(math.radians(j.axis_deg or 0.0)), math.sin(math.radians(j.axis_deg or 0.0))])
    return t, sol.point(link, j.at) @ u


@pytest.mark.parametrize("name,lk", [c for c in CASES if not c[0].startswith("chain16")],
                         ids=[n for n, _ in CASES if not n.startswith("chain16")])
def test_extremes_equal_a_dense_sampling_of_the_cycle(name, lk):
    """Least and greatest value within the dense grid's own error (curvature × spacing² / 8, below
    1e-9 of the output's size at 200,000 samples), never beyond it by more than roundoff; their
    times within two grid spacings (mod T)."""
    plan = compile_plan(lk)
    sol = plan.sweep(order=2)
    T = lk.driver.period
    m_dense = 200_000
    for mo in output_motions(lk, plan, sol):
        if mo.note:
            continue
        t, y = _dense(lk, plan, mo.link, mo.kind, mo.joint, m_dense)
        assert np.all(np.isfinite(y))
        scale = max(1.0, float(np.max(np.abs(y))))
        lo, hi = float(np.min(y)), float(np.max(y))
        assert lo - 1e-9 * scale <= mo.low <= lo + 1e-12 * scale
        assert hi - 1e-12 * scale <= mo.high <= hi + 1e-9 * scale
        t_lo, t_hi = float(t[np.argmin(y)]), float(t[np.argmax(y)])
        fwd = (t_hi - t_lo) % T
        d = abs(math.remainder(mo.t_out - fwd, T))
        assert d <= 4 * T / m_dense, (mo, fwd)
