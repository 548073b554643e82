"""PRP and RPP dyads and Insert, drawn by clicks and checked against closed forms and the core."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtCore import QRectF

from canvas_user import make_view
from mechsketch.core.model.linkage import JointKind
from mechsketch.core.model.transform import extent
from mechsketch.gui.canvas.insert_tool import insert_menu
from test_tools_build import build_fourbar


def test_a_six_bar_with_a_prp_group_on_the_rocker_and_the_frame(qtbot):
    ctl, view, user = make_view(qtbot, window=QRectF(-60.0, -60.0, 320.0, 260.0))
    build_fourbar(user)                         # A, B pivots; crank A-C; RRR C-D-B (link2 = rocker B-D)
    user.tool("prp")
    user.click((145, 55))                       # guide 1 on the rocker (the 5 mm grid keeps it)
    user.click((100, 150))                      # the pin
    user.click((0, 150))                        # guide 2 on the frame, horizontal through the pin
    lk = ctl.linkages()[0]
    pin = lk.joint("E")
    s1, s2 = lk.joint("F"), lk.joint("G")
    assert pin.kind is JointKind.R and s1.kind is s2.kind is JointKind.P and pin.at == s1.at == s2.at == (100.0, 150.0)
    assert "F" in lk.link("link2").joints and "G" in lk.link("ground").joints
    assert s1.axis_deg == pytest.approx(math.degrees(math.atan2(95.0, -45.0))) and s2.axis_deg == pytest.approx(0.0)
    plan = ctl.workspace.plan(lk.id)
    assert [str(g.kind) for g in plan.groups] == ["RRR", "PRP"]
    res = ctl.result(lk.id)
    assert res.ok and res.diagnostics.full_turn and ctl.undo_stack.count() == 5
    sol = res.solution
    e = sol.position("E")
    np.testing.assert_allclose(e[:, 1], 150.0, atol=1e-9)               # on the frame's guide
    g0, g1 = sol.point("link2", (145.0, 55.0)), sol.point("link2", (100.0, 150.0))
    d = g1 - g0
    cross = d[:, 0] * (e - g0)[:, 1] - d[:, 1] * (e - g0)[:, 0]
    assert np.max(np.abs(cross) / np.linalg.norm(d, axis=1)) < 1e-9      # and on the rocker's guide
    view.grab()


def test_prp_refuses_two_guides_on_the_frame_and_parallel_guides(qtbot):
    ctl, view, user = make_view(qtbot)
    build_fourbar(user)
    user.tool("prp")
    ctl.set_selection([("linkage1", "joint", "A")])
    user.click((0, 150))
    user.click((100, 150))
    user.click((100, 200))                      # frame again
    assert "both guides are on the frame" in view.messages[-1]
    assert len(ctl.linkages()[0].joints) == 4


def test_a_scotch_yoke_by_the_rpp_tool(qtbot):
    ctl, view, user = make_view(qtbot)
    user.tool("ground")
    user.click((0, 0))
    user.tool("crank")
    user.click((0, 0))
    user.click((40, 0))
    user.tool("rpp")
    user.click((40, 0))                         # M: the crank tip B
    user.click((100, 50))                       # the guide's start, on the frame
    user.click((40, 50))                        # the yoke point: slot vertical, guide horizontal
    lk = ctl.linkages()[0]
    q, s = lk.joint("C"), lk.joint("D")
    assert q.kind is s.kind is JointKind.P and q.at == (40.0, 0.0) and s.at == (40.0, 50.0)
    assert q.axis_deg == pytest.approx(90.0) and s.axis_deg == pytest.approx(180.0)
    assert [str(g.kind) for g in ctl.workspace.plan(lk.id).groups] == ["RPP"]
    res = ctl.result(lk.id)
    assert res.ok and res.diagnostics.full_turn
    sol = res.solution
    yoke = sol.position("D")
    np.testing.assert_allclose(yoke[:, 0], 40.0 * np.cos(sol.input), atol=1e-9)   # x = r cos θ
    np.testing.assert_allclose(yoke[:, 1], 50.0, atol=1e-9)


class _Dialogs:
    def __init__(self, path=None):
        self.path, self.errors = path, []

    def open_file_name(self, *a, **k):
        return self.path

    def error(self, title, text, details=""):
        self.errors.append(text)


def test_insert_places_an_example_where_clicked_renaming_what_collides(qtbot, tmp_path):
    ctl, view, user = make_view(qtbot, window=QRectF(-200.0, -200.0, 800.0, 600.0))
    menu = insert_menu(view, _Dialogs())
    act = next(a for a in menu.actions() if a.objectName() == "insert:fourbar_crank_rocker")
    act.trigger()
    assert view.toolbox.name == "insert"
    user.click((300, 100))
    (el,) = ctl.scene.elements
    x0, y0, x1, y1 = extent(el)
    assert ((x0 + x1) / 2, (y0 + y1) / 2) == pytest.approx((300.0, 100.0))
    act.trigger()
    user.click((0, 0))
    assert ctl.scene.ids == ("fourbar", "fourbar2") and ctl.undo_stack.count() == 2
    assert "renamed fourbar → fourbar2" in view.messages[-1]
    assert ctl.result("fourbar2").ok and ctl.result("fourbar").ok
    ctl.undo_stack.undo()
    assert ctl.scene.ids == ("fourbar",)


def test_insert_a_saved_scene_file_with_several_elements_is_one_undo_step(qtbot, tmp_path):
    from mechsketch.core import Scene, load_scene, save_scene
    from mechsketch.resources import example_path

    a = load_scene(example_path("geneva_z6")).elements[0]
    b = load_scene(example_path("fourbar_crank_rocker")).elements[0]
    path = tmp_path / "two.json"
    save_scene(Scene((a, b)), path)
    ctl, view, user = make_view(qtbot, window=QRectF(-200.0, -200.0, 800.0, 600.0))
    menu = insert_menu(view, _Dialogs(str(path)))
    next(x for x in menu.actions() if x.objectName() == "insert:file").trigger()
    user.click((200, 0))
    assert ctl.scene.ids == ("indexer", "fourbar") and ctl.undo_stack.count() == 1
    assert ctl.element_result("indexer").ok
    menu2 = insert_menu(view, _Dialogs(str(tmp_path / "missing.json")))
    next(x for x in menu2.actions() if x.objectName() == "insert:file").trigger()
    assert "cannot insert" in view.messages[-1] and ctl.scene.ids == ("indexer", "fourbar")
