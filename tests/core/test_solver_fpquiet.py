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


def test_falls_back_to_errstate_where_numpys_private_calls_do_not_behave(monkeypatch):
    """A numpy whose private helper changed its signature: the import-time check sends every
    solve to ``np.errstate`` instead of failing inside it."""
    import importlib

    import numpy._core.umath as umath

    def changed(*args, **kwargs):
        raise TypeError("_make_extobj() got an unexpected keyword argument 'invalid'")

    monkeypatch.setattr(umath, "_make_extobj", changed)
    fresh = importlib.reload(fpquiet)
    try:
        assert fresh._VAR is None
        t = fresh.enter()
        try:
            assert np.geterr()["invalid"] == "ignore"
        finally:
            fresh.leave(t)
    finally:
        monkeypatch.undo()
        importlib.reload(fpquiet)
    assert fpquiet._VAR is not None
