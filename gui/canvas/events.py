"""The small event type the canvas tools consume, so tools are testable without Qt events.

The view turns each Qt mouse event into a :class:`CanvasEvent` in world millimetres (y up),
already snapped when snapping is on, with the element under the cursor found by
:func:`mechsketch.gui.canvas.pose.pick`. A test builds the same events by hand::

    ev = CanvasEvent("press", (40.0, 60.0), hit=Hit("fourbar", "joint", "B"))
    tool.handle(ev)
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

XY = tuple[float, float]


class Hit(NamedTuple):
    """What is under the cursor: ``(element id, "joint" | "link", id)`` - the selection format."""

    element: str
    kind: str
    id: str


@dataclass(frozen=True)
class CanvasEvent:
    """One mouse event on the canvas.

    Attributes
    ----------
    kind : "press" | "move" | "release" | "double"
    pos : world position in mm (snapped to the grid or a joint when snapping is on)
    raw : world position in mm before snapping (defaults to ``pos``)
    button : the button that changed ("left", "right", "middle"; "none" for a move)
    buttons : buttons held during the event
    modifiers : subset of {"shift", "ctrl", "alt"}
    hit : the joint or link under the cursor, or None
    tolerance : the pick radius at the current zoom, mm
    """

    kind: str
    pos: XY
    raw: XY | None = None
    button: str = "left"
    buttons: frozenset[str] = field(default_factory=frozenset)
    modifiers: frozenset[str] = field(default_factory=frozenset)
    hit: Hit | None = None
    tolerance: float = 1.0

    def __post_init__(self) -> None:
        if self.kind not in ("press", "move", "release", "double"):
            raise ValueError(f"CanvasEvent kind must be press, move, release or double, got {self.kind!r}")
        if self.raw is None:
            object.__setattr__(self, "raw", self.pos)

    @property
    def left(self) -> bool:
        """The left button changed (press/release) or is held (move)."""
        return self.button == "left" or (self.kind == "move" and "left" in self.buttons)

    @property
    def shift(self) -> bool:
        return "shift" in self.modifiers
