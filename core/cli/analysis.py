"""What ``analyze`` and ``synthesize`` return for any element type: a table and its summary."""
from __future__ import annotations

from typing import Callable

from ..analyses.table import Table


class Analysis:
    """A computed table plus its human summary (what ``analyze`` and ``synthesize`` return).

    ``summary`` may be given as text or as a function making it: it is made on first read, so a
    command writing only the CSV does not compute what only the summary reports (a linkage's
    diagnostics, a Geneva drive's drawn geometry)."""

    def __init__(self, table: Table, summary: "str | Callable[[], str]") -> None:
        self.table = table
        self._summary = summary

    @property
    def summary(self) -> str:
        if not isinstance(self._summary, str):
            self._summary = self._summary()
        return self._summary
