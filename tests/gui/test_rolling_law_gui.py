"""A rolling lever with a prescribed slider law (issue 25, item 2) in the app: drawn with its
derived lever element Π30 (no slider circle), animated, the lever's contact on Π30 carried with the
lever onto P0, the properties panel showing the law, no slider-circle handles."""
from __future__ import annotations

import numpy as np
from PySide6.QtWidgets import QLabel

from mechsketch.core import Scene, load_scene
from mechsketch.core.design.rolling import design_rolling, requirements_of
from mechsketch.gui import units
from mechsketch.resources import example_path

from app_fakes import shell  # noqa: F401 - fixture


def _dense(item, n=1500):
    path = item.path()
    return np.array([[q.x(), q.y()] for q in (item.mapToScene(path.pointAtPercent(float(t)))
                                               for t in np.linspace(0, 1, n))])


def test_a_law_lever_is_drawn_animated_and_shown(shell, qtbot):
    press = load_scene(example_path("rolling_lever_press")).elements[0]
    req = requirements_of(press)
    req["slider_law"] = {"law": "constant", "travel": 50.43}
    el = design_rolling(req, "press").element
    parts = shell()
    c, view = parts.controller, parts.window.canvas
    c.reset(Scene((el,)), None)
    res = c.element_result("press")
    assert res.error is None and len(res.lever_profile_e) > 10
    item = view.element_items["press"]
    assert {"frame_profile", "slider_profile", "slider_arc", "lever_arc"} <= set(item.paths)
    for k in (0, res.n_frames // 3, res.n_frames // 2):
        c.set_frame(k)
        fr = res.frames
        # the lever element, carried by the lever, passes through the pair-E contact P0 of the frame
        pts = _dense(item.paths["slider_arc"])
        assert np.min(np.linalg.norm(pts - fr.P0[k], axis=1)) < 0.05
        # and the slider profile, carried by the slider, touches it there too
        sp = _dense(item.paths["slider_profile"])
        assert np.min(np.linalg.norm(sp - fr.P0[k], axis=1)) < 0.05
    view.grab()
    c.set_selection([("press", "element", "press")])
    texts = " ".join(w.text() for w in parts.window.properties.findChildren(QLabel))
    texts = units.plain(texts)   # shown with each value kept on one line with its unit
    assert "S5(θ): constant, travel 50.43 mm" in texts
    assert "slider_circle.radius" not in parts.window.properties.fields
    from mechsketch.gui.canvas.handles import rolling_handles
    names = {h.name for h in rolling_handles(el, res, 0)}
    assert "slider_centre" not in names and "pin" in names
