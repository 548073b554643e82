"""core.runtime.tune_allocator: glibc's two malloc thresholds set once, seen in malloc's own counts."""
from __future__ import annotations

import os
import subprocess
import sys

import pytest

from mechsketch.core import runtime

GLIBC = (os.confstr("CS_GNU_LIBC_VERSION") or "").startswith("glibc") if hasattr(os, "confstr") else False

# A fresh interpreter mallocs one 1 MiB block (above glibc's default 128 KiB mmap threshold, below
# the tuned 64 MiB) and prints how many blocks malloc holds as separate mmaps (mallinfo2.hblks)
# before and after: +1 with the default settings, +0 once tuned.
PROBE = r"""
import ctypes, sys
from mechsketch.core.runtime import tune_allocator
class MallInfo2(ctypes.Structure):
    _fields_ = [(n, ctypes.c_size_t) for n in
                ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks",
                 "uordblks", "fordblks", "keepcost")]
libc = ctypes.CDLL(None)
libc.mallinfo2.restype = MallInfo2
libc.malloc.restype = ctypes.c_void_p
libc.malloc.argtypes = [ctypes.c_size_t]
tuned = tune_allocator() if sys.argv[1] == "tuned" else None
h0 = libc.mallinfo2().hblks
p = libc.malloc(1 << 20)
h1 = libc.mallinfo2().hblks
print(tuned, h1 - h0, bool(p))
"""


@pytest.mark.skipif(not (GLIBC and sys.platform.startswith("linux")), reason="glibc only")
def test_tune_allocator_true_on_glibc_and_idempotent():
    first = runtime.tune_allocator()
    assert first is True
    assert runtime.tune_allocator() is True
    assert runtime.allocator_tuned() is True


@pytest.mark.skipif(not (GLIBC and sys.platform.startswith("linux")), reason="glibc only")
@pytest.mark.parametrize("mode, tuned, new_mmaps", [("default", "None", "1"), ("tuned", "True", "0")])
def test_tuned_allocator_serves_a_1MiB_block_from_the_heap(mode, tuned, new_mmaps):
    out = subprocess.run([sys.executable, "-c", PROBE, mode], capture_output=True, text=True,
                         timeout=60, check=True).stdout.split()
    assert out == [tuned, new_mmaps, "True"]


def test_no_glibc_is_a_quiet_false(monkeypatch):
    monkeypatch.setattr(runtime, "_tuned", None)
    monkeypatch.setattr(runtime.os, "confstr", lambda name: "musl 1.2", raising=False)
    assert runtime.tune_allocator() is False
    assert runtime.tune_allocator() is False
    assert runtime.allocator_tuned() is False


# A plain process (no tune_allocator) sweeping the six-bar at N = 36,000 and dropping each solution
# before the next sweep: minor page faults per sweep, and malloc's separately mapped blocks after
# the first sweep (issue 26, item 3: glibc trimmed the freed heap and every sweep faulted all its
# pages in again; solver.memory.reserve lets glibc's dynamic thresholds keep it).
SWEEPS = r"""
import ctypes, resource, sys
from mechsketch.core import Workspace
plan = Workspace.open(sys.argv[1])["sixbar"].compile()
faults = []
for _ in range(5):
    f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    sol = plan.sweep(36000, order=2)
    sol.acceleration("E")
    del sol
    faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0)
print(" ".join(map(str, faults)))
"""


@pytest.mark.skipif(not (GLIBC and sys.platform.startswith("linux")), reason="glibc only")
def test_a_plain_process_keeps_a_sweeps_memory_between_sweeps():
    from mechsketch.resources import example_path

    out = subprocess.run([sys.executable, "-c", SWEEPS, str(example_path("sixbar_moving_guide"))],
                         capture_output=True, text=True, timeout=120, check=True).stdout.split()
    faults = [int(x) for x in out]
    # the first sweep grows the heap (~4,700 pages, ~560 in huge pages); before the reserve every
    # later one faulted ~4,680 pages in again
    assert faults[0] > 100
    assert max(faults[1:]) < 0.05 * faults[0], faults
    if _thp_advisable():
        # the reserve's heap block is advised for huge pages (by numpy): the first sweep faults
        # its ~18 MB in 2 MiB pages, as a process after tune_allocator() did (was 4,697)
        assert faults[0] < 1500, faults


def _thp_advisable() -> bool:
    """Linux backs madvise(MADV_HUGEPAGE) ranges with transparent huge pages."""
    try:
        with open("/sys/kernel/mm/transparent_hugepage/enabled") as f:
            return "[never]" not in f.read()
    except OSError:
        return False


def test_reserve_is_once_per_size_and_never_touches_memory(monkeypatch):
    from mechsketch.core.solver import memory

    monkeypatch.setattr(memory, "_reserved", 0)
    made = []
    monkeypatch.setattr(memory.np, "empty", lambda size, dtype=None: made.append(size))
    memory.reserve(100)            # 100 KiB: below the default thresholds, nothing to do
    memory.reserve(3600)           # at least HUGE_MIN (numpy advises huge pages from 4 MiB)
    memory.reserve(5000)           # within what is reserved: nothing
    memory.reserve(10000)
    memory.reserve(3600)           # smaller than reserved: nothing
    memory.reserve(10000)
    memory.reserve(10 ** 6)        # capped below glibc's 32 MiB limit of dynamic adaptation
    memory.reserve(10 ** 7)
    # each time: the block that raises glibc's thresholds, then one just below them (the heap's)
    sizes = [memory.HUGE_MIN, 10000 * memory.PER_SAMPLE, memory.MOST]
    assert made == [x for s in sizes for x in (s, s - memory.SLACK)]
    assert memory.MOST < 32 << 20 and memory.HUGE_MIN - memory.SLACK >= 4 << 20
