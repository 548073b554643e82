"""The column-at-a-time CSV writer (Table.write) gives the same text as the cell-by-cell one it
replaced (issue 14), and the text reads back to the same floats exactly."""
from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np
import pytest

from mechsketch.core.analyses import table as table_module
from mechsketch.core.analyses.table import Table
from mechsketch.core.cli import HANDLERS, _handler
from mechsketch.core.io.scene_file import load_scene
from mechsketch.core.workspace import Workspace

EX = Path(__file__).resolve().parents[2] / "resources" / "examples"


def cell_by_cell(table: Table) -> str:
    """The formatter before issue 14 (the reference)."""
    fh = io.StringIO()
    csv.writer(fh, lineterminator="\n").writerow(table.columns)
    ints = [c in table.integer for c in table.columns]
    for row in table.data:
        fh.write(",".join("" if not np.isfinite(v) else (str(int(v)) if isint else repr(float(v)))
                          for v, isint in zip(row, ints)) + "\n")
    return fh.getvalue()


def read_back(text: str) -> np.ndarray:
    rows = list(csv.reader(io.StringIO(text)))[1:]
    return np.array([[float(f) if f else np.nan for f in r] for r in rows], dtype=float).reshape(len(rows), -1)


def _tables():
    for path in sorted(EX.glob("*.json")):
        ws = Workspace(load_scene(path))
        for el in ws.scene.elements:
            for command in ("analyze", "analyze_forces", "synthesize"):
                try:
                    fn = _handler(el, command)
                except ValueError:
                    continue
                yield f"{path.stem}:{command}", fn(ws, el.id).table


@pytest.mark.parametrize("name, table", list(_tables()), ids=lambda v: v if isinstance(v, str) else "")
def test_examples_same_text_as_cell_by_cell_and_exact_read_back(name, table):
    text = table.to_csv()
    assert text == cell_by_cell(table)
    got = read_back(text)
    want = np.where(np.isfinite(table.data), table.data, np.nan)
    assert np.array_equal(got, want, equal_nan=True)


def test_edge_values_and_chunk_boundaries(monkeypatch):
    monkeypatch.setattr(table_module, "ROWS_PER_WRITE", 7)   # several writes, a partial last one
    rng = np.random.default_rng(3)
    n = 40
    special = np.array([0.0, -0.0, np.nan, np.inf, -np.inf, 5e-324, -2.2250738585072014e-308, 1e16, 1e-5,
                        0.1 + 0.2, 1.7976931348623157e308, 123456789012345678.0, -1.5, 2.0, 1e22])
    cols = {
        "x": np.resize(special, n),
        "y, with comma": rng.standard_normal(n) * 10.0 ** rng.integers(-20, 20, n),
        'q"uote': np.where(rng.random(n) < 0.3, np.nan, rng.random(n)),
        "valid": np.resize(np.array([1.0, 0.0, np.nan, -0.0, 3.0, np.inf, 1e20]), n),
    }
    t = Table.from_columns(cols, integer={"valid"})
    text = t.to_csv()
    assert text == cell_by_cell(t)
    assert text.splitlines()[1].split(",")[0] == "0.0" and text.splitlines()[3].split(",")[0] == ""
    assert text.splitlines()[7].split(",")[-1] == "100000000000000000000"
    assert np.array_equal(read_back(text)[:, :3], np.where(np.isfinite(t.data), t.data, np.nan)[:, :3],
                          equal_nan=True)


def test_empty_and_integer_dtype_tables():
    for t in (Table([], np.empty((0, 0))), Table(["a"], np.empty((0, 1))), Table(["a", "b"], np.arange(6).reshape(3, 2)),
              Table([], np.empty((3, 0)))):
        assert t.to_csv() == cell_by_cell(t)


def test_handlers_cover_every_element_type():
    """Every kind that is part of the machine has CLI handlers (an underlay has none: nothing to analyse)."""
    from mechsketch.core.model.kinds import ELEMENT_KINDS

    assert set(HANDLERS) == {name for name, kind in ELEMENT_KINDS.items() if kind.parts}
    assert {"linkage", "geneva", "rolling_lever", "gear_pair", "geared_geneva"} <= set(HANDLERS)
