"""A simulated user for the canvas tests: clicks and drags at world points (mm) via pytest-qt.

Used by tests/gui/test_canvas*.py, test_tools*.py and test_animation*.py (not a test module).
"""
from __future__ import annotations

import cmath
import math

import numpy as np
from PySide6.QtCore import QPoint, QPointF, QRectF, Qt

from mechsketch.core import load_scene
from mechsketch.gui.canvas.view import CanvasView
from mechsketch.gui.controller import SceneController
from mechsketch.resources import example_path

#: world window shown by the tests (mm) at 900 x 700 px: 2.33 px/mm, grid (and snap) step 10 mm
WINDOW = QRectF(-60.0, -100.0, 320.0, 300.0)


def example(name: str):
    return load_scene(example_path(name))


class User:
    """Drives a :class:`CanvasView` with real mouse events at world coordinates."""

    def __init__(self, qtbot, view: CanvasView) -> None:
        self.qtbot = qtbot
        self.view = view
        self.vp = view.viewport()

    def at(self, xy) -> QPoint:
        return self.view.mapFromScene(QPointF(float(xy[0]), float(xy[1])))

    def tool(self, name: str) -> None:
        self.view.toolbox.actions[name].trigger()

    def move(self, xy, buttons: bool = False) -> None:
        self.qtbot.mouseMove(self.vp, self.at(xy))

    def click(self, xy, button=Qt.MouseButton.LeftButton, modifiers=Qt.KeyboardModifier.NoModifier) -> None:
        self.move(xy)
        self.qtbot.mouseClick(self.vp, button, modifiers, self.at(xy))

    def press(self, xy) -> None:
        self.move(xy)
        self.qtbot.mousePress(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, self.at(xy))

    def release(self, xy) -> None:
        self.qtbot.mouseRelease(self.vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, self.at(xy))

    def drag(self, a, b, steps: int = 6, release: bool = True) -> None:
        """Press at ``a``, move in ``steps`` to ``b`` (and release)."""
        self.press(a)
        for t in np.linspace(0.0, 1.0, steps + 1)[1:]:
            p = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
            self.qtbot.mouseMove(self.vp, self.at(p))
        if release:
            self.release(b)


def make_view(qtbot, scene=None, window: QRectF = WINDOW) -> tuple[SceneController, CanvasView, User]:
    """A controller and a shown canvas (900 x 700) looking at ``window``."""
    ctl = SceneController(scene)
    view = CanvasView(ctl)
    qtbot.addWidget(view)
    view.resize(900, 700)
    view.show()
    qtbot.waitExposed(view)
    view.zoom_to_rect(window)
    messages: list[str] = []
    ctl.message.connect(messages.append)
    view.messages = messages  # type: ignore[attr-defined]
    return ctl, view, User(qtbot, view)


def circle_intersection(c1: complex, r1: float, c2: complex, r2: float, side: float) -> complex:
    """The intersection of two circles left (side > 0) or right of c1 -> c2, computed from scratch."""
    d = abs(c2 - c1)
    a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h = math.sqrt(max(r1 * r1 - a * a, 0.0))
    u = (c2 - c1) / d
    return c1 + a * u + math.copysign(1.0, side) * h * u * 1j


def fourbar_by_formula(a: complex, b: complex, c: complex, d: complex, theta: float) -> complex:
    """Where C is when the crank A-B is at angle ``theta``, the assembly mode taken from the drawing."""
    side = ((d - b).conjugate() * (c - b)).imag
    b_t = a + abs(b - a) * cmath.exp(1j * theta)
    return circle_intersection(b_t, abs(c - b), d, abs(c - d), side)
