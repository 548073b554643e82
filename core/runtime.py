"""Process-wide run-time settings made once at start-up by the command line and the GUI launcher.

:func:`tune_allocator` sets glibc's malloc so that the arrays of a sweep are reused instead of
being handed back to the kernel and faulted in again on the next sweep. The measurements behind
it (benchmarks/bench_kernels.py, benchmarks/README.md): with glibc's default settings repeated
order-2 sweeps are 1.7-2.6x slower in a fresh process than in a process whose heap has already
grown, because

* every block above ``M_MMAP_THRESHOLD`` (128 KiB at start, raised dynamically by glibc only after
  such a block is freed) is a fresh ``mmap`` whose pages fault in on first write and are unmapped
  again on ``free``;
* the top of the heap is given back (``M_TRIM_THRESHOLD``, 128 KiB at start) as soon as that much
  is free, so the next sweep faults the same pages in again.

Both thresholds are needed: setting ``M_TRIM_THRESHOLD`` alone switches glibc's dynamic mmap
threshold off and leaves it at 128 KiB, so every array of more than 16,384 doubles (N >= 36,000)
becomes an mmap/munmap pair per use, up to 2.3x slower than the default.

Values, measured in fresh processes (order-2 sweep + extraction, µs/sample, minor page faults per
sweep; four-bar / six-bar with a moving guide):

=====================  ===============  ===============  ================  ================
trim / mmap threshold  four-bar 36,000  six-bar 36,000   four-bar 360,000  six-bar 360,000
=====================  ===============  ===============  ================  ================
glibc default          0.25 (4,300)     0.37 (6,400)     0.26 (38,000)     0.38 (57,000)
128 MiB / 32 MiB       0.057 (0)        0.091 (0)        0.21 (29,000)     0.40 (57,000)
256 MiB / 64 MiB       0.057 (0)        0.091 (0)        0.079 (0)         0.39 (57,000)
512 MiB / 64 MiB       0.058 (0)        0.091 (0)        0.079 (0)         0.118 (0)
=====================  ===============  ===============  ================  ================

So ``M_MMAP_THRESHOLD`` = 64 MiB: arrays up to 8 M doubles (any sweep of up to the CLI's 1,000,000
samples) come from the heap, while a truly large block still gets its own mapping and is returned
at once; ``M_TRIM_THRESHOLD`` = 512 MiB: the freed heap of a 360,000-sample six-bar sweep (peak
resident set 293 MB) stays in the process for the next sweep (256 MiB did not suffice), and more
than that is still given back. Nothing here changes results, only where memory comes from.
"""
from __future__ import annotations

import ctypes
import os

#: glibc's mallopt parameter numbers (<malloc.h>)
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3

#: freed heap memory kept in the process before glibc trims the top of the heap, bytes
TRIM_THRESHOLD_BYTES = 512 << 20
#: blocks at least this large get their own mmap (and are unmapped on free), bytes
MMAP_THRESHOLD_BYTES = 64 << 20

_tuned: bool | None = None


def _glibc() -> ctypes.CDLL | None:
    """The running glibc, or None on another C library or platform (no subprocess, no search)."""
    try:
        version = os.confstr("CS_GNU_LIBC_VERSION")
    except (AttributeError, ValueError, OSError):
        return None
    if not version or not version.startswith("glibc"):
        return None
    try:
        libc = ctypes.CDLL(None)
        libc.mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
        libc.mallopt.restype = ctypes.c_int
    except (OSError, AttributeError):
        return None
    return libc


def tune_allocator() -> bool:
    """Set glibc's ``M_MMAP_THRESHOLD`` (64 MiB) and ``M_TRIM_THRESHOLD`` (512 MiB) once.

    Returns True when both settings took effect (now or at an earlier call), False where glibc is
    not the C library (macOS, Windows, musl) or refused a value. Never raises; calling it again
    does nothing and returns the first call's answer. Call it at start-up, before large arrays are
    allocated, from the entry points (CLI main, GUI launcher) and never from library code.
    """
    global _tuned
    if _tuned is not None:
        return _tuned
    libc = _glibc()
    ok = False
    if libc is not None:
        try:
            ok = (libc.mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) == 1
                  and libc.mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES) == 1)
        except (OSError, ctypes.ArgumentError):
            ok = False
    _tuned = ok
    return ok


def allocator_tuned() -> bool:
    """Whether :func:`tune_allocator` has run in this process and succeeded."""
    return bool(_tuned)
