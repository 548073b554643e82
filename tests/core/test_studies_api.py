"""The studies' one-line API on a workspace element, by the names the issue fixes."""
from __future__ import annotations

import numpy as np
import pytest

from mechsketch.core.errors import RequestError
from mechsketch.core.workspace import Workspace


def test_the_facade_names():
    view = Workspace.open("resources/examples/fourbar_crank_rocker.json")["fourbar"]
    D, N = 5, 36
    crank = next(d.value for d in view.dimensions() if d.key == "length:crank:A:B")
    b = view.solve_variants({"length:crank:A:B": crank + np.arange(-2.0, 3.0)}, samples=N, order=2)
    assert b.position("E").shape == (D, N, 2) and b.velocity("E").shape == (D, N, 2)
    assert b.acceleration("E").shape == (D, N, 2) and b.angle("rocker").shape == (D, N)
    assert b.valid.shape == (D, N) and b.full_cycle.shape == (D,) and b.min_transmission_angle.shape == (D,)
    one = view.solve(samples=N, order=2)          # the middle design is the drawn one
    assert np.max(np.abs(b.position("E")[2] - one.position("E"))) < 1e-12 * 200
    assert b.forces().effort.shape == (D, N)
    spec = {"length:crank:A:B": {"normal": 0.0167}, "length:coupler:B:C": {"uniform": 0.05},
            "clearance": {"B": "H7/g6", "C": "H8/f7"}}
    t = view.tolerance(spec, builds=500, samples=N, seed=3, client=None)
    assert t.deviation("E").shape == (500,) and t.envelope("E", 0.9).shape == (N, 2)
    assert t.angle_deviation("rocker").shape == (500,)
    assert set(t.sensitivity()) == {"length:crank:A:B", "length:coupler:B:C", "clearance:B", "clearance:C"}
    lin = view.linearised_tolerance({k: v for k, v in spec.items() if k != "clearance"}, samples=N)
    assert lin.band("E").shape == (N,)
    with pytest.raises(RequestError):
        Workspace.open("resources/examples/geneva_z6.json")["indexer"].solve_variants({"x": [1.0]})
