"""Gear pairs and the smooth (geared) Geneva drive in the app (issue 25, items 3-4): opened from
the Examples menu, drawn from the core's pitch curves and animated by the precomputed rotations
(nothing solved per frame); at every frame the two placed pitch curves touch at the pitch point,
and the Geneva's crank is the gears' output; the properties panel shows the derived figures."""
from __future__ import annotations

import math

import numpy as np
import pytest
from PySide6.QtWidgets import QLabel

from mechsketch.core.analyses.gears import pitch
from mechsketch.core.analyses.geneva import contact as contact_mod, driven

from app_fakes import shell  # noqa: F401 - fixture
from app_fakes import open_example as _open, patch_everywhere


def _world_curve(item, body) -> np.ndarray:
    path = item.path()
    pts = [item.mapToScene(path.elementAt(k).x, path.elementAt(k).y) for k in range(path.elementCount())]
    return np.array([[p.x(), p.y()] for p in pts])


def _touch(gears) -> float:
    """The gap (mm) between the two placed pitch curves at the shown frame."""
    a = _world_curve(gears.items["input_gear"], gears.input)
    b = _world_curve(gears.items["output_gear"], gears.output)
    return float(np.min(np.linalg.norm(a[:, None, :] - b[None, ::4, :], axis=2)))


def test_the_elliptic_gears_turn_in_contact(shell, monkeypatch):
    parts, c, view = _open(shell, "gears_elliptic")
    item = view.element_items["ellipses"]
    res = c.element_result("ellipses")
    assert item.gears is not None and res.n_frames == res.element.samples

    def boom(*a, **k):
        raise AssertionError("the animation solved something")
    for func in (pitch.kinematics, pitch.checks, pitch.curves):
        patch_everywhere(monkeypatch, func, boom)
    a = res.element.center_distance
    for k in (0, 50, 200, 333, 600):
        c.set_frame(k)
        assert item.input_rotation() == pytest.approx(math.remainder(res.input_rotation[item.index], 2 * math.pi),
                                                      abs=1e-9)
        assert _touch(item.gears) < 2e-3 * a        # polylines of 400 points: they touch at the pitch point
    view.grab()
    c.set_selection([("ellipses", "element", "ellipses")])
    texts = " ".join(w.text() for w in parts.window.properties.findChildren(QLabel))
    assert "ψ' from 0.5385 to 1.857" in texts and "convex" in texts


def test_the_smooth_geneva_drive_turns_its_crank_by_the_gears(shell, monkeypatch):
    parts, c, view = _open(shell, "smooth_geneva_z5")
    item = view.element_items["indexer"]
    res = c.element_result("indexer")
    assert item.gears is not None and res.gears is not None
    for func in (driven.driven_kinematics, contact_mod.contact):
        patch_everywhere(monkeypatch, func, lambda *a, **k: (_ for _ in ()).throw(AssertionError("solved")))
    g = res.element
    for k in (0, 700, 1300, 1800, 2500):
        c.set_frame(k)
        j = item.index
        # the crank turns as the gears' output: world rotation = direction + φ_j, and the output gear
        # turned by the same angle from its built frame (its line of centres points back to the input)
        assert item.crank_rotation() == pytest.approx(math.remainder(res.crank_rotation[j], 2 * math.pi), abs=1e-9)
        out = item.gears.output.transform()
        out_rot = math.atan2(out.m12(), out.m11())
        assert math.remainder(out_rot - res.gears.output_rotation[j], 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        step = math.remainder(res.gears.output_rotation[j] - res.gears.output_rotation[0], 2 * math.pi)
        turn = math.remainder(res.crank_rotation[j] - res.crank_rotation[0], 2 * math.pi)
        assert step == pytest.approx(turn, abs=1e-9)
        assert _touch(item.gears) < 2e-3 * res.composite.center_distance
    assert "smooth Geneva drive" in item.label_text
    view.grab()
    c.set_selection([("indexer", "element", "indexer")])
    texts = " ".join(w.text() for w in parts.window.properties.findChildren(QLabel))
    assert "jump" in texts and "% less" in texts
    diag = " ".join(parts.window.diagnostics.plain_text().split())
    assert "peak jerk" in diag and "geared Geneva 'indexer'" in diag
    assert g.slots == 5
