"""The Study dock (issue 21, item 5), driven as a user: tick rows of the variables table, type
tolerances and ranges, choose fits, press Run and Cancel; the worker's signals are waited on (no
sleeping). Every number shown is checked against an independent reference:

- the band drawn on the canvas (one variable, uniform ±w) against the one-design path solved at
  the variable's ends (``set_dimension`` + ``solve``): the 99.7 % envelope of a uniform variable
  reaches the ends of its range;
- the sensitivity bars against central differences of the one-design path (each variable's
  first-order variance of the point's displacement over the cycle);
- the default fit's radial play against ISO 286's tables read by hand (H7/g6 on 9.63 mm);
- the Pareto front against a non-domination check of every feasible evaluation, and the variant's
  least transmission angle against the four-bar's closed form at its dead-centre lines.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QApplication, QLineEdit

from mechsketch.core import ReplaceElement, Workspace
from mechsketch.core.solver.dimensions import SetDimension, dimensions
from mechsketch.gui import units
from mechsketch.gui.panels.study_inputs import HIGH, LOW, P_DIA, P_FIT, P_PLAY, P_USE, TOL, USE

from app_fakes import open_example, shell  # noqa: F401 - fixture

SAMPLES = 72


@pytest.fixture
def study(shell, qtbot):  # noqa: F811
    """The app on the four-bar example with the Study dock in front: (parts, panel, layer)."""
    parts, ctl, canvas = open_example(shell, "fourbar_crank_rocker")
    dock = parts.window.docks["study"]
    dock.show()
    dock.raise_()
    qtbot.waitUntil(lambda: parts.window.design_docks.study.isVisible(), timeout=5000)
    return parts, parts.window.design_docks.study, canvas.design_layer


def row(panel, key: str) -> int:
    return panel.variables.row_of(key)


def type_cell(qtbot, table, r: int, c: int, text: str) -> None:
    """Type ``text`` into a cell as a user would: double-click it, replace the text, Enter."""
    table.scrollToItem(table.item(r, c))
    at = table.visualItemRect(table.item(r, c)).center()
    qtbot.mouseClick(table.viewport(), Qt.MouseButton.LeftButton, pos=at)
    qtbot.mouseDClick(table.viewport(), Qt.MouseButton.LeftButton, pos=at)
    editors = [e for e in table.viewport().findChildren(QLineEdit) if e.isVisible()]
    assert len(editors) == 1, "the cell did not open for editing"
    editor = editors[0]
    editor.selectAll()
    qtbot.keyClicks(editor, text)
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    QApplication.processEvents()    # the delegate commits through a queued call
    assert table.item(r, c).text() == text


def toggle(qtbot, table, r: int, c: int = USE) -> None:
    """Click a check box cell's box."""
    table.scrollToItem(table.item(r, c))
    rect = table.visualItemRect(table.item(r, c))
    before = table.item(r, c).checkState()
    qtbot.mouseClick(table.viewport(), Qt.MouseButton.LeftButton, pos=QPoint(rect.left() + 10, rect.center().y()))
    assert table.item(r, c).checkState() != before


def only(qtbot, panel, keys: list[str], pins: list[str] = ()) -> None:
    """Tick exactly ``keys`` among the variables and ``pins`` among the pins."""
    t = panel.variables.widget
    for r, rw in enumerate(panel.variables.rows):
        if (t.item(r, USE).checkState() == Qt.CheckState.Checked) != (rw.key in keys):
            toggle(qtbot, t, r)
    p = panel.clearances.widget
    for r, j in enumerate(panel.clearances.pins):
        if (p.item(r, P_USE).checkState() == Qt.CheckState.Checked) != (j in pins):
            toggle(qtbot, p, r, P_USE)


def set_spin(qtbot, spin, value: int) -> None:
    spin.setFocus()
    spin.selectAll()
    qtbot.keyClicks(spin, str(value))
    qtbot.keyClick(spin, Qt.Key.Key_Return)
    assert spin.value() == value


