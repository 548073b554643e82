"""Forces in the app, driven as a user would: masses, friction, gravity and loads typed into
Properties (units shown, each edit one undo step), loads added and removed with buttons, a load
dragged on the canvas by its handle, the driving torque and a selected joint's reaction in the
plots (the workspace's numbers), the forces overlay from the View menu, and the Geneva crank torque.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtWidgets import QLabel

from mechsketch.core.analyses.geneva.torque import crank_torque
from mechsketch.core.model.loads import PointForce
from mechsketch.resources import example_path

from app_fakes import shell  # noqa: F401 - fixture
from app_fakes import type_into
from canvas_user import User, example, make_view

EID = "loaded_fourbar"


def loaded_app(shell):
    parts = shell(example_path("fourbar_loaded"))
    return parts, parts.controller, parts.window.properties


def units_beside(edit) -> str:
    row = edit.parentWidget()
    return " ".join(w.text() for w in row.findChildren(QLabel))


def test_mass_centre_and_inertia_are_typed_with_units_and_undone(shell, qtbot):
    parts, c, props = loaded_app(shell)
    c.set_selection([(EID, "link", "rocker")])
    assert units_beside(props.fields["mass"]) == "kg" and units_beside(props.fields["com_x"]) == "mm"
    assert "kg·m² (estimate)" in units_beside(props.fields["inertia"])     # the rocker has no inertia given
    estimate = float(props.fields["inertia"].text())
    assert math.isclose(estimate, 0.6 * 0.12 ** 2 / 12, rel_tol=1e-5)      # m·L²/12, L = 120 mm
    before = c.workspace.forces(EID).driver.values.copy()
    type_into(qtbot, props.fields["mass"], "1.2")
    assert c.scene.element(EID).mass_of("rocker").mass == 1.2
    type_into(qtbot, props.fields["inertia"], "0.002")
    qtbot.waitUntil(lambda: units_beside(props.fields["inertia"]) == "kg·m²", timeout=20000)
    type_into(qtbot, props.fields["com_y"], "40")
    m = c.scene.element(EID).mass_of("rocker")
    assert m.inertia == 0.002 and m.com[1] == 40.0
    assert not np.allclose(c.workspace.forces(EID).driver.values, before)
    assert c.undo_stack.count() == 3
    for _ in range(3):
        c.undo_stack.undo()
    assert c.scene.element(EID).mass_of("rocker").mass == 0.6
    assert np.array_equal(c.workspace.forces(EID).driver.values, before)


def test_friction_and_gravity_fields(shell, qtbot):
    parts, c, props = loaded_app(shell)
    c.set_selection([(EID, "joint", "B")])
    assert units_beside(props.fields["friction"]) == "mm"
    type_into(qtbot, props.fields["friction"], "2.5")
    assert c.scene.element(EID).friction_of("B") == 2.5
    assert units_beside(props.fields["gy"]) == "m/s²"
    type_into(qtbot, props.fields["gy"], "-3.71")           # Mars
    assert c.scene.element(EID).gravity == (0.0, -3.71)
    type_into(qtbot, props.fields["friction"], "-1")          # refused, nothing changes
    assert c.scene.element(EID).friction_of("B") == 2.5
    assert "0 mm or more" in parts.window.statusBar().currentMessage()


def test_loads_are_added_edited_and_removed_with_undo(shell, qtbot):
    parts, c, props = loaded_app(shell)
    c.set_selection([(EID, "link", "coupler")])
    qtbot.mouseClick(props.buttons["add_force"], Qt.MouseButton.LeftButton)
    lk = c.scene.element(EID)
    assert lk.load_ids[-1] == "F1" and lk.load("F1").link == "coupler"
    qtbot.waitUntil(lambda: "F1.Fx" in props.fields, timeout=20000)
    assert units_beside(props.fields["F1.Fx"]) == "N" and units_beside(props.fields["F1.x"]) == "mm"
    type_into(qtbot, props.fields["F1.Fx"], "25")
    assert c.scene.element(EID).load("F1").force == (25.0, -10.0)
    type_into(qtbot, props.fields["brake.T"], "-4")
    assert c.scene.element(EID).load("brake").torque == -4.0
    assert units_beside(props.fields["return.k"]) == "N/mm" and units_beside(props.fields["damper.c"]) == "N·s/mm"
    qtbot.mouseClick(props.buttons["remove:cut"], Qt.MouseButton.LeftButton)
    assert "cut" not in c.scene.element(EID).load_ids
    for kind in ("torque", "spring", "damper"):
        qtbot.mouseClick(props.buttons[f"add_{kind}"], Qt.MouseButton.LeftButton)
        qtbot.waitUntil(lambda: f"add_{kind}" in props.buttons, timeout=20000)
    assert c.scene.element(EID).load_ids[-3:] == ("T1", "K1", "C1")
    count = c.undo_stack.count()
    for _ in range(count):
        c.undo_stack.undo()
    assert c.scene.element(EID).load_ids == ("cut", "brake", "return", "damper")


def test_a_load_is_dragged_on_the_canvas_by_its_handle(qtbot):
    scene = example("fourbar_loaded")
    ctl, view, user = make_view(qtbot, scene, QRectF(-60.0, -80.0, 320.0, 280.0))
    view.snap_enabled = False
    handles = view.extras.loads_item.handles
    cut = next(h for h in handles if h.load == "cut")
    drawn = scene.element(EID).load("cut").at
    assert cut.point == pytest.approx(drawn)                                # frame 0 is the drawn pose
    assert cut.at != cut.point           # the grip is the arrow's tail, clear of joint E under the point
    target = (cut.at[0] - 20.0, cut.at[1] + 10.0)
    user.drag(cut.at, target, steps=8)
    qtbot.waitUntil(lambda: ctl.undo_stack.count() == 1, timeout=20000)
    moved = ctl.scene.element(EID).load("cut").at
    assert moved == pytest.approx((drawn[0] - 20.0, drawn[1] + 10.0), abs=view.px() * 2)
    assert ctl.scene.element(EID).joints == scene.element(EID).joints      # the kinematics untouched
    # the damper's grip near the crank pin B moves the damper's end, not the joint
    end = next(h for h in view.extras.loads_item.handles if h.load == "damper" and h.end == 1)
    user.drag(end.at, (end.at[0] + 5.0, end.at[1] + 5.0), steps=4)
    qtbot.waitUntil(lambda: ctl.undo_stack.count() == 2, timeout=20000)
    assert ctl.scene.element(EID).joints == scene.element(EID).joints
    assert ctl.scene.element(EID).load("damper").ends[1].at != scene.element(EID).load("damper").ends[1].at
    ctl.undo_stack.undo()
    ctl.undo_stack.undo()
    assert ctl.scene.element(EID).load("cut").at == scene.element(EID).load("cut").at


def test_dragging_a_load_at_another_frame_maps_back_to_the_drawn_pose(qtbot):
    scene = example("fourbar_loaded")
    ctl, view, user = make_view(qtbot, scene, QRectF(-60.0, -80.0, 320.0, 280.0))
    ctl.set_frame(90)
    qtbot.waitUntil(lambda: view.extras.loads_item.handles and
                    next(h for h in view.extras.loads_item.handles if h.load == "cut").at
                    != scene.element(EID).load("cut").at, timeout=20000)
    cut = next(h for h in view.extras.loads_item.handles if h.load == "cut")
    view.snap_enabled = False
    target = (cut.at[0] + 8.0, cut.at[1] - 6.0)
    user.drag(cut.at, target, steps=6)
    qtbot.waitUntil(lambda: ctl.undo_stack.count() == 1, timeout=20000)
    sol = ctl.result(EID).solution
    p0 = ctl.scene.element(EID).load("cut").at
    shown = sol.point("coupler", p0)[90]                                     # where it now is at frame 90
    assert shown == pytest.approx((cut.point[0] + 8.0, cut.point[1] - 6.0), abs=3 * view.px())


def test_plots_show_the_driving_torque_and_the_selected_joints_reaction(shell, qtbot):
    parts, c, _ = loaded_app(shell)
    plots = parts.window.plots
    c.set_selection([(EID, "joint", "C")])
    plots.refresh()
    assert "torque" in plots.plots and "reaction" in plots.plots
    res = c.workspace.forces(EID)
    curve = plots.curves["driver.torque (crank)"]
    assert np.array_equal(curve.yData, res.driver.values)
    assert np.array_equal(plots.curves["C.Fx"].yData, res.pins["C"]["rocker"][:, 0])
    assert "driver.torque with friction" in plots.curves                    # the example has bearing friction
    table = plots.data.table()
    assert "driver.torque_(crank)_N·m" in table.columns or any(col.startswith("driver.torque") for col in table.columns)


def test_forces_overlay_from_the_view_menu(shell, qtbot):
    parts, c, _ = loaded_app(shell)
    view = parts.window.canvas
    action = view.extras.actions["forces"]
    assert action.text().startswith("Joint Forces")
    action.trigger()
    item = view.extras.overlays.items["forces"]
    c.set_frame(40)
    qtbot.waitUntil(lambda: any("torque" in r for r in item.records), timeout=20000)
    res = c.workspace.forces(EID)
    text = next(r["torque"] for r in item.records if "torque" in r)
    assert f"{res.driver.values[40]:.4g} N·m" in text
    arrows = [r for r in item.records if "tip" in r]
    assert {r["text"].split()[0] for r in arrows} == {"A", "B", "C", "D"}
    legend = next(r["text"] for r in item.records if "legend" in r)
    scale = float(legend.split("≙")[1].split()[0])
    b = next(r for r in arrows if r["text"].startswith("B "))
    f = res.pins["B"]["coupler"][40]
    assert (b["tip"][0] - b["at"][0]) * scale == pytest.approx(f[0], rel=1e-9, abs=1e-9)
    action.trigger()
    assert item.records == []


def test_geneva_crank_torque_in_plots_and_overlay(shell, qtbot):
    parts = shell(example_path("geneva_z6"))
    c = parts.controller
    eid = c.scene.elements[0].id
    c.set_selection([(eid, "element", eid)])
    plots = parts.window.plots
    plots.refresh()
    assert "torque" in plots.plots
    res = c.element_result(eid)
    assert np.array_equal(plots.curves["driver.torque"].yData, crank_torque(res.element, res.contact).torque)
    view = parts.window.canvas
    view.extras.actions["forces"].trigger()
    item = view.extras.overlays.items["forces"]
    qtbot.waitUntil(lambda: any("crank torque" in r.get("torque", "") for r in item.records), timeout=20000)


def test_a_cylinder_driven_arm_plots_its_driving_force(shell, qtbot, tmp_path):
    """The excavator arm (a cylinder with a cycloidal stroke) with masses: the plots show the
    driving force (N, positive extending) where a crank's torque is, against the stroke in mm;
    the overlay writes it at the cylinder's slide."""
    import json
    doc = json.loads(example_path("excavator_arm").read_text())
    el = doc["elements"][0]
    for link in el["links"]:
        if link["id"] != el["ground"]:
            link["mass"] = 40.0
    el["gravity"] = [0.0, -9.81]
    path = tmp_path / "arm.json"
    path.write_text(json.dumps(doc))
    parts = shell(path)
    c = parts.controller
    plots = parts.window.plots
    c.set_selection([("arm", "joint", "C2")])
    plots.refresh()
    assert "torque" in plots.plots
    res = c.workspace.forces("arm")
    assert res.driver.kind == "force" and res.power.worst < 1e-13
    assert np.array_equal(plots.curves["driver.force (barrel)"].yData, res.driver.values)
    assert plots.data.labels["torque"] == "driving force (N)"
    assert np.array_equal(plots.curves["C2.Fx"].yData, res.pins["C2"]["rod"][:, 0])
    assert np.array_equal(plots.data.x, res.input) and plots.data.x_label == "input: cylinder length (mm)"
    assert plots.data.table().columns[0] == "input_mm" and 850.0 <= res.input.min() < res.input.max() <= 1250.0
    view = parts.window.canvas
    view.extras.actions["forces"].trigger()
    item = view.extras.overlays.items["forces"]
    c.set_frame(30)
    qtbot.waitUntil(lambda: any("torque" in r for r in item.records), timeout=20000)
    text = next(r["torque"] for r in item.records if "torque" in r)
    assert text == f"barrel: F = {res.driver.values[30]:.4g} N"
