"""The atlas built by the studies engine (core/design/atlas_engine.py, the default build) against
the closed form of core/design/families.py (the build before atlas format v2):

- every design's coupler points, output and transmission angle agree to 1e-12 of the size, for
  all nine topologies (the six-bars with a slider or a guided rocker included);
- a chunk built on the engine admits the same designs as the closed form's, with descriptors and
  output harmonics equal to 1e-12 (float64, before the atlas's float16 storage), and a whole
  small atlas is the closed form's bit for bit once stored;
- the build runs through the studies engine's task runner: two threads (``workers=2``) and a
  Dask LocalCluster give the atlas of one thread bit for bit; progress reaches 1, a cancel
  (from the progress callback or an Event) stops it with Cancelled; an atlas cached in the
  older format is named and rebuilt.
"""
from __future__ import annotations

import json
import math
import threading

import numpy as np
import pytest

from mechsketch.core.design import atlas as AT
from mechsketch.core.design import families as F
from mechsketch.core.design.atlas_engine import engine_solver
from mechsketch.core.design.atlas_store import VERSION, atlas_folder
from mechsketch.core.design.targets import Cancelled

TOPOLOGIES = ("fourbar", "slider_crank", "inverted_slider_crank", "sixbar", "watt_sixbar", "sixbar_slider",
              "watt_sixbar_slider", "sixbar_guide", "watt_sixbar_guide")
ARRAYS = ("shape", "points", "desc", "func", "turns", "mu")


def _designs(topology: str, n: int = 200):
    shape, points = AT._draw(topology, 0, 2048, 0)
    keep = AT.screen(topology, shape)
    shape, points = shape[keep], points[keep]
    if topology in F.ALL_SIXBARS:
        lengths = (AT.slider_lengths if topology in F.SLIDER_SIXBARS else
                   AT.guide_lengths if topology in F.GUIDE_SIXBARS else AT.sixbar_lengths)
        shape, points, ok = lengths(shape, points, watt=topology in F.WATTS)
        shape, points = shape[ok], points[ok]
    return shape[:n], points[:n]


@pytest.mark.parametrize("topology", TOPOLOGIES)
def test_engine_agrees_with_the_closed_form(topology):
    shape, points = _designs(topology)
    theta = 2 * math.pi * np.arange(96) / 96
    P1, out1, mu1, ok1 = AT.closed_form_solver(topology, shape, points, theta)
    P2, out2, mu2, ok2 = engine_solver(topology, shape, points, theta)
    assert np.array_equal(ok1.all(axis=1), ok2.all(axis=1))
    both = ok1.all(axis=1)
    assert both.sum() > 0.5 * len(shape)
    size = np.max(np.abs(P1[both]))
    assert np.max(np.abs(P1[both] - P2[both])) <= 1e-12 * size
    d = out1[both] - out2[both]
    if F.OUTPUT_UNIT[topology] == "rad":
        d = np.angle(np.exp(1j * d))
    assert np.max(np.abs(d)) <= 1e-12 * max(1.0, size)
    assert np.max(np.abs(mu1[both] - mu2[both])) <= 1e-12


@pytest.mark.parametrize("topology", TOPOLOGIES)
def test_engine_chunk_admits_the_same_designs_with_the_same_descriptors(topology):
    a = AT.describe_chunk(topology, 1, 0, 2048, solver=AT.closed_form_solver)
    b = AT.describe_chunk(topology, 1, 0, 2048)        # the default: the studies engine
    assert len(a["drawn"]) > 50
    assert np.array_equal(a["drawn"], b["drawn"])       # the same designs admitted
    assert np.array_equal(a["shape"], b["shape"]) and np.array_equal(a["turns"], b["turns"])
    assert np.max(np.abs(a["desc"] - b["desc"])) <= 1e-12    # descriptors: in units of the curve's size
    scale = max(1.0, float(np.max(np.abs(a["func"]))))
    assert np.max(np.abs(a["func"] - b["func"])) <= 1e-12 * scale
    assert np.max(np.abs(a["mu"] - b["mu"])) <= 1e-9        # degrees


