"""Every property field shows what the model holds after every accepted or refused edit, also when
the previous value is typed back into the same field (issue 10 item 6; these tests failed first:
the field kept the text of its last refresh while it had the focus, so typing the old value back
looked like "no change", and a refusal put back a stale number). The window is activated so that
the field really has the focus, as it has for a user (offscreen it would not, hiding the bug)."""
from __future__ import annotations

import math

from app_fakes import shell  # noqa: F401 - fixture
from app_fakes import type_into as _type_into


def type_into(qtbot, edit, text: str) -> None:
    """Type as a user at a real display does: the window active and the field holding the focus
    (offscreen, a window is not active unless asked, and then no widget has the focus)."""
    window = edit.window()
    if not window.isActiveWindow():
        window.activateWindow()
    edit.setFocus()
    qtbot.waitUntil(edit.hasFocus, timeout=20000)
    _type_into(qtbot, edit, text)


def crank_length(c) -> float:
    lk = c.scene.element("fourbar")
    return math.dist(lk.joint("A").at, lk.joint("B").at)


def test_crank_40_50_40_in_the_same_field_leaves_40_in_the_model(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "link", "crank")])
    field = props.fields["length:A-B"]
    type_into(qtbot, field, "50")
    assert crank_length(c) == 50.0 or abs(crank_length(c) - 50.0) < 1e-12
    assert field is props.fields["length:A-B"]   # the same field, still focused
    type_into(qtbot, field, "40")
    assert abs(crank_length(c) - 40.0) < 1e-12
    assert float(field.text()) == 40.0
    assert c.undo_stack.count() == 2


def test_geneva_slots_6_8_6_leaves_6_in_the_model(shell, qtbot):
    from mechsketch.resources import example_path

    parts = shell(example_path("geneva_z6"))
    c, props = parts.controller, parts.window.properties
    eid = c.scene.elements[0].id
    c.set_selection([(eid, "element", eid)])
    field = props.fields["slots"]
    assert field.text() == "6"
    type_into(qtbot, field, "8")
    assert c.scene.element(eid).slots == 8
    type_into(qtbot, field, "6")
    assert c.scene.element(eid).slots == 6 and field.text() == "6"


def test_a_refused_value_shows_the_models_value_not_a_stale_one(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "link", "crank")])
    field = props.fields["length:A-B"]
    type_into(qtbot, field, "50")
    type_into(qtbot, field, "-7")           # refused: a length must be positive
    assert abs(crank_length(c) - 50.0) < 1e-12
    assert float(field.text()) == 50.0      # the model's value, not the 40 shown before the edit
    type_into(qtbot, field, "abc")          # not a number
    assert float(field.text()) == 50.0


def test_a_joint_coordinate_typed_back_is_applied(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "joint", "D")])
    field = props.fields["x"]
    type_into(qtbot, field, "170")
    type_into(qtbot, field, "160")
    assert c.scene.element("fourbar").joint("D").at[0] == 160.0 and field.text() == "160"


def test_after_an_undo_the_value_shown_before_it_can_be_typed_again(shell, qtbot):
    parts = shell()
    c, props = parts.controller, parts.window.properties
    c.set_selection([("fourbar", "link", "crank")])
    field = props.fields["length:A-B"]
    type_into(qtbot, field, "50")
    parts.window.actions["undo"].trigger()
    assert abs(crank_length(c) - 40.0) < 1e-6 and float(field.text()) == 40.0   # the file holds 39.9999999997
    type_into(qtbot, field, "50")
    assert abs(crank_length(c) - 50.0) < 1e-12 and c.undo_stack.count() == 1
