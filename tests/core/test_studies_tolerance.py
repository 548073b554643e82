"""Tolerance and clearance Monte Carlo (core/studies/tolerance.py) against an independent numpy
Monte Carlo, the linearised band against the Monte Carlo, ISO 286 against its published tables.

The independent Monte Carlo below knows nothing of the engine: the four-bar's closed form (B on
the crank, C where the coupler's and the rocker's circles meet, E held at its distances from B
and C), pin play as the displacement of the later link's copy of the pin, its derivative matrices
by central differences, and the worst play direction per sample by a dense grid of directions.
"""
from __future__ import annotations

import math
import threading

import numpy as np
import pytest

from mechsketch.core.errors import RequestError
from mechsketch.core.studies.execute import StudyCancelled
from mechsketch.core.studies.iso286 import fit
from mechsketch.core.studies.keys import variables
from mechsketch.core.studies.tolerance import BLOCK, draw, linearised_tolerance, parse_spec, tolerance
from mechsketch.core.workspace import Workspace

FOURBAR = "resources/examples/fourbar_crank_rocker.json"


@pytest.fixture(scope="module")
def fourbar():
    return Workspace.open(FOURBAR).element("fourbar")


# -- ISO 286 --------------------------------------------------------------------------------------
def test_iso286_limits_are_the_published_ones():
    f = fit("H7/g6", 10.0)                      # over 6 up to 10 mm
    assert f.hole == pytest.approx((0.0, 0.015)) and f.shaft == pytest.approx((-0.014, -0.005))
    assert (f.clearance_min, f.clearance_max) == pytest.approx((0.005, 0.029))
    assert (fit("H7/g6", 25.0).clearance_min, fit("H7/g6", 25.0).clearance_max) == pytest.approx((0.007, 0.041))
    f = fit("H8/f7", 50.0)
    assert f.hole == pytest.approx((0.0, 0.039)) and f.shaft == pytest.approx((-0.050, -0.025))
    f = fit("H7/k6", 8.0)                       # a transition fit: interference possible
    assert f.shaft == pytest.approx((0.001, 0.010)) and f.clearance_min == pytest.approx(-0.010)
    assert fit("G7/h6", 30.0).hole == pytest.approx((0.007, 0.028))
    assert fit("JS7/h6", 12.0).hole == pytest.approx((-0.009, 0.009))
    rng = np.random.default_rng(0)
    play = fit("H7/p6", 10.0).radial_play(rng, 1000)   # interference: no play
    assert (play == 0.0).all()
    play = fit("H7/g6", 10.0).radial_play(rng, 100_000)
    assert play.min() >= 0.0025 and play.max() <= 0.0145
    assert play.mean() == pytest.approx(0.5 * (0.0075 + 0.0095), rel=0.01)   # half the mean clearance


@pytest.mark.parametrize("name", ["X7/g6", "H7g6", "H13/g6", "H7/q6", "", "h7/G6"])
def test_unknown_fits_are_refused_by_name(name):
    with pytest.raises(RequestError):
        fit(name, 10.0)


# -- the independent Monte Carlo ----------------------------------------------------------------
def closed_form(lk, crank, coupler, th, eB=(0.0, 0.0), eC=(0.0, 0.0)):
    """E (..., N) complex of the four-bar with the given crank and coupler lengths (arrays that
    broadcast) at crank angles th (N,), the coupler's B displaced by eB from the crank's and the
    rocker's C by eC from the coupler's."""
    j = {x.id: complex(*x.at) for x in lk.joints}
    A, D, C0, B0, E0 = j["A"], j["D"], j["C"], j["B"], j["E"]
    rocker = abs(C0 - D)
    mode = 1.0 if ((D - B0).conjugate() * (C0 - B0)).imag >= 0 else -1.0
    be, ce = abs(E0 - B0), abs(E0 - C0)
    side = 1.0 if ((C0 - B0).conjugate() * (E0 - B0)).imag >= 0 else -1.0
    B = A + crank * np.exp(1j * th) + complex(*eB)
    Dm = D - complex(*eC)
    d = Dm - B
    dist = np.abs(d)
    a = (coupler ** 2 - rocker ** 2 + dist ** 2) / (2 * dist)
    h = mode * np.sqrt(coupler ** 2 - a ** 2)
    C = B + (a + 1j * h) * d / dist
    x = (be ** 2 - ce ** 2 + coupler ** 2) / (2 * coupler)
    y = side * np.sqrt(be ** 2 - x ** 2)
    return B + (x + 1j * y) * (C - B) / coupler