def run(qtbot, panel, timeout: int = 180_000):
    """Press Run and wait for the worker to end (its busyChanged(False))."""
    with qtbot.waitSignal(panel.runner.busyChanged, timeout=timeout, check_params_cb=lambda busy: not busy):
        qtbot.mouseClick(panel.run_button, Qt.MouseButton.LeftButton)
    return panel.outcome


def one_design_path(scene, key: str, value: float, joint: str = "E") -> np.ndarray:
    """The joint's path (samples, 2) of the four-bar with ``key`` set to ``value`` (the one-design path)."""
    ws = Workspace(scene)
    ws["fourbar"].set_dimension(key, value)
    return ws["fourbar"].solve(samples=SAMPLES, order=0).position(joint)


def test_defaults_are_scaled_to_the_part_with_units_and_iso_fits(study, qtbot):
    parts, panel, _layer = study
    t = panel.variables.widget
    assert panel.element_box.currentText() == "fourbar"
    # ±(0.02 mm + 0.02 % of the length): crank 40 mm -> 0.028, ground 160 mm -> 0.052; an angle ±0.05°
    assert t.item(row(panel, "length:crank:A:B"), TOL).text() == "0.028"
    assert t.item(row(panel, "length:ground:A:D"), TOL).text() == "0.052"
    assert t.item(row(panel, "angle:coupler:B:C:E"), TOL).text() == "0.05"
    assert t.item(row(panel, "angle:coupler:B:C:E"), 7).text() == "°"
    # ranges ±15 %; a ternary link by its polar dimensions (C–E not ticked), pivots not ticked
    assert t.item(row(panel, "length:rocker:D:C"), LOW).text() == "102"
    assert t.item(row(panel, "length:rocker:D:C"), HIGH).text() == "138"
    ticked = {rw.key for rw in panel.variables.used()}
    assert "length:coupler:C:E" not in ticked and "x:D" not in ticked and "length:coupler:B:E" in ticked
    # pins: H7/g6 on the drawn bore 9.63 mm; ISO 286: H7 = +0/+15 µm, g6 = -5/-14 µm (6-10 mm)
    p = panel.clearances.widget
    assert panel.clearances.pins == ["A", "B", "C", "D"]
    r = panel.clearances.pins.index("B")
    assert panel.clearances.fit_box(r).currentText() == "H7/g6" and p.item(r, P_DIA).text() == "9.63"
    assert p.item(r, P_PLAY).text() == f"{(0 + 5) / 2:.1f}–{(15 + 14) / 2:.1f} µm"
    # the display unit follows the preferences; what was typed is kept
    type_cell(qtbot, t, row(panel, "length:crank:A:B"), TOL, "0.254")
    try:
        units.set_current(units.Units(length="in"))
        assert t.item(row(panel, "length:crank:A:B"), TOL).text() == "0.01"          # 0.254 mm
        assert t.item(row(panel, "length:crank:A:B"), 7).text() == "in"
        assert p.item(r, P_DIA).text() == units.format_value(9.63, "mm", digits=4)
    finally:
        units.set_current(units.Units())
    assert t.item(row(panel, "length:crank:A:B"), TOL).text() == "0.254"


