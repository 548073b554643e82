"""Tools never act on a document that is gone (issue 20, item 8).

A half-done placement (a PRP dyad's first guide picked, a crank's pivot, a Geneva drive's centre,
a drag in progress) refers to elements and joints of the document it started in. When the
document is replaced (New, Open, an example) or the element is removed (undo, delete), every tool
starts again: the next mouse move raises nothing, the preview is gone, and nothing of the old
document reaches the new one.
"""
from __future__ import annotations

import pytest
from PySide6.QtCore import QEvent, Qt
from PySide6.QtWidgets import QApplication

from app_fakes import DISCARD, shell  # noqa: F401 - fixture
from canvas_user import User

ROCKER_MID = (146.6, 58.5)     # on the four-bar's rocker D-C
FREE = (80.0, 60.0)            # empty space inside the four-bar
B, C = (20.0, 34.641016151), (133.22973437, 116.975864511)


@pytest.fixture
def app(shell, qtbot):
    parts = shell()
    parts.window.actions["example:fourbar_crank_rocker"].trigger()
    view = parts.window.canvas
    return parts, parts.controller, view, User(qtbot, view)


def _wander(user: User, view) -> None:
    """Mouse moves over the whole visible canvas, then a click and Esc (what a user does next)."""
    r = view.mapToScene(view.viewport().rect()).boundingRect()
    for k in range(9):
        user.move((r.left() + r.width() * (k + 0.5) / 9, r.top() + r.height() * ((k * 4) % 9 + 0.5) / 9))


# a half-done placement of each tool on the four-bar "fourbar"
HALF_DONE = {
    "prp": [ROCKER_MID, FREE],              # guide 1 on the rocker, the pin
    "rpp": [B, ROCKER_MID],                 # M = B, the guide on the rocker
    "rrp": [C, ROCKER_MID],                 # the rod's joint C, the guide on the rocker
    "rrr": [B, C],                          # M and H picked
    "rpr": [B],                             # M picked
    "crank": [(0.0, 0.0)],                  # the pivot A (it has a driver: refused, nothing held)
    "geneva": [(300.0, 300.0)],             # the crank centre
    "rolling": [(300.0, 300.0), (340.0, 300.0), (330.0, 260.0)],
    "measure": [B],
    "coupler": [],
    "ground": [],
    "delete": [],
}


def test_a_half_done_placement_is_dropped_when_the_document_is_replaced(app):
    """Each tool in turn (one window: New and Open alternate) half-places on the four-bar, then
    the document is replaced."""
    parts, ctl, view, user = app
    for k, tool in enumerate(sorted(HALF_DONE)):
        parts.window.actions["example:fourbar_crank_rocker"].trigger()
        user.tool(tool)
        for p in HALF_DONE[tool]:
            user.click(p)
        user.move((100.0, 100.0))
        name = "example:geneva_z6" if k % 2 else "new"
        parts.dialogs.save_changes.append(DISCARD)
        parts.window.actions[name].trigger()
        assert "fourbar" not in ctl.scene.ids
        _wander(user, view)            # raised UnknownIdError for prp/rpp/rrp before the fix
        assert view.toolbox.name == "select", f"{tool}: a new document starts with the select tool"
        for t in view.toolbox.tools.values():
            assert not t.refers_to(), f"{tool}: {t.name} still refers to {t.refers_to()}"
        assert view.toolbox.tools["geneva"].placed is None
        assert view.toolbox.tools["insert"].elements == []


