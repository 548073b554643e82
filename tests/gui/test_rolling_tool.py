"""Drawing a rolling lever with the canvas tool and reshaping it by its handles, as a user would."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QRectF

from canvas_user import example, make_view
from app_fakes import shell  # noqa: F401 - fixture
from mechsketch.core.analyses.rolling.synthesis import synthesize

WINDOW = QRectF(-170.0, -110.0, 320.0, 230.0)
# the notes' example 5: R1 = 50 about (0, 0), pin (60, −20), pivot (−150, −40), R2 = 80 about (20, 0)
CLICKS = [(0, 0), (50, 0), (60, -20), (-150, -40), (20, 0), (100, 0), (60, 0)]


def _draw(user, clicks=CLICKS):
    user.tool("rolling")
    for p in clicks:
        user.click(p)


def test_seven_clicks_make_the_notes_rolling_lever_with_a_stroke_in_its_working_range(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user)
    (el,) = ctl.scene.elements
    press = example("rolling_lever_press").elements[0]
    assert el.type == "rolling_lever" and ctl.undo_stack.count() == 1
    assert el.lever_circle == press.lever_circle and el.slider_circle == press.slider_circle
    assert el.pin == press.pin and el.rocker_pivot == press.rocker_pivot
    assert el.slider_axis_deg == 0.0 and el.contact_branch == "near" and el.slider_side == 1
    res = ctl.element_result(el.id)
    assert res.ok, res.error
    wr = res.synthesis.working_range
    assert el.stroke.start == 0.0 and wr.lower < el.stroke.end < wr.upper
    assert "working range" in view.messages[-1]
    # the canvas shows the core's synthesis: the same profile, and P is the instant centre
    ref = synthesize(el)
    np.testing.assert_array_equal(res.synthesis.P, ref.P)
    fr = res.frames
    G = np.asarray(el.rocker_pivot)
    e = fr.F - G
    cross = e[:, 0] * (fr.P - G)[:, 1] - e[:, 1] * (fr.P - G)[:, 0]
    assert np.max(np.abs(cross) / np.linalg.norm(e, axis=1)) < 1e-8     # P on the rocker line G-F
    view.grab()


def test_the_working_range_is_shown_once_the_pivot_is_placed(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user, CLICKS[:4])
    user.move((30, 30))
    tool = view.toolbox.tool
    lo, hi = tool._range
    assert lo < -0.59 < 0 < hi
    assert any("working range" in text for _, text in tool.overlay().labels)


def test_a_rocker_line_missing_the_lever_circle_is_explained_and_not_placed(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user, CLICKS[:3] + [(60, 100)])   # the vertical x = 60 passes 10 mm outside R1 = 50
    assert "misses the lever circle" in view.messages[-1]
    assert len(view.toolbox.tool._pts) == 3 and ctl.scene.elements == ()


def test_dragging_the_rocker_pivot_resynthesises_live_without_the_slip_report_then_one_undo_step(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user)
    eid = ctl.scene.ids[0]
    user.tool("select")
    names = {h.name for h in view.extras.handles.handles()}
    assert {"lever_centre", "lever_radius", "pin", "pivot", "slider_centre", "slider_radius", "axis"} <= names
    count = ctl.undo_stack.count()
    user.drag((-150, -40), (-140, -50), steps=3, release=False)
    live = ctl.element_result(eid)
    assert ctl.scene.element(eid).rocker_pivot == (-140.0, -50.0) and live.ok
    assert live.synthesis.slip is None                      # previews skip the 50 ms slip report
    user.release((-140, -50))
    res = ctl.element_result(eid)
    assert res.synthesis.slip is not None and ctl.undo_stack.count() == count + 1
    ctl.undo_stack.undo()
    assert ctl.scene.element(eid).rocker_pivot == (-150.0, -40.0)


def test_the_lever_radius_handle_maps_back_to_the_drawn_pose(qtbot):
    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user)
    eid = ctl.scene.ids[0]
    user.tool("select")
    h = next(h for h in view.extras.handles.handles() if h.name == "lever_radius")
    view.snap_enabled = False
    d = (h.at[0] / 50.0, h.at[1] / 50.0)          # frame 0 is the drawn pose (stroke from 0)
    user.drag(h.at, (55.0 * d[0], 55.0 * d[1]), steps=3)
    assert ctl.scene.element(eid).lever_circle.radius == pytest.approx(55.0, abs=0.4)   # one pixel: 0.35 mm
    assert math.isfinite(ctl.element_result(eid).synthesis.slip.continuous.slip_d)


def test_matching_marks_on_both_bodies_meet_at_the_contact_as_the_lever_rolls(qtbot):
    from PySide6.QtCore import QPointF

    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user)
    eid = ctl.scene.ids[0]
    item = view.element_items[eid]
    res = ctl.element_result(eid)
    syn, fr = res.synthesis, res.frames

    def mid(path, i):
        a, b = path.elementAt(2 * i), path.elementAt(2 * i + 1)
        return QPointF((a.x + b.x) / 2, (a.y + b.y) / 2)

    n_ticks = item.paths["lever_ticks"].path().elementCount() // 2
    assert n_ticks == item.paths["frame_ticks"].path().elementCount() // 2 >= 10
    for frame, tick in ((0, 0), (len(fr) // 2, n_ticks - 1)):      # stroke start and end (cosine law)
        ctl.set_frame(frame)
        lever = item.lever.transform().map(mid(item.paths["lever_ticks"].path(), tick))
        ground = mid(item.paths["frame_ticks"].path(), tick)
        assert (lever.x(), lever.y()) == pytest.approx((ground.x(), ground.y()), abs=1e-6)
        slider = item.slider.transform().map(mid(item.paths["slider_ticks"].path(), tick))
        arc = item.lever.transform().map(mid(item.paths["slider_arc_ticks"].path(), tick))
        assert (slider.x(), slider.y()) == pytest.approx((arc.x(), arc.y()), abs=1e-6)
    assert syn.theta[-1] == pytest.approx(fr.theta[len(fr) // 2])


def test_methods_side_by_side_in_the_properties_show_the_cores_slip_measures(shell):
    from app_fakes import open_example
    from mechsketch.core.analyses.rolling.synthesis import error_table
    from PySide6.QtWidgets import QPushButton, QTableWidget

    parts, ctl, view = open_example(shell, "rolling_lever_press")
    ctl.set_selection([("press", "element", "press")])
    props = parts.window.properties
    button = props.findChild(QPushButton, "compare:press")
    table = props.findChild(QTableWidget, "comparison:press")
    button.click()
    cols = [table.horizontalHeaderItem(j).text() for j in range(3)]
    assert cols == ["exact", "corrected", "paper"]
    rows = error_table(ctl.scene.element("press"), ns=(200,), methods=tuple(cols), repeat=1)
    labels = [table.verticalHeaderItem(i).text() for i in range(table.rowCount())]
    i = labels.index("kinematic slip, points (mm)")
    for j, row in enumerate(rows):
        assert float(table.item(i, j).text()) == pytest.approx(row.kinematic_slip, rel=1e-3)
    # the paper's construction levels off near a millimetre; the exact motion slides ~1e-10 mm
    assert float(table.item(i, 2).text()) > 0.5
    k = labels.index("slip of the motion (mm)")
    assert float(table.item(k, 0).text()) < 1e-8 and table.item(k, 1).text() == "—"


def test_handles_of_a_lever_that_cannot_be_synthesised_still_drag_back_to_a_good_one(qtbot):
    """A lever whose stroke leaves the working range draws only its note; its handles still work."""
    from dataclasses import replace as dc_replace

    from mechsketch.core.model.edits import ReplaceElement
    from mechsketch.core.model.rolling_lever import Stroke

    ctl, view, user = make_view(qtbot, window=WINDOW)
    _draw(user)
    eid = ctl.scene.ids[0]
    bad = dc_replace(ctl.scene.element(eid), stroke=Stroke(0.0, -3.0))      # far beyond the range
    assert ctl.push(ReplaceElement(bad, "too long a stroke"))
    assert ctl.element_result(eid).frames is None
    user.tool("select")
    ctl.set_selection([(eid, "element", eid)])
    names = {h.name for h in view.extras.handles.handles()}
    assert "pivot" in names and "axis" in names
    user.drag((-150, -40), (-140, -40), steps=2)          # still impossible: explained, nothing raised
    assert ctl.scene.element(eid).rocker_pivot == (-150.0, -40.0)
    assert "impossible" in " ".join(view.messages[-3:]) or "kept as it was" in view.messages[-1]
