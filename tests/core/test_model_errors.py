"""The model raises the project's errors, which are also the builtins they stand for: an unknown id
is an UnknownIdError (a KeyError, printed as its plain message), a refused edit an EditError (a
ValueError). The messages are those the model always gave."""
from __future__ import annotations

import pytest

from mechsketch.core import (AddElement, EditError, MechsketchError, MoveJoint, RemoveElement,
                             UnknownIdError, load_scene)
from mechsketch.resources import example_path
from mechsketch.core.workspace import Workspace


@pytest.fixture
def scene():
    return load_scene(example_path("fourbar_crank_rocker"))


def test_unknown_joint_link_and_element_are_unknown_id_errors(scene):
    lk = scene.element("fourbar")
    cases = [
        (lambda: lk.joint("Z"), "linkage 'fourbar' has no joint 'Z'"),
        (lambda: lk.link("nope"), "linkage 'fourbar' has no link 'nope'"),
        (lambda: lk.with_joint_moved("Z", (0.0, 0.0)), "linkage 'fourbar' has no joint 'Z'"),
        (lambda: scene.element("x"), "scene has no element 'x' (elements: 'fourbar')"),
        (lambda: scene.index_of("x"), "scene has no element 'x' (elements: 'fourbar')"),
        (lambda: scene.without_element("x"), "scene has no element 'x' (elements: 'fourbar')"),
    ]
    for call, message in cases:
        with pytest.raises(UnknownIdError) as info:
            call()
        assert isinstance(info.value, KeyError) and isinstance(info.value, MechsketchError)
        assert str(info.value) == message          # not quoted, as a bare KeyError would be
        assert info.value.args == (message,)


def test_edits_raise_edit_error_or_unknown_id_and_leave_the_document(scene):
    doc = Workspace(scene)
    with pytest.raises(EditError, match="^an element with id 'fourbar' exists already$") as info:
        doc.apply(AddElement(scene.element("fourbar")))
    assert isinstance(info.value, ValueError)
    for edit in (RemoveElement("x"), MoveJoint("fourbar", "Z", (1.0, 2.0)), MoveJoint("x", "B", (1.0, 2.0))):
        with pytest.raises(UnknownIdError):
            doc.apply(edit)
    assert doc.scene is scene
