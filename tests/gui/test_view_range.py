"""Drawing gaps (issue 24, item 6): the zoom range follows the scene (a 160 m mechanism is seen
whole), a newly placed Geneva drive that does not fit is brought into view, and a new document
starts without the old one's centrodes overlay or tool."""
from __future__ import annotations

from PySide6.QtCore import QRectF

from app_fakes import DISCARD, shell  # noqa: F401 - fixture
from canvas_user import User
from mechsketch.core import Scene, load_scene
from mechsketch.resources import example_path


def _huge_fourbar(factor: float = 1000.0):
    lk = load_scene(example_path("fourbar_crank_rocker")).elements[0]
    return lk.with_joints_moved({j.id: (j.at[0] * factor, j.at[1] * factor) for j in lk.joints})


def test_a_160_m_mechanism_is_seen_whole_and_zoom_reaches_past_it(shell, qtbot):
    parts = shell()
    view = parts.window.canvas
    parts.controller.reset(Scene((_huge_fourbar(),)), None)   # ground 160 m
    view.zoom_to_fit()
    shown = view.mapToScene(view.viewport().rect()).boundingRect()
    ext = view.extent()
    assert ext.width() > 150_000 and shown.contains(ext)
    for _ in range(40):                                 # the wheel zooms further out than the fit
        view.zoom_by(0.8)
    out = view.mapToScene(view.viewport().rect()).boundingRect()
    assert out.width() >= 2.5 * ext.width()
    lo, _hi = view.scale_range()
    assert abs(view.transform().m11()) >= lo * 0.999


def test_a_new_geneva_drive_that_does_not_fit_is_brought_into_view(shell, qtbot):
    parts = shell()
    view, ctl = parts.window.canvas, parts.controller
    view.zoom_to_rect(QRectF(-50, -50, 300, 250))
    user = User(qtbot, view)
    user.tool("geneva")
    user.click((150.0, 50.0))                           # the crank centre in view ...
    user.click((1150.0, 50.0))                          # ... the wheel 1 m away, off screen
    eid = next(e.id for e in ctl.scene.elements if e.type == "geneva")
    shown = view.mapToScene(view.viewport().rect()).boundingRect()
    assert shown.contains(view.element_items[eid].extent())
    assert shown.contains(QRectF(0, 0, 160, 120))      # and the four-bar is still in view


def test_a_new_document_drops_the_old_centrodes_overlay(shell, qtbot):
    parts = shell()
    w, ctl = parts.window, parts.controller
    view = w.canvas
    ctl.set_selection([("fourbar", "link", "coupler")])
    view.extras.actions["centrodes"].setChecked(True)
    assert view.extras.overlays.shown["centrodes"]
    parts.dialogs.save_changes.append(DISCARD)
    w.actions["example:double_rocker"].trigger()
    assert not view.extras.actions["centrodes"].isChecked() and not view.extras.overlays.shown["centrodes"]