def independent(lk, crank, coupler, rB, rC, N, dirs=360):
    """Per build the largest worst-case deviation of E (mm): dimensions exact, pins linearised
    with S by central differences at the nominal, the worst direction by a grid."""
    drive = next(x for x in lk.joints if x.id == "B")
    th0 = math.atan2(drive.at[1], drive.at[0])
    th = th0 + 2 * np.pi * np.arange(N) / N
    c0, b0 = abs(complex(*drive.at)), abs(complex(*lk.joint("C").at) - complex(*drive.at))
    nom = closed_form(lk, c0, b0, th)
    h = 1e-6
    S = {}
    for pin in ("B", "C"):
        cols = []
        for e in ((h, 0.0), (0.0, h)):
            kw = {"eB": e} if pin == "B" else {"eC": e}
            kw2 = {"eB": (-e[0], -e[1])} if pin == "B" else {"eC": (-e[0], -e[1])}
            cols.append((closed_form(lk, c0, b0, th, **kw) - closed_form(lk, c0, b0, th, **kw2)) / (2 * h))
        S[pin] = cols                                    # dE/dex, dE/dey (complex (N,))
    phi = np.linspace(0.0, 2 * np.pi, dirs, endpoint=False)
    n = np.exp(1j * phi)                                 # (dirs,)
    g = {p: np.hypot((np.conj(S[p][0])[:, None] * n).real, (np.conj(S[p][1])[:, None] * n).real)   # |S_pᵀ n| (N, dirs)
         for p in ("B", "C")}
    top = {p: g[p].max(axis=1) for p in g}               # a bound of |S_pᵀ n| per sample
    out = np.empty(crank.size)
    for b in range(crank.size):
        a = closed_form(lk, crank[b], coupler[b], th) - nom                    # (N,)
        bound = np.abs(a) + rB[b] * top["B"] + rC[b] * top["C"]
        k = bound >= np.abs(a).max()                      # only these samples can hold the worst case
        f = (np.conj(a[k])[:, None] * n).real + rB[b] * g["B"][k] + rC[b] * g["C"][k]
        out[b] = f.max()
    return out


SPEC = {"length:crank:A:B": {"normal": 0.02}, "length:coupler:B:C": {"uniform": 0.05},
        "clearance": {"B": {"fit": "H7/g6", "diameter": 12.0}, "C": {"fit": "H8/f7", "diameter": 12.0}}}


def test_the_same_builds_give_the_independent_deviations(fourbar):
    """Our draws fed to the independent Monte Carlo: per build the same deviation (to the grid's
    resolution, 1 − cos(0.5°) relative)."""
    t = tolerance(fourbar, SPEC, builds=600, samples=90, seed=11, joints=["E"], links=[])
    sp = parse_spec(fourbar, SPEC)
    nominal = {k: v.nominal for k, v in variables(fourbar).items()}
    values, plays = draw(sp, nominal, 11, 0, 600)
    ref = independent(fourbar, values["length:crank:A:B"], values["length:coupler:B:C"], plays[:, 0], plays[:, 1],
                      90, dirs=720)
    rel = (t.deviation("E") - ref) / ref
    assert rel.min() > -1e-6 and rel.max() < 4e-5      # ours maximises exactly; the grid from below


