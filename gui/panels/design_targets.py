"""The Design dock's target: a table of points (a path: x, y and, timed, the crank angle; poses: x,
y, angle; a function: input and output), filled by typing, from a CSV file (the columns of
``mechsketch design path|motion|function``), or from the canvas (the dock asks the window: click
points, draw freehand, pick an underlay's polyline — see :mod:`mechsketch.gui.design_docks`).

Positions are shown and typed in the display length unit, angles in degrees; :meth:`TargetTable.rows`
gives them in the model's units (mm, °) or raises :class:`~.study_inputs.EntryError` naming the
row and column at fault.
"""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QObject, Qt, Signal
from PySide6.QtWidgets import QAbstractItemView, QHeaderView, QTableWidget, QTableWidgetItem

from .. import units
from .study_inputs import EntryError

#: the columns of each mode: (CSV name, header, model unit)
COLUMNS = {
    "path": (("x", "x", "mm"), ("y", "y", "mm"), ("input_deg", "crank °", "°")),
    "motion": (("x", "x", "mm"), ("y", "y", "mm"), ("angle_deg", "angle", "°")),
    "function": (("input_deg", "input °", "°"), ("output", "output", "°")),
}


class TargetTable(QObject):
    """The target's rows (a QTableWidget in :attr:`widget`) for one mode at a time; ``edited()``
    after any change of its cells."""

    edited = Signal()

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.widget = QTableWidget(0, 3)
        self.widget.setObjectName("designTarget")
        self.widget.verticalHeader().setVisible(True)
        self.widget.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.Stretch)
        self.widget.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.widget.itemChanged.connect(lambda _item: self.edited.emit())
        self.mode = "path"
        self.timed = False
        self.output_unit = "°"
        self._rows: dict[str, np.ndarray] = {}   # what each mode holds (model units) while another shows
        self.shown = units.current()
        self.set_mode("path")

    def columns(self) -> tuple:
        cols = COLUMNS[self.mode]
        if self.mode == "function":
            return (cols[0], ("output", f"output {self.output_unit}", "mm" if self.output_unit == "mm" else "°"))
        return cols

    def set_mode(self, mode: str) -> None:
        """Show the rows of ``mode`` (each mode keeps its own rows)."""
        if self.widget.rowCount():
            try:
                self._rows[self.mode] = self._read(strict=False)
            except EntryError:
                pass
        self.mode = mode
        self._fill(self._rows.get(mode, np.zeros((0, 3))))

    def set_output_unit(self, unit: str) -> None:
        """A function's output in degrees ("°") or millimetres ("mm")."""
        rows = self._read(strict=False)
        self.output_unit = unit
        self._fill(rows)

    def set_timed(self, timed: bool) -> None:
        self.timed = bool(timed)
        self.widget.setColumnHidden(2, self.mode == "path" and not self.timed)

    def _fill(self, rows: np.ndarray) -> None:
        cols = self.columns()
        t = self.widget
        t.blockSignals(True)
        t.setColumnCount(len(cols))
        t.setHorizontalHeaderLabels([f"{h} ({units.display_unit(u)})" if u == "mm" else h for _n, h, u in cols])
        t.setRowCount(len(rows))
        for r, row in enumerate(rows):
            for c, (_n, _h, unit) in enumerate(cols):
                v = row[c] if c < len(row) else 0.0
                t.setItem(r, c, QTableWidgetItem(units.format_value(float(v), unit, digits=4)
                                                 if np.isfinite(v) else ""))
        t.blockSignals(False)
        self.shown = units.current()
        self.set_timed(self.timed)
        self.edited.emit()

    def redisplay(self) -> None:
        """The display units changed: the same rows in the new units."""
        try:
            rows = self._read(strict=False, shown=self.shown)
        except EntryError:
            return
        self._fill(rows)

    def set_points(self, points, angles=None, inputs=None) -> None:
        """Replace the rows by ``points`` (M, 2) mm, with ``angles`` (M,) ° of poses or the crank
        ``inputs`` (M,) ° of a timed path."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        third = angles if angles is not None else inputs
        third = np.zeros(len(pts)) if third is None else np.asarray(third, dtype=float).reshape(-1)
        self._fill(np.column_stack([pts, third]))

    def set_rows(self, rows) -> None:
        """Replace the rows by ``rows`` (M, columns) in model units."""
        self._fill(np.asarray(rows, dtype=float).reshape(len(rows), -1))

    def add_row(self) -> None:
        t = self.widget
        r = t.rowCount()
        t.insertRow(r)
        for c in range(t.columnCount()):
            t.setItem(r, c, QTableWidgetItem("0"))
        t.setCurrentCell(r, 0)

    def remove_rows(self) -> None:
        t = self.widget
        for r in sorted({i.row() for i in t.selectedIndexes()}, reverse=True):
            t.removeRow(r)
        self.edited.emit()

    def clear(self) -> None:
        self._fill(np.zeros((0, 3)))

    def _read(self, strict: bool = True, shown: units.Units | None = None) -> np.ndarray:
        cols = self.columns()
        t = self.widget
        out = np.full((t.rowCount(), len(cols)), np.nan)
        for r in range(t.rowCount()):
            for c, (_n, header, unit) in enumerate(cols):
                item = t.item(r, c)
                text = item.text().strip() if item is not None else ""
                if not text and not strict:
                    continue
                if self.mode == "path" and c == 2 and not self.timed:
                    out[r, c] = 0.0
                    continue
                try:
                    out[r, c] = units.parse(text, unit, shown)
                except ValueError as exc:
                    if strict:
                        raise EntryError(f"target row {r + 1}, {header}: {exc}", t, r, c) from None
        return out

    def rows(self) -> np.ndarray:
        """(M, columns) in model units (mm, °); EntryError for a cell that is not a number."""
        return self._read(strict=True)

    def shape(self) -> dict | None:
        """What the canvas draws of the target: {"points", "angles", "closed"} (None: a function)."""
        if self.mode == "function":
            return None
        rows = self._read(strict=False)
        ok = np.isfinite(rows[:, :2]).all(axis=1) if len(rows) else np.zeros(0, bool)
        pts = rows[ok, :2]
        return {"points": pts, "angles": rows[ok, 2] if self.mode == "motion" else None}

    def read_csv(self, path: str) -> int:
        """Rows from a CSV file with this mode's columns (a header row names them; else in order);
        the number of rows read. DesignError naming the file, row and column at fault."""
        from mechsketch.core.cli.design_linkage import read_columns
        from mechsketch.core.design.targets import DesignError

        if self.mode == "path":
            cols = read_columns(path, ("x", "y"), ("input_deg",))
            self.set_timed("input_deg" in cols)
            third = cols.get("input_deg", [0.0] * len(cols["x"]))
            rows = np.column_stack([cols["x"], cols["y"], third])
        elif self.mode == "motion":
            cols = read_columns(path, ("x", "y", "angle_deg"))
            rows = np.column_stack([cols["x"], cols["y"], cols["angle_deg"]])
        else:
            try:
                cols, unit = read_columns(path, ("input_deg", "output_deg")), "°"
            except DesignError as first:
                try:
                    cols, unit = read_columns(path, ("input_deg", "output_mm")), "mm"
                except DesignError:
                    raise first from None
            self.output_unit = unit
            rows = np.column_stack([cols["input_deg"], cols["output_deg" if unit == "°" else "output_mm"]])
        self._fill(rows)
        return len(rows)


__all__ = ["COLUMNS", "TargetTable"]