def test_the_band_reaches_the_one_design_path_at_the_ends_of_a_uniform_tolerance(study, qtbot):
    parts, panel, layer = study
    key, w = "length:crank:A:B", 0.05
    only(qtbot, panel, [key])
    type_cell(qtbot, panel.variables.widget, row(panel, key), TOL, str(w))
    panel.distribution.setCurrentIndex(panel.distribution.findData("uniform"))
    panel.confidence.setCurrentText("99.7 %")
    set_spin(qtbot, panel.builds, 1500)
    set_spin(qtbot, panel.tol_samples, SAMPLES)
    out = run(qtbot, panel)
    assert out is not None and out.joint == "E" and out.spec == {key: {"uniform": w}}
    assert parts.controller.undo_stack.count() == 0          # a study changes nothing
    band = panel.current_band()
    assert layer.band.isVisible() and layer.band.data is not None
    nominal, lower, upper = layer.band.data
    k = band["factor"]
    assert k >= 1 and f"×{k:g} magnified" in layer.band.label and "99.7 % band of E" in layer.band.label
    nu = out.result.nominal.normal["E"]
    up = ((upper - nominal) * nu).sum(axis=1) / k               # signed along the path's normal, mm
    lo = ((lower - nominal) * nu).sum(axis=1) / k
    scene = parts.controller.scene
    nom = next(d.value for d in dimensions(scene.element("fourbar")) if d.key == key)
    base = one_design_path(scene, key, nom)
    ends = np.stack([((one_design_path(scene, key, nom + s * w) - base) * nu).sum(axis=1) for s in (1, -1)])
    assert np.max(np.abs(base - nominal)) < 1e-9
    reach = np.max(np.abs(ends))
    assert np.max(np.abs(up - ends.max(axis=0))) <= 0.05 * reach
    assert np.max(np.abs(lo - ends.min(axis=0))) <= 0.05 * reach
    # the histogram: every build counted; the largest deviation is that of the ends
    view = panel.tolerance_view
    assert view.isVisible() and view.counts.sum() == 1500 and out.result.failed == 0
    dist = [np.max(np.hypot(*(one_design_path(scene, key, nom + s * w) - base).T)) for s in (1, -1)]
    assert 0.95 * max(dist) <= np.max(out.result.deviation("E")) <= 1.001 * max(dist)
    assert "the linearised 3σ band" in panel.status.text()
    # magnified ×10 on request: the same band, ten times wider on the canvas
    panel.magnify.setCurrentText("×10")
    _n2, _l2, u2 = layer.band.data
    assert np.allclose(((u2 - nominal) * nu).sum(axis=1) / 10, up, atol=1e-12)


def test_sensitivity_bars_are_the_first_order_shares_of_the_one_design_path(study, qtbot):
    parts, panel, _layer = study
    crank, rocker = "length:crank:A:B", "length:rocker:D:C"
    only(qtbot, panel, [crank, rocker])
    t = panel.variables.widget
    type_cell(qtbot, t, row(panel, crank), TOL, "0.05")
    type_cell(qtbot, t, row(panel, rocker), TOL, "0.09")      # normal: σ = 0.03 mm
    set_spin(qtbot, panel.builds, 300)
    set_spin(qtbot, panel.tol_samples, SAMPLES)
    out = run(qtbot, panel)
    scene = parts.controller.scene
    nu = out.result.nominal.normal["E"]
    var = {}
    for key, sigma in ((crank, 0.05 / 3), (rocker, 0.03)):
        nom = next(d.value for d in dimensions(scene.element("fourbar")) if d.key == key)
        h = 1e-4
        dp = (one_design_path(scene, key, nom + h) - one_design_path(scene, key, nom - h)) / (2 * h)
        var[key] = sigma ** 2 * float(np.sum(dp ** 2))          # of the point's displacement, both axes
    total = sum(var.values())
    shown = dict(panel.tolerance_view.shares)
    assert set(shown) == {crank, rocker}
    for key in var:
        assert shown[key] == pytest.approx(var[key] / total, rel=1e-5)
    assert [k for k, _ in panel.tolerance_view.shares] == sorted(var, key=lambda k: -var[k])   # largest first


def test_bad_entries_are_refused_naming_the_row_and_nothing_runs(study, qtbot):
    parts, panel, layer = study
    t = panel.variables.widget
    r = row(panel, "length:crank:A:B")
    type_cell(qtbot, t, r, TOL, "-0.05")
    assert panel.run() is False and not panel.runner.busy
    assert "crank A–B" in panel.status.text() and "not negative" in panel.status.text()
    assert (t.currentRow(), t.currentColumn()) == (r, TOL)
    type_cell(qtbot, t, r, TOL, "abc")
    qtbot.mouseClick(panel.run_button, Qt.MouseButton.LeftButton)
    assert not panel.runner.busy and "is not a number" in panel.status.text()
    type_cell(qtbot, t, r, TOL, "0.03")
    box = panel.clearances.fit_box(panel.clearances.pins.index("B"))
    box.setFocus()
    box.lineEdit().selectAll()
    qtbot.keyClicks(box.lineEdit(), "Q7/z9")
    assert panel.run() is False and "pin B" in panel.status.text()
    assert (panel.clearances.widget.currentRow(), panel.clearances.widget.currentColumn()) == (1, P_FIT)
    box.setCurrentText("H7/g6")
    panel.mode_box.setCurrentIndex(panel.mode_box.findData("optimize"))
    type_cell(qtbot, t, r, LOW, "50")                           # from above to (46)
    assert panel.run() is False and "'from' must be below 'to'" in panel.status.text()
    only(qtbot, panel, [])
    assert panel.run() is False and "tick at least one variable" in panel.status.text()
    assert parts.controller.undo_stack.count() == 0 and not layer.band.isVisible()


