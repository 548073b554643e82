"""The atlas and its descriptors (core/design/atlas*.py, descriptors.py).

- Descriptors are invariant to translation, rotation, scale and the start point (hypothesis),
  the reversed and mirrored curves are found among the query variants, and the compiled
  arc-length resampling equals the numpy reference.
- Every design in an atlas is checked against the product's solver: its linkage turns its crank
  fully with the stored transmission angle, and the stored descriptor is that of the curve the
  solver traces.
- The atlas is stored versioned in the cache folder and read back identical; an atlas of another
  version is rebuilt; a Dask LocalCluster builds the same atlas bit for bit.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from design_atlas_fixture import TEST_DESIGNS
from hypothesis import given, settings
from hypothesis import strategies as st

from mechsketch.core.design import descriptors as DS
from mechsketch.core.design import families as F
from mechsketch.core.design.atlas import build_atlas, forget_loaded, load_atlas
from mechsketch.core.design.atlas_store import (POINTS, VERSION, atlas_folder, disk_bytes, function_values,
                                                read_atlas)
from mechsketch.core.design.candidates import build_linkage
from mechsketch.core.solver.plan import compile_plan

CURVE = F.evaluate("fourbar", np.array([[0, 0, 1, 0, 0.3, 1.1, 0.9, 0.4, 0.5]]),
                   np.linspace(0, 2 * math.pi, 400, endpoint=False)[None], 1.0).P[0]


@given(st.floats(0.01, 100), st.floats(-math.pi, math.pi), st.complex_numbers(max_magnitude=1e3),
       st.integers(0, 399))
@settings(max_examples=40, deadline=None)
def test_descriptor_is_similarity_and_start_invariant(scale, turn, shift, start):
    d0 = DS.fourier_descriptor(CURVE)
    moved = scale * np.exp(1j * turn) * np.roll(CURVE, start) + shift
    q, _, _ = DS.query_variants(moved)
    assert np.min(np.abs(q - d0).max(axis=1)) < 2e-3       # a polygon's resampling, not exact


def test_reversed_and_mirrored_curves_are_found():
    d0 = DS.fourier_descriptor(CURVE)
    for w, mir, rev in ((CURVE[::-1], False, True), (np.conj(CURVE), True, False), (np.conj(CURVE[::-1]), True, True)):
        q, m, r = DS.query_variants(w)
        k = int(np.argmin(np.abs(q - d0).max(axis=1)))
        assert np.abs(q[k] - d0).max() < 2e-3 and m[k] == mir and r[k] == rev


def test_compiled_resampling_equals_numpy():
    rng = np.random.default_rng(0)
    z = np.cumsum(rng.normal(size=(25_000, 40)) + 1j * rng.normal(size=(25_000, 40)), axis=1)
    z[5] = 3 + 4j   # a row of zero length
    a = DS.resample_closed(z, 64, compiled=True)
    b = DS.resample_closed_numpy(z, 64)
    assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(z))


def test_align_recovers_the_similarity():
    s0, t0 = 1.7 * np.exp(0.8j), 3 - 2j
    target = s0 * np.roll(CURVE, 57)[::3] + t0
    j, rev, s, t, fit = DS.align(CURVE, target)
    assert not rev and abs(s - s0) < 1e-2 * abs(s0) and fit < 1e-2


@pytest.mark.parametrize("topology", ["fourbar", "slider_crank", "inverted_slider_crank", "sixbar", "watt_sixbar",
                                      "sixbar_slider", "watt_sixbar_slider", "sixbar_guide", "watt_sixbar_guide"])
def test_atlas_designs_are_what_the_solver_says(atlas_cache, topology):
    atlas = load_atlas(topology)
    assert len(atlas) == TEST_DESIGNS
    rng = np.random.default_rng(1)
    for d in rng.choice(len(atlas), 6, replace=False):
        for p in range(POINTS):
            row = d * POINTS + p
            x = atlas.params(np.array([row]))[0]
            lk = build_linkage(topology, x, 1.0, 0.0, "a")
            sol = compile_plan(lk).sweep(96, order=0)
            assert sol.valid.all()
            P = sol.position("P")
            z = P[:, 0] + 1j * P[:, 1]
            desc = DS.fourier_descriptor(z)
            assert np.max(np.abs(desc - np.asarray(atlas.desc[row], float))) < 2e-3   # float16 storage
            if topology in F.GUIDE_SIXBARS:   # the block's: √(1 − e²/|E − F|²) where the solver puts E
                e = sol.position("E")
                r = np.abs(e[:, 0] + 1j * e[:, 1] - (x[9] + 1j * x[10]))
                rrr = [g.name for g in sol.groups if g.kind.name == "RRR"]
                cond = min(np.sqrt(1 - (x[11] / r) ** 2).min(), min(sol.conditioning(g).min() for g in rrr))
                assert math.degrees(math.asin(cond)) >= float(atlas.mu[d]) - 0.1
            elif topology != "inverted_slider_crank":
                cond = min(sol.conditioning(g.name).min() for g in sol.groups)
                assert math.degrees(math.asin(cond)) >= float(atlas.mu[d]) - 0.1
        # the stored output harmonics rebuild the output the solver gives
        th = 2 * math.pi * np.arange(96) / 96
        got = function_values(atlas, np.array([d]), th)[0]
        ev = F.evaluate(topology, atlas.params(np.array([d * POINTS])), th[None], 1.0).out[0]
        linear = F.OUTPUT_UNIT[topology] == "mm"        # a slider's position
        ref = ev if linear else np.unwrap(ev)
        err = np.abs(got - ref) if linear else np.abs(np.angle(np.exp(1j * (got - ref))))
        # the stored numbers are the output's first harmonics (float16), whatever is left out
        turns = float(atlas.turns[d])
        c = np.fft.rfft(ref - turns * th) / len(th)
        want = [c[0].real] + [v for k in range(1, 5) for v in (2 * c[k].real, -2 * c[k].imag)]
        assert np.allclose(np.asarray(atlas.func[d], float), want, rtol=2e-3, atol=2e-3 * max(1.0, np.ptp(ref)))
        if topology not in F.GUIDE_SIXBARS:   # a guided rocker may swing faster than four harmonics follow
            assert np.max(err) < 0.05 * max(1.0, np.ptp(ref))


def test_atlas_is_stored_and_versioned(atlas_cache, tmp_path, monkeypatch):
    folder = atlas_folder("fourbar", TEST_DESIGNS)
    assert folder.is_dir() and str(folder).startswith(str(atlas_cache))
    meta = json.loads((folder / "meta.json").read_text())
    assert meta["version"] == VERSION and meta["designs"] == TEST_DESIGNS
    again = read_atlas(folder)
    built = build_atlas("fourbar", TEST_DESIGNS)
    for name in ("shape", "points", "desc", "func", "mu"):
        assert np.array_equal(np.asarray(getattr(again, name)), getattr(built, name))
    assert disk_bytes(folder) < 300 * TEST_DESIGNS    # 300 MB per million designs at most
    monkeypatch.setenv("MECHSKETCH_CACHE_DIR", str(tmp_path))
    forget_loaded()
    old = atlas_folder("fourbar", 3000)
    old.mkdir(parents=True)
    (old / "meta.json").write_text(json.dumps({"version": VERSION - 1, "topology": "fourbar"}))
    assert read_atlas(old) is None                      # another version: not read
    seen = []
    atlas = load_atlas("fourbar", 3000, progress=lambda f, m: seen.append(f))
    assert len(atlas) == 3000 and seen[-1] == 1.0 and read_atlas(old) is not None
    forget_loaded()


def test_dask_builds_the_same_atlas():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None,
                                  protocol="inproc") as cl, \
            distributed.Client(cl) as client:
        remote = build_atlas("slider_crank", 2000, client=client, chunk=4096)
    local = build_atlas("slider_crank", 2000, chunk=4096)
    for name in ("shape", "points", "desc", "func", "turns", "mu"):
        assert np.array_equal(getattr(remote, name), getattr(local, name))
