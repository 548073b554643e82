"""The locking disc's relief search against the search as it was (tests/core/geneva_relief_reference.py,
every wheel segment, one candidate after another): the same drawn radius and the same exact and
touch radii to 1e-12, for z = 3 … 24, the examples and random drives with extreme ratios
(hypothesis); the segments the faster search leaves out never come within the disc radius of the
crank centre (checked by dense sampling, independent of the bound that picked them)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from geneva_relief_reference import relief_old, relief_values_old
from mechsketch.core.analyses.geneva.geometry import relief, relief_values, wheel_outline
from mechsketch.core.analyses.geneva.relief import bounding_circles, reaching
from mechsketch.core.model.geneva import Clearances, Geneva, WheelDimensions, parse

EXAMPLES = Path(__file__).resolve().parents[2] / "resources" / "examples"


def assert_same_relief(d: WheelDimensions, lock: float) -> None:
    new, old = relief(d, lock), relief_old(d, lock)
    assert new.drawn == old.drawn
    assert new.exact == pytest.approx(old.exact, rel=1e-12, abs=0)
    assert new.touch == pytest.approx(old.touch, rel=1e-12, abs=0)
    assert new.phi_exact == pytest.approx(old.phi_exact, rel=0, abs=1e-12)
    assert (new.classical, new.limit_end) == (old.classical, old.limit_end)


@pytest.mark.parametrize("z", [3, 4, 5, 6, 8, 12, 16, 24])
@pytest.mark.parametrize("rp_fraction", [0.02, 0.16, 0.3])
@pytest.mark.parametrize("lock", [0.0, 0.1])
def test_relief_equals_the_old_search(z, rp_fraction, lock):
    a = 100.0
    d = Geneva("g", z, a, rp_fraction * a * math.sin(math.pi / z), clearance=Clearances(lock=lock)).dimensions()
    assert_same_relief(d, lock)


@pytest.mark.parametrize("name", ["geneva_z4.json", "geneva_z6.json", "geneva_z8.json"])
def test_relief_of_the_examples_equals_the_old_search(name):
    doc = json.loads((EXAMPLES / name).read_text())
    (data,) = [e for e in doc["elements"] if e["type"] == "geneva"]
    el, problems = parse(data, "$")
    assert el is not None, problems
    assert_same_relief(el.dimensions(), el.clearance.lock)


@st.composite
def extreme_drives(draw):
    z = draw(st.integers(3, 30))
    a = draw(st.floats(1.0, 5000.0))
    r = a * math.sin(math.pi / z)
    rp = draw(st.floats(0.01, 0.35)) * r
    cl = Clearances(draw(st.floats(0.0, 0.02)) * rp, draw(st.floats(0.0, 0.05)) * rp,
                    draw(st.floats(0.0, 0.03)) * r)
    data = {"type": "geneva", "id": "h", "slots": z, "center_distance": a, "roller_radius": rp,
            "clearance": cl.to_dict()}
    el, _ = parse(data, "$")
    assume(el is not None)
    lo, hi = el.dimensions().lock_arc_range
    frac = draw(st.floats(0.02, 1.0))  # the locking arc anywhere in its admissible range
    data["drawing"] = {"locking_arc_radius": lo + frac * (hi - lo)}
    el, _ = parse(data, "$")
    assume(el is not None)
    return el


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(extreme_drives())
def test_relief_of_random_drives_equals_the_old_search(el):
    assert_same_relief(el.dimensions(), el.clearance.lock)


@pytest.mark.parametrize("z", [3, 6, 12])
def test_relief_values_on_a_dense_grid_equal_every_segment(z):
    el = Geneva("g", z, 100.0, 4.0)
    d = el.dimensions()
    off = wheel_outline(d).offset(el.clearance.lock)
    phis = np.linspace(-d.phi0, d.phi0, 4001)
    new, old = relief_values(phis, off, d), relief_values_old(phis, off, d)
    assert np.array_equal(np.isfinite(new), np.isfinite(old)) and np.isfinite(old).sum() > 1000
    assert np.allclose(new[np.isfinite(new)], old[np.isfinite(old)], rtol=1e-14, atol=0)


def _dense_points(sg, k: int, step: float) -> np.ndarray:
    n = max(2, int(math.ceil(sg.length[k] / step)) + 1)
    t = np.linspace(0.0, 1.0, n)
    if sg.is_arc[k]:
        ang = sg.a0[k] + sg.theta[k] * t
        return sg.centre[k] + sg.radius[k] * np.c_[np.cos(ang), np.sin(ang)]
    return sg.p0[k] + np.outer(t, sg.p1[k] - sg.p0[k])


@pytest.mark.parametrize("z,rp", [(3, 2.0), (3, 12.0), (6, 8.0), (12, 1.0), (12, 5.0), (24, 2.0)])
def test_left_out_segments_never_reach_the_disc(z, rp):
    """Over the whole engagement, the grid's windows and small windows like the zoom's."""
    el = Geneva("g", z, 100.0, rp)
    d = el.dimensions()
    sg = wheel_outline(d).offset(el.clearance.lock).segments()
    edges = np.linspace(-d.phi0, d.phi0, 9)
    small = np.linspace(-d.phi0, d.phi0 - 0.03, 7)
    lo = np.r_[-d.phi0, edges[:-1], small]
    hi = np.r_[d.phi0, edges[1:], small + 0.03]
    keep = reaching(*bounding_circles(sg), d, lo, hi)
    assert (~keep[0]).sum() >= len(sg.theta) // 4  # the whole engagement leaves out something (least at z = 3)
    assert (~keep[1:]).sum(axis=1).min() > (~keep[0]).sum()  # each window more
    for w in range(len(lo)):
        # the crank centre in the wheel frame: distance A at angle π + θ(φ)
        phis = np.linspace(lo[w], hi[w], 301)
        th = math.pi + np.arctan2(d.lam * np.sin(phis), 1 - d.lam * np.cos(phis))
        o1 = d.center_distance * np.c_[np.cos(th), np.sin(th)]
        for k in np.nonzero(~keep[w])[0]:
            p = _dense_points(sg, k, 0.1)
            dist = np.hypot(p[:, None, 0] - o1[None, :, 0], p[:, None, 1] - o1[None, :, 1])
            assert dist.min() > d.lock_disc_radius, (w, k)  # outside the disc at every crank angle
