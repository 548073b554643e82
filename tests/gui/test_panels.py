"""Properties, plots and diagnostics panels driven through their widgets; the mode flip."""
from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from PySide6.QtCore import Qt

from mechsketch import resources
from mechsketch.core import MoveJoint, load_scene
from mechsketch.core.solver.flip import flip_group, group_modes
from mechsketch.core.solver.plan import compile_plan

from app_fakes import shell  # noqa: F401 - fixture
from app_fakes import type_into as _type


def test_typing_a_joint_coordinate_is_one_undo_command(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "joint", "B")])
    assert props.fields["x"].text() == "20" and props.fields["y"].text() == "34.641016"
    before = c.scene
    _type(qtbot, props.fields["x"], "25.5")
    assert c.scene.element("fourbar").joint("B").at == (25.5, 34.641016151)
    assert c.undo_stack.count() == 1 and c.undo_stack.undoText() == "move joint B"
    parts.window.actions["undo"].trigger()
    assert c.scene == before and props.fields["x"].text() == "20"
    parts.window.actions["redo"].trigger()
    assert props.fields["x"].text() == "25.5"


def test_enter_without_a_change_adds_nothing_and_garbage_is_refused(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "joint", "C")])
    props.fields["y"].setFocus()
    qtbot.keyClick(props.fields["y"], Qt.Key.Key_Return)
    assert c.undo_stack.count() == 0
    _type(qtbot, props.fields["y"], "abc")
    assert c.undo_stack.count() == 0 and "not a number" in parts.window.statusBar().currentMessage()
    assert props.fields["y"].text() == "116.975865"


def test_the_selector_selects_without_the_canvas(shell):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    index = props.selector.findText("fourbar: link rocker")
    props.selector.activated.emit(index)
    assert c.selection == [("fourbar", "link", "rocker")]
    assert props.selector.currentText() == "fourbar: link rocker"


def test_a_link_length_is_a_dimension_edit_the_others_are_kept(shell, qtbot):
    """Typing the crank's length re-assembles the linkage: the crank keeps its angle, the coupler
    and the rocker keep their lengths (the old edit moved one joint and changed the coupler)."""
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "link", "crank")])
    field = props.fields["length:A-B"]
    assert float(field.text()) == pytest.approx(40.0)
    before = c.scene.element("fourbar")
    _type(qtbot, field, "50")
    lk = c.scene.element("fourbar")
    assert lk.joint("A").at == (0.0, 0.0)
    assert math.hypot(*lk.joint("B").at) == pytest.approx(50.0, abs=1e-12)
    assert math.degrees(math.atan2(lk.joint("B").at[1], lk.joint("B").at[0])) == pytest.approx(60.0)
    for a, b in (("B", "C"), ("D", "C"), ("A", "D")):
        assert math.dist(lk.joint(a).at, lk.joint(b).at) == pytest.approx(math.dist(before.joint(a).at,
                                                                                    before.joint(b).at), abs=1e-9)
    assert c.undo_stack.undoText() == "set length A:B"