def test_cancel_stops_the_study_and_changes_nothing(study, qtbot):
    parts, panel, layer = study
    before = parts.controller.scene
    set_spin(qtbot, panel.builds, 400_000)
    with qtbot.waitSignal(panel.runner.busyChanged, timeout=180_000, check_params_cb=lambda busy: not busy):
        with qtbot.waitSignal(panel.runner.started, timeout=5000):
            qtbot.mouseClick(panel.run_button, Qt.MouseButton.LeftButton)
        assert panel.cancel_button.isEnabled() and not panel.run_button.isEnabled()
        qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    assert panel.outcome is None and "cancelled" in panel.status.text()
    assert parts.controller.scene is before and parts.controller.undo_stack.count() == 0
    assert not layer.band.isVisible() and panel.run_button.isEnabled() and not panel.cancel_button.isEnabled()


def closed_form_min_mu(lk) -> float:
    """The four-bar's least transmission angle (°, folded to 0-90): at the crank's two dead-centre
    lines, cos μ = (b² + c² − (d ∓ a)²)/(2bc)."""
    d = {x.key: x.value for x in dimensions(lk)}
    a, b, c, g = d["length:crank:A:B"], d["length:coupler:B:C"], d["length:rocker:D:C"], d["length:ground:A:D"]
    mus = [math.degrees(math.acos((b * b + c * c - (g - s * a) ** 2) / (2 * b * c))) for s in (1, -1)]
    return min(min(m, 180 - m) for m in mus)


def test_optimisation_front_previews_applies_and_adds_variants_in_one_undo_step(study, qtbot):
    parts, panel, layer = study
    ctl = parts.controller
    crank, rocker = "length:crank:A:B", "length:rocker:D:C"
    panel.mode_box.setCurrentIndex(panel.mode_box.findData("optimize"))
    only(qtbot, panel, [crank, rocker])
    assert panel.objective1.currentData() == "maximize min_transmission_angle"
    assert panel.objective2.currentData() == "maximize swing:rocker"
    set_spin(qtbot, panel.population, 12)
    set_spin(qtbot, panel.generations, 4)
    set_spin(qtbot, panel.opt_samples, 60)      # samples every 6°: the dead-centre lines are sampled
    out = run(qtbot, panel)
    assert out is not None and len(out.front) >= 2
    cols = out.result.columns
    feas = np.flatnonzero(cols["feasible"] > 0)
    F = np.column_stack([-cols["min_transmission_angle"], -cols["swing:rocker"]])[feas]
    dominated = [bool(np.any(np.all(F <= f, axis=1) & np.any(F < f, axis=1))) for f in F]
    shown = {(float(x), float(y)) for x, y in panel.pareto_view.xy}
    expect = {(float(-f[0]), float(-f[1])) for f, dom in zip(F, dominated) if not dom}
    assert shown == expect                                 # the scatter's front is the non-dominated set
    assert np.all(cols["min_transmission_angle"][feas] >= 40.0 - 1e-9)   # the constraint held
    # a click on a front point previews that variant on the canvas
    pick = len(out.front) - 1
    pw = panel.pareto_view.plot
    qtbot.mouseClick(pw.viewport(), Qt.MouseButton.LeftButton, pos=pw.mapFromScene(panel.pareto_view.scene_point(pick)))
    assert panel.picked == pick
    rec = out.front[pick][1]
    assert layer.ghost.linkage is rec and layer.ghost.frames > 1 and layer.timer.isActive()
    f0 = layer.ghost.item.pose.index
    layer.tick()
    assert layer.ghost.item.pose.index == (f0 + 1) % layer.ghost.frames
    row_ = out.front[pick][0]
    assert cols["min_transmission_angle"][row_] == pytest.approx(closed_form_min_mu(rec), abs=1e-7)
    # Apply: the linkage takes the variant's dimensions, one undo step
    qtbot.mouseClick(panel.apply_button, Qt.MouseButton.LeftButton)
    assert ctl.scene.element("fourbar") is rec and ctl.undo_stack.count() == 1
    assert ctl.result("fourbar").error is None and not layer.ghost.item
    parts.window.actions["undo"].trigger()
    assert ctl.scene.element("fourbar") is out.linkage
    # Add as new element: placed beside, one undo step, an ordinary linkage
    panel.pick(0)
    qtbot.mouseClick(panel.add_button, Qt.MouseButton.LeftButton)
    new = ctl.scene.element("fourbar_v1")
    assert ctl.undo_stack.count() == 1 and ctl.result("fourbar_v1").error is None
    src = out.front[0][1]
    assert [d.value for d in dimensions(new)] == pytest.approx([d.value for d in dimensions(src)], abs=1e-9)
    assert min(j.at[0] for j in new.joints) > max(j.at[0] for j in src.joints)
    parts.window.actions["undo"].trigger()
    assert "fourbar_v1" not in ctl.scene.ids
    panel.clear_results()
    assert layer.ghost.linkage is None and not layer.timer.isActive()


