"""Geneva drives in the app: opened from the Examples menu, drawn from the exact geometry, animated
from the kinematics, edited in the properties panel, summarised and plotted."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QPointF, Qt
from PySide6.QtGui import QPainterPath

from mechsketch import resources
from mechsketch.core import Scene, Workspace, load_scene
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.geneva.geometry import geometry
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.cli import geneva_cmds
from mechsketch.core.model.geneva import Geneva
from mechsketch.gui.canvas.geneva_items import ARC_PIECE

from app_fakes import play_ticks, shell  # noqa: F401 - fixture
from app_fakes import patch_everywhere, type_into as _type, open_example as _open


def _subpaths(path):
    """The closed subpaths of a QPainterPath (outer outline first, then the holes), rebuilt."""
    out, k = [], 0
    while k < path.elementCount():
        e = path.elementAt(k)
        if e.isMoveTo():
            out.append(QPainterPath(QPointF(e.x, e.y)))
            k += 1
        elif e.isLineTo():
            out[-1].lineTo(e.x, e.y)
            k += 1
        else:
            c1, c2 = path.elementAt(k + 1), path.elementAt(k + 2)
            out[-1].cubicTo(e.x, e.y, c1.x, c1.y, c2.x, c2.y)
            k += 3
    return out


def _dense(path, n=6000):
    """(n, 2) points along a path (Qt's exact evaluation of its lines and cubics)."""
    return np.array([[q.x(), q.y()] for q in (path.pointAtPercent(float(t)) for t in np.linspace(0, 1, n))])


def _area(xy):
    return 0.5 * abs(np.dot(xy[:-1, 0], xy[1:, 1]) - np.dot(xy[1:, 0], xy[:-1, 1]))


def _wrap(a):
    return math.remainder(a, 2 * math.pi)


@pytest.mark.parametrize("name", ["geneva_z4", "geneva_z6", "geneva_z8"])
def test_opening_an_example_draws_the_exact_wheel_and_driver(shell, name):
    parts, c, view = _open(shell, name)
    el = c.scene.elements[0]
    assert isinstance(el, Geneva)
    item = view.element_items[el.id]
    assert set(item.parts) == {"wheel", "locking_disc", "crank_arm", "roller"}
    d = el.dimensions()
    geo = c.element_result(el.id).geometry
    wheel = item.parts["wheel"]
    path = wheel.path()
    # every arc of the core's outline is a curve (pieces of at most 22.5°), every line one line:
    # no polyline anywhere
    kinds = [path.elementAt(k).type for k in range(path.elementCount())]
    contours = (geo.wheel.outer, *geo.wheel.holes)
    segs = [c.segments() for c in contours]
    pieces = sum(int(np.ceil(abs(t) / ARC_PIECE - 1e-12)) for sg in segs for t in sg.theta[sg.is_arc])
    assert kinds.count(QPainterPath.ElementType.CurveToElement) == pieces
    assert kinds.count(QPainterPath.ElementType.LineToElement) == sum(int((~sg.is_arc).sum()) for sg in segs)
    # the outer outline reaches exactly R_o (the horn lands) about the wheel centre, never beyond
    outer, *holes = _subpaths(path)
    pts = _dense(outer)
    r = np.hypot(pts[:, 0], pts[:, 1])        # the wheel's own frame: centred on its axis
    assert r.max() == pytest.approx(d.outer_radius, abs=1e-4)
    # so its bounding box spans at most 2·R_o, and more than the chord between two slots
    box = path.boundingRect()
    assert box.width() <= 2 * d.outer_radius + 0.05 and box.height() <= 2 * d.outer_radius + 0.05
    assert max(box.width(), box.height()) > 2 * d.outer_radius * math.cos(math.pi / el.slots) - 0.05
    # the drawn wheel's area equals the core's exact area (every arc bulges the right way)
    area = _area(pts) - sum(_area(_dense(h)) for h in holes)
    assert area == pytest.approx(geo.wheel_area, rel=2e-4)
    # the roller (radius r_p about the crank pin at r) and the locking disc with its relief cut
    roller = _dense(_subpaths(item.parts["roller"].path())[0])
    assert np.hypot(roller[:, 0] - d.crank_radius, roller[:, 1]) == pytest.approx(el.roller_radius, abs=1e-6)
    disc = _dense(_subpaths(item.parts["locking_disc"].path())[0])
    on_disc = np.isclose(np.hypot(disc[:, 0], disc[:, 1]), d.lock_disc_radius, atol=1e-6)
    on_relief = np.isclose(np.hypot(disc[:, 0] - d.center_distance, disc[:, 1]), geo.relief.drawn, atol=1e-6)
    assert np.all(on_disc | on_relief) and on_relief.sum() > 10
    # placed in the world: the centre of the drawn outline is the wheel centre
    world = wheel.mapToScene(outer.boundingRect()).boundingRect().center()
    assert (world.x(), world.y()) == pytest.approx(geo.wheel_center, abs=0.5 * d.outer_radius)
    # the canvas is fitted to the whole drive when the example opens
    assert view.mapToScene(view.viewport().rect()).boundingRect().contains(item.extent())


def test_playing_turns_the_crank_and_the_wheel_by_the_kinematics(shell, qtbot, monkeypatch):
    parts, c, view = _open(shell, "geneva_z6")
    el = c.scene.element("indexer")
    kin = kinematics(el, el.samples)
    item = view.element_items["indexer"]
    player = parts.window.player
    assert c.sample_count() == el.samples == 3600

    def boom(*a, **k):
        raise AssertionError("the animation solved something")
    for func in (kinematics, contact, geometry):
        patch_everywhere(monkeypatch, func, boom)
    frames = []
    c.frameChanged.connect(frames.append)
    play_ticks(player, ticks=3)            # three timer ticks on a fake clock: no waiting
    assert len(frames) == 3 and c.frame > 0
    direction = math.radians(el.wheel_direction_deg)
    for k in (c.frame, 0, 1500, 1799, 1800, 2399, 3000):
        c.set_frame(k)
        assert item.index == k
        assert _wrap(item.wheel_rotation() - direction - kin.wheel_angle[k]) == pytest.approx(0.0, abs=1e-9)
        assert _wrap(item.crank_rotation() - direction - kin.phi[k]) == pytest.approx(0.0, abs=1e-9)
    # the dwell holds the wheel still while the crank turns
    c.set_frame(100)
    held, crank = item.wheel_rotation(), item.crank_rotation()
    c.set_frame(500)
    assert item.wheel_rotation() == pytest.approx(held) and item.crank_rotation() != pytest.approx(crank)
    assert "crank φ" in parts.window.frame_label.text()


def test_a_property_edit_is_one_undo_step(shell, qtbot):
    parts, c, view = _open(shell, "geneva_z6")
    props = parts.window.properties
    assert props.fields["slots"].text() == "6" and props.fields["center_distance"].text() == "100"
    before = c.scene
    _type(qtbot, props.fields["slots"], "8")
    assert c.scene.element("indexer").slots == 8
    assert c.undo_stack.count() == 1 and c.undo_stack.undoText() == "set slots of indexer"
    assert view.element_items["indexer"].result.element.slots == 8      # redrawn with 8 slots
    parts.window.actions["undo"].trigger()
    assert c.scene == before and props.fields["slots"].text() == "6"
    assert view.element_items["indexer"].result.element.slots == 6
    parts.window.actions["redo"].trigger()
    assert c.scene.element("indexer").slots == 8 and props.fields["slots"].text() == "8"
    _type(qtbot, props.fields["clearance.slot"], "0.1")
    assert c.scene.element("indexer").clearance.slot == 0.1 and c.undo_stack.count() == 2


@pytest.mark.parametrize("field, text, says", [
    ("slots", "2", "at least 3 slots; got 2"),
    ("roller_radius", "30", "locking arc"),
    ("slots", "6.5", "whole number"),
    ("clearance.lock", "-1", "must be >= 0 mm"),
])
def test_an_invalid_edit_is_refused_with_the_cores_message(shell, qtbot, field, text, says):
    parts, c, _ = _open(shell, "geneva_z6")
    props = parts.window.properties
    before = c.scene
    shown = props.fields[field].text()
    _type(qtbot, props.fields[field], text)
    assert c.scene is before and c.undo_stack.count() == 0 and not c.is_dirty
    assert says in parts.window.statusBar().currentMessage()
    assert props.fields[field].text() == shown


def test_speed_and_turning_sense(shell, qtbot):
    parts, c, _ = _open(shell, "geneva_z6")
    props = parts.window.properties
    _type(qtbot, props.fields["speed_rpm"], "60")
    assert c.scene.element("indexer").speed_rpm == 60.0
    sense = props.combos["geneva.sense"]
    sense.activated.emit(1)
    assert c.scene.element("indexer").speed_rpm == -60.0 and c.undo_stack.count() == 2
    assert c.element_result("indexer").kinematics.omega1 < 0


def test_diagnostics_show_the_analyze_summary(shell):
    parts, c, _ = _open(shell, "geneva_z6")
    el = c.scene.element("indexer")
    text = " ".join(parts.window.diagnostics.plain_text().split())
    cli = geneva_cmds.analyze(Workspace(Scene((el,))), el.id).summary   # a workspace of its own
    for line in cli.splitlines():
        assert " ".join(line.split()) in text


def test_plots_show_kinematics_and_contact_against_the_crank_angle(shell):
    parts, c, _ = _open(shell, "geneva_z6")
    plots = parts.window.plots
    el = c.scene.element("indexer")
    kin, con = kinematics(el, el.samples), contact(el, el.samples, el.model)
    assert {"wheel.angle", "wheel.ω", "wheel.α", "wheel.jerk", "Rn (derived)", "slip path", "p_max"} <= set(plots.curves)
    x, y = plots.curves["wheel.ω"].getData()
    assert np.allclose(x, np.degrees(kin.phi)) and np.allclose(y, kin.omega)
    assert np.all(y[~kin.engaged] == 0.0)                                   # the dwell is an explicit zero
    xa, ya = plots.curves["wheel.α"].getData()
    phi0 = math.degrees(kin.phi0)
    at_entry = np.flatnonzero(np.isclose(xa, -phi0))
    assert len(at_entry) == 2 and 0.0 in ya[at_entry]
    assert abs(ya[at_entry[1]] - ya[at_entry[0]]) == pytest.approx(kin.jump)  # a vertical jump
    xr, rn = plots.curves["Rn (derived)"].getData()
    assert np.isnan(rn[~con.engaged]).all() and np.isfinite(rn[con.engaged]).all()
    assert plots.curves["Rn (derived)"].opts["connect"] == "finite"
    assert plots.plots["pressure"].getAxis("left").labelText == "p_max (MPa)"
    c.set_frame(2000)
    assert plots.cursor_x() == pytest.approx(math.degrees(kin.phi[2000]))
    plots.go_to(0.0)
    assert c.frame == 1800


def test_clicking_the_wheel_selects_the_drive_and_delete_removes_it(shell, qtbot):
    parts, c, view = _open(shell, "geneva_z4")
    geo = c.element_result("indexer").geometry
    wc = geo.wheel_center
    hub = view.mapFromScene(QPointF(wc[0] + 0.5 * (geo.wheel_bore + geo.dims.hub_max), wc[1]))
    qtbot.mouseClick(view.viewport(), Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, hub)
    assert c.selection == [("indexer", "element", "indexer")]
    assert view.element_items["indexer"].selected
    assert parts.window.properties.selector.currentText() == "indexer: Geneva drive"
    parts.window.actions["delete"].trigger()
    assert c.scene.elements == () and "indexer" not in view.element_items
    parts.window.actions["undo"].trigger()
    assert c.scene == load_scene(resources.example_path("geneva_z4"))
    assert "indexer" in view.element_items


def test_with_a_linkage_the_drive_follows_by_cycle_phase(shell):
    from mechsketch.core import Scene

    parts = shell()
    c, view = parts.controller, parts.window.canvas
    fourbar = load_scene(resources.example_path("fourbar_crank_rocker")).elements[0]
    geneva = load_scene(resources.example_path("geneva_z8")).elements[0]
    c.reset(Scene((fourbar, geneva)), None)
    assert c.sample_count() == 360 and c.element_result("indexer").n_frames == 3600
    item = view.element_items["indexer"]
    kin = kinematics(geneva, geneva.samples)
    c.set_frame(90)                                   # a quarter of the cycle: sample 900 of 3600
    assert item.index == 900
    assert _wrap(item.wheel_rotation() - kin.wheel_angle[900]) == pytest.approx(0.0, abs=1e-9)
    assert "fourbar" in parts.window.plots.title.text()          # nothing selected: the linkage is plotted
    c.set_selection([("indexer", "element", "indexer")])   # selecting the drive plots it
    assert "wheel.ω" in parts.window.plots.curves
    assert parts.window.plots.cursor_x() == pytest.approx(math.degrees(kin.phi[900]))


def test_a_geneva_scene_animates_at_its_crank_speed_and_reads_out_the_crank_angle(shell):
    """The scrub bar and the status bar read the Geneva's own frames; 1x plays one crank
    revolution in 60/rpm seconds (not in a nominal second)."""
    parts, c, _ = _open(shell, "geneva_z6")
    el = next(e for e in c.scene.elements if isinstance(e, Geneva))
    assert c.cycle_period() == pytest.approx(60.0 / abs(el.speed_rpm))
    kin = kinematics(el, el.samples)
    c.set_frame(900)
    text, ok = c.frame_text()
    assert ok and f"crank φ {math.degrees(kin.phi[900]):.1f}°" in text and "frame 901/3600" in text
    assert f"t {kin.t[900]:.3f} s" in text
    assert text in parts.window.frame_label.text()
