"""The Design dock (issue 22 item 6, issue 25), driven as a user: targets clicked, drawn and picked
from an underlay on the canvas, read from CSV or typed; Design and Cancel; a candidate chosen,
previewed and inserted; requirement forms, their reports, refusals and relaxations. The worker's
signals are waited on (no sleeping). The results are checked against independent references:

- a reachable path (a known four-bar's coupler curve, moved, turned, scaled): the inserted
  candidate's coupler curve, swept densely by the solver, passes through every target point;
- 3 poses and 3 function pairs: the solver puts the candidate's coupler through the poses and its
  output through the pairs (exact synthesis);
- the Geneva drive's crank radius A·sin(π/z) (its textbook kinematics), the elliptic gears' pitch
  curves against the focal ellipse r = A(1 − e²)/(1 − e·cos θ);
- exports read back with ezdxf (audit clean, millimetres, one layer per link).
"""
from __future__ import annotations

import math
import os

import ezdxf
import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt

from mechsketch.core.design import families as F
from mechsketch.core.design.atlas import forget_loaded, load_atlas
from mechsketch.core.io.scene_file import element_problems
from mechsketch.core.model.geneva import Geneva
from mechsketch.core.solver.dimensions import dimensions
from mechsketch.core.solver.plan import compile_plan

from app_fakes import shell  # noqa: F401 - fixture
from canvas_user import User
from test_study_dock import type_cell

ATLAS_DESIGNS = 2000


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    """A small four-bar atlas in a temporary cache folder (no test touches the user's cache)."""
    folder = tmp_path_factory.mktemp("atlas")
    old = {k: os.environ.get(k) for k in ("MECHSKETCH_CACHE_DIR", "MECHSKETCH_ATLAS_DESIGNS")}
    os.environ["MECHSKETCH_CACHE_DIR"] = str(folder)
    os.environ["MECHSKETCH_ATLAS_DESIGNS"] = str(ATLAS_DESIGNS)
    forget_loaded()
    load_atlas("fourbar")
    yield folder
    forget_loaded()
    for k, v in old.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


@pytest.fixture
def design(shell, qtbot):  # noqa: F811
    """A new, empty document with the Design dock in front: (parts, panel, layer, user)."""
    parts = shell()
    w = parts.window
    w.actions["new"].trigger()
    dock = w.docks["design"]
    dock.show()
    dock.raise_()
    panel = w.design_docks.design
    qtbot.waitUntil(panel.isVisible, timeout=5000)
    w.canvas.zoom_to_rect(w.canvas.mapToScene(w.canvas.viewport().rect()).boundingRect().adjusted(0, 0, 0, 0))
    return parts, panel, w.canvas.design_layer, User(qtbot, w.canvas)


def choose(panel, mode: str) -> None:
    panel.mode_box.setCurrentIndex(panel.mode_box.findData(mode))


def run(qtbot, panel, timeout: int = 240_000):
    """Press Design and wait for the worker to end."""
    with qtbot.waitSignal(panel.runner.busyChanged, timeout=timeout, check_params_cb=lambda busy: not busy):
        qtbot.mouseClick(panel.run_button, Qt.MouseButton.LeftButton)
    return panel.result


def click(qtbot, button) -> None:
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)


def reachable(n: int = 24) -> np.ndarray:
    """A four-bar's coupler curve, moved, turned and scaled: (n, 2) mm."""
    x = np.array([0, 0, 100, 0, 35, 110, 90, 60, 35.0])
    th = np.linspace(0.3, 0.3 + 2 * math.pi, n, endpoint=False)
    P = 0.7 * np.exp(1.2j) * F.evaluate("fourbar", x[None], th[None], 1.0).P[0] + (60 - 20j)
    return np.column_stack([P.real, P.imag])


