"""Dragging on the canvas: live re-solve with one undo command, the crank turning the input,
impossible drags, and editing at an animation frame."""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import Qt

from canvas_user import example, fourbar_by_formula, make_view
from mechsketch.core.model.linkage import JointKind


def lengths(lk) -> dict[tuple[str, str, str], float]:
    """Distances between the revolute joints of every link (what a rigid motion keeps)."""
    out = {}
    for link in lk.links:
        revs = [lk.joint(j) for j in link.joints if lk.joint(j).kind is JointKind.R]
        for a in range(len(revs)):
            for b in range(a + 1, len(revs)):
                out[(link.id, revs[a].id, revs[b].id)] = math.dist(revs[a].at, revs[b].at)
    return out


def test_dragging_a_joint_resolves_live_and_commits_one_command(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    before = ctl.scene
    c0 = ctl.scene.element("fourbar").joint("C").at
    trace0 = view._items["fourbar"].trace.traces[0].boundingRect()
    seen = []
    changes = []
    ctl.changed.connect(lambda ch: (changes.append(ch), seen.append(ctl.result("fourbar").solution)))
    user.drag(c0, (140.0, 100.0), steps=5, release=False)
    # while dragging: no history, the document and the whole cycle re-solved at every move;
    # each move is one preview change naming only the dragged linkage
    assert ctl.undo_stack.count() == 0
    assert changes and all(ch.preview and ch.ids == {"fourbar"} for ch in changes)
    assert ctl.scene.element("fourbar").joint("C").at == (140.0, 100.0)
    # one new solution per move that changed the (grid-snapped) position, none for the others
    assert len({id(s) for s in seen}) == len(changes) >= 3
    sol = ctl.result("fourbar").solution
    assert len(sol) == 360 and np.allclose(sol.position("C")[0], (140.0, 100.0))
    assert view._items["fourbar"].trace.traces[0].boundingRect() != trace0   # coupler curve redrawn
    n_previews = len(changes)
    user.release((140.0, 100.0))
    assert ctl.undo_stack.count() == 1 and ctl.undo_stack.text(0) == "move joint C"
    assert len(changes) == n_previews + 1 and not changes[-1].preview   # one final change on release
    moved = ctl.scene
    sol = ctl.result("fourbar").solution
    for k in (10, 123, 300):
        want = fourbar_by_formula(0j, complex(20.0, 34.641016151), 140 + 100j, 160 + 0j, float(sol.input[k]))
        assert abs(complex(*sol.position("C")[k]) - want) < 1e-9
    ctl.undo_stack.undo()
    assert ctl.scene == before
    ctl.undo_stack.redo()
    assert ctl.scene == moved


def test_an_impossible_drag_explains_and_leaves_the_document_consistent(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    before = ctl.scene
    c0 = ctl.scene.element("fourbar").joint("C").at
    # pull C onto D: the rocker D-C would have no length, so the dyad cannot close
    user.drag(c0, (160.0, 0.0), steps=1, release=False)
    assert "would be at the same point" in view.messages[-1] and "zero length" in view.messages[-1]
    assert view._overlay.overlay.bad
    assert ctl.scene.element("fourbar").joint("C").at == c0          # nothing impossible was shown
    user.release((160.0, 0.0))
    assert ctl.scene == before and ctl.undo_stack.count() == 0 and not ctl.is_dirty
    assert ctl.result("fourbar").ok
    # dragging towards D and then onto it keeps the last possible position, as one command
    user.drag(c0, (150.0, 40.0), steps=3, release=False)
    user.qtbot.mouseMove(user.vp, user.at((160.0, 0.0)))
    user.release((160.0, 0.0))
    assert ctl.undo_stack.count() == 1
    assert ctl.scene.element("fourbar").joint("C").at == (150.0, 40.0)
    assert ctl.result("fourbar").error is None
    ctl.undo_stack.undo()
    assert ctl.scene == before and ctl.result("fourbar").ok


def test_a_drag_that_breaks_the_full_turn_shows_the_limits_live(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    d0 = ctl.scene.element("fourbar").joint("D").at
    user.drag(d0, (160.0, 100.0), steps=4, release=False)  # short rocker, long frame: no full turn
    res = ctl.result("fourbar")
    assert res.ok and not res.diagnostics.full_turn
    assert "reaches only" in view.messages[-1]
    assert not view._items["fourbar"].trace.circle_bad.isEmpty()   # infeasible arc drawn in red
    assert view._items["fourbar"].dead.marks                          # limits marked on the canvas
    view.grab()
    user.release((160.0, 100.0))
    assert ctl.undo_stack.count() == 1


def test_dragging_the_crank_turns_the_input_without_an_undo_command(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    before = ctl.scene
    started, finished = [], []
    view.dragStarted.connect(lambda: started.append(1))
    view.dragFinished.connect(lambda: finished.append(1))
    r = 40.0
    user.press((10.0, 17.320508))                 # on the crank bar, between A and B
    for deg in range(70, 151, 10):
        user.qtbot.mouseMove(user.vp, user.at((r * math.cos(math.radians(deg)), r * math.sin(math.radians(deg)))))
    user.release((r * math.cos(math.radians(150)), r * math.sin(math.radians(150))))
    sol = ctl.result("fourbar").solution
    assert math.degrees(float(sol.input[ctl.frame])) % 360 == approx_deg(150.0, 1.0)
    assert ctl.scene == before and ctl.undo_stack.count() == 0
    assert started == [1] and finished == [1]
    # the canvas shows that frame
    pose = view.ctx.pose("fourbar")
    assert pose.index == ctl.frame
    assert np.allclose(pose.at["C"], sol.position("C")[ctl.frame])


class approx_deg:  # noqa: N801 - reads like pytest.approx
    def __init__(self, value: float, tol: float) -> None:
        self.value, self.tol = value, tol

    def __eq__(self, other: object) -> bool:
        return abs(math.remainder(float(other) - self.value, 360.0)) <= self.tol

    def __repr__(self) -> str:
        return f"{self.value}° ± {self.tol}°"


def test_pulling_the_crank_past_a_limit_stops_there_and_never_jumps(qtbot):
    ctl, view, user = make_view(qtbot, example("double_rocker"))
    before = ctl.scene
    res = ctl.result("double_rocker")
    sol = res.solution
    (lo, hi), = res.diagnostics.reachable
    frames = []
    start = ctl.frame
    ctl.frameChanged.connect(frames.append)
    r = 45.0
    user.press((0.0, r))                          # the input link A(0,0)-B(0,90), vertical
    for deg in range(95, 200, 5):                 # pull it round through the infeasible range
        user.qtbot.mouseMove(user.vp, user.at((r * math.cos(math.radians(deg)), r * math.sin(math.radians(deg)))))
    assert any("cannot be assembled at input" in m for m in view.messages)
    assert frames and all(sol.valid[f] for f in frames)
    steps = np.abs(np.diff([start] + frames))
    assert (np.minimum(steps, len(sol) - steps) <= 40).all()     # small moves only: no jump
    limit = math.degrees(max(lo, hi))
    assert math.degrees(float(sol.input[ctl.frame])) <= limit + 1e-9
    assert math.degrees(float(sol.input[ctl.frame])) > limit - 0.6
    user.release((r * math.cos(math.radians(195)), r * math.sin(math.radians(195))))
    assert ctl.scene == before and ctl.undo_stack.count() == 0


def test_editing_at_an_animation_frame_keeps_the_mechanism_and_shows_no_jump(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    before = ctl.scene.element("fourbar")
    ctl.set_frame(90)
    shown = dict(view.ctx.pose("fourbar").at)
    # drag the coupler point E (it changes no other length)
    user.drag(shown["E"], (40.0, 130.0), steps=3)
    after = ctl.scene.element("fourbar")
    assert ctl.frame == 0 and ctl.undo_stack.count() == 1
    keep = {k: v for k, v in lengths(before).items() if "E" not in k}
    got = lengths(after)
    for k, v in keep.items():
        assert abs(got[k] - v) < 1e-9
    pose = view.ctx.pose("fourbar")
    for j in "ABCD":
        assert np.allclose(pose.at[j], shown[j], atol=1e-9)    # everything else stays where it was
    assert np.allclose(pose.at["E"], (40.0, 130.0), atol=1e-9)
    # same linkage, drawn at another input angle: the cycle is the same curve for C
    c_before = ctl.result("fourbar").solution.position("C")
    ctl.undo_stack.undo()
    assert ctl.scene.element("fourbar") == before
    c_orig = ctl.result("fourbar").solution.position("C")
    d = np.abs(c_before[:, None, 0] + 1j * c_before[:, None, 1] - (c_orig[None, :, 0] + 1j * c_orig[None, :, 1]))
    assert d.min(axis=1).max() < 3.0     # every point of one path lies on the other (within a sample)


def test_dragging_a_slider_pin_moves_its_p_joint_with_it(qtbot):
    ctl, view, user = make_view(qtbot, example("slider_crank_offset"))
    c0 = ctl.scene.element("slider_crank").joint("C").at
    user.drag(c0, (200.0, 30.0), steps=3)
    lk = ctl.scene.element("slider_crank")
    assert lk.joint("C").at == lk.joint("S").at == (200.0, 30.0)
    assert ctl.undo_stack.count() == 1 and ctl.result("slider_crank").ok
    y = ctl.result("slider_crank").solution.position("C")[:, 1]
    np.testing.assert_allclose(y, 30.0, atol=1e-9)      # the guide moved with the block


def test_escape_cancels_a_drag(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    before = ctl.scene
    c0 = before.element("fourbar").joint("C").at
    user.drag(c0, (140.0, 100.0), steps=2, release=False)
    assert ctl.scene != before
    user.qtbot.keyClick(view, Qt.Key.Key_Escape)
    assert ctl.scene == before and not view.ctx.hold_frame
    user.release((140.0, 100.0))
    assert ctl.scene == before and ctl.undo_stack.count() == 0


def test_rubber_band_and_shift_click_selection(qtbot):
    ctl, view, user = make_view(qtbot, example("fourbar_crank_rocker"))
    user.drag((-20.0, -20.0), (70.0, 60.0), steps=3)       # around A and B
    assert set(ctl.selection) == {("fourbar", "joint", "A"), ("fourbar", "joint", "B"),
                                  ("fourbar", "link", "crank")}
    user.click((160.0, 0.0), modifiers=Qt.KeyboardModifier.ShiftModifier)
    assert ("fourbar", "joint", "D") in ctl.selection and len(ctl.selection) == 4
    user.click((230.0, 180.0))                             # empty space clears
    assert ctl.selection == []