def test_ternary_and_ground_lengths_are_editable(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    eid = "fourbar"
    c.set_selection([(eid, "link", "ground")])
    _type(qtbot, props.fields["length:A-D"], "150")
    lk = c.scene.element(eid)
    assert math.dist(lk.joint("A").at, lk.joint("D").at) == pytest.approx(150.0, abs=1e-9)
    coupler = next(k for k in lk.links if len(k.joints) == 3)
    c.set_selection([(eid, "link", coupler.id)])
    names = [k for k in props.fields if k.startswith(("length:", "angle:"))]
    assert len(names) == 4   # three sides and the angle at the first joint
    b, cc, e = coupler.joints
    _type(qtbot, props.fields[f"length:{b}-{e}"], "70")
    lk = c.scene.element(eid)
    assert math.dist(lk.joint(b).at, lk.joint(e).at) == pytest.approx(70.0, abs=1e-9)


def test_the_dimension_table_lists_every_length_and_edits_it(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    table = props.tables["dimensions"]
    rows = {table.item(r, 2).data(Qt.ItemDataRole.UserRole): r for r in range(table.rowCount())}
    assert set(rows) == {"length:ground:A:D", "length:crank:A:B", "length:coupler:B:C", "length:coupler:B:E",
                         "length:coupler:C:E", "angle:coupler:B:C:E", "length:rocker:D:C"}
    assert table.item(rows["angle:coupler:B:C:E"], 3).text() == "°"
    assert table.item(rows["length:rocker:D:C"], 3).text() == "mm"
    assert float(table.item(rows["length:rocker:D:C"], 2).text()) == pytest.approx(120.0)
    table.item(rows["length:rocker:D:C"], 2).setText("125")
    lk = c.scene.element("fourbar")
    assert math.dist(lk.joint("D").at, lk.joint("C").at) == pytest.approx(125.0, abs=1e-9)
    assert c.undo_stack.count() == 1
    table = props.tables["dimensions"]
    r = {table.item(k, 2).data(Qt.ItemDataRole.UserRole): k for k in range(table.rowCount())}["length:crank:A:B"]
    table.item(r, 2).setText("400")   # cannot assemble: refused, the cell shows the model again
    assert "RRR(coupler,rocker)" in parts.window.statusBar().currentMessage()
    assert float(props.tables["dimensions"].item(r, 2).text()) == pytest.approx(40.0)
    assert c.undo_stack.count() == 1


def test_driver_speed_and_direction(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    assert float(props.fields["speed"].text()) == pytest.approx(95.4929658551372, rel=1e-6)
    _type(qtbot, props.fields["speed"], "30")
    assert c.scene.element("fourbar").driver.speed_rpm == 30.0
    _type(qtbot, props.fields["speed"], "-5")                 # refused: the sign is the direction
    assert c.scene.element("fourbar").driver.speed_rpm == 30.0
    assert "positive" in parts.window.statusBar().currentMessage()
    props.direction.setCurrentIndex(1)
    props.direction.activated.emit(1)
    assert c.scene.element("fourbar").driver.speed_rpm == -30.0
    sol = c.result("fourbar").solution
    assert sol.input[1] < sol.input[0]                         # the sweep turns clockwise now
    assert c.undo_stack.count() == 2


def test_prismatic_joint_axis_is_editable_in_degrees(shell, qtbot):
    parts = shell(resources.example_path("slider_crank_offset"))
    c, props = parts.controller, parts.window.properties
    c.set_selection([("slider_crank", "joint", "S")])
    assert props.fields["axis"].text() == "0"
    _type(qtbot, props.fields["axis"], "10")
    assert c.scene.element("slider_crank").joint("S").axis_deg == 10.0


def test_flip_changes_the_mode_shown_in_the_diagnostics_and_undoes(shell, qtbot):
    parts = shell()
    c, w = parts.controller, parts.window
    assert "group RRR(coupler,rocker): kind RRR, mode +1" in w.diagnostics.plain_text()
    before = c.scene
    qtbot.mouseClick(w.properties.flip_buttons["RRR(coupler,rocker)"], Qt.MouseButton.LeftButton)
    assert "group RRR(coupler,rocker): kind RRR, mode -1" in w.diagnostics.plain_text()
    old, new = before.element("fourbar"), c.scene.element("fourbar")
    for a, b in (("B", "C"), ("C", "D"), ("B", "E"), ("C", "E")):   # lengths and the coupler's shape kept
        d0 = math.dist(old.joint(a).at, old.joint(b).at)
        assert math.dist(new.joint(a).at, new.joint(b).at) == pytest.approx(d0, abs=1e-9)
    w.actions["undo"].trigger()
    assert c.scene == before and "mode +1" in w.diagnostics.plain_text()


@pytest.mark.parametrize("name", ["fourbar_crank_rocker", "double_rocker", "slider_crank_offset",
                                  "inverted_slider_crank", "sixbar_moving_guide"])
def test_flip_twice_is_the_identity_and_keeps_later_groups(name):
    for lk in load_scene(resources.example_path(name)).elements:
        modes = group_modes(lk)
        for group, mode in modes.items():
            if mode is None:
                continue
            flipped = flip_group(lk, group)
            new = group_modes(flipped)
            assert new[group] == -mode
            assert {g: m for g, m in new.items() if g != group} == {g: m for g, m in modes.items() if g != group}
            back = flip_group(flipped, group)
            for j0, j1 in zip(lk.joints, back.joints):
                assert j0.at == pytest.approx(j1.at, abs=1e-6)
            a = compile_plan(lk).sweep(order=0)
            b = compile_plan(flipped).sweep(order=0)
            assert a.valid.mean() == pytest.approx(b.valid.mean())


def test_plots_show_the_selected_joint_and_link_with_units(shell):
    parts = shell()
    c, plots = parts.controller, parts.window.plots
    c.set_selection([("fourbar", "joint", "C")])
    sol = c.result("fourbar").solution
    x, y = plots.curves["C.x"].getData()
    assert np.allclose(x, np.degrees(sol.input)) and np.allclose(y, sol.position("C")[:, 0])
    assert {"C.vx", "C.vy", "|v C|", "C.ax", "C.ay", "|a C|", "μ RRR(coupler,rocker)"} <= set(plots.curves)
    assert plots.plots["velocity"].getAxis("left").labelText == "velocity (mm/s)"
    c.set_selection([("fourbar", "link", "rocker")])
    assert set(plots.curves) == {"rocker.angle", "rocker.ω", "rocker.ε", "μ RRR(coupler,rocker)"}
    assert np.allclose(plots.curves["rocker.ω"].getData()[1], sol.omega("rocker"))
    assert plots.plots["acceleration"].getAxis("left").labelText == "ε (rad/s²)"
    mu = plots.curves["μ RRR(coupler,rocker)"].getData()[1]
    assert 54.3 < np.nanmin(mu) < 54.4 and 100.2 < np.nanmax(mu) < 100.3


def test_plot_cursor_follows_the_frame(shell):
    parts = shell()
    c, plots = parts.controller, parts.window.plots
    c.set_frame(90)
    assert plots.cursor_x() == pytest.approx(math.degrees(c.result("fourbar").solution.input[90]))


def test_infeasible_poses_are_gaps_in_the_lines(shell):
    parts = shell(resources.example_path("double_rocker"))
    c, plots = parts.controller, parts.window.plots
    y = plots.curves[next(iter(plots.curves))].getData()[1]
    assert np.isnan(y).any() and np.isfinite(y).any()
    assert plots.curves[next(iter(plots.curves))].opts["connect"] == "finite"
    assert "dead point" in parts.window.diagnostics.plain_text()


def test_export_png_and_csv(shell, tmp_path):
    parts = shell()
    w = parts.window
    parts.controller.set_selection([("fourbar", "joint", "C")])
    parts.dialogs.save_names.extend([str(tmp_path / "p.png"), str(tmp_path / "p.csv")])
    w.actions["export_png"].trigger()
    w.actions["export_csv"].trigger()
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.reader((tmp_path / "p.csv").open()))
    assert rows[0][:3] == ["input_deg", "C.x_mm", "C.y_mm"] and len(rows) == 361
    sol = parts.controller.result("fourbar").solution
    assert float(rows[1][1]) == pytest.approx(sol.position("C")[0, 0])
    assert not parts.dialogs.errors


def test_export_to_an_unwritable_path_is_a_message(shell, tmp_path):
    parts = shell()
    parts.dialogs.save_names.extend([str(tmp_path / "nope" / "p.png"), str(tmp_path / "nope" / "p.csv")])
    assert parts.window.export_plot_png() is False
    assert parts.window.export_plot_csv() is False
    assert len(parts.dialogs.errors) == 2 and "nope" in parts.dialogs.errors[0][1]


def test_diagnostics_show_groups_ranges_dead_points_and_the_solve(shell):
    text = shell(resources.example_path("double_rocker")).window.diagnostics.plain_text()
    for expected in ("mobility: 1", "group RRR(coupler,output): kind RRR, mode -1", "reachable: input",
                     "dead point", "transmission angle RRR(coupler,output)", "poses in",
                     "max loop-closure residual"):
        assert expected in text
    # the same text as `mechsketch analyze --summary` (one report, in core/analyses), timings aside
    from mechsketch.core.cli import main
    import contextlib
    import io
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["analyze", str(resources.example_path("double_rocker")), "--summary"]) == 0
    flat = " ".join(text.split())
    for line in out.getvalue().splitlines():
        if not line.startswith("solve:"):
            assert " ".join(line.split()) in flat, line


def test_an_impossible_drag_is_shown_not_fatal(shell):
    parts = shell()
    c, w = parts.controller, parts.window
    c.set_selection([("fourbar", "joint", "C")])
    c.begin_preview()
    c.preview(MoveJoint("fourbar", "C", (160.0, 0.0)))   # onto D: the rocker has no length left
    assert "'rocker': joints 'D' and 'C' are at the same point" in w.diagnostics.plain_text()
    assert c.result("fourbar").error is not None            # a message, not a crash
    c.end_preview(None)
    assert not c.is_dirty and "reachable: full revolution" in w.diagnostics.plain_text()


class _Gear:
    """An element of a type the panels have no editor for (like a Geneva drive)."""

    id, type = "gear1", "geneva"

    def to_dict(self):
        return {"type": self.type, "id": self.id}


def test_a_scene_without_a_linkage_lists_its_elements(shell):
    from mechsketch.core import Scene

    parts = shell()
    parts.controller.reset(Scene((_Gear(),)), None)
    w = parts.window
    assert "geneva gear1" in w.diagnostics.plain_text()
    assert "no linkage" in w.plots.title.text()
    labels = [lab.text() for lab in w.properties._content.findChildren(type(w.plots.title))]
    assert "gear1" in labels


def test_a_click_on_a_plot_moves_the_frame_to_the_nearest_assemblable_pose(shell):
    parts = shell(resources.example_path("double_rocker"))
    c, plots = parts.controller, parts.window.plots
    sol = c.result("double_rocker").solution
    ok = np.flatnonzero(sol.valid)
    k = int(ok[len(ok) // 2])
    plots.go_to(float(np.degrees(sol.input[k])) + 0.1)
    assert c.frame == k
    gap = int(np.flatnonzero(~sol.valid)[len(np.flatnonzero(~sol.valid)) // 2])   # middle of the gap
    plots.go_to(float(np.degrees(sol.input[gap])))
    assert sol.valid[c.frame]
    assert plots.cursor_x() == pytest.approx(np.degrees(sol.input[c.frame]))
