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
"""
from __future__ import annotations

import numpy as np

#: bytes reserved per sample (a six-bar sweep with rates frees ~520 bytes a sample at once)
PER_SAMPLE = 1024
#: below this the default thresholds keep a sweep's memory already (N < 256)
LEAST = 128 << 10
#: glibc adapts its thresholds only to blocks of at most 32 MiB (DEFAULT_MMAP_THRESHOLD_MAX)
MOST = 31 << 20

_reserved = 0


def reserve(samples: int) -> None:
    """Let the allocator keep the working memory of sweeps of ``samples`` samples (see the module
    docstring); once per process and size, ~20 µs."""
    global _reserved
    size = min(MOST, PER_SAMPLE * samples)
    if size <= _reserved or size < LEAST:
        return
    _reserved = size
    np.empty(size, dtype=np.uint8)   # mapped and unmapped at once, never written


__all__ = ["reserve"]