@pytest.mark.parametrize("topology", ["fourbar", "sixbar", "sixbar_slider", "watt_sixbar_guide"])
def test_engine_atlas_is_the_closed_form_atlas(topology):
    a = AT.build_atlas(topology, 300, chunk=2048, solver=AT.closed_form_solver)
    b = AT.build_atlas(topology, 300, chunk=2048)
    assert b.meta["solver"].startswith("studies engine") and a.meta["solver"] == "closed form"
    for name in ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_threads_and_progress_and_cancel():
    seen = []
    one = AT.build_atlas("watt_sixbar_slider", 1500, chunk=1024, progress=lambda f, m: seen.append((f, m)))
    assert seen[-1][0] == 1.0 and "1,500 of 1,500" in seen[-1][1]
    assert all(0.0 <= f <= 1.0 for f, _ in seen) and [f for f, _ in seen] == sorted(f for f, _ in seen)
    two = AT.build_atlas("watt_sixbar_slider", 1500, chunk=1024, workers=2)
    for name in ARRAYS:
        assert np.array_equal(getattr(one, name), getattr(two, name)), name
    with pytest.raises(Cancelled, match="cancelled"):
        AT.build_atlas("sixbar_slider", 5000, chunk=1024, progress=lambda f, m: f > 0.0)
    stop = threading.Event()
    stop.set()
    with pytest.raises(Cancelled):
        AT.build_atlas("fourbar", 5000, chunk=1024, cancel=stop)


def test_dask_builds_the_engine_atlas_bit_for_bit():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None,
                                  protocol="inproc") as cl, distributed.Client(cl) as client:
        remote = AT.build_atlas("sixbar_slider", 1200, client=client, chunk=1024)
    local = AT.build_atlas("sixbar_slider", 1200, chunk=1024)
    assert remote.meta["dask"] and remote.meta["drawn"] == local.meta["drawn"]
    for name in ARRAYS:
        assert np.array_equal(getattr(remote, name), getattr(local, name)), name


def test_an_older_cached_atlas_is_named_and_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHSKETCH_CACHE_DIR", str(tmp_path))
    AT.forget_loaded()
    old = atlas_folder("slider_crank", 1000, VERSION - 1)
    old.mkdir(parents=True)
    (old / "meta.json").write_text(json.dumps({"version": VERSION - 1, "topology": "slider_crank"}))
    with pytest.raises(Exception, match=rf"format v{VERSION - 1} \(older than v{VERSION}"):
        AT.load_atlas("slider_crank", 1000, build=False)
    seen = []
    atlas = AT.load_atlas("slider_crank", 1000, progress=lambda f, m: seen.append(m))
    assert len(atlas) == 1000 and "rebuilding" in seen[0] and "studies engine" in seen[0]
    assert atlas.meta["version"] == VERSION and "replaces" in atlas.meta
    assert (atlas_folder("slider_crank", 1000) / "meta.json").exists()
    AT.forget_loaded()


def test_the_fused_loop_gives_the_numpy_path_bits():
    from mechsketch.core.design.atlas_engine import fused_engine_solver

    a = AT.describe_chunk("sixbar_slider", 2, 0, 2048)
    b = AT.describe_chunk("sixbar_slider", 2, 0, 2048, solver=fused_engine_solver)
    for name in ARRAYS + ("drawn",):
        assert np.array_equal(a[name], b[name]), name


def test_a_chunk_cut_at_its_limit_is_the_start_of_the_whole_chunk(monkeypatch):
    # many slices, so that the cut falls inside the chunk (the slices are the same either way:
    # numpy's rounding may depend on an array's length, so the slicing is part of the format)
    monkeypatch.setattr(AT, "SLICE", 128)
    whole = AT.describe_chunk("watt_sixbar", 0, 0, 4096, solver=AT.closed_form_solver)
    assert len(whole["drawn"]) > 400
    part = AT.describe_chunk("watt_sixbar", 0, 0, 4096, solver=AT.closed_form_solver, limit=300)
    k = len(part["drawn"])
    assert 300 <= k < len(whole["drawn"])
    for name in ARRAYS + ("drawn",):
        w = whole[name][: k * 2] if name == "desc" else whole[name][:k]
        assert np.array_equal(part[name], w), name
