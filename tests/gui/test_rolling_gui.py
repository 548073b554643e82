"""Rolling levers in the app: opened from the Examples menu, drawn from the synthesis, animated
from the drive's frames, edited in the properties panel, summarised and plotted."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from PySide6.QtCore import QPointF
from PySide6.QtGui import QPainterPath

from mechsketch.core import ReplaceElement, Workspace
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.cli import rolling_cmds
from mechsketch.core.model.rolling_lever import RollingLever

from app_fakes import play_ticks, shell  # noqa: F401 - fixture
from app_fakes import patch_everywhere, type_into as _type, open_example as _open


def _dense(item, n=2000):
    """(n, 2) scene points along a path item's path."""
    path = item.path()
    return np.array([[q.x(), q.y()] for q in (item.mapToScene(path.pointAtPercent(float(t)))
                                               for t in np.linspace(0, 1, n))])


@pytest.mark.parametrize("name", ["rolling_lever_press", "rolling_lever_inclined"])
def test_opening_an_example_draws_profiles_lever_and_slider(shell, name):
    parts, c, view = _open(shell, name)
    el = c.scene.elements[0]
    assert isinstance(el, RollingLever)
    res = synthesize(el, measures=False)
    item = view.element_items[el.id]
    assert {"frame_profile", "bicentrode", "lever_plate", "lever_arc", "slider_arc", "slider_profile"} <= set(item.paths)
    # the frame profile is the fixed centrode: it passes through every synthesised contact P_k
    prof = _dense(item.paths["frame_profile"], 4000)
    gap = np.min(np.linalg.norm(prof[None, :, :] - res.P[::20, None, :], axis=2), axis=1)
    assert gap.max() < 0.05
    box = item.paths["frame_profile"].path().boundingRect()     # static: item = scene coordinates
    assert box.left() == pytest.approx(res.P[:, 0].min(), abs=1e-3)
    assert box.right() == pytest.approx(res.P[:, 0].max(), abs=1e-3)
    # the lever's working arcs are curves on their circles (lever frame), over the stroke's u1, u2
    c.set_frame(0)
    arc = item.paths["lever_arc"]
    kinds = [arc.path().elementAt(k).type for k in range(arc.path().elementCount())]
    assert QPainterPath.ElementType.CurveToElement in kinds and len(kinds) < 40
    local = np.array([[p.x(), p.y()] for p in (arc.path().pointAtPercent(float(t)) for t in np.linspace(0, 1, 200))])
    lc = el.lever_circle
    assert np.hypot(local[:, 0] - lc.center[0], local[:, 1] - lc.center[1]) == pytest.approx(lc.radius, abs=1e-7 * lc.radius)
    ends = np.degrees(np.arctan2(local[[0, -1], 1] - lc.center[1], local[[0, -1], 0] - lc.center[0]))
    assert sorted(ends) == pytest.approx(sorted(np.degrees([res.u1.min(), res.u1.max()])), abs=1e-6)
    # the slider profile sits on the pair-E contact P0 at the current frame
    fr = c.element_result(el.id).frames
    k = item.index
    sp = _dense(item.paths["slider_profile"])
    assert np.min(np.linalg.norm(sp - fr.P0[k], axis=1)) < 0.05
    assert view.mapToScene(view.viewport().rect()).boundingRect().contains(item.extent())


