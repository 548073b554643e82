"""Underlays in the app (issue 22 item 6, issue 24 item 10), driven as a user: File › Import
Underlay, two clicks and a typed distance to place it, its vertices snapping the tools, Show
Underlays (Ctrl+Shift+U) hiding it, Move by dragging, Remove, a picture dropped on the canvas,
each change one undo step, and the underlay saved in the scene file."""
from __future__ import annotations

import io
import math

import ezdxf
import numpy as np
import pytest
from PIL import Image
from PySide6.QtCore import QMimeData, QPointF, Qt, QUrl
from PySide6.QtGui import QDragEnterEvent, QDropEvent
from PySide6.QtWidgets import QApplication

from mechsketch.core import load_scene
from mechsketch.core.model.underlay import Underlay

from app_fakes import shell  # noqa: F401 - fixture
from canvas_user import User


@pytest.fixture
def frame_dxf(tmp_path):
    """An outline in mm: a 120 × 60 rectangle from (200, -100) and a line between two points off
    any grid, (211.1, -88.8) and (233.3, -71.7)."""
    doc = ezdxf.new(units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(200, -100), (320, -100), (320, -40), (200, -40)], close=True)
    msp.add_line((211.1, -88.8), (233.3, -71.7))
    path = tmp_path / "frame.dxf"
    doc.saveas(path)
    return path


def underlays(parts) -> list[Underlay]:
    return [e for e in parts.controller.scene.elements if isinstance(e, Underlay)]


def imported(shell, path, qtbot):
    parts = shell()
    w = parts.window
    parts.dialogs.open_names.append(str(path))
    w.actions["import_underlay"].trigger()
    (u,) = underlays(parts)
    return parts, w, u, User(qtbot, w.canvas)


def test_import_place_by_two_points_and_undo(shell, qtbot, frame_dxf):
    parts, w, u, user = imported(shell, frame_dxf, qtbot)
    c = parts.controller
    assert u.kind == "drawing" and len(u.paths) == 2 and c.undo_stack.count() == 1
    assert u.id == "frame"                              # named after its file
    assert u.world_bounds() == pytest.approx((200.0, -100.0, 320.0, -40.0))   # the DXF's own mm
    assert c.selection == [(u.id, "element", u.id)]
    item = w.canvas.underlays.items[u.id]
    assert item.isVisible() and len(item.points) == 7
    assert "click the first of two points" in w.statusBar().currentMessage()
    parts.dialogs.numbers.append(240.0)                 # the bottom edge is 240 mm, not 120
    px = w.canvas.px()
    user.click((200.0 + 2 * px, -100.0 - 2 * px))       # near a corner: it snaps to it
    user.click((320.0 - 3 * px, -100.0 + 1 * px))
    (placed,) = underlays(parts)
    pts = np.array(placed.world_paths()[0])
    assert pts[0] == pytest.approx([200.0, -100.0], abs=1e-9)        # the first point stays
    assert math.dist(pts[0], pts[1]) == pytest.approx(240.0, rel=1e-12)
    assert c.undo_stack.count() == 2
    assert parts.dialogs.questions[-1] == ("Distance between the two points",
                                           "The distance the two points are apart [120 mm]")   # offered: now
    c.undo_stack.undo()
    assert underlays(parts)[0] == u
    c.undo_stack.undo()
    assert underlays(parts) == [] and u.id not in w.canvas.underlays.items


