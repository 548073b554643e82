"""The kernels' cheap silencing of numpy's floating-point warnings (:mod:`~.solver.fpquiet`) does
what ``np.errstate(invalid="ignore", divide="ignore", over="ignore")`` does, and no more."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from mechsketch.core.solver import fpquiet


def test_silences_and_restores_like_errstate():
    before = np.geterr()
    t = fpquiet.enter()
    try:
        inside = np.geterr()
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            np.sqrt(np.array([-1.0]))          # invalid
            np.array([1.0]) / np.array([0.0])  # divide
            np.array([1e308]) * 10.0           # overflow
    finally:
        fpquiet.leave(t)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        assert inside == np.geterr()
    assert np.geterr() == before
    with pytest.warns(RuntimeWarning):
        np.sqrt(np.array([-1.0]))


def test_keeps_the_callers_other_settings_and_nests():
    with np.errstate(under="raise", invalid="raise"):
        outer = fpquiet.enter()
        inner = fpquiet.enter()
        assert np.geterr()["under"] == "raise" and np.geterr()["invalid"] == "ignore"
        fpquiet.leave(inner)
        fpquiet.leave(outer)
        assert np.geterr()["invalid"] == "raise"
        with pytest.raises(FloatingPointError):
            np.array([1e-308]) * 1e-308