def test_an_edit_of_the_studied_linkage_takes_its_band_away(study, qtbot):
    parts, panel, layer = study
    only(qtbot, panel, ["length:crank:A:B"], ["B"])
    set_spin(qtbot, panel.builds, 200)
    set_spin(qtbot, panel.tol_samples, 36)
    out = run(qtbot, panel)
    shares = dict(panel.tolerance_view.shares)
    assert set(shares) == {"length:crank:A:B", "clearance:B"} and sum(shares.values()) == pytest.approx(1.0)
    assert shares["clearance:B"] > 0 and layer.band.isVisible()
    assert out.spec["clearance"] == {"B": {"fit": "H7/g6", "diameter": pytest.approx(9.63)}}
    parts.controller.push(SetDimension("fourbar", "length:crank:A:B", 41.0, "set crank"))
    assert not layer.band.isVisible() and "changed since its tolerance study" in panel.status.text()


def test_the_study_panel_redraws_only_when_its_dock_is_in_front(shell, qtbot):  # noqa: F811
    """Tabbed behind the plots the Study panel costs nothing per edit; brought to the front it
    shows the scene once; in front it follows edits, and a drag preview waits for its release."""
    parts, ctl, canvas = open_example(shell, "fourbar_crank_rocker")
    win, panel = parts.window, parts.window.design_docks.study
    calls = []
    original = panel.refresh
    panel.refresh = lambda: (calls.append(1), original())[1]
    win.docks["plots"].raise_()
    QApplication.processEvents()
    assert not getattr(panel, "on_screen", False)
    lk = ctl.scene.element("fourbar")
    moved = lk.with_joint_moved("C", (lk.joint("C").at[0] + 1.0, lk.joint("C").at[1]))
    ctl.push(ReplaceElement(moved), "move C")
    ctl.undo_stack.undo()
    ctl.set_selection([("fourbar", "element", "fourbar")])
    assert calls == []                                   # behind the plots: nothing redrawn
    win.docks["study"].raise_()
    qtbot.waitUntil(lambda: panel.on_screen, timeout=5000)
    assert len(calls) == 1                               # in front: the scene as it is, once
    ctl.undo_stack.redo()
    assert len(calls) == 2                               # in front: follows each edit
    ctl.begin_preview()
    ctl.preview(ReplaceElement(lk.with_joint_moved("C", (lk.joint("C").at[0] + 2.0, lk.joint("C").at[1]))))
    assert len(calls) == 2                               # a drag preview waits ...
    ctl.end_preview(None)
    assert len(calls) == 3                               # ... for its release
    win.docks["plots"].raise_()
    qtbot.waitUntil(lambda: not panel.on_screen, timeout=5000)
    ctl.undo_stack.undo()
    assert len(calls) == 3