def test_percentiles_agree_with_an_independent_monte_carlo(fourbar):
    """Independent draws (numpy's own stream, the fits' limits typed from the tables): the
    50th, 90th and 95th percentiles of the deviation within 2 %."""
    B = 20_000
    t = tolerance(fourbar, SPEC, builds=B, samples=36, seed=3, joints=["E"], links=[], workers=2)
    rng = np.random.default_rng(20260101)
    crank = 40.0 + rng.normal(0.0, 0.02, B)
    coupler = 140.0 + rng.uniform(-0.05, 0.05, B)
    # Ø12: H7 +0.018/0, g6 −0.006/−0.017; H8 +0.027/0, f7 −0.016/−0.034 (ISO 286-1, over 10 up to 18)
    rB = np.maximum(rng.uniform(0, 0.018, B) - rng.uniform(-0.017, -0.006, B), 0) / 2
    rC = np.maximum(rng.uniform(0, 0.027, B) - rng.uniform(-0.034, -0.016, B), 0) / 2
    ref = independent(fourbar, crank, coupler, rB, rC, 36)
    for q in (50, 90, 95):
        ours, theirs = t.percentile("E", q), np.percentile(ref, q)
        assert abs(ours - theirs) <= 0.02 * theirs, (q, ours, theirs)
    assert t.failed == 0


def test_linearised_band_matches_the_monte_carlo_three_sigma(fourbar):
    small = {"length:crank:A:B": {"normal": 0.002}, "length:coupler:B:C": {"uniform": 0.004},
             "length:rocker:D:C": {"normal": 0.003}, "x:D": {"normal": 0.002}}
    lin = linearised_tolerance(fourbar, small, samples=36, joints=["E"])
    t = tolerance(fourbar, small, builds=8_000, samples=36, seed=5, joints=["E"], links=[])
    assert lin.agreement(t, "E") < 0.05
    # the shares: one variable at a time, the Monte Carlo's variance of the normal deviation
    shares = lin.sensitivity("E")
    assert sum(shares.values()) == pytest.approx(1.0)
    var = {}
    for k, d in small.items():
        one = tolerance(fourbar, {k: d}, builds=4_000, samples=36, seed=9, joints=["E"], links=[])
        var[k] = float(np.nansum(one.sigma("E") ** 2))
    total = sum(var.values())
    for k in small:     # the MC's shares of the normal variance against the first-order shares
        assert var[k] / total == pytest.approx(_normal_share(lin, small, k), abs=0.03), k
    assert set(shares) == set(small)


def _normal_share(lin, spec, key):
    n = lin.nominal
    nu = n.normal["E"]
    tot, mine = 0.0, 0.0
    for i, (k, kind, w, _b) in enumerate(lin.spec.variables):
        s2 = w * w if kind == "normal" else w * w / 3.0
        v = s2 * float(np.nansum(((n.dpos["E"][i] * nu).sum(axis=1) ** 2)[n.valid]))
        tot += v
        mine += v if k == key else 0.0
    return mine / tot


def test_builds_that_do_not_assemble_are_counted_never_dropped(fourbar):
    spec = {"length:rocker:D:C": {"normal": 25.0}}
    t = tolerance(fourbar, spec, builds=3000, samples=36, seed=1, joints=["E"], links=["rocker"])
    bad = ~np.isfinite(t.deviation("E"))
    assert t.failed == bad.sum() > 0
    assert np.array_equal(bad, ~np.isfinite(t.angle_deviation("rocker")))
    q = 100.0 * (1.0 - 0.5 * bad.mean())
    assert t.percentile("E", q) == np.inf             # the failures sit at the top of the percentiles
    assert "do not assemble" in t.summary("E")