def test_playing_moves_the_lever_and_slider_by_the_drives_frames(shell, qtbot, monkeypatch):
    parts, c, view = _open(shell, "rolling_lever_press")
    el = c.scene.element("press")
    res = synthesize(el, measures=False)
    item = view.element_items["press"]
    n = c.sample_count()
    assert n == max(2 * el.points, 360) == item.n_frames

    def boom(*a, **k):
        raise AssertionError("the animation solved something")
    patch_everywhere(monkeypatch, synthesize, boom)
    frames = []
    c.frameChanged.connect(frames.append)
    play_ticks(parts.window.player, ticks=3)            # three timer ticks on a fake clock: no waiting
    assert len(frames) == 3 and c.frame > 0
    d = res.drive
    for k in (c.frame, 0, 57, n // 2, n - 1):
        c.set_frame(k)
        m = d.frames(np.array([d.phi_folded + 2 * math.pi * k / n]))   # the core, independently
        assert math.remainder(item.lever_rotation() - m.theta[0], 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        # the pin f of the lever's own frame lands on the mechanism's F
        f = item.lever.mapToScene(QPointF(*el.pin))
        assert (f.x(), f.y()) == pytest.approx(tuple(m.F[0]), abs=1e-9)
        s5 = m.S5[0]
        assert item.slider_offset() == pytest.approx((s5 * el.slider_axis[0], s5 * el.slider_axis[1]), abs=1e-9)
    c.set_frame(0)
    assert item.lever_rotation() == pytest.approx(d.theta_folded, abs=1e-9)
    assert "lever θ" in parts.window.frame_label.text()


def test_a_stroke_edit_and_the_method_are_one_undo_step_each(shell, qtbot):
    parts, c, view = _open(shell, "rolling_lever_press")
    props, w = parts.window.properties, parts.window
    assert props.fields["stroke.to"].text() == "-0.5926" and props.fields["lever_circle.radius"].text() == "50"
    before = c.scene
    _type(qtbot, props.fields["stroke.to"], "-0.5")
    assert c.scene.element("press").stroke.end == -0.5
    assert c.undo_stack.count() == 1 and c.undo_stack.undoText() == "set stroke end of press"
    assert view.element_items["press"].result.element.stroke.end == -0.5
    props.combos["method"].activated.emit(props.combos["method"].findData("paper"))
    assert c.scene.element("press").method == "paper" and c.undo_stack.count() == 2
    assert "levels off" in w.diagnostics.plain_text()
    w.actions["undo"].trigger()
    w.actions["undo"].trigger()
    assert c.scene == before and props.fields["stroke.to"].text() == "-0.5926"
    assert props.combos["method"].currentData() == "exact"
    w.actions["redo"].trigger()
    assert c.scene.element("press").stroke.end == -0.5
    _type(qtbot, props.fields["pin.0"], "62")
    assert c.scene.element("press").pin == (62.0, -20.0) and c.undo_stack.count() == 2


@pytest.mark.parametrize("field, text, says", [
    ("stroke.to", "-2", "goes beyond the working range"),
    ("stroke.to", "0", "the stroke is empty"),
    ("lever_circle.radius", "5", "misses the lever circle"),
    ("points", "1.5", "whole number"),
])
def test_an_invalid_edit_is_refused_with_the_cores_message(shell, qtbot, field, text, says):
    parts, c, _ = _open(shell, "rolling_lever_press")
    props = parts.window.properties
    before, shown = c.scene, props.fields[field].text()
    _type(qtbot, props.fields[field], text)
    assert c.scene is before and c.undo_stack.count() == 0 and not c.is_dirty
    assert says in parts.window.statusBar().currentMessage()
    assert props.fields[field].text() == shown


def test_diagnostics_show_the_synthesize_summary(shell):
    parts, c, _ = _open(shell, "rolling_lever_inclined")
    text = " ".join(parts.window.diagnostics.plain_text().split())
    cli = rolling_cmds.synthesize(Workspace(c.scene), "inclined").summary   # a workspace of its own
    timed = ("time:", "(measures computed in")
    for line in cli.splitlines():
        if not line.strip().startswith(timed):
            assert " ".join(line.split()) in text


def test_plots_show_alpha_k53_s5_and_the_slip_against_theta(shell):
    parts, c, _ = _open(shell, "rolling_lever_press")
    plots = parts.window.plots
    res = c.element_result("press").synthesis
    assert set(plots.curves) == {"α", "k53", "S5", "slip pair D", "slip pair E"}
    x, y = plots.curves["k53"].getData()
    assert np.allclose(x, np.degrees(res.theta)) and np.allclose(y, res.k53)
    assert np.allclose(plots.curves["S5"].getData()[1], res.S5)
    # the slip plot ends at the figure the synthesis reports (the computed motion's slip, ~1e-11 mm
    # for the exact method), not at a GUI re-derived chord sum (3.8e-5 mm at N = 200)
    slip = plots.curves["slip pair D"].getData()[1]
    assert slip[-1] == res.slip.continuous.slip_d < 1e-9
    assert plots.curves["slip pair E"].getData()[1][-1] == res.slip.continuous.slip_e
    fr = c.element_result("press").frames
    c.set_frame(123)
    assert plots.cursor_x() == pytest.approx(math.degrees(fr.theta[123]))


def test_without_a_drive_the_lever_runs_the_stroke_there_and_back(shell):
    parts, c, view = _open(shell, "rolling_lever_inclined")
    props = parts.window.properties
    assert "drive.crank_pivot.0" in props.fields
    el = replace(c.scene.element("inclined"), drive=None)
    assert c.push(ReplaceElement(el, "remove the drive"))
    assert "drive.crank_pivot.0" not in props.fields                 # the panel follows the element
    fr = c.element_result("inclined").frames
    n = len(fr)
    assert fr.A is None and n == c.sample_count()
    assert fr.theta[0] == pytest.approx(el.stroke.start) and fr.theta[n // 2] == pytest.approx(el.stroke.end)
    item = view.element_items["inclined"]
    k = n // 4
    c.set_frame(k)
    state, s5 = synthesize(el, measures=False).pose(np.array([fr.theta[k]]))   # the core's exact motion
    f = item.lever.mapToScene(QPointF(*el.pin))
    assert (f.x(), f.y()) == pytest.approx(tuple(state.F[0]), abs=1e-9)
    assert item.lever_rotation() == pytest.approx(fr.theta[k], abs=1e-12)
    assert item.slider_offset() == pytest.approx((s5[0] * el.slider_axis[0], s5[0] * el.slider_axis[1]), abs=1e-9)
