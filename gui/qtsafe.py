"""Python overrides of Qt virtual functions whose errors are reported, never a segfault.

With Python 3.11 and PySide6 (measured with 6.8.3, 6.9.3, 6.10.3 and 6.11.3), an exception raised
by C code — ``1/0``, ``len(5)``, ``int("x")``, a call on a deleted Qt object — that leaves a Python
override of a Qt virtual function (``paint``, ``mouseMoveEvent``, ``showEvent``, ...) while Python
code is driving Qt (a test, ``processEvents``, ``grab``, ``QAction.trigger``) kills the process:
shiboken prepends "Error calling Python override of ..." to the exception's arguments, and the
exception object CPython 3.11 left unnormalised (its value still a plain string) makes
``PepException_GetArgs`` read garbage (SIGSEGV in ``storePythonOverrideErrorOrPrint``). An
exception raised by Python code (``raise ValueError(...)``), or one caught and re-raised once, is
a normal exception object and is reported as PySide always did.

:func:`qt_safe` (a class decorator) wraps each method of a class that overrides a Qt method so
that no exception ever leaves it into shiboken: the error is reported through ``sys.excepthook``
(the app shows it and keeps running; pytest-qt fails the test) and Qt's own implementation
answers instead (a paint with none draws nothing). Only re-raising is not enough: a second error
while shiboken still holds the first one (two items failing in one paint) crashes the same way.
``tests/gui/test_crash_safety.py`` checks that every override in the GUI is wrapped.
:func:`guard_library` does the same for a library's Qt classes (pyqtgraph's items and views,
whose overrides also run our slots).
"""
from __future__ import annotations

import functools
import inspect
import sys
from collections.abc import Callable, Iterable, Iterator
from typing import Any, TypeVar

T = TypeVar("T", bound=type)

_QT_MODULES = ("PySide6", "shiboken6")


def _is_qt(cls: type) -> bool:
    return cls.__module__.startswith(_QT_MODULES)


def qt_overrides(cls: type) -> Iterator[tuple[type, str, Callable[..., Any]]]:
    """(defining class, name, function) of each method of ``cls`` or its Python bases that has
    the name of a method of one of its Qt bases."""
    qt_bases = [b for b in cls.__mro__ if _is_qt(b)]
    if not qt_bases:
        return
    for owner in cls.__mro__:
        if _is_qt(owner) or owner is object:
            continue
        for name, fn in vars(owner).items():
            if (inspect.isfunction(fn) and not (name.startswith("__") and name.endswith("__"))
                    and any(name in vars(q) for q in qt_bases)):
                yield owner, name, fn


def _qt_default(obj: Any, name: str, args: tuple, kwargs: dict) -> Any:
    """What Qt's own implementation of ``name`` answers (None for a pure virtual)."""
    for base in type(obj).__mro__:
        if _is_qt(base) and name in vars(base):
            try:
                return vars(base)[name](obj, *args, **kwargs)
            except Exception:   # a pure virtual has no answer; an error here is already reported
                return None
    return None


def _reported(fn: Callable[..., Any]) -> Callable[..., Any]:
    name = fn.__name__

    @functools.wraps(fn)
    def override(self: Any, *args: Any, **kwargs: Any) -> Any:
        try:
            return fn(self, *args, **kwargs)
        except Exception:   # the boundary to Qt: reported, never swallowed (module docstring)
            sys.excepthook(*sys.exc_info())
            return _qt_default(self, name, args, kwargs)
    override.__qtsafe__ = True   # type: ignore[attr-defined]
    return override


def qt_safe(cls: T) -> T:
    """Class decorator: wrap every Qt override of ``cls`` (and of its Python bases) so that its
    errors are reported and Qt's own implementation answers (see the module docstring).
    Idempotent."""
    for owner, name, fn in list(qt_overrides(cls)):
        if not getattr(fn, "__qtsafe__", False):
            setattr(owner, name, _reported(fn))
    return cls


def _subclasses(roots: Iterable[type]) -> Iterator[type]:
    seen: set[type] = set()
    stack = list(roots)
    while stack:
        cls = stack.pop()
        for sub in cls.__subclasses__():
            if sub not in seen:
                seen.add(sub)
                stack.append(sub)
                yield sub


def guard_library(prefix: str) -> int:
    """Apply :func:`qt_safe` to every loaded Qt class whose module starts with ``prefix`` (e.g.
    "pyqtgraph"); returns how many classes it guarded. Call it after the library is imported."""
    from PySide6.QtCore import QObject
    from PySide6.QtWidgets import QGraphicsItem

    count = 0
    for cls in _subclasses((QObject, QGraphicsItem)):
        if cls.__module__.startswith(prefix):
            qt_safe(cls)
            count += 1
    return count
