"""Keeping a sweep's working memory in the process between sweeps, whatever its allocator settings.

A sweep of N samples allocates and frees a few hundred (N,) arrays. With glibc's default malloc, a
process that did not call :func:`mechsketch.core.runtime.tune_allocator` (any script that imports
mechsketch) gives the top of its heap back to the kernel as soon as more than ``M_TRIM_THRESHOLD``
of it is free — 128 KiB at start, then twice the largest block it has mapped and unmapped
(glibc's dynamic threshold) — and faults it in again on the next sweep. At N = 36,000 that was
every page a sweep uses, every sweep (the six-bar: 4,679 minor faults, 2.0x the tuned process's
time, benchmarks/bench_api_alloc.py), whenever the previous solution had been let go first.

:func:`reserve` tells glibc the working size of the sweeps to come the way any program does when
it frees a large block: once per process (and again only for a larger size) it allocates and frees
one untouched block of 1 KiB per sample, at most 31 MiB. glibc maps such a block, and on
its free raises its mmap threshold to the block's size and its trim threshold to twice that, so
the sweeps' arrays come from the heap and stay there. Nothing is touched (no memory is used), no
setting is changed where the user set one (glibc then keeps its fixed thresholds), and on another
C library it is a harmless allocation. Results do not depend on it.

The first sweep of a size: it grows the heap by its working set and faults every new page in
(the six-bar at N = 36,000: 4,697 faults in a plain process). A process that called
``tune_allocator`` faulted only ~440: there the untouched reserve block itself came from the heap
(below its 64 MiB mmap threshold), and numpy asks Linux to back any allocation of at least 4 MiB
with transparent huge pages (``madvise(MADV_HUGEPAGE)``, honoured where THP is "madvise" or
"always"); the sweep's arrays then reused that advised stretch of the heap, one fault per 2 MiB.
:func:`reserve` does the same on purpose: after the first block has raised glibc's thresholds it
allocates and frees a second untouched block just below the new mmap threshold, which now comes
from the heap and stays there (below the trim threshold), advised for huge pages by numpy. For
that the reserve is at least :data:`HUGE_MIN` (8 MiB of address space, nothing touched).
"""
from __future__ import annotations

import numpy as np

#: bytes reserved per sample (a six-bar sweep with rates frees ~520 bytes a sample at once)
PER_SAMPLE = 1024
#: below this the default thresholds keep a sweep's memory already (N < 256)
LEAST = 128 << 10
#: glibc adapts its thresholds only to blocks of at most 32 MiB (DEFAULT_MMAP_THRESHOLD_MAX)
MOST = 31 << 20
#: numpy advises huge pages for allocations of at least 4 MiB; the reserve is at least this
HUGE_MIN = 8 << 20
#: the heap block is this much smaller than the first one (so that it is below the mmap threshold)
SLACK = 64 << 10

_reserved = 0


def reserve(samples: int) -> None:
    """Let the allocator keep the working memory of sweeps of ``samples`` samples, in huge pages
    where Linux gives them (see the module docstring); once per process and size, ~40 µs."""
    global _reserved
    size = PER_SAMPLE * samples
    if size < LEAST:
        return
    size = min(MOST, max(HUGE_MIN, size))
    if size <= _reserved:
        return
    _reserved = size
    np.empty(size, dtype=np.uint8)           # mapped and unmapped at once, never written
    np.empty(size - SLACK, dtype=np.uint8)   # from the heap now, advised for huge pages; kept there


__all__ = ["reserve"]
