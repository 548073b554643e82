"""The atlas built by the studies engine (core/design/atlas_engine.py) against the closed form:
every design's coupler points, output and transmission angle agree to 1e-12 of the size, and
an atlas built on the engine is the closed form's bit for bit (float16/float32 storage)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mechsketch.core.design import atlas as AT
from mechsketch.core.design import families as F
from mechsketch.core.design.atlas_engine import engine_solver

TOPOLOGIES = ("fourbar", "slider_crank", "inverted_slider_crank", "sixbar", "watt_sixbar")


def _designs(topology: str, n: int = 200):
    shape, points = AT._draw(topology, 0, 2048, 0)
    keep = AT.screen(topology, shape)
    shape, points = shape[keep], points[keep]
    if topology in F.SIXBARS:
        shape, points, ok = AT.sixbar_lengths(shape, points, watt=topology == F.WATT)
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
    if topology != "slider_crank":
        d = np.angle(np.exp(1j * d))
    assert np.max(np.abs(d)) <= 1e-12 * max(1.0, size)
    assert np.max(np.abs(mu1[both] - mu2[both])) <= 1e-12


@pytest.mark.parametrize("topology", ["fourbar", "sixbar"])
def test_engine_atlas_is_the_closed_form_atlas(topology):
    a = AT.build_atlas(topology, 300, chunk=2048)
    b = AT.build_atlas(topology, 300, chunk=2048, solver=engine_solver)
    for name in ("shape", "points", "desc", "func", "turns", "mu"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
