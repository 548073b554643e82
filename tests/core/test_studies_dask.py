"""Studies on Dask: the same bits as in this process, progress and cancel on the cluster.

One LocalCluster (two workers, threads in this process) serves the module; one test starts real
worker processes through ``mechsketch study --workers 2``.
"""
from __future__ import annotations

import json
import threading
from pathlib import Path

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

from mechsketch.core.cli import main  # noqa: E402
from mechsketch.core.studies.execute import StudyCancelled  # noqa: E402
from mechsketch.core.studies.tolerance import BLOCK  # noqa: E402
from mechsketch.core.workspace import Workspace  # noqa: E402

FOURBAR = "resources/examples/fourbar_crank_rocker.json"
SPEC = {"length:crank:A:B": {"normal": 0.02}, "length:coupler:B:C": {"uniform": 0.05}, "clearance": {"C": "H8/f7"}}


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0")
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_tolerance_on_the_cluster_is_bit_identical(client):
    view = Workspace.open(FOURBAR)["fourbar"]
    here = view.tolerance(SPEC, builds=3 * BLOCK + 7, samples=24, seed=4, joints=["E"], links=["rocker"])
    there = view.tolerance(SPEC, builds=3 * BLOCK + 7, samples=24, seed=4, joints=["E"], links=["rocker"], client=client)
    assert np.array_equal(here.deviation("E"), there.deviation("E"))
    assert np.array_equal(here.angle_deviation("rocker"), there.angle_deviation("rocker"))
    for q in (0.005, 0.5, 0.995):
        assert np.array_equal(here.envelope("E", q), there.envelope("E", q), equal_nan=True)
    assert np.array_equal(here.sigma("E"), there.sigma("E"), equal_nan=True)


def test_progress_and_cancel_on_the_cluster(client):
    view = Workspace.open(FOURBAR)["fourbar"]
    seen = []
    view.tolerance(SPEC, builds=2 * BLOCK, samples=12, seed=1, joints=["E"], links=[], client=client,
                   progress=lambda done, total: seen.append((done, total)))
    assert seen[0] == (0, 2) and seen[-1] == (2, 2) and len(seen) == 3
    stop = threading.Event()
    with pytest.raises(StudyCancelled):
        view.tolerance(SPEC, builds=6 * BLOCK, samples=12, seed=1, joints=["E"], links=[], client=client,
                       progress=lambda done, total: stop.set() if done >= 1 else None, cancel=stop)


def test_a_sweep_on_the_cluster_equals_the_local_one(client, tmp_path):
    from mechsketch.core.cli.study_cmds import prepare
    from mechsketch.core.studies.study import run_study

    study = {"scene": str(Path(FOURBAR).resolve()),
             "variables": {"length:crank:A:B": {"range": [30, 60]}, "length:rocker:D:C": {"range": [90, 140]}},
             "metrics": ["min_transmission_angle", "full_cycle"], "samples": 36,
             "sweep": {"method": "sobol", "designs": 4500}}
    p = tmp_path / "s.json"
    p.write_text(json.dumps(study))
    _, st = prepare(str(p))
    a = run_study(st)
    b = run_study(st, client=client)
    for k in a.columns:
        assert np.array_equal(a.columns[k], b.columns[k], equal_nan=True), k


@pytest.mark.slow   # starts two worker processes (~10 s quiet, 35 s under load 12)
def test_real_worker_processes_give_the_same_files(tmp_path):
    study = {"scene": str(Path(FOURBAR).resolve()), "samples": 12, "seed": 9,
             "variables": {"length:crank:A:B": {"normal": 0.02}}, "clearance": {"B": "H7/g6"},
             "montecarlo": {"builds": BLOCK + 50, "joints": ["E"], "links": []}}
    p = tmp_path / "mc.json"
    p.write_text(json.dumps(study))
    assert main(["study", str(p), "--out", str(tmp_path / "one")]) == 0
    assert main(["study", str(p), "--out", str(tmp_path / "two"), "--workers", "2"]) == 0
    assert (tmp_path / "one" / "builds.csv").read_bytes() == (tmp_path / "two" / "builds.csv").read_bytes()
    assert (tmp_path / "one" / "envelope.csv").read_bytes() == (tmp_path / "two" / "envelope.csv").read_bytes()


def _sum_with(ctx, i):
    a, b, name = ctx
    return (a + b * i, name)


def test_a_tuple_context_is_one_object_on_the_cluster_whatever_the_calls_before(client):
    """A tuple context went out element by element under content-hashed keys: equal numbers of two
    calls shared a key, and a call released them under the next ("lost dependencies")."""
    from concurrent.futures import ThreadPoolExecutor

    from mechsketch.core.studies.execute import run_tasks

    want = [(3 + 0.5 * i, "x") for i in range(6)]
    for _ in range(8):
        assert run_tasks(_sum_with, (3, 0.5, "x"), 6, client=client) == want
    with ThreadPoolExecutor(4) as pool:
        runs = list(pool.map(lambda _: run_tasks(_sum_with, (3, 0.5, "x"), 6, client=client), range(8)))
    assert runs == [want] * 8
