"""Drawing gaps (issue 24, item 6): a link that carries a moving guide is drawn joined to it — the
excavator's cylinder barrel from its pivot C1 to the slide (C1 floated before), a guide on a
rocker from the rocker's joints to the rail."""
from __future__ import annotations

import pytest

from mechsketch.core import load_scene
from mechsketch.core.model.linkage import JointKind
from mechsketch.gui.canvas.pose import drawn_pose, link_outline, slider_roles
from mechsketch.gui.controller import SceneController
from mechsketch.gui.canvas.pose import PoseCache
from mechsketch.resources import example_path


@pytest.mark.parametrize("example", ["excavator_arm", "sixbar_moving_guide"])
def test_a_link_carrying_a_moving_guide_is_drawn_joined_to_it(qtbot, example):
    ctl = SceneController(load_scene(example_path(example)))
    lk = ctl.linkages()[0]
    moving = [(j.id, slider_roles(lk, j.id)[0]) for j in lk.joints
              if j.kind is JointKind.P and slider_roles(lk, j.id)[0] not in ("", lk.ground)]
    assert moving, "the example has a guide on a moving link"
    for pose in (drawn_pose(lk), PoseCache().poses(ctl, 0)[0]):
        for jid, guide in moving:
            outline = link_outline(pose, guide)
            ends = [complex(*e) for e in pose.guide[jid]]
            assert len(outline) >= 2, f"{guide} is not drawn"
            assert any(min(abs(p - e) for e in ends) < 1e-9 for p in outline), f"{guide} is detached from its guide"
            others = [complex(*pose.at[j]) for j in lk.link(guide).joints if j != jid]
            assert all(any(abs(p - o) < 1e-9 for p in outline) for o in others)
