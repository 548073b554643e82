"""Cold-process time of the headless commands, and the CSV formatting (a report, not a test).

Each case runs the ``mechsketch`` console script (the launcher, as a user types it) in a fresh
process several times; the report prints the wall time (median, min, max) and the child's CPU
time (user + system), beside the load average. Targets (issue 14): ``analyze --summary`` ≤ 0.15 s
end to end.

Then, in-process: the CSV text of a large table (the six-bar's analysis table at N = 36,000)
formatted cell by cell (the formatter before issue 14, kept here as the reference) and by
:meth:`Table.write` now, interleaved best-of-k CPU times, and the error: the new text is compared
with the old byte for byte, and read back with ``float()`` against the table (max |Δ|, NaN fields
compared as empty).

Bytecode: as in bench_gui_startup.py, the children use a private ``.pyc`` cache (as an installed
mechsketch has) after one warm-up run per command; ``--compile`` keeps the environment as it is
(``PYTHONDONTWRITEBYTECODE=1`` compiles our modules from source in every run).

Usage::

    .venv/bin/python benchmarks/bench_cli.py [--runs 7] [--skip-csv-format] [--compile]
"""
from __future__ import annotations

import argparse
import io
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "resources" / "examples"
TARGET_SUMMARY_S = 0.15


def _script() -> list[str]:
    exe = Path(sys.executable).with_name("mechsketch")
    if exe.exists():
        return [str(exe)]
    return [sys.executable, "-c", "import sys; from mechsketch.gui.launcher import main; sys.exit(main())"]


def cases(tmp: str) -> list[tuple[str, list[str]]]:
    csv = os.path.join(tmp, "out.csv")
    return [
        ("analyze --summary four-bar", ["analyze", str(EX / "fourbar_crank_rocker.json"), "--summary"]),
        ("analyze --summary six-bar", ["analyze", str(EX / "sixbar_moving_guide.json"), "--summary"]),
        ("analyze --summary Geneva z6", ["analyze", str(EX / "geneva_z6.json"), "--summary"]),
        ("synthesize --summary rolling lever", ["synthesize", str(EX / "rolling_lever_press.json"), "--summary"]),
        ("analyze --csv six-bar N=3600", ["analyze", str(EX / "sixbar_moving_guide.json"), "--samples", "3600",
                                          "--csv", csv]),
        ("analyze --csv six-bar N=36000", ["analyze", str(EX / "sixbar_moving_guide.json"), "--samples", "36000",
                                           "--csv", csv]),
        ("analyze --csv Geneva z6", ["analyze", str(EX / "geneva_z6.json"), "--csv", csv]),
        ("synthesize --csv rolling lever", ["synthesize", str(EX / "rolling_lever_press.json"), "--csv", csv]),
        ("validate four-bar", ["validate", str(EX / "fourbar_crank_rocker.json")]),
        ("validate Geneva z6", ["validate", str(EX / "geneva_z6.json")]),
    ]


def run_once(cmd: list[str], env: dict) -> tuple[float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300, env=env)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{out.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def old_write(table, fh) -> None:
    """The formatter before issue 14: one cell at a time (the reference)."""
    import csv

    csv.writer(fh, lineterminator="\n").writerow(table.columns)
    ints = [c in table.integer for c in table.columns]
    for row in table.data:
        fh.write(",".join("" if not np.isfinite(v) else (str(int(v)) if isint else repr(float(v)))
                          for v, isint in zip(row, ints)) + "\n")


def read_back_error(text: str, table) -> float:
    """max |Δ| between the CSV fields read with float() and the table (inf if a field is wrong)."""
    lines = text.splitlines()[1:]
    got = np.array([[float(f) if f else np.nan for f in ln.split(",")] for ln in lines])
    same_nan = np.isnan(got) == ~np.isfinite(table.data)
    if got.shape != table.data.shape or not same_nan.all():
        return float("inf")
    fin = np.isfinite(table.data)
    return float(np.max(np.abs(got[fin] - table.data[fin]), initial=0.0))


def csv_format_report(k: int = 3) -> None:
    from mechsketch.core.cli import linkage_cmds
    from mechsketch.core.io.scene_file import load_scene
    from mechsketch.core.workspace import Workspace

    ws = Workspace(load_scene(EX / "sixbar_moving_guide.json"))
    ws.samples = 36000
    table = linkage_cmds.analyze(ws, ws.scene.elements[0].id).table
    old_t, new_t = [], []
    for _ in range(k):  # interleaved A/B, CPU time
        for fn, acc in ((old_write, old_t), (lambda t, f: t.write(f), new_t)):
            buf = io.StringIO()
            c0 = time.process_time()
            fn(table, buf)
            acc.append(time.process_time() - c0)
    ref, new = io.StringIO(), io.StringIO()
    old_write(table, ref)
    table.write(new)
    n, c = table.data.shape
    print(f"\nCSV formatting, six-bar analysis table {n} x {c} = {n * c:,} cells, best of {k} (CPU s):")
    print(f"  cell by cell (before)   {min(old_t):8.3f}")
    print(f"  Table.write (now)       {min(new_t):8.3f}   ({min(old_t) / min(new_t):.1f}x)")
    print(f"  text identical to the cell-by-cell output: {ref.getvalue() == new.getvalue()}; "
          f"read back max |Δ| = {read_back_error(new.getvalue(), table):.3g}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--skip-csv-format", action="store_true")
    ap.add_argument("--compile", action="store_true", help="no bytecode cache: as the environment says")
    args = ap.parse_args(argv)
    script = _script()
    load0 = os.getloadavg()[0]
    cache = tempfile.mkdtemp(prefix="mechsketch-pyc-")
    env = dict(os.environ)
    if not args.compile:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = cache
    how = "compiled from source each run" if args.compile else "bytecode cached after a warm-up run"
    print(f"mechsketch headless commands, {args.runs} cold runs each ({how}), {' '.join(script[:1])}, "
          f"Python {sys.version.split()[0]}, {os.cpu_count()} CPUs")
    print(f"{'command':36}{'wall median':>12}{'min':>8}{'max':>8}{'CPU median':>12}")
    worst_summary = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for label, cmd in cases(tmp):
            if not args.compile:
                run_once(script + cmd, env)   # warm-up: writes the bytecode cache
            runs = [run_once(script + cmd, env) for _ in range(args.runs)]
            walls, cpus = [r[0] for r in runs], [r[1] for r in runs]
            print(f"{label:36}{statistics.median(walls):12.3f}{min(walls):8.3f}{max(walls):8.3f}"
                  f"{statistics.median(cpus):12.3f}")
            if label.startswith("analyze --summary"):
                worst_summary = max(worst_summary, statistics.median(walls))
    print(f"load average {load0:.2f} at the start, {os.getloadavg()[0]:.2f} at the end (wall times grow "
          "with load; the CPU time is what the command itself costs)")
    verdict = "within" if worst_summary <= TARGET_SUMMARY_S else "OVER"
    print(f"target analyze --summary ≤ {TARGET_SUMMARY_S} s end to end: slowest median "
          f"{worst_summary:.3f} s, {verdict} the target")
    shutil.rmtree(cache, ignore_errors=True)
    if not args.skip_csv_format:
        csv_format_report()
    return 0


if __name__ == "__main__":
    sys.exit(main())