def test_envelope_quantiles_against_the_builds(fourbar):
    """Without pins, the envelope's q-quantile of the normal deviation per sample against numpy's
    quantile of the same builds' deviations (to the histogram's resolution)."""
    spec = {"length:crank:A:B": {"normal": 0.02}, "length:coupler:B:C": {"uniform": 0.05}}
    t = tolerance(fourbar, spec, builds=5000, samples=36, seed=2, joints=["E"], links=[])
    values, _ = draw(parse_spec(fourbar, spec), {k: v.nominal for k, v in variables(fourbar).items()}, 2, 0, 5000)
    drive = fourbar.joint("B")
    th = math.atan2(drive.at[1], drive.at[0]) + 2 * np.pi * np.arange(36) / 36
    E = closed_form(fourbar, values["length:crank:A:B"][:, None], values["length:coupler:B:C"][:, None], th)
    nom = t.nominal.pos["E"][:, 0] + 1j * t.nominal.pos["E"][:, 1]
    nu = t.nominal.normal["E"][:, 0] + 1j * t.nominal.normal["E"][:, 1]
    s = (np.conj(nu) * (E - nom)).real
    for q in (0.005, 0.5, 0.995):
        env = t.envelope("E", q)
        got = ((env[:, 0] + 1j * env[:, 1] - nom) * np.conj(nu)).real
        want = np.quantile(s, q, axis=0)
        band = np.quantile(s, 0.995, axis=0) - np.quantile(s, 0.005, axis=0)
        assert np.max(np.abs(got - want) / band) < 0.02, q


def test_same_seed_same_numbers_whatever_the_threads(fourbar):
    a = tolerance(fourbar, SPEC, builds=2 * BLOCK + 100, samples=24, seed=7, joints=["E"], links=["rocker"])
    b = tolerance(fourbar, SPEC, builds=2 * BLOCK + 100, samples=24, seed=7, joints=["E"], links=["rocker"], workers=3)
    c = tolerance(fourbar, SPEC, builds=2 * BLOCK + 100, samples=24, seed=8, joints=["E"], links=["rocker"])
    assert np.array_equal(a.deviation("E"), b.deviation("E"))
    assert np.array_equal(a.angle_deviation("rocker"), b.angle_deviation("rocker"))
    assert np.array_equal(a.envelope("E", 0.9), b.envelope("E", 0.9), equal_nan=True)
    assert not np.array_equal(a.deviation("E"), c.deviation("E"))


def test_progress_and_cancel(fourbar):
    seen = []
    tolerance(fourbar, SPEC, builds=3 * BLOCK, samples=12, seed=1, joints=["E"], links=[],
              progress=lambda done, total: seen.append((done, total)))
    assert seen == [(0, 3), (1, 3), (2, 3), (3, 3)]
    stop = threading.Event()

    def tick(done, total):
        if done >= 1:
            stop.set()

    with pytest.raises(StudyCancelled):
        tolerance(fourbar, SPEC, builds=4 * BLOCK, samples=12, seed=1, joints=["E"], links=[], progress=tick,
                  cancel=stop)


@pytest.mark.parametrize("spec, words", [
    ({"length:crank:A:Q": {"normal": 0.1}}, "length:crank:A:Q"),
    ({"length:crank:A:B": {"normal": -0.1}}, "negative"),
    ({"length:crank:A:B": {"normal": 0.1, "uniform": 0.1}}, "length:crank:A:B"),
    ({"length:crank:A:B": {"gauss": 0.1}}, "length:crank:A:B"),
    ({"clearance": {"B": "H7/x6"}}, "clearance 'B'"),
    ({"clearance": {"E": "H7/g6"}}, "clearance 'E'"),
    ({"clearance": {"Z": "H7/g6"}}, "clearance 'Z'"),
])
def test_bad_specs_name_the_entry(fourbar, spec, words):
    with pytest.raises(RequestError, match=words):
        tolerance(fourbar, spec, builds=10, samples=8)


def test_a_budget_too_small_is_refused_before_anything_runs(fourbar, monkeypatch):
    monkeypatch.setenv("MECHSKETCH_MEMORY_MB", "1")
    with pytest.raises(RequestError, match="MECHSKETCH_MEMORY_MB"):
        tolerance(fourbar, SPEC, builds=100_000, samples=360)