def distance_to_curve(linkage, pts: np.ndarray, joint: str = "P") -> np.ndarray:
    """Each point's distance (mm) to the polyline of ``joint`` over a dense sweep by the solver."""
    c = compile_plan(linkage).sweep(7200, order=0, joints=[joint]).position(joint)
    a, b = c, np.roll(c, -1, axis=0)
    d = b - a
    out = []
    for p in pts:
        t = np.clip(((p - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0, 1)
        q = a + t[:, None] * d
        out.append(np.min(np.hypot(*(q - p).T)))
    return np.array(out)


def test_a_path_from_csv_gives_candidates_that_trace_it_and_one_inserts_and_exports(design, qtbot, atlas, tmp_path):
    parts, panel, layer, _user = design
    ctl = parts.controller
    pts = reachable()
    csv = tmp_path / "path.csv"
    csv.write_text("x,y\n" + "\n".join(f"{x:.17g},{y:.17g}" for x, y in pts))
    parts.dialogs.open_names.append(str(csv))
    click(qtbot, panel.findChild(type(panel.run_button), "designCsv"))
    assert panel.target.widget.rowCount() == len(pts) and panel.closed.isChecked(), panel.status.text()
    assert layer.target.isVisible() and np.allclose(layer.target.points, pts, atol=1e-4)
    panel.count.setValue(3)
    result = run(qtbot, panel)
    assert result is not None and 1 <= panel.candidates.count() <= 3
    best = panel.candidates.candidates[0]
    size = float(np.hypot(*np.ptp(pts, axis=0)))
    assert np.max(distance_to_curve(best.linkage, pts)) <= 1e-4 * size
    for k, c in enumerate(panel.candidates.candidates):          # the list shows the core's numbers
        text = panel.candidates.item(k).text()
        assert f"max deviation {c.deviation:.3g} mm" in text and f"μmin {c.min_transmission_deg:.1f}°" in text
        assert not panel.candidates.item(k).icon().isNull()
    # choosing a candidate previews it, animated, over the target
    panel.candidates.setCurrentRow(panel.candidates.count() - 1)
    chosen = panel.candidates.candidates[-1]
    assert layer.ghost.linkage is chosen.linkage and layer.timer.isActive()
    f0 = layer.ghost.frame
    layer.tick()
    assert layer.ghost.frame == (f0 + 1) % layer.ghost.frames
    assert ctl.undo_stack.count() == 1 or ctl.undo_stack.count() == 0    # New cleared it; nothing added yet
    count = ctl.undo_stack.count()
    # Insert: an ordinary linkage, one undo step, its dimension table in Properties
    panel.candidates.setCurrentRow(0)
    click(qtbot, panel.insert_button)
    assert ctl.undo_stack.count() == count + 1 and "path_1" in ctl.scene.ids
    new = ctl.scene.element("path_1")
    assert new.joints == best.linkage.joints and not element_problems(new)
    assert ctl.result("path_1").error is None and layer.ghost.linkage is None and not layer.timer.isActive()
    table = parts.window.properties.tables["dimensions"]
    assert table.rowCount() == len(dimensions(new))
    # export, read back
    parts.dialogs.save_names.append(str(tmp_path / "path_1.dxf"))
    with qtbot.waitSignal(parts.window.exporter.finished, timeout=60_000):
        parts.window.actions["export_dxf"].trigger()
    doc = ezdxf.readfile(tmp_path / "path_1.dxf")
    assert doc.header["$INSUNITS"] == 4 and not doc.audit().has_errors
    assert {"crank", "coupler", "rocker"} <= {layer_.dxf.name for layer_ in doc.layers}
    parts.window.actions["undo"].trigger()
    assert "path_1" not in ctl.scene.ids


def test_three_typed_poses_give_exact_four_bars(design, qtbot):
    parts, panel, layer, _user = design
    choose(panel, "motion")
    poses = [(0.0, 0.0, 0.0), (40.0, 10.0, 20.0), (70.0, 40.0, 45.0)]
    t = panel.target.widget
    for r, pose in enumerate(poses):
        click(qtbot, panel.findChild(type(panel.run_button), "designAddRow"))
        for c, v in enumerate(pose):
            type_cell(qtbot, t, r, c, f"{v:g}")
    assert layer.target.angles is not None and np.allclose(layer.target.angles, [p[2] for p in poses])
    panel.count.setValue(2)
    result = run(qtbot, panel)
    assert result.candidates
    target = np.array(poses)
    for c in result.candidates:
        sol = compile_plan(c.linkage).evaluate(c.inputs_rad, order=0, joints=["P"])
        assert np.max(np.hypot(*(sol.position("P") - target[:, :2]).T)) <= 1e-9 * 100
        turn = np.degrees(sol.angle("coupler") - sol.angle("coupler")[0])
        assert np.max(np.abs(np.remainder(turn - target[:, 2] + 180, 360) - 180)) <= 1e-7
        assert c.deviation <= 1e-9 * 100 and c.angle_deviation <= 1e-7


def test_three_function_pairs_give_exact_four_bars(design, qtbot):
    parts, panel, _layer, _user = design
    choose(panel, "function")
    assert not panel.click_button.isEnabled() and panel.output_unit.isVisible()
    pairs = [(0.0, 0.0), (60.0, 20.0), (120.0, 45.0)]
    panel.target.set_rows(np.array(pairs))
    panel.count.setValue(2)
    result = run(qtbot, panel)
    assert result.candidates
    for c in result.candidates:
        sol = compile_plan(c.linkage).evaluate(c.inputs_rad, order=0)
        out = np.degrees(sol.angle("output") - sol.angle("output")[0])
        assert np.max(np.abs(np.remainder(out - [p[1] for p in pairs] + 180, 360) - 180)) <= 1e-8
        assert np.degrees(np.remainder(c.inputs_rad - c.inputs_rad[0], 2 * math.pi)) == \
            pytest.approx([p[0] for p in pairs], abs=1e-8) or \
            np.degrees(np.remainder(c.inputs_rad[0] - c.inputs_rad, 2 * math.pi)) == pytest.approx(
                [p[0] for p in pairs], abs=1e-8)


def test_clicked_drawn_and_underlay_targets_fill_the_table(design, qtbot, tmp_path):
    parts, panel, layer, user = design
    canvas = parts.window.canvas
    canvas.snap_action.trigger()                       # F9: snapping off, the points are where clicked
    assert not canvas.snap_enabled
    click(qtbot, panel.click_button)
    clicks = [(0, 0), (40, 5), (60, 30), (45, 60), (10, 55), (-10, 30), (-5, 10)]
    placed = []
    for xy in clicks:
        user.click(xy)
        p = canvas.mapToScene(user.at(xy))
        placed.append((p.x(), p.y()))
    assert layer.target.isVisible() and len(layer.target.points) == len(clicks)
    assert panel.target.widget.rowCount() == 0                      # the table waits for Enter
    qtbot.keyClick(canvas.viewport(), Qt.Key.Key_Backspace)         # the last point goes
    assert len(layer.target.points) == len(clicks) - 1
    qtbot.keyClick(canvas.viewport(), Qt.Key.Key_Return)
    rows = panel.target.rows()
    assert rows.shape[0] == len(clicks) - 1 and np.allclose(rows[:, :2], placed[:-1], atol=1e-4)
    # Esc: a second session leaves the table as it is
    click(qtbot, panel.click_button)
    user.click((100, 100))
    qtbot.keyClick(canvas.viewport(), Qt.Key.Key_Escape)
    assert np.array_equal(panel.target.rows(), rows) and "cancelled" in panel.status.text()
    # freehand: a loop drawn with the button held becomes 40 points along it, closed
    panel.closed.setChecked(False)
    click(qtbot, panel.draw_button)
    ring = [(50 + 40 * math.cos(a), 40 * math.sin(a)) for a in np.linspace(0, 2 * math.pi * 0.98, 80)]
    user.press(ring[0])
    for xy in ring[1:]:
        qtbot.mouseMove(canvas.viewport(), user.at(xy))
    user.release(ring[-1])
    drawn = panel.target.rows()[:, :2]
    r = np.hypot(drawn[:, 0] - 50, drawn[:, 1])
    px = canvas.px()
    assert len(drawn) == 40 and panel.closed.isChecked() and np.all(np.abs(r - 40) <= 3 * px)
    steps = np.hypot(*np.diff(np.vstack([drawn, drawn[:1]]), axis=0).T)
    assert steps.max() <= 1.05 * steps.min()
    # an underlay's polyline: a 120 x 60 rectangle picked by a click on its edge
    doc = ezdxf.new(units=4)
    doc.modelspace().add_lwpolyline([(200, -100), (320, -100), (320, -40), (200, -40)], close=True)
    doc.saveas(tmp_path / "frame.dxf")
    parts.dialogs.open_names.append(str(tmp_path / "frame.dxf"))
    parts.window.actions["import_underlay"].trigger()
    qtbot.keyClick(canvas.viewport(), Qt.Key.Key_Escape)            # keep its placement as it is
    canvas.zoom_to_fit()
    click(qtbot, panel.underlay_button)
    user.click((260.0, -100.0 + 2 * canvas.px()))                   # near the bottom edge
    got = panel.target.rows()[:, :2]
    x, y = got[:, 0], got[:, 1]
    edge = np.minimum.reduce([np.abs(x - 200), np.abs(x - 320), np.abs(y + 100), np.abs(y + 40)])
    assert len(got) == 40 and panel.closed.isChecked() and np.max(edge) <= 1e-9
    assert np.all((x >= 200 - 1e-9) & (x <= 320 + 1e-9) & (y >= -100 - 1e-9) & (y <= -40 + 1e-9))


def test_bad_targets_are_refused_with_what_to_add_and_nothing_runs(design, qtbot):
    parts, panel, _layer, _user = design
    panel.target.set_rows(np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]]))
    assert panel.run() is False and not panel.runner.busy
    assert "needs at least 6 points" in panel.status.text()
    panel.target.set_rows(np.array([[0, 0, 0], [10, 0, 0], [10, 0, 0], [5, 5, 0], [0, 9, 0], [-3, 4, 0.0]]))
    assert panel.run() is False and "the same point" in panel.status.text()
    type_cell(qtbot, panel.target.widget, 1, 1, "abc")
    assert panel.run() is False and "target row 2" in panel.status.text() and "is not a number" in panel.status.text()
    choose(panel, "motion")
    panel.target.set_rows(np.array([[0, 0, 0], [10, 0, 0], [20, 0, 0.0]]))
    assert panel.run() is False and "translation along a line" in panel.status.text()
    assert parts.controller.undo_stack.count() == 0


