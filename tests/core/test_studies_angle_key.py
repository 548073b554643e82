"""Regression: a tolerance on an angle key (``angle:LINK:A:B:C``) is differentiated by complex step
like a length (the Study dock ticks the coupler's angle by default). The linearised band's σ of
the coupler point is checked against central differences of the one-design path
(``set_dimension`` + ``solve``)."""
from __future__ import annotations

import numpy as np

from mechsketch.core import Workspace
from mechsketch.core.studies.tolerance import linearised_tolerance
from mechsketch.resources import example_path

KEY = "angle:coupler:B:C:E"


def _path(ws, value: float) -> np.ndarray:
    view = ws["fourbar"]
    old = view.set_dimension(KEY, value)
    p = ws["fourbar"].solve(samples=72, order=0).position("E")
    ws.apply(old)
    return p


def test_an_angle_tolerance_gives_the_band_of_the_one_design_path():
    ws = Workspace.open(example_path("fourbar_crank_rocker"))
    lk = ws.scene.element("fourbar")
    nominal = next(d.value for d in ws["fourbar"].dimensions() if d.key == KEY)
    sigma = 0.05   # degrees
    band = linearised_tolerance(lk, {KEY: {"normal": sigma}}, samples=72, joints=["E"])
    h = 1e-4
    dp = (_path(ws, nominal + h) - _path(ws, nominal - h)) / (2 * h)    # mm per degree
    nu = band.nominal.normal["E"]
    ref = sigma * np.abs((dp * nu).sum(axis=1))
    got = band.sigma("E")
    assert np.all(np.isfinite(got)) and ref.max() > 1e-3
    assert np.max(np.abs(got - ref)) <= 1e-6 * ref.max()
