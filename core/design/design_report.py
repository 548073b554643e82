"""What every requirement-driven design returns and how it reports: requirement rows with value,
limit and margin, the binding one, refusals naming what to relax, progress and cancel.

Used by :mod:`.geneva`, :mod:`.rolling`, :mod:`.gears` and :mod:`.smooth_geneva`. A design
function takes the requirements and an optional ``progress`` callback and returns a result whose
``element`` is an ordinary scene element and whose ``report`` is a :class:`DesignReport`.

Calling a design from a worker thread (the app's Design dock)::

    def progress(fraction: float, text: str) -> bool:   # called from the worker thread
        signals.progress.emit(fraction, text)          # queued to the GUI thread
        return not cancel_requested.is_set()           # False: stop as soon as possible

    try:
        result = design_geneva(requirements, progress=progress)
    except DesignCancelled:
        ...                                            # nothing was made
    except DesignError as exc:                         # infeasible: exc.relax says what to change
        ...

``progress(fraction, text)`` is called with a non-decreasing ``fraction`` in [0, 1] and a short
text at least every few hundred evaluations (tens of milliseconds); returning ``False`` makes the
design raise :class:`DesignCancelled` at that point (returning None or True carries on). The
design functions touch no global state and share nothing between calls, so several may run on
different threads at once.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

from mechsketch import resources   # the shipped schemas (a data package)

from ..errors import MechsketchError

#: ``progress(fraction, text) -> bool | None``: False cancels (see the module docstring)
Progress = Callable[[float, str], "bool | None"]


class DesignError(MechsketchError, ValueError):
    """A set of requirements no design meets (or a malformed request).

    ``relax``: the requirements whose relaxation alone would make the set feasible, as
    :class:`Relaxation` records sorted by the relative change they need (the first is the least
    change); empty for a malformed request.
    """

    def __init__(self, message: str, relax: Sequence["Relaxation"] = ()) -> None:
        super().__init__(message)
        self.relax = tuple(relax)


class DesignCancelled(MechsketchError):
    """The ``progress`` callback asked to stop; nothing was made."""


@dataclass(frozen=True)
class Relaxation:
    """Relax requirement ``name`` (its REQ key) from ``current`` to ``needed`` (``unit``)."""

    name: str
    current: float
    needed: float
    unit: str
    relative: bool = True   # False for a choice (a side, a sign): no percentage is stated

    @property
    def change(self) -> float:
        """The relative change needed, |needed − current| / |current| (inf from 0)."""
        return abs(self.needed - self.current) / abs(self.current) if self.current else math.inf

    def text(self) -> str:
        sign = "+" if self.needed > self.current else "−"
        rel = f" ({sign}{100 * self.change:.3g} %)" if math.isfinite(self.change) and self.relative else ""
        return f"{self.name} from {_num(self.current)} to {_num(self.needed)} {self.unit}{rel}".replace(" ''", "")


def infeasible(summary: str, relax: Sequence[Relaxation], several: bool = False) -> DesignError:
    """A :class:`DesignError` whose message names every relaxation, the least change first;
    ``several``: more than one requirement fails, so each named relaxation mends only its own."""
    options = sorted(relax, key=lambda r: r.change)
    if options and several:
        summary = f"{summary}. Each failing requirement needs its own change: " + "; ".join(r.text() for r in options)
    elif options:
        what = "; or ".join(r.text() for r in options)
        summary = f"{summary}. Relax {options[0].name} (the least change): {what}"
    return DesignError(summary, options)


@dataclass(frozen=True)
class Requirement:
    """One row of a design report.

    ``name`` the REQ key (or a name for a derived check), ``what`` in words, ``value`` achieved,
    ``limit`` required, ``sense`` ``"<="``, ``">="`` or ``"=="`` (value against limit), ``unit``.
    :attr:`margin` is the relative margin, positive when met; ``binding`` marks the requirement
    that decided the design's size.
    """

    name: str
    what: str
    value: float
    limit: float
    sense: str
    unit: str = ""
    binding: bool = False
    tolerance: float = 0.0   # for "==": the accepted |value − limit|

    @property
    def margin(self) -> float:
        """Relative margin: (limit − value)/|limit| for "<=", (value − limit)/|limit| for ">=",
        (tolerance − |value − limit|)/|limit| for "==" (0 limit: absolute)."""
        scale = abs(self.limit) or 1.0
        if self.sense == "<=":
            return (self.limit - self.value) / scale
        if self.sense == ">=":
            return (self.value - self.limit) / scale
        return (self.tolerance - abs(self.value - self.limit)) / scale

    @property
    def met(self) -> bool:
        return self.margin >= 0.0

    def line(self) -> str:
        mark = "  <- binding" if self.binding else ""
        unit = f" {self.unit}" if self.unit else ""
        return (f"  {self.name}: {self.what} {_num(self.value)}{unit} {self.sense} {_num(self.limit)}{unit}, "
                f"margin {100 * self.margin:+.3g} %{mark}")


@dataclass(frozen=True)
class DesignReport:
    """The report of one design: its ``title``, every requirement (:class:`Requirement`), notes
    (sizes chosen, methods, errors) and the time taken (s)."""

    title: str
    requirements: tuple[Requirement, ...]
    notes: tuple[str, ...] = ()
    seconds: float = 0.0
    extra: dict = field(default_factory=dict)

    @property
    def binding(self) -> Requirement | None:
        """The binding requirement (the one marked, else the smallest margin)."""
        marked = [r for r in self.requirements if r.binding]
        if marked:
            return marked[0]
        return min(self.requirements, key=lambda r: r.margin) if self.requirements else None

    def requirement(self, name: str) -> Requirement:
        for r in self.requirements:
            if r.name == name:
                return r
        raise KeyError(name)

    def text(self) -> str:
        """The report as printed by ``mechsketch design``."""
        b = self.binding
        lines = [self.title, "requirements (value, limit, relative margin):"]
        lines += [r.line() for r in self.requirements]
        if b is not None:
            lines.append(f"binding: {b.name} ({b.what})")
        lines += [f"  {n}" for n in self.notes]
        lines.append(f"designed in {self.seconds:.3g} s")
        return "\n".join(lines)


def schema_problems(schema: str, data: dict) -> list[str]:
    """The ranges an element dict breaks, against its shipped JSON schema (``path: message``):
    what the scene reader would refuse, checked before a design spends time on it."""
    import jsonschema   # heavy (~40 ms): only when a design runs

    validator = jsonschema.Draft202012Validator(resources.schema(schema))
    return [f"{'.'.join(map(str, e.absolute_path)) or 'element'}: {e.message}" for e in validator.iter_errors(data)]


def report_progress(progress: Progress | None, fraction: float, text: str) -> None:
    """Call ``progress``; raise :class:`DesignCancelled` if it returns False."""
    if progress is not None and progress(min(max(fraction, 0.0), 1.0), text) is False:
        raise DesignCancelled(f"cancelled at {100 * fraction:.0f} %: {text}")


def _num(x: float) -> str:
    if isinstance(x, int) or (math.isfinite(x) and x == int(x) and abs(x) < 1e15):
        return f"{int(x)}"
    return f"{x:.6g}"
