"""Issue 13 item 6: what is not a regular file is refused before it is read, a file is read with
a cap, and a request whose memory exceeds the stated budget is refused before anything is
allocated. Each case runs the CLI in a child process with an address-space limit and a timeout,
so that the failure before the fix (a hang, memory running out) is a failed test, not a dead CI."""
from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import pytest

from mechsketch.core.io.scene_file import MAX_FILE_BYTES, read_scene_text
from mechsketch.core.model.scene import Scene
from mechsketch.core.io.scene_file import save_scene
from mechsketch.resources import example_path

HERE = os.path.dirname(os.path.abspath(__file__))
pytestmark = pytest.mark.skipif(sys.platform.startswith("win"), reason="POSIX devices, FIFOs, rlimits")

CHILD = textwrap.dedent("""
    import resource, sys
    limit = int(sys.argv[1]) * 1024 * 1024
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    from mechsketch.core.cli import main
    sys.exit(main(sys.argv[2:]))
""")


def cli(*args, memory_mb: int = 1500, timeout: float = 60.0, env=None) -> tuple[int, str]:
    """Run the CLI in a child limited to ``memory_mb`` of address space; (exit code, stderr)."""
    try:
        r = subprocess.run([sys.executable, "-c", CHILD, str(memory_mb), *map(str, args)],
                           capture_output=True, text=True, timeout=timeout,
                           env=dict(os.environ, **(env or {})))
    except subprocess.TimeoutExpired:
        return -1, f"timed out after {timeout} s"
    return r.returncode, r.stdout + r.stderr


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_a_device_is_refused_before_it_is_read(device):
    code, out = cli("validate", device, timeout=30)
    assert code == 1 and "not a regular file" in out and "Traceback" not in out, out
    doc, problems = read_scene_text(device)
    assert doc is None and "not a regular file" in problems[0].message


def test_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "scene.json"
    os.mkfifo(fifo)
    code, out = cli("validate", fifo, timeout=30)
    assert code == 1 and "not a regular file" in out and "FIFO" in out, out
    link = tmp_path / "link.json"
    link.symlink_to("/dev/zero")
    code, out = cli("analyze", link, timeout=30)
    assert code == 1 and "not a regular file" in out, out


def test_a_file_that_grows_past_the_cap_is_read_no_further(tmp_path, monkeypatch):
    from mechsketch.core.io import scene_file
    p = tmp_path / "big.json"
    p.write_text(" " * 2000 + "{}")
    monkeypatch.setattr(scene_file, "MAX_FILE_BYTES", 1000)
    real_stat = os.stat

    class Small:            # what st_size says for a file written to while we read (or /proc)
        def __init__(self, st):
            self._st = st

        def __getattr__(self, name):
            return 0 if name == "st_size" else getattr(self._st, name)
    monkeypatch.setattr(scene_file.os, "fstat", lambda fd: Small(real_stat(fd)))
    monkeypatch.setattr(scene_file.os, "stat", lambda path, **kw: Small(real_stat(path, **kw)))
    doc, problems = read_scene_text(p)
    assert doc is None and "limited to" in problems[0].message
    assert MAX_FILE_BYTES == 10 * 1024 * 1024


def _chain_scene(tmp_path, dyads: int, samples: int):
    sys.path.insert(0, HERE)
    from chains import dyad_chain
    p = tmp_path / "chain.json"
    save_scene(Scene((dyad_chain(dyads, samples=samples),)), p)
    return p


def test_a_linkage_at_the_schema_maxima_is_refused_with_its_memory(tmp_path):
    p = _chain_scene(tmp_path, 999, 1_000_000)          # 2,000 joints x 1e6 samples
    assert json.loads(p.read_text())["elements"][0]["samples"] == 1_000_000
    code, out = cli("analyze", p, "--summary", timeout=120)
    assert code == 1 and "Traceback" not in out, out
    assert "GB" in out and "budget" in out and "--samples" in out, out


def test_a_geneva_with_ten_million_samples_is_refused(tmp_path):
    doc = json.loads(example_path("geneva_z4").read_text())
    doc["elements"][0]["samples"] = 10_000_000
    p = tmp_path / "g.json"
    p.write_text(json.dumps(doc))
    code, out = cli("analyze", p, "--csv", tmp_path / "g.csv", timeout=60)
    assert code == 1 and "budget" in out and "samples" in out and "Traceback" not in out, out
    assert not (tmp_path / "g.csv").exists()


def test_the_budget_is_stated_and_can_be_raised(tmp_path):
    from mechsketch.core.workspace import budget
    from mechsketch.core import load_scene
    g = load_scene(example_path("geneva_z4")).elements[0]
    need = budget.request_bytes(g, 10_000_000)
    assert need > budget.memory_budget()
    assert budget.request_bytes(g, 3600) < 1e7
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    p = tmp_path / "f.json"
    p.write_text(json.dumps(doc))
    code, out = cli("analyze", p, "--samples", 1_000_000, "--summary", memory_mb=3000, timeout=120,
                    env={"MECHSKETCH_MEMORY_MB": "100"})
    assert code == 1 and "100 MB" in out and "MECHSKETCH_MEMORY_MB" in out, out
