"""What ``mechsketch design path|motion|function`` share: the target CSV reader, the common
options, the final ``validate`` gate and the scene writer.

CSV files have one row per point; a first row of column names picks the columns by name (in any
order; extra columns are refused), else the columns are read in the documented order. Problems
(an unreadable file, a missing column, a cell that is not a number) raise
:class:`~mechsketch.core.design.targets.DesignError` naming the file, row and column. The output
scene is checked for writability before any work and written atomically only when the synthesis
succeeded: a failure leaves nothing behind.
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import sys
from typing import Sequence

from ..design.options import DesignResult, LinkageOptions
from ..design.targets import DesignError, Progress
from ..errors import ExportError
from ..io.scene_file import element_problems, save_scene
from ..model.scene import Scene

MAX_ROWS = 100_000


def read_columns(path: str, names: Sequence[str], optional: Sequence[str] = ()) -> dict[str, list[float]]:
    """The columns ``names`` (and any of ``optional`` present) of CSV ``path`` as floats."""
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    except (OSError, UnicodeDecodeError) as exc:
        raise DesignError(f"cannot read {path}: {exc}") from None
    if not rows:
        raise DesignError(f"{path}: the file has no rows; expected columns {', '.join(names)}")
    if len(rows) > MAX_ROWS:
        raise DesignError(f"{path}: {len(rows):,} rows, more than {MAX_ROWS:,}; thin the points out")
    head = [c.strip().lower() for c in rows[0]]
    if not _is_number(head[0]):
        known = list(names) + list(optional)
        unknown = [h for h in head if h not in known]
        missing = [n for n in names if n not in head]
        if unknown or missing:
            raise DesignError(f"{path}: columns {', '.join(rows[0])}; expected {', '.join(names)}"
                              + (f" (optional: {', '.join(optional)})" if optional else "")
                              + (f"; unknown: {', '.join(unknown)}" if unknown else "")
                              + (f"; missing: {', '.join(missing)}" if missing else ""))
        order, body, first = head, rows[1:], 2
    else:
        order, body, first = list(names) + list(optional)[: max(0, len(rows[0]) - len(names))], rows, 1
    out: dict[str, list[float]] = {n: [] for n in order}
    for k, row in enumerate(body):
        if len(row) != len(order):
            raise DesignError(f"{path}: row {k + first} has {len(row)} fields, expected {len(order)} ({', '.join(order)})")
        for name, cell in zip(order, row):
            try:
                v = float(cell)
            except ValueError:
                raise DesignError(f"{path}: row {k + first}, column {name}: {cell.strip()!r} is not a number") from None
            if not math.isfinite(v):
                raise DesignError(f"{path}: row {k + first}, column {name}: {cell.strip()!r} is not a finite number")
            out[name].append(v)
    return out


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def options_from(args: argparse.Namespace) -> LinkageOptions:
    region = None
    if args.pivot_region is not None:
        try:
            region = tuple(float(v) for v in args.pivot_region.split(","))
        except ValueError:
            raise DesignError(f"--pivot-region must be four numbers XMIN,YMIN,XMAX,YMAX, got {args.pivot_region!r}") \
                from None
        if len(region) != 4:
            raise DesignError(f"--pivot-region must be four numbers XMIN,YMIN,XMAX,YMAX, got {args.pivot_region!r}")
    if not (math.isfinite(args.rpm) and 1e-3 <= abs(args.rpm) <= 1e5):
        raise DesignError(f"--rpm must be from 0.001 to 100000, got {args.rpm:g}")
    return LinkageOptions(candidates=args.candidates, min_transmission_deg=args.min_transmission,
                          full_turn=args.full_turn, grashof=args.grashof, pivot_region=region,
                          max_size=args.max_size, max_deviation=args.max_deviation,
                          speed_rpm=abs(args.rpm)).check()


def check_writable(path: str) -> None:
    """Refuse an output that cannot be written, before any work (ExportError naming it)."""
    folder = os.path.dirname(os.path.abspath(path)) or "."
    if os.path.isdir(path):
        raise ExportError(f"cannot write {path}: it is a folder")
    if not os.path.isdir(folder):
        raise ExportError(f"cannot write {path}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        raise ExportError(f"cannot write {path}: permission denied")


def stderr_progress() -> Progress | None:
    """A progress line on standard error when it is a terminal (else None)."""
    if not sys.stderr.isatty():
        return None

    def show(fraction: float, message: str) -> bool:
        print(f"\r{fraction:4.0%} {message[:70]:<70}", end="", file=sys.stderr, flush=True)
        return False

    return show


def write_result(result: DesignResult, out: str) -> int:
    """Gate every candidate through the scene reader's checks (``validate``), print one line per
    candidate, write the scene; exit status 0."""
    if sys.stderr.isatty():
        print("\r" + " " * 76 + "\r", end="", file=sys.stderr)
    keep = []
    for c in result.candidates:
        probs = element_problems(c.linkage)
        if probs:   # never expected: the synthesis checks the same; reported, not written
            print(f"note: {c.linkage.id} dropped: {probs[0]}", file=sys.stderr)
            continue
        keep.append(c)
    if not keep:
        raise DesignError("no candidate passed validation; see the notes above")
    save_scene(Scene(tuple(c.linkage for c in keep)), out)
    for k, c in enumerate(keep):
        print(c.line(k + 1))
    for note in result.notes:
        print(f"note: {note}", file=sys.stderr)
    print(f"wrote {len(keep)} candidate{'s' if len(keep) != 1 else ''} to {out} in {result.seconds:.2f} s",
          file=sys.stderr)
    return 0


__all__ = ["check_writable", "options_from", "read_columns", "stderr_progress", "write_result"]