def test_cancel_stops_a_synthesis_and_changes_nothing(design, qtbot, atlas):
    parts, panel, layer, _user = design
    panel.target.set_points(reachable())
    before = parts.controller.scene
    with qtbot.waitSignal(panel.runner.busyChanged, timeout=240_000, check_params_cb=lambda busy: not busy):
        with qtbot.waitSignal(panel.runner.started, timeout=5000):
            click(qtbot, panel.run_button)
        click(qtbot, panel.cancel_button)
    assert panel.result is None and "cancelled" in panel.status.text()
    assert parts.controller.scene is before and not panel.candidates.isVisible() and layer.ghost.linkage is None


def test_a_geneva_drive_from_requirements_relaxed_then_inserted(design, qtbot):
    parts, panel, _layer, _user = design
    ctl = parts.controller
    choose(panel, "geneva")
    form = panel.geneva
    form.edits["max_center_distance"].setText("40")
    assert run(qtbot, panel) is None
    assert "refused" in panel.status.text() and panel.report.title.text().startswith("Refused: ")
    (relax,) = [b for b in panel.report.relax_buttons if b.objectName() == "relax:max_center_distance"]
    click(qtbot, relax)
    assert form.edits["max_center_distance"].text() == "183.3"
    res = run(qtbot, panel)
    el = res.element
    assert isinstance(el, Geneva) and el.center_distance == pytest.approx(183.3)
    assert el.crank_radius == pytest.approx(el.center_distance * math.sin(math.pi / 6), rel=1e-12)
    rows = {panel.report.table.item(r, 0).text(): r for r in range(panel.report.table.rowCount())}
    binding = [k for k in rows if k.endswith("← binding")]
    assert len(binding) == 1 and binding[0].startswith(res.report.binding.name)
    r = rows["max_center_distance"]
    assert panel.report.table.item(r, 1).text() == "183.3 mm" and panel.report.table.item(r, 2).text() == "<= 183.3 mm"
    click(qtbot, panel.insert_button)
    assert ctl.undo_stack.count() == 1 and ctl.scene.element("geneva") == el and not element_problems(el)
    assert ctl.selection == [("geneva", "element", "geneva")] and ctl.element_result("geneva").n_frames > 0


