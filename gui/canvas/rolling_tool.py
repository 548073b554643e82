"""The rolling-lever tool: place the lever circle, the pin, the rocker pivot, the slider circle and
the slider axis with seven clicks; the profiles are synthesised when the last one lands.

1. the lever circle's centre, 2. a point on it (its radius R1), 3. the pin f, 4. the rocker pivot
G (the rocker line from G through f must meet the lever circle: the contact P of pair D is shown),
5. the slider circle's centre, 6. a point on it (R2), 7. a point giving the slider axis' direction
from the slider circle's centre (the contact P0 of pair E is shown). From the fourth click on the
preview states the working range of the lever (θ, rad, from the drawn pose). The stroke is chosen
inside it: 60 % of the longer side, halved until the synthesis succeeds. One undo step adds the
element; handles (:mod:`.handles`) reshape it afterwards, re-synthesised live.
"""
from __future__ import annotations

import math

from mechsketch.core.analyses.rolling.exact import working_range
from mechsketch.core.analyses.rolling.geometry import LeverGeometry
from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.rolling_lever import Circle, RollingLever, Stroke, parse

from ..selection import ELEMENT
from . import ops
from .events import XY, CanvasEvent
from .items import Overlay
from .tool_base import Tool

STEPS = ("the lever circle's centre", "a point on the lever circle (its radius)", "the pin f",
         "the rocker pivot G", "the slider circle's centre", "a point on the slider circle (its radius)",
         "a point giving the slider axis' direction")
#: fraction of the longer side of the working range the default stroke takes
STROKE_FRACTION = 0.6


def _dist(a: XY, b: XY) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


def lever_from(points: list[XY], eid: str = "lever", stroke: tuple[float, float] = (0.0, -0.1)) -> RollingLever:
    """The element from the seven placement points (mm), with a stand-in slider before the
    fifth (a circle about the lever's centre so large that pair E never limits the motion)."""
    c1, on1, pin, pivot = points[:4]
    lever = Circle((float(c1[0]), float(c1[1])), _dist(c1, on1))
    if len(points) >= 7:
        c2, on2, ax = points[4:7]
        slider = Circle((float(c2[0]), float(c2[1])), _dist(c2, on2))
        axis = math.degrees(math.atan2(ax[1] - c2[1], ax[0] - c2[0]))
    else:
        slider = Circle(lever.center, 1e3 * max(lever.radius, _dist(pin, pivot)))
        axis = 0.0
    return RollingLever(eid, lever, (float(pin[0]), float(pin[1])), (float(pivot[0]), float(pivot[1])), slider,
                        Stroke(*stroke), slider_axis_deg=axis)


def problems_of(el: RollingLever) -> str | None:
    """The model's objections (None if the drawn pose is sound)."""
    _, probs = parse(el.to_dict(), "$")
    return "; ".join(p.message for p in probs) if probs else None


def range_of(el: RollingLever) -> tuple[float, float] | str:
    """The working range (lower, upper) rad from the drawn pose, or why there is none."""
    try:
        wr = working_range(LeverGeometry.from_element(el))
    except MechsketchError as exc:
        return str(exc)
    return (float(wr.lower), float(wr.upper))


def default_strokes(rng: tuple[float, float]) -> list[tuple[float, float]]:
    """Strokes to try, from 0 towards the longer side of the range: 60 %, then halved (5 tries)."""
    lo, hi = rng
    end = STROKE_FRACTION * (lo if abs(lo) >= abs(hi) else hi)
    end = max(-math.pi / 2, min(math.pi / 2, end))
    return [(0.0, end / 2 ** k) for k in range(5)]