def test_vertices_snap_the_tools_until_the_underlay_is_hidden(shell, qtbot, frame_dxf):
    parts, w, u, user = imported(shell, frame_dxf, qtbot)
    c = parts.controller
    qtbot.keyClick(w.canvas, Qt.Key.Key_Escape)          # keep the placement as it is
    assert "placement cancelled" in w.statusBar().currentMessage()
    w.canvas.zoom_to_rect(w.canvas.underlays.extent().adjusted(-50, -50, 50, 50))
    px = w.canvas.px()
    user.tool("ground")
    user.click((233.3 + 3 * px, -71.7 - 2 * px))         # near the diagonal's end
    lk = next(e for e in c.scene.elements if e.type == "linkage" and e.id != "fourbar")
    assert lk.joints[0].at == (233.3, -71.7)
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow, timeout=20000)
    qtbot.keyClick(w, Qt.Key.Key_U, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    assert not underlays(parts)[0].visible and not w.canvas.underlays.items[u.id].isVisible()
    assert not w.actions["show_underlays"].isChecked()
    c.set_selection([])
    user.tool("ground")
    user.click((211.1 + 3 * px, -88.8 - 2 * px))
    second = [e for e in c.scene.elements if e.type == "linkage" and e.id != "fourbar"][-1]
    assert len(second.joints) == 1 and second.joints[-1].at != (211.1, -88.8)   # the grid, not the vertex
    assert "hidden" in w.diagnostics.plain_text()
    while not underlays(parts)[0].visible:
        c.undo_stack.undo()
    assert w.canvas.underlays.items[u.id].isVisible() and w.actions["show_underlays"].isChecked()


def test_move_by_dragging_is_one_undo_step_and_esc_cancels(shell, qtbot, frame_dxf):
    parts, w, u, user = imported(shell, frame_dxf, qtbot)
    c = parts.controller
    qtbot.keyClick(w.canvas, Qt.Key.Key_Escape)
    count = c.undo_stack.count()
    w.actions["move_underlay"].trigger()
    a, b = user.view.mapToScene(user.at((250.0, -80.0))), user.view.mapToScene(user.at((290.0, -20.0)))
    user.drag((250.0, -80.0), (290.0, -20.0))
    (moved,) = underlays(parts)
    assert moved.placement.offset == pytest.approx((b.x() - a.x(), b.y() - a.y()), abs=1e-9)
    assert c.undo_stack.count() == count + 1 and "move underlay" in c.undo_stack.undoText()
    w.actions["move_underlay"].trigger()
    user.drag((250.0, -80.0), (100.0, 100.0), release=False)
    assert underlays(parts)[0] != moved                  # the preview moves it...
    qtbot.keyClick(w.canvas, Qt.Key.Key_Escape)
    assert underlays(parts)[0] == moved and c.undo_stack.count() == count + 1   # ...Esc puts it back
    user.release((100.0, 100.0))
    c.undo_stack.undo()
    assert underlays(parts)[0] == u


def test_remove_and_undo_and_the_file_keeps_it(shell, qtbot, frame_dxf, tmp_path):
    parts, w, u, user = imported(shell, frame_dxf, qtbot)
    qtbot.keyClick(w.canvas, Qt.Key.Key_Escape)
    assert parts.file_ops.save_as(tmp_path / "with_underlay.json")
    assert load_scene(tmp_path / "with_underlay.json").element(u.id) == u
    w.actions["remove_underlay"].trigger()
    assert underlays(parts) == [] and not w.actions["show_underlays"].isEnabled()
    parts.controller.undo_stack.undo()
    assert underlays(parts) == [u]
    again = shell(tmp_path / "with_underlay.json")
    assert again.window.canvas.underlays.items[u.id].isVisible()
    assert f"underlay {u.id}: frame.dxf" in again.window.diagnostics.plain_text()


def drop(widget, paths, pos) -> bool:
    data = QMimeData()
    data.setUrls([QUrl.fromLocalFile(str(p)) for p in paths])
    enter = QDragEnterEvent(pos, Qt.DropAction.CopyAction, data, Qt.MouseButton.LeftButton,
                            Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, enter)
    if not enter.isAccepted():
        return False
    event = QDropEvent(QPointF(pos), Qt.DropAction.CopyAction, data, Qt.MouseButton.LeftButton,
                       Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, event)
    return event.isAccepted()


def test_a_picture_dropped_on_the_canvas_is_centred_where_it_fell(shell, qtbot, tmp_path):
    buf = io.BytesIO()
    Image.new("RGB", (400, 200), (30, 90, 200)).save(buf, "PNG")
    (tmp_path / "photo.png").write_bytes(buf.getvalue())
    parts = shell()
    w = parts.window
    view = w.canvas
    spot = view.viewport().rect().center() + view.viewport().rect().topLeft() / 2
    assert drop(view.viewport(), [tmp_path / "photo.png"], spot)
    (u,) = underlays(parts)
    world = view.mapToScene(spot)
    x0, y0, x1, y1 = u.world_bounds()
    assert ((x0 + x1) / 2, (y0 + y1) / 2) == pytest.approx((world.x(), world.y()), abs=1e-6)
    visible = view.mapToScene(view.viewport().rect()).boundingRect()
    assert x1 - x0 == pytest.approx(0.8 * visible.width(), rel=1e-9) and (y1 - y0) == pytest.approx((x1 - x0) / 2)
    assert u.image.format == "png" and w.canvas.underlays.items[u.id].isVisible()
    qtbot.keyClick(view, Qt.Key.Key_Escape)
    grab = view.viewport().grab().toImage()
    c = grab.pixelColor(spot)
    assert c.blue() > c.red() + 20                         # the picture is painted under the grid


def test_dropping_a_scene_opens_it_and_other_files_are_refused(shell, qtbot, tmp_path):
    from mechsketch.resources import example_path

    parts = shell()
    w = parts.window
    assert drop(w, [example_path("geneva_z6")], w.rect().center())
    assert parts.controller.scene.ids == ("gear1",) or "geneva" in [e.type for e in parts.controller.scene.elements]
    (tmp_path / "notes.txt").write_text("hi")
    assert not drop(w.canvas.viewport(), [tmp_path / "notes.txt"], w.canvas.viewport().rect().center())
    assert w.drops.drop([tmp_path / "notes.txt"]) == 0
    assert "not opened: notes.txt" in w.statusBar().currentMessage()
    bad = tmp_path / "broken.dxf"
    bad.write_text("0\nSECTION\n2\nENTITIES\n0\nENDSEC\n0\nEOF\n")
    assert w.drops.drop([bad]) == 0
    assert parts.dialogs.errors[-1][0] == "Cannot import underlay" and "broken.dxf" in parts.dialogs.errors[-1][1]


def test_placing_refuses_coinciding_points_and_a_cancelled_distance(shell, qtbot, frame_dxf):
    parts, w, u, user = imported(shell, frame_dxf, qtbot)
    cmds = w.underlay_commands
    qtbot.keyClick(w.canvas, Qt.Key.Key_Escape)
    assert not cmds.place(u.id, (200.0, -100.0), (200.0, -100.0), 50.0)
    assert "coincide" in w.statusBar().currentMessage()
    assert not cmds.place(u.id, (200.0, -100.0), (320.0, -100.0))   # the dialog answers Cancel
    assert underlays(parts) == [u]
    assert cmds.place(u.id, (200.0, -100.0), (320.0, -100.0), 60.0)
    assert np.ptp(np.array(underlays(parts)[0].world_points())[:, 0]) == pytest.approx(60.0, rel=1e-12)


def test_an_underlay_is_named_after_its_file():
    from mechsketch.gui.underlays import id_from

    assert id_from("/x/My Frame\t2.svg") == "My_Frame_2" and id_from("/x/   .png") == "underlay"
    assert len(id_from("/x/" + "a" * 100 + ".dxf")) == 48
