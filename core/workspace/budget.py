"""Memory of a request, estimated before anything is solved, against a stated budget.

A request is refused (:class:`RequestError`, naming the estimate, the budget and what to change)
when its estimate exceeds :func:`memory_budget`: 4 GB unless ``$MECHSKETCH_MEMORY_MB`` says
otherwise. The estimates are linear models of the peak memory measured with ``tracemalloc`` for a
whole ``mechsketch analyze`` (solve, diagnostics and the CSV table, which is built in memory
before its atomic write), with a margin:

- a linkage: :data:`LINKAGE_BYTES` per (joint + link) per sample — measured 200 B per joint and
  sample for the solve and its diagnostics, 390 B with the CSV table (chains of 10 and 34 joints,
  50,000 samples);
- a Geneva drive: :data:`GENEVA_BYTES` per sample — measured 640–890 B with the CSV table
  (1e5 and 1e6 samples);
- a rolling lever: its points are at most 100,000 by the schema, a few MB: not estimated.

So the schema's maxima (2,000 joints and 1e6 samples: about 1.6 TB) and a Geneva drive of 1e7
samples (10 GB) are refused in milliseconds instead of running out of memory or for minutes.
"""
from __future__ import annotations

import os
from typing import Any

from ..errors import RequestError

#: the default budget, bytes
DEFAULT_BUDGET = 4e9
#: estimated peak bytes per (joint + link) and sample of a linkage request
LINKAGE_BYTES = 400.0
#: estimated peak bytes per sample of a Geneva request
GENEVA_BYTES = 1000.0
ENV = "MECHSKETCH_MEMORY_MB"


def memory_budget() -> float:
    """Bytes a request may use: ``$MECHSKETCH_MEMORY_MB`` (megabytes) if set and valid, else 4 GB."""
    text = os.environ.get(ENV, "").strip()
    try:
        mb = float(text)
    except ValueError:
        return DEFAULT_BUDGET
    return mb * 1e6 if mb > 0 and mb == mb and mb != float("inf") else DEFAULT_BUDGET


def request_bytes(element: Any, samples: int) -> float:
    """Estimated peak bytes of solving and tabulating ``element`` at ``samples`` samples (0 for
    element types whose size the schema already bounds)."""
    kind = getattr(element, "type", None)
    if kind == "linkage":
        return LINKAGE_BYTES * (len(element.joints) + len(element.links)) * float(samples)
    if kind == "geneva":
        return GENEVA_BYTES * float(samples)
    return 0.0


def _size(n: float) -> str:
    return f"{n / 1e9:,.1f} GB" if n >= 1e9 else f"{n / 1e6:,.0f} MB"


def check_request(element: Any, samples: int) -> None:
    """Raise :class:`RequestError` if ``element`` at ``samples`` samples would exceed the budget."""
    need, budget = request_bytes(element, samples), memory_budget()
    if need <= budget:
        return
    fit = int(samples * budget / need)
    if element.type == "linkage":
        what = (f"{len(element.joints):,} joints and {len(element.links):,} links × {samples:,} samples × "
                f"{LINKAGE_BYTES:.0f} B")
    else:
        what = f"{samples:,} samples × {GENEVA_BYTES:.0f} B"
    raise RequestError(
        f"{element.type} {element.id!r}: solving {samples:,} samples needs about {_size(need)} of memory "
        f"({what}), over the budget of {_size(budget)}; use at most {max(fit, 0):,} samples (the "
        f"element's 'samples', or --samples) or raise the budget with {ENV}")
