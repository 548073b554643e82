"""Edit › Preferences, Ctrl+, (issue 24 item 9), driven as a user: the dialog is opened with its
key, its boxes are changed with keys and clicks, OK stores and applies. Units (mm/in, °/rad,
rpm/rad/s) change what Properties, the Dimensions table and the cursor read-out show and read,
while the model and the files stay in mm, ° and rpm; grid snap step, samples of new linkages,
autosave interval, dead-point policy, Geneva materials and plate sizes reach the parts that use
them; all of it is kept in the settings file and read back by the next start."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QWheelEvent
from PySide6.QtWidgets import QApplication, QDialogButtonBox, QLabel

from mechsketch.core import MoveJoint
from mechsketch.gui import units
from mechsketch.gui.export_dialog import ExportRequest
from mechsketch.gui.preferences import Preferences, PreferencesDialog, load_preferences
from mechsketch.gui.units import Units

from app_fakes import shell, type_into  # noqa: F401 - fixture
from canvas_user import User


@pytest.fixture(autouse=True)
def _mm_again():
    yield
    units.set_current(Units())          # units are process-wide: the next test starts in mm


def open_preferences(qtbot, w) -> PreferencesDialog:
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow, timeout=20000)
    qtbot.keyClick(w, Qt.Key.Key_Comma, Qt.KeyboardModifier.ControlModifier)   # Ctrl+,
    qtbot.waitUntil(lambda: w.preferences_dialog is not None and w.preferences_dialog.isVisible(),
                    timeout=20000)
    return w.preferences_dialog


def choose(qtbot, dlg: PreferencesDialog, name: str, data: str) -> None:
    """Pick the entry ``data`` of a combo box with the arrow keys, as a user would."""
    box = dlg.widgets[name]
    dlg.tabs.setCurrentWidget(box.parentWidget())
    box.setFocus()
    target = box.findData(data)
    assert target >= 0, (name, data)
    while box.currentIndex() != target:
        qtbot.keyClick(box, Qt.Key.Key_Down if box.currentIndex() < target else Qt.Key.Key_Up)


def set_number(qtbot, dlg: PreferencesDialog, name: str, text: str) -> None:
    box = dlg.widgets[name]
    dlg.tabs.setCurrentWidget(box.parentWidget())
    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box, text)


def ok(qtbot, dlg: PreferencesDialog) -> None:
    qtbot.mouseClick(dlg.buttons.button(QDialogButtonBox.StandardButton.Ok), Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: not dlg.isVisible(), timeout=20000)


def unit_beside(edit) -> str:
    return " ".join(lbl.text() for lbl in edit.parentWidget().findChildren(QLabel))


def test_inches_are_shown_and_typed_while_the_model_and_file_stay_in_mm(shell, qtbot, tmp_path):
    parts = shell()
    w, c = parts.window, parts.controller
    dlg = open_preferences(qtbot, w)
    choose(qtbot, dlg, "length_unit", "in")
    ok(qtbot, dlg)
    assert units.current().length == "in"
    assert "in" in w.statusBar().currentMessage()
    c.set_selection([("fourbar", "joint", "B")])
    props = w.properties
    bx = c.scene.element("fourbar").joint("B").at[0]
    assert unit_beside(props.fields["x"]) == "in"
    assert float(props.fields["x"].text()) == pytest.approx(bx / 25.4, abs=1e-8)
    type_into(qtbot, props.fields["x"], "2")                  # inches
    assert c.scene.element("fourbar").joint("B").at[0] == 50.8
    type_into(qtbot, props.fields["y"], "30 mm")              # a value with its own unit
    assert c.scene.element("fourbar").joint("B").at[1] == 30.0
    table = props.tables["dimensions"]
    assert {table.item(r, 3).text() for r in range(table.rowCount())} <= {"in", "°"}
    row = next(r for r in range(table.rowCount()) if table.item(r, 2).data(Qt.ItemDataRole.UserRole)
               == "length:crank:A:B")
    assert float(table.item(row, 2).text()) == pytest.approx(math.dist(c.scene.element("fourbar").joint("A").at,
                                                                       (50.8, 30.0)) / 25.4, rel=1e-9)
    table.item(row, 2).setText("1.5")                         # typed into the cell: 1.5 in
    crank = math.dist(c.scene.element("fourbar").joint("A").at, c.scene.element("fourbar").joint("B").at)
    assert crank == pytest.approx(38.1, abs=1e-9)
    w.show_cursor(25.4, -50.8)
    assert w.cursor_label.text() == "1.0000, -2.0000 in"
    assert parts.file_ops.save_as(tmp_path / "inch.json")
    doc = json.loads((tmp_path / "inch.json").read_text())
    joints = {j["id"]: j["at"] for j in doc["elements"][0]["joints"]}
    assert doc["units"] == "mm" and joints["B"][0] == pytest.approx(c.scene.element("fourbar").joint("B").at[0])


def test_radians_and_rad_per_s(shell, qtbot):
    parts = shell()
    w, c = parts.window, parts.controller
    dlg = open_preferences(qtbot, w)
    choose(qtbot, dlg, "angle_unit", "rad")
    choose(qtbot, dlg, "speed_unit", "rad/s")
    ok(qtbot, dlg)
    speed = w.properties.fields["speed"]
    rpm = c.scene.element("fourbar").driver.speed_rpm
    assert unit_beside(speed).startswith("rad/s")
    assert float(speed.text()) == pytest.approx(rpm * 2 * math.pi / 60, rel=1e-8)
    type_into(qtbot, speed, "20")                             # rad/s
    assert c.scene.element("fourbar").driver.speed_rpm == pytest.approx(20 * 60 / (2 * math.pi), rel=1e-12)
    table = w.properties.tables["dimensions"]
    angles = [r for r in range(table.rowCount()) if table.item(r, 3).text() == "rad"]
    for r in angles:
        key = table.item(r, 2).data(Qt.ItemDataRole.UserRole)
        assert key.startswith(("angle:", "axis:"))


def test_preferences_are_kept_in_the_settings_file_and_read_by_the_next_start(shell, qtbot, tmp_path):
    settings = tmp_path / "prefs.ini"
    parts = shell(settings_path=settings)
    dlg = open_preferences(qtbot, parts.window)
    choose(qtbot, dlg, "length_unit", "in")
    choose(qtbot, dlg, "dead_points", "stop")
    set_number(qtbot, dlg, "autosave_s", "30")
    set_number(qtbot, dlg, "samples", "720")
    ok(qtbot, dlg)
    text = settings.read_text()
    assert "length_unit=in" in text and "samples=720" in text and "autosave_s=30" in text
    units.set_current(Units())
    again = shell(settings_path=settings)
    assert again.window.preferences.length_unit == "in" and units.current().length == "in"
    assert again.autosave.timer.interval() == 30_000
    assert again.window.player._dead_actions["stop"].isChecked()


def test_snap_step_samples_and_materials_reach_the_canvas_tools(shell, qtbot):
    parts = shell()
    w, c = parts.window, parts.controller
    dlg = open_preferences(qtbot, w)
    set_number(qtbot, dlg, "snap_step", "7.5")
    set_number(qtbot, dlg, "samples", "720")
    choose(qtbot, dlg, "roller_material", "aluminium")
    choose(qtbot, dlg, "wheel_material", "POM (acetal)")
    ok(qtbot, dlg)
    view = w.canvas
    assert view.snap_step() == 7.5 and view.snap((13.0, -4.0)) == (15.0, -7.5)
    w.actions["new"].trigger()
    user = User(qtbot, view)
    user.tool("ground")
    user.click((31.0, 22.0))                                  # snapped to the 7.5 mm step
    (lk,) = c.scene.elements
    assert lk.samples == 720 and lk.joints[0].at == (30.0, 22.5)
    user.tool("geneva")
    user.click((-150.0, -150.0))
    user.click((-50.0, -150.0))
    drive = next(e for e in c.scene.elements if e.type == "geneva")
    assert (drive.roller_material.E, drive.roller_material.poisson) == (70000.0, 0.33)
    assert drive.wheel_material.E == 2900.0


def test_plate_sizes_and_minimum_web_are_the_exports_defaults(shell, qtbot, tmp_path):
    parts = shell()
    w = parts.window
    dlg = open_preferences(qtbot, w)
    set_number(qtbot, dlg, "boss_radius", "9")
    set_number(qtbot, dlg, "bore_diameter", "4")
    set_number(qtbot, dlg, "min_web", "1.5")
    ok(qtbot, dlg)
    assert w.preferences.boss_radius == 9.0 and w.preferences.min_web == 1.5
    started = []
    w.exporter.start = lambda el, path, req: started.append(req) or True
    parts.dialogs.export_requests.append(lambda eid, fmt: ExportRequest(eid, fmt))
    parts.dialogs.save_names.append(str(tmp_path / "fb.dxf"))
    assert w.export_dxf()
    (req,) = started
    assert (req.options.boss_radius, req.options.bore_diameter, req.options.link_width) == (9.0, 4.0, None)
    assert parts.dialogs.export_choices and "fourbar" in parts.dialogs.export_choices


def test_an_unreadable_settings_value_is_its_default(shell, tmp_path):
    ini = tmp_path / "bad.ini"
    ini.write_text("[preferences]\nlength_unit=cm\nsamples=abc\nautosave_s=2\nangle_unit=rad\nsnap=maybe\n")
    parts = shell(settings_path=ini)
    prefs = parts.window.preferences
    assert prefs == Preferences(angle_unit="rad")
    assert parts.autosave.timer.interval() == 60_000


def test_restore_defaults_cancel_and_the_wheel(shell, qtbot):
    parts = shell()
    w = parts.window
    dlg = open_preferences(qtbot, w)
    choose(qtbot, dlg, "length_unit", "in")
    set_number(qtbot, dlg, "boss_radius", "0.5")              # inches while inch is chosen
    assert dlg.value().boss_radius == pytest.approx(12.7, rel=1e-12)
    choose(qtbot, dlg, "length_unit", "mm")                   # the same length, now in mm
    assert dlg.widgets["boss_radius"].value() == pytest.approx(12.7, abs=1e-3)
    qtbot.mouseClick(dlg.buttons.button(QDialogButtonBox.StandardButton.RestoreDefaults), Qt.MouseButton.LeftButton)
    assert dlg.value() == Preferences()
    box = dlg.widgets["speed_unit"]
    dlg.tabs.setCurrentIndex(0)
    dlg.buttons.setFocus()
    before = box.currentIndex()
    centre = QPointF(box.rect().center())
    wheel = QWheelEvent(centre, QPointF(box.mapToGlobal(centre.toPoint())), QPoint(0, 0), QPoint(0, -120),
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False)
    QApplication.sendEvent(box, wheel)
    assert box.currentIndex() == before                       # not focused: the wheel does nothing
    qtbot.mouseClick(dlg.buttons.button(QDialogButtonBox.StandardButton.Cancel), Qt.MouseButton.LeftButton)
    assert w.preferences == Preferences() and units.current() == Units()
    parts.controller.push(MoveJoint("fourbar", "B", (21.0, 35.0)), "move")   # the app works on
    assert load_preferences(parts.file_ops.settings) == Preferences()


def test_the_plots_follow_the_units(shell, qtbot, tmp_path):
    parts = shell()
    w, c = parts.window, parts.controller
    c.set_selection([("fourbar", "joint", "C")])
    plots = w.plots
    plots.refresh()
    mm_y = {s.name: s.y.copy() for s in plots.data.series}
    mm_x = plots.data.x.copy()
    dlg = open_preferences(qtbot, w)
    choose(qtbot, dlg, "length_unit", "in")
    choose(qtbot, dlg, "angle_unit", "rad")
    ok(qtbot, dlg)
    data = plots.data
    shown = {s.name: s for s in data.series}
    assert shown["C.x"].unit == "in" and shown["C.vx"].unit == "in/s" and shown["C.ax"].unit == "in/s²"
    assert shown["C.x"].y == pytest.approx(mm_y["C.x"] / 25.4, rel=1e-14, nan_ok=True)
    mu = next(s for s in data.series if s.name.startswith("μ"))
    assert mu.unit == "rad" and mu.y == pytest.approx(np.radians(mm_y[mu.name]), rel=1e-14, nan_ok=True)
    assert data.x == pytest.approx(np.radians(mm_x), rel=1e-14)
    assert data.labels["position"] == "position (in)" and data.x_label.endswith("(rad)")
    assert plots.plots["position"].getAxis("left").labelText == "position (in)"
    plots.go_to(float(data.x[90]))                            # a click at the 90th sample's input
    assert c.frame == 90
    plots.export_csv(str(tmp_path / "p.csv"))
    head = (tmp_path / "p.csv").read_text().splitlines()[0]
    assert head.startswith("input_rad") and "C.x_in" in head


def test_out_of_range_preferences_are_not_saved(shell):
    parts = shell()
    w = parts.window
    assert not w.set_preferences(Preferences(samples=1, dead_points="jump"))
    title, text, _ = parts.dialogs.errors[-1]
    assert title == "Preferences" and "samples 1 outside 8..1,000,000" in text and "'jump'" in text
    assert w.preferences == Preferences() and load_preferences(parts.file_ops.settings) == Preferences()
