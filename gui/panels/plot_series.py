"""What the plots show, as plain records: the curves (:class:`Series`) and everything else a set
of stacked plots needs (:class:`PlotData`). Filled by the linkage, element and force plots; read
by the plots panel.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from mechsketch.core.io.table import Table

from .. import units

PLOTS = (("position", "position"), ("velocity", "velocity"), ("acceleration", "acceleration"),
         ("transmission", "transmission angle μ (°)"))
COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


@dataclass
class Series:
    """One plotted curve: ``plot`` name, curve ``name``, ``unit`` and (N,) values; ``x`` its own
    x values (M,) when it is not sampled at the plot data's x (e.g. α with both sides of a jump)."""

    plot: str
    name: str
    unit: str
    y: np.ndarray
    x: np.ndarray | None = None


@dataclass
class PlotData:
    """Everything the plots show: a title, the x values (input angle, °) and the curves."""

    title: str
    x: np.ndarray = field(default_factory=lambda: np.zeros(0))
    valid: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    series: list[Series] = field(default_factory=list)
    labels: dict[str, str] = field(default_factory=dict)   # plot -> y-axis label with unit
    #: the stacked plots (name, default y label), top to bottom, and the shared x-axis label
    rows: tuple[tuple[str, str], ...] = PLOTS
    x_label: str = "input angle (°)"
    #: the unit of ``x``: "deg" (a crank's angle) or "mm" (an actuator's input); names the table's first column
    x_unit: str = "deg"
    #: x of every animation frame (the cursor; a click goes to the nearest), when not ``x`` itself
    frame_x: np.ndarray | None = None
    #: the table "Export plot data as CSV" writes, when not the plotted columns
    make_table: Callable[[], Table] | None = None
    #: the kind of element plotted ("linkage", "geneva", "rolling_lever"): which plots the user
    #: chose to see is remembered per kind
    kind: str = "linkage"

    def table(self) -> Table:
        """The plotted data as a table: ``input_deg`` (``input_mm`` for an actuator) then one
        column per curve (unit in the name)."""
        if self.make_table is not None:
            return self.make_table()
        cols = {f"input_{self.x_unit}": self.x}
        for s in self.series:
            if s.x is not None:
                continue
            cols[f"{s.name}_{s.unit}".replace("/", "_per_").replace("²", "2").replace("°", "deg")] = s.y
        return Table.from_columns(cols)


def in_display_units(data: PlotData) -> PlotData:
    """``data`` with its x values, curves and axis labels in the display units (Edit ›
    Preferences: mm or in, ° or rad; :mod:`mechsketch.gui.units`); ``data`` itself in the model's."""
    u = units.current()
    if u == units.MODEL:
        return data
    x_model = "mm" if data.x_unit == "mm" else "°"

    def shown_x(x: np.ndarray | None) -> np.ndarray | None:
        return None if x is None else units.to_display(x, x_model, u)

    series = [replace(s, unit=units.display_unit(s.unit, u), y=units.to_display(s.y, s.unit, u), x=shown_x(s.x))
              for s in data.series]
    x_unit = units.display_unit(x_model, u).replace("°", "deg")
    return replace(data, x=shown_x(data.x), frame_x=shown_x(data.frame_x), series=series,
                   labels={k: units.relabel(v, u) for k, v in data.labels.items()},
                   rows=tuple((n, units.relabel(t, u)) for n, t in data.rows),
                   x_label=units.relabel(data.x_label, u), x_unit=x_unit)
