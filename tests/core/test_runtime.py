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
