"""Column tables of sampled results.

A :class:`Table` holds named columns of equal length N (float arrays; NaN marks "no value",
written as an empty CSV field). Units are stated by whoever builds the table. Writing one to a
file is :func:`mechsketch.core.io.table.write_csv`.
"""
from __future__ import annotations

import csv
import io
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Table:
    """Named columns, each an (N,) array; ``integer`` columns are written without decimals."""

    columns: list[str]
    data: np.ndarray  # (N, C) float64
    integer: set[str] = field(default_factory=set)

    @classmethod
    def from_columns(cls, cols: dict[str, np.ndarray], integer: set[str] | None = None) -> "Table":
        names = list(cols)
        arr = np.column_stack([np.asarray(cols[n], dtype=float) for n in names]) if names else np.empty((0, 0))
        return cls(names, arr, set(integer or ()))

    def column(self, name: str) -> np.ndarray:
        return self.data[:, self.columns.index(name)]

    def __len__(self) -> int:
        return self.data.shape[0]

    def to_csv(self) -> str:
        buf = io.StringIO()
        self.write(buf)
        return buf.getvalue()

    def write(self, fh) -> None:
        """CSV: the header quoted as the csv module does (a name holding a comma, a quote or a
        line break is quoted, its quotes doubled), then one row per sample."""
        csv.writer(fh, lineterminator="\n").writerow(self.columns)
        ints = [c in self.integer for c in self.columns]
        for row in self.data:
            fh.write(",".join("" if not np.isfinite(v) else (str(int(v)) if isint else repr(float(v)))
                              for v, isint in zip(row, ints)) + "\n")