class RollingTool(Tool):
    """Seven clicks place a rolling lever (see the module docstring)."""

    name, title, shortcut = "rolling", "Rolling lever", "O"
    hint = "Rolling lever: click the lever circle's centre, its radius, the pin, the rocker pivot, the slider circle, its radius, the slider axis"

    def reset(self) -> None:
        super().reset()
        self._pts: list[XY] = []
        self._range: tuple[float, float] | str | None = None

    def _range_text(self) -> str:
        r = self._range
        if r is None:
            return ""
        if isinstance(r, str):
            return f"no working range: {r}"
        return f"working range θ from {r[0]:.3f} to {r[1]:.3f} rad"

    def _preview(self, pos: XY) -> tuple[Overlay, str | None]:
        pts = self._pts + [pos]
        n = len(pts)
        lines, circles, points, labels, why = [], [], list(pts), [], None
        if n >= 2:
            circles.append((pts[0], _dist(pts[0], pts[1])))
            labels.append((pts[1], f"R1 = {_dist(pts[0], pts[1]):.2f} mm"))
        if n in (1, 2) and _dist(pts[0], pos) <= ops.SAME_POINT and n == 2:
            why = "the lever circle needs a radius: click away from its centre"
        if n >= 4:
            el = lever_from(pts[:4])
            why = problems_of(el)
            lines.append((pts[3], pts[2]))
            if why is None:
                p, _ = el.drawn_contacts()
                lines.append((pts[2], p))
                points.append(p)
                labels.append((p, "P (pair D)"))
                if n == 4:
                    self._range = range_of(el)
                labels.append((pts[3], self._range_text()))
        if n >= 6:
            circles.append((pts[4], _dist(pts[4], pts[5])))
            labels.append((pts[5], f"R2 = {_dist(pts[4], pts[5]):.2f} mm"))
        if n == 7 and why is None:
            el = lever_from(pts)
            why = problems_of(el)
            ds = el.slider_axis
            if why is None:
                p0 = el.drawn_contacts()[1]
                far = 0.8 * el.slider_circle.radius
                lines.append(((p0[0] - far * ds[0], p0[1] - far * ds[1]), (p0[0] + far * ds[0], p0[1] + far * ds[1])))
                points.append(p0)
                labels.append((p0, f"P0 (pair E), axis {el.slider_axis_deg:.1f}°"))
        step = STEPS[min(n, len(STEPS) - 1)]
        if why is None:
            labels.append((pos, step if n <= len(STEPS) else ""))
        return Overlay(lines=lines, points=points, circles=circles, labels=labels, bad=why is not None), why

    def on_move(self, ev: CanvasEvent) -> None:
        self._overlay, why = self._preview(ev.pos)
        if why:
            self.explain(f"rolling lever: {why}")

    def on_press(self, ev: CanvasEvent) -> None:
        if ev.button != "left":
            return
        ov, why = self._preview(ev.pos)
        if why is not None:
            self.explain(f"rolling lever: cannot place {STEPS[len(self._pts)]} here: {why}")
            return
        if self._pts and any(_dist(p, ev.pos) <= ops.SAME_POINT for p in self._pts[-1:]):
            self.explain("rolling lever: click a different point")
            return
        self._pts.append(ev.pos)
        if len(self._pts) == 4:
            self._range = range_of(lever_from(self._pts))
            if isinstance(self._range, str):
                self._pts.pop()
                self.explain(f"rolling lever: {self._range}; place the rocker pivot elsewhere")
                return
        if len(self._pts) < len(STEPS):
            self._overlay = ov
            self.explain(f"rolling lever: now {STEPS[len(self._pts)]}" +
                         (f" ({self._range_text()})" if self._range is not None else ""))
            return
        self._finish()

    def _finish(self) -> None:
        ctl = self.ctx.controller
        eid = ops.fresh_element_id(ctl.scene.ids, "lever")
        base = lever_from(self._pts, eid)
        rng = range_of(base)
        if isinstance(rng, str):
            self.explain(f"rolling lever: {rng}")
            self._pts.pop()
            return
        last = None
        for stroke in default_strokes(rng):
            el = lever_from(self._pts, eid, stroke)
            last = problems_of(el) or ctl.check_element(el)
            if last is None:
                break
        else:
            self.explain(f"rolling lever: no stroke could be synthesised: {last}; move the slider axis")
            self._pts.pop()
            return
        if self.ctx.commit(None, el, f"add rolling lever {eid}"):
            ctl.set_selection([(eid, ELEMENT, eid)])
            self.explain(f"rolling lever {eid}: stroke θ from 0 to {el.stroke.end:.4f} rad in the working range "
                         f"{rng[0]:.3f} … {rng[1]:.3f} rad; drag its handles to reshape it")
        self.reset()
