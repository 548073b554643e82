"""CSV form of column tables (:class:`~mechsketch.core.analyses.table.Table`, re-exported here).

A table is written with one header line of column names, then one line per sample; NaN is an
empty field, ``integer`` columns have no decimals.
"""
from __future__ import annotations

import os
import sys

from ..analyses.table import Table
from ..errors import ExportError
from .atomic import atomic_write_text

__all__ = ["Table", "write_csv"]


def write_csv(table: Table, target: str | os.PathLike) -> None:
    """Write ``table`` to ``target`` ('-' is standard output); atomic for files."""
    if str(target) == "-":
        table.write(sys.stdout)
        sys.stdout.flush()
        return
    atomic_write_text(target, table.to_csv())
    if not os.path.exists(target):  # pragma: no cover - atomic_write_text raises instead
        raise ExportError(f"cannot write {target}")
