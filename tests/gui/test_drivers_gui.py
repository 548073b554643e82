"""Drivers in the app (issue 10 items 2-4): the excavator arm (a cylinder with a cycloidal stroke)
and the V-engine (a crank with two pins) open, animate, plot and report like any linkage; the
driver box shows the kind, law and stroke and edits them as one undo step; any link pivoted on the
frame, a cylinder or a slider becomes the input with one click; points on the crank are traced."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import Qt

from mechsketch.core import Workspace, load_scene
from mechsketch.core.model.drivers import DriverKind, LawKind
from mechsketch.resources import example_path

from app_fakes import open_example, shell  # noqa: F401 - fixture
from app_fakes import type_into


def test_the_excavator_arm_animates_plots_and_reports(shell, qtbot):
    parts, c, canvas = open_example(shell, "excavator_arm")
    failed = []
    c.solveFailed.connect(lambda eid, msg: failed.append(msg))
    res = c.result("arm")
    assert res.error is None and res.solution.valid.all()
    assert c.sample_count() == 360
    c.set_frame(90)
    text, ok = c.frame_text()
    assert ok and text.startswith("input ") and " mm " in text
    assert float(text.split()[1]) == pytest.approx(res.solution.input[90], abs=0.01)
    # the diagnostics panel shows the core's summary (also what the CLI prints)
    qtbot.waitUntil(lambda: "cylinder between two pivots" in parts.window.diagnostics.text.toPlainText(), timeout=20000)
    assert Workspace.open(example_path("excavator_arm"))["arm"].summary().splitlines()[1] in \
        parts.window.diagnostics.text.toPlainText()
    # the plots of the bucket tip: velocities and accelerations over the stroke
    c.set_selection([("arm", "joint", "K")])
    plots = parts.window.plots
    plots.refresh()
    names = {s.name for s in plots.data.series}
    assert {"K.vx", "K.vy", "K.ax", "K.ay"} <= names
    ax = next(s for s in plots.data.series if s.name == "K.ax").y
    assert np.all(np.isfinite(ax)) and np.max(np.abs(ax)) > 0
    canvas.grab()   # paints without raising
    parts.window.player.step(5)
    assert not failed


def test_the_driver_box_edits_the_law_and_the_stroke(shell, qtbot):
    parts, c, _ = open_example(shell, "excavator_arm")
    props = parts.window.properties
    law = props.combos["law"]
    assert law.currentData() == LawKind.CYCLOIDAL
    law.setCurrentIndex(law.findData(LawKind.MODIFIED_TRAPEZOID))
    law.activated.emit(law.currentIndex())
    assert c.scene.element("arm").driver.law.kind is LawKind.MODIFIED_TRAPEZOID
    assert c.undo_stack.count() == 1
    type_into(qtbot, props.fields["stroke.1"], "1200")
    assert c.scene.element("arm").driver.stroke == (850.0, 1200.0)
    assert c.result("arm").solution.input.max() == pytest.approx(1200.0, abs=1e-9)
    type_into(qtbot, props.fields["stroke.0"], "5000")   # refused: the stroke must increase
    assert c.scene.element("arm").driver.stroke == (850.0, 1200.0)
    assert props.fields["stroke.0"].text() == "850"
    assert c.undo_stack.count() == 2


def test_the_vengine_crank_carries_two_pins_and_a_traced_point(shell, qtbot):
    parts, c, canvas = open_example(shell, "v_engine")
    res = c.result("vengine")
    assert res.error is None and [s.group.kind for s in res.plan.steps] == ["RRP", "RRP"]
    canvas.grab()
    from mechsketch.gui.canvas.view import default_traced
    lk = c.scene.element("vengine")
    ext = lk.with_joint(lk.joint("B1").__class__("T", lk.joint("B1").kind, (10.0, -20.0)))
    ext = ext.with_link(lk.link("crank").__class__("crank", ("A", "B1", "B2", "T")))
    assert "T" in default_traced(ext)   # a point on the crank is traced like a coupler point


@pytest.mark.parametrize("example,kind,ident,want", [
    ("fourbar_crank_rocker", "link", "rocker", DriverKind.CRANK),
    ("inverted_slider_crank", "joint", "Q", DriverKind.CYLINDER),
    ("slider_crank_offset", "joint", "S", DriverKind.SLIDER),
])
def test_any_link_cylinder_or_slider_becomes_the_input_in_one_click(shell, qtbot, example, kind, ident, want):
    parts, c, _ = open_example(shell, example)
    lk = c.scene.elements[0]
    if example == "inverted_slider_crank":   # a plain RPR: block B–Q and rocker C–Q (no traced point)
        from mechsketch.core import ReplaceElement
        c.push(ReplaceElement(lk.without_joint("T")))
        lk = c.scene.elements[0]
    count = c.undo_stack.count()
    c.set_selection([(lk.id, kind, ident)])
    props = parts.window.properties
    qtbot.waitUntil(lambda: "drive" in props.buttons, timeout=20000)
    qtbot.mouseClick(props.buttons["drive"], Qt.MouseButton.LeftButton)
    drv = c.scene.element(lk.id).driver
    assert drv.kind is want and c.undo_stack.count() == count + 1
    res = c.result(lk.id)
    assert res.error is None and res.solution.valid[0]
    parts.window.actions["undo"].trigger()
    assert c.scene.element(lk.id) == lk


def test_the_plots_x_axis_says_what_the_input_is(shell, qtbot):
    parts, c, _ = open_example(shell, "fourbar_crank_rocker")
    plots = parts.window.plots
    plots.refresh()
    bottom = lambda: plots.plots["transmission"].getAxis("bottom").labelText   # noqa: E731
    assert bottom() == "input angle (°)"
    parts.window.actions["example:excavator_arm"].trigger()
    plots.refresh()
    assert bottom() == "input: cylinder length (mm)"
    parts.window.actions["example:v_engine"].trigger()
    plots.refresh()
    assert bottom() == "input angle (°)"


def test_dragging_a_joint_of_the_cylinder_arm_is_one_undo_step(qtbot):
    """At frame 0 the arm shows the start of the stroke (not the drawn length): a dragged joint
    lands where the mouse lets go, the cylinder and the rest re-solve, one undo step."""
    from PySide6.QtCore import QRectF

    from canvas_user import example, make_view
    ctl, view, user = make_view(qtbot, example("excavator_arm"), QRectF(-500, -800, 4200, 2400))
    view.snap_enabled = False
    sol = ctl.result("arm").solution
    k0 = tuple(sol.position("K")[0])
    target = (k0[0] + 150.0, k0[1] - 100.0)
    user.drag(k0, target)
    assert ctl.undo_stack.count() == 1
    res = ctl.result("arm")
    assert res.error is None and res.solution.valid.all()
    got = res.solution.position("K")[ctl.frame]
    assert abs(got[0] - target[0]) < 5.0 and abs(got[1] - target[1]) < 5.0   # within a few pixels
    assert res.element.joint("C1").at == (800.0, -550.0)   # the frame pivot did not move


def test_rebasing_a_slider_driven_linkage_keeps_its_motion():
    """Drawn again at a sample (what a drag at that frame does), a slider driver's stroke, counted
    from its drawn place, moves with it: the rebased linkage sweeps the same poses."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "core"))
    import drive_builders as DB
    from mechsketch.core.solver.plan import compile_plan
    from mechsketch.gui.canvas.pose import SolutionArrays, rebase, shows_drawn

    lk = DB.pushed_crank(kind="cycloidal", stroke=(-20.0, 15.0))
    sol = compile_plan(lk).sweep(120)
    arrays = SolutionArrays(lk, sol, [])
    assert not shows_drawn(arrays, 0)   # the stroke starts 20 mm before the drawn place
    new = rebase(lk, arrays, 0)
    assert new.driver.stroke == (0.0, 35.0)
    again = compile_plan(new).sweep(120)
    for j in ("B", "C", "T"):
        assert np.allclose(again.position(j), sol.position(j), rtol=0, atol=1e-9)
    assert shows_drawn(SolutionArrays(new, again, []), 0)


def test_a_table_law_is_chosen_and_typed_in_the_driver_box(shell, qtbot):
    parts, c, _ = open_example(shell, "excavator_arm")
    props = parts.window.properties
    law = props.combos["law"]
    law.setCurrentIndex(law.findData(LawKind.TABLE))
    law.activated.emit(law.currentIndex())
    drv = c.scene.element("arm").driver
    assert drv.law.kind is LawKind.TABLE and drv.law.points[0] == (0.0, 850.0)
    qtbot.waitUntil(lambda: "law.points" in props.fields, timeout=20000)
    type_into(qtbot, props.fields["law.points"], "0 900; 0.3 1200; 0.6 1000")
    drv = c.scene.element("arm").driver
    assert drv.law.points == ((0.0, 900.0), (0.3, 1200.0), (0.6, 1000.0))
    sol = c.result("arm").solution
    assert sol.input[0] == pytest.approx(900.0, abs=1e-9) and sol.valid.all()
    type_into(qtbot, props.fields["law.points"], "0 900; 0.3")     # not pairs: refused
    assert c.scene.element("arm").driver.law.points == drv.law.points
    assert props.fields["law.points"].text() == "0 900; 0.3 1200; 0.6 1000"
    assert c.undo_stack.count() == 2
