"""Memory of a study, stated before anything runs, and the chunks that keep it bounded.

A study of 1e7 designs never holds more than :func:`memory_budget` bytes (``$MECHSKETCH_MEMORY_MB``,
else 4 GB, the same budget as every other request of the workspace): designs are solved in
chunks of a few hundred thousand design-samples — small enough that the kernels' temporaries stay
in the processor's cache — and what is kept of each chunk is reduced to what the caller asked for.
A request whose *kept* results alone exceed the budget is refused up front with the estimate, the
budget and what to change.
"""
from __future__ import annotations

import os

from ..errors import RequestError

ENV = "MECHSKETCH_MEMORY_MB"
DEFAULT_BUDGET = 4e9
#: design-samples per chunk: the temporaries of one chunk (~100 arrays) stay within a few MB
CHUNK_ELEMS = 1 << 15
#: estimated working bytes per design-sample and per (joint + link) while a chunk is solved
WORK_BYTES = 250.0


def memory_budget() -> float:
    """Bytes a study may use: ``$MECHSKETCH_MEMORY_MB`` (megabytes) if set and valid, else 4 GB."""
    text = os.environ.get(ENV, "").strip()
    try:
        mb = float(text)
    except ValueError:
        return DEFAULT_BUDGET
    return mb * 1e6 if mb > 0 and mb == mb and mb != float("inf") else DEFAULT_BUDGET


def size_text(n: float) -> str:
    return f"{n / 1e9:,.1f} GB" if n >= 1e9 else f"{n / 1e6:,.1f} MB"


def check_kept(nbytes: float, what: str, advice: str) -> None:
    """RequestError when ``nbytes`` (the results a request keeps) exceed the budget."""
    budget = memory_budget()
    if nbytes > budget:
        raise RequestError(f"{what} would keep about {size_text(nbytes)} of results, over the memory budget of "
                           f"{size_text(budget)} (${ENV}); {advice}")


def chunk_designs(samples: int, parts: int, total: int, kept_per_design: float = 0.0) -> int:
    """Designs per chunk for ``samples`` samples and a linkage of ``parts`` joints + links: about
    :data:`CHUNK_ELEMS` design-samples, fewer if the working memory would exceed the budget."""
    n = max(1, CHUNK_ELEMS // max(int(samples), 1))
    work = WORK_BYTES * max(parts, 1) * max(int(samples), 1)
    room = memory_budget() - kept_per_design * total
    if work * n > room > 0:
        n = max(1, int(room // work))
    return max(1, min(n, max(int(total), 1)))


__all__ = ["CHUNK_ELEMS", "ENV", "check_kept", "chunk_designs", "memory_budget", "size_text"]