def test_a_rolling_lever_law_and_elliptic_gears_from_requirements(design, qtbot):
    parts, panel, _layer, _user = design
    ctl = parts.controller
    choose(panel, "rolling")
    assert panel.rolling.base.currentText().startswith("the press example")
    panel.rolling.law.setCurrentText("constant")
    res = run(qtbot, panel)
    assert res is not None and res.element.slider_law is not None, panel.status.text()
    click(qtbot, panel.insert_button)
    lever = ctl.scene.element("lever")
    assert lever.slider_law == res.element.slider_law and ctl.element_result("lever").error is None
    choose(panel, "gears")
    assert panel.gears.function.currentText() == "elliptic"
    panel.gears.edits["function.elliptic.eccentricity"].setText("0.3")
    res = run(qtbot, panel)
    assert res is not None, panel.status.text()
    click(qtbot, panel.insert_button)
    assert ctl.undo_stack.count() == 2
    gears = ctl.element_result("gears")
    A, e = 50.0, 0.3
    c = gears.input_curve
    r, th = np.hypot(*c.T), np.arctan2(c[:, 1], c[:, 0])
    assert np.max(np.abs(r - A * (1 - e * e) / (1 - e * np.cos(th)))) <= 1e-9 * A
    # placed beside the lever, not on it
    lever_right = max(p[0] for p in (lever.lever_circle.center, lever.pin, lever.rocker_pivot))
    assert gears.input_center[0] > lever_right