def test_a_half_done_placement_on_an_element_that_is_undone_starts_again(shell, qtbot):
    """The four-bar is inserted (one undo step), a placement starts on it, Ctrl+Z removes it;
    each tool in turn."""
    parts = shell()
    ctl, view = parts.controller, parts.window.canvas
    parts.dialogs.save_changes.append(DISCARD)
    parts.window.actions["new"].trigger()
    user = User(qtbot, view)
    for tool in ["prp", "rpp", "rrp", "rrr", "rpr", "measure"]:
        view.set_tool("insert")
        view.toolbox.tools["insert"].load(list(_fourbar().elements), "fourbar")
        user.click((80.0, 58.5))        # the box's centre: the four-bar lands where it is drawn
        assert "fourbar" in ctl.scene.ids
        view.zoom_to_fit()
        pose = {j.id: j.at for j in ctl.scene.element("fourbar").joints}
        points = {B: pose["B"], C: pose["C"], ROCKER_MID: ((pose["C"][0] + pose["D"][0]) / 2,
                                                           (pose["C"][1] + pose["D"][1]) / 2)}
        user.tool(tool)
        for p in HALF_DONE[tool]:
            user.click(points.get(p, p))
        qtbot.keyClick(view, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
        assert "fourbar" not in ctl.scene.ids
        _wander(user, view)
        assert not view.toolbox.tool.refers_to(), tool
        for p in (FREE, (10.0, 10.0)):
            user.click(p)
        assert not view.toolbox.tool.refers_to(), tool
        assert not ctl.scene.elements, f"{tool}: nothing of the undone element came back"
        user.tool("select")


def _fourbar():
    from mechsketch.core import load_scene
    from mechsketch.resources import example_path

    return load_scene(example_path("fourbar_crank_rocker"))


def test_a_joint_drag_when_the_document_is_replaced_does_not_write_into_the_new_one(app, qtbot):
    """Press on joint C, drag (a live preview), open the same example again mid-drag (a shortcut
    pressed while dragging), drag on and release: the new document is untouched, no history."""
    parts, ctl, view, user = app
    user.press(C)
    user.move((C[0] + 10.0, C[1] + 10.0))
    assert ctl.workspace.previewing
    parts.dialogs.save_changes.append(DISCARD)
    parts.window.actions["example:fourbar_crank_rocker"].trigger()
    fresh = ctl.scene.element("fourbar")
    for d in (20.0, 30.0):
        user.move((C[0] + d, C[1] + d))
    user.release((C[0] + 30.0, C[1] + 30.0))
    assert ctl.scene.element("fourbar") is fresh
    assert ctl.undo_stack.count() == 0 and not ctl.workspace.previewing
    assert not view.toolbox.tool.busy


def test_a_handle_drag_when_the_document_is_replaced_leaves_the_new_one_alone(shell, qtbot):
    parts = shell()
    ctl, view = parts.controller, parts.window.canvas
    parts.window.actions["example:geneva_z6"].trigger()
    user = User(qtbot, view)
    eid = ctl.scene.elements[0].id
    ctl.set_selection([(eid, "element", eid)])
    wheel = next(h for h in view.extras.handles.handles() if h.name == "wheel")
    user.press(wheel.at)
    user.move((wheel.at[0] + 8.0, wheel.at[1]))
    user.move((wheel.at[0] + 12.0, wheel.at[1]))
    assert ctl.workspace.previewing
    parts.dialogs.save_changes.append(DISCARD)
    parts.window.actions["example:geneva_z6"].trigger()
    fresh = ctl.scene.element(eid)
    user.move((wheel.at[0] + 20.0, wheel.at[1]))
    user.release((wheel.at[0] + 20.0, wheel.at[1]))
    assert ctl.scene.element(eid) is fresh and ctl.undo_stack.count() == 0


def test_a_tool_refers_to_a_linkage_id_now_taken_by_another_kind(app, qtbot):
    """The id of the linkage a placement started on may come back as a Geneva drive."""
    parts, ctl, view, user = app
    user.tool("prp")
    user.click(ROCKER_MID)
    from mechsketch.core.model.edits import AddElement, RemoveElement
    from mechsketch.gui.canvas.geneva_tool import scaled_drive

    ctl.push(RemoveElement("fourbar", "x"))
    ctl.push(AddElement(scaled_drive("fourbar", 6, (0.0, 0.0), (100.0, 0.0))))
    _wander(user, view)
    assert not view.toolbox.tool.refers_to()
    user.click(FREE)
    assert not view.toolbox.tool.refers_to()


def test_ctrl_z_in_the_middle_of_a_drag_undoes_the_document_and_ends_the_drag(app, qtbot):
    """A shortcut pressed while dragging: the undo applies to the document (not to the drag's
    preview of it), the drag stops, and its release adds nothing."""
    parts, ctl, view, user = app
    original = ctl.scene.element("fourbar")
    e = original.joint("E").at
    user.drag(e, (e[0] + 10.0, e[1] - 10.0))          # one undo step: E moved
    assert ctl.undo_stack.count() == 1
    user.press(C)
    user.move((C[0] + 10.0, C[1] + 10.0))
    assert ctl.workspace.previewing and view.toolbox.tool.busy
    qtbot.keyClick(view, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert not ctl.workspace.previewing and not view.toolbox.tool.busy
    assert ctl.scene.element("fourbar") == original, "the undo took back the move of E, and C is where it was"
    user.move((C[0] + 20.0, C[1] + 20.0))
    user.release((C[0] + 20.0, C[1] + 20.0))
    assert ctl.scene.element("fourbar") == original
    assert ctl.undo_stack.index() == 0 and ctl.undo_stack.count() == 1   # redo brings E's move back


def test_a_field_half_typed_when_the_document_is_replaced_commits_nothing(shell, qtbot):
    """Found by the monkey: the crank's law set to a table, '1' typed into its points (no Enter),
    then another example opened: the field lost its focus as the panel was rebuilt and committed
    into a linkage that was gone (UnknownIdError)."""
    parts = shell()
    w, ctl = parts.window, parts.controller
    w.actions["example:double_rocker"].trigger()
    props = w.properties
    law = props.combos["law"]
    law.setCurrentIndex(law.findData("table") if law.findData("table") >= 0 else law.count() - 1)
    law.activated.emit(law.currentIndex())
    edit = props.fields["law.points"]
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    edit.setFocus()
    qtbot.keyClicks(edit, "1")
    assert edit.hasFocus() and edit.isModified()
    parts.dialogs.save_changes.append(DISCARD)
    w.actions["example:rolling_lever_inclined"].trigger()
    view = w.canvas                          # the user clicks on the canvas at once: the focus moves
    qtbot.mouseClick(view.viewport(), Qt.MouseButton.LeftButton, pos=view.viewport().rect().center())
    view.setFocus()
    QApplication.processEvents()
    QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)
    assert "double_rocker" not in ctl.scene.ids and ctl.undo_stack.count() == 0
