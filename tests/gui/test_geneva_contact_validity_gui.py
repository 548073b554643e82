"""A Geneva drive outside the contact model's validity range in the app (issue 20, item 3): the
plots leave the flagged rows empty, the properties panel and the overlay say so, the diagnostics
are the CLI summary; the numbers shown are those of the core."""
from __future__ import annotations

import numpy as np
from PySide6.QtWidgets import QLabel

from mechsketch.core import Scene, Workspace
from mechsketch.core.cli import geneva_cmds
from mechsketch.core.model.geneva import Geneva, Material

from app_fakes import shell  # noqa: F401 - fixture


def soft() -> Geneva:
    return Geneva("indexer", 6, 100.0, 8.0, roller_material=Material(E=1.0), samples=720)


def test_soft_roller_plots_panel_overlay_and_summary_agree(shell):
    parts = shell()
    c, view = parts.controller, parts.window.canvas
    el = soft()
    c.reset(Scene((el,)), None)
    c.set_selection([("indexer", "element", "indexer")])
    con = c.element_result("indexer").contact
    bad = con.engaged & ~con.contact_valid
    assert bad.sum() > 0.5 * con.engaged.sum()
    plots = parts.window.plots
    _, slip = plots.curves["slip path"].getData()
    _, p = plots.curves["p_max"].getData()
    assert np.isnan(slip[bad]).all() and np.isnan(p[bad]).all()
    fin = slip[np.isfinite(slip)]
    assert (fin >= 0).all() and np.array_equal(np.isfinite(p), con.contact_valid)
    _, rn = plots.curves["Rn (derived)"].getData()
    assert np.isfinite(rn[con.engaged]).all()           # the normal force is rigid-body statics: kept
    table = plots.data.make_table()                      # what "Export plot data as CSV" writes
    assert np.array_equal(table.column("contact_valid"), con.contact_valid.astype(float))
    label = parts.window.properties.findChildren(QLabel)
    texts = " ".join(lb.text() for lb in label)
    assert f"outside its validity range at {con.validity.invalid_rows} of {con.validity.engaged_rows}" in texts
    diag = " ".join(parts.window.diagnostics.plain_text().split())
    cli = geneva_cmds.analyze(Workspace(Scene((el,))), el.id).summary
    assert "outside the contact model's validity range" in cli
    for line in cli.splitlines():
        assert " ".join(line.split()) in diag
    view.extras.actions["geneva"].trigger()
    c.set_frame(int(np.nanargmax(con.Rn)))
    (rec,) = view.extras.overlays.items["geneva"].records
    assert "not computed" in rec["loaded_text"] and "nan" not in rec["loaded_text"]
    view.grab()
