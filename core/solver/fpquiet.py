"""Numpy's floating-point warnings (invalid, divide, overflow) silenced around the kernels'
sample arithmetic, as ``np.errstate(invalid="ignore", divide="ignore", over="ignore")`` does,
for a fraction of its cost (~0.5 µs instead of ~2.5 µs a solve: numpy builds its error object
anew at every ``errstate``; here it is built once per caller's error state and kept).

``token = enter()`` … ``leave(token)`` (in ``try``/``finally``). On a numpy without the context
variable this relies on (numpy ≥ 2.0 has it), it falls back to ``np.errstate``. The caller's other
settings (underflow, a ``seterrcall`` handler) are kept, as ``errstate`` keeps them.
"""
from __future__ import annotations

import numpy as np

try:   # numpy ≥ 2: the error state is a context variable holding an immutable error object
    from numpy._core._ufunc_config import _extobj_contextvar as _VAR
    from numpy._core.umath import _make_extobj
except ImportError:   # pragma: no cover - older or future numpy
    _VAR = None

#: the caller's error object -> the same with invalid, divide and overflow ignored (the key is
#: held, so its identity cannot be reused by another object)
_MADE: dict = {}


def enter():
    """Silence the warnings until :func:`leave` is called with what this returns."""
    if _VAR is None:   # pragma: no cover
        e = np.errstate(invalid="ignore", divide="ignore", over="ignore")
        e.__enter__()
        return e
    cur = _VAR.get()
    quiet = _MADE.get(cur)
    if quiet is None:
        if len(_MADE) >= 16:
            _MADE.clear()
        quiet = _MADE[cur] = _make_extobj(invalid="ignore", divide="ignore", over="ignore")
    return _VAR.set(quiet)


def leave(token) -> None:
    """Restore the error state :func:`enter` replaced."""
    if _VAR is None:   # pragma: no cover
        token.__exit__(None, None, None)
    else:
        _VAR.reset(token)


def _works() -> bool:
    """Whether the private numpy calls behave here as this module expects (checked once, at
    import): a numpy whose private helpers changed signature or meaning falls back to
    ``np.errstate`` instead of failing inside a solve."""
    try:
        before = np.geterr()
        token = enter()
        try:
            quiet = np.geterr()
        finally:
            leave(token)
        return (quiet["invalid"] == quiet["divide"] == quiet["over"] == "ignore"
                and quiet["under"] == before["under"] and np.geterr() == before)
    except (TypeError, ValueError, AttributeError, LookupError, RuntimeError):
        return False


if _VAR is not None and not _works():   # pragma: no cover - depends on numpy's internals
    _VAR = None
    _MADE.clear()


__all__ = ["enter", "leave"]
