"""Handles of a selected Geneva drive or rolling lever, dragged to reshape it live.

:class:`HandleLayer` behaves like a tool (``handle(ev)``, ``overlay()``, ``busy``): the view routes
a press on a handle of a selected element to it (with the select tool, the Geneva tool or the
rolling-lever tool active) and keeps the drag there until release. A drag previews each candidate
element through the workspace (a Geneva drive re-analysed, a rolling lever re-synthesised, about
5 ms: previews skip the slip report) and pushes one undo command on release. An impossible
candidate is not shown: the status bar says why and the last valid one stays drawn; releasing on
an impossible candidate leaves the element as it was before the drag.

Handles (world mm at the displayed frame):

- Geneva drive: ``crank`` and ``wheel`` centres (A and the direction follow), ``roller`` on the
  roller's rim (its radius);
- rolling lever: ``lever_centre``, ``lever_radius``, ``pin``, ``pivot``, ``slider_centre``,
  ``slider_radius``, ``axis`` (the slider axis' direction from the contact P0), and with a drive
  ``crank_pivot`` and ``coupler_point``. Points of the lever are shown where the lever is at the
  displayed frame and mapped back to its drawn pose.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.edits import ReplaceElement
from mechsketch.core.model.geneva import Geneva
from mechsketch.core.model.geneva import parse as parse_geneva
from mechsketch.core.model.rolling_lever import Circle, Drive, RollingLever
from mechsketch.core.model.rolling_lever import parse as parse_rolling

from ..selection import ELEMENT
from .events import XY, CanvasEvent
from .items import Overlay
from ..frames import map_frame

#: tools under which handles can be dragged
HANDLE_TOOLS = ("select", "geneva", "rolling")


@dataclass(frozen=True)
class Handle:
    """One draggable point: ``element``, ``name``, world position ``at`` (mm), ``label``."""

    element: str
    name: str
    at: XY
    label: str


def _rot(v: XY, a: float) -> XY:
    c, s = math.cos(a), math.sin(a)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _unit(v: XY, fallback: XY = (1.0, 0.0)) -> XY:
    n = math.hypot(*v)
    return (v[0] / n, v[1] / n) if n > 1e-12 else fallback


class LeverFrame:
    """The lever's placement at one frame: drawn point p -> F + Rot(θ)(p − f), and back."""

    def __init__(self, F: XY, theta: float, f: XY) -> None:
        self.F, self.theta, self.f = (float(F[0]), float(F[1])), float(theta), (float(f[0]), float(f[1]))

    def world(self, p: XY) -> XY:
        d = _rot((p[0] - self.f[0], p[1] - self.f[1]), self.theta)
        return (self.F[0] + d[0], self.F[1] + d[1])

    def drawn(self, x: XY) -> XY:
        d = _rot((x[0] - self.F[0], x[1] - self.F[1]), -self.theta)
        return (self.f[0] + d[0], self.f[1] + d[1])


def _radius_dirs(el: RollingLever) -> tuple[XY, XY]:
    """Directions (drawn pose) of the two radius handles on the lever and slider circles."""
    lc = el.lever_circle.center
    sc = el.slider_circle.center if el.slider_circle is not None else el.pin
    away = _unit((lc[0] - el.pin[0], lc[1] - el.pin[1]))
    return _rot(away, math.radians(60)), _rot(_unit((sc[0] - el.pin[0], sc[1] - el.pin[1])), math.radians(-60))


def geneva_handles(el: Geneva, res, k: int) -> list[Handle]:
    """Crank centre, wheel centre and the roller rim at frame ``k`` of ``res`` (a GenevaResult)."""
    cc, wc = el.crank_center, el.wheel_center
    rho = float(res.crank_rotation[k]) if res is not None and res.n_frames else math.radians(el.wheel_direction_deg)
    r = el.crank_radius
    roller = (cc[0] + r * math.cos(rho), cc[1] + r * math.sin(rho))
    rim = (roller[0] + el.roller_radius * math.cos(rho), roller[1] + el.roller_radius * math.sin(rho))
    return [Handle(el.id, "crank", cc, "crank centre"), Handle(el.id, "wheel", wc, f"wheel centre (A = {el.center_distance:.2f} mm)"),
            Handle(el.id, "roller", rim, f"roller r = {el.roller_radius:.2f} mm")]


def lever_frame(el: RollingLever, res, k: int) -> LeverFrame:
    """The lever placement shown at frame ``k`` (the drawn pose without frames)."""
    fr = getattr(res, "frames", None)
    if fr is None or len(fr) == 0:
        return LeverFrame(el.pin, 0.0, el.pin)
    return LeverFrame(tuple(fr.F[k]), float(fr.theta[k]), el.pin)


def rolling_handles(el: RollingLever, res, k: int) -> list[Handle]:
    """The rolling lever's handles at frame ``k`` (see the module docstring)."""
    lf = lever_frame(el, res, k)
    lc, sc = el.lever_circle, el.slider_circle
    d1, d2 = _radius_dirs(el)
    out = [Handle(el.id, "lever_centre", lf.world(lc.center), "lever circle centre"),
           Handle(el.id, "lever_radius", lf.world((lc.center[0] + lc.radius * d1[0], lc.center[1] + lc.radius * d1[1])),
                  f"R1 = {lc.radius:.2f} mm"),
           Handle(el.id, "pin", lf.world(el.pin), "pin f"),
           Handle(el.id, "pivot", el.rocker_pivot, "rocker pivot G")]
    if sc is not None:   # a slider law has no slider circle: its pair E is derived, not drawn
        out += [Handle(el.id, "slider_centre", lf.world(sc.center), "slider circle centre"),
                Handle(el.id, "slider_radius", lf.world((sc.center[0] + sc.radius * d2[0],
                                                         sc.center[1] + sc.radius * d2[1])), f"R2 = {sc.radius:.2f} mm")]
    fr = getattr(res, "frames", None)
    p0 = tuple(fr.P0[k]) if fr is not None and len(fr) else None
    if p0 is None or not all(math.isfinite(v) for v in p0):
        try:
            p0 = el.drawn_contacts()[1]
        except MechsketchError:
            p0 = sc.center if sc is not None else el.pin
    ds = el.slider_axis
    reach = 0.5 * (sc.radius if sc is not None else lc.radius)
    out.append(Handle(el.id, "axis", (p0[0] + reach * ds[0], p0[1] + reach * ds[1]),
                      f"slider axis {el.slider_axis_deg:.1f}°"))
    if el.drive is not None:
        out += [Handle(el.id, "crank_pivot", el.drive.crank_pivot, "crank pivot A"),
                Handle(el.id, "coupler_point", lf.world(el.drive.coupler_point), "coupler point C")]
    return out


def moved(el, name: str, pos: XY, grip: dict) -> object:
    """``el`` with handle ``name`` dragged to world ``pos`` (``grip``: what the press fixed:
    ``frame`` a :class:`LeverFrame`, ``p0`` the slider contact, ``roller`` the roller centre)."""
    x, y = float(pos[0]), float(pos[1])
    if isinstance(el, Geneva):
        if name in ("crank", "wheel"):
            cc, wc = (el.crank_center, (x, y)) if name == "wheel" else ((x, y), el.wheel_center)
            a = math.hypot(wc[0] - cc[0], wc[1] - cc[1])
            return replace(el, crank_center=cc, center_distance=a,
                           wheel_direction_deg=math.degrees(math.atan2(wc[1] - cc[1], wc[0] - cc[0])))
        rc = grip["roller"]
        return replace(el, roller_radius=math.hypot(x - rc[0], y - rc[1]))
    lf: LeverFrame = grip["frame"]
    p = lf.drawn((x, y))
    lc, sc = el.lever_circle, el.slider_circle
    if name == "lever_centre":
        return replace(el, lever_circle=Circle(p, lc.radius))
    if name == "lever_radius":
        return replace(el, lever_circle=Circle(lc.center, math.hypot(p[0] - lc.center[0], p[1] - lc.center[1])))
    if name == "pin":
        return replace(el, pin=p)
    if name == "pivot":
        return replace(el, rocker_pivot=(x, y))
    if name == "slider_centre":
        return replace(el, slider_circle=Circle(p, sc.radius))
    if name == "slider_radius":
        return replace(el, slider_circle=Circle(sc.center, math.hypot(p[0] - sc.center[0], p[1] - sc.center[1])))
    if name == "axis":
        p0 = grip["p0"]
        return replace(el, slider_axis_deg=math.degrees(math.atan2(y - p0[1], x - p0[0])))
    if name == "crank_pivot":
        return replace(el, drive=Drive((x, y), el.drive.coupler_point))
    if name == "coupler_point":
        return replace(el, drive=Drive(el.drive.crank_pivot, p))
    raise KeyError(name)


def problems(el) -> str | None:
    """The model's objections to ``el`` (None: it parses)."""
    parse = parse_geneva if isinstance(el, Geneva) else parse_rolling
    _, probs = parse(el.to_dict(), "$")
    return "; ".join(p.message for p in probs) if probs else None


class HandleLayer:
    """Handle dragging for the canvas (tool-like; see the module docstring)."""

    def __init__(self, ctx) -> None:
        self.ctx = ctx
        self._overlay = Overlay()
        self._grab: Handle | None = None
        self._grip: dict = {}
        self._base = None
        self._good = None
        self._bad: str | None = None
        self._started = False
        self._said: str | None = None

    # -- what is shown ------------------------------------------------------------------------
    def _frame(self, res) -> int:
        total = self.ctx.controller.sample_count()
        n = res.n_frames if res is not None else 0
        return map_frame(self.ctx.display_frame(), total, n) if n else 0

    def handles(self) -> list[Handle]:
        """Handles of the selected Geneva drives and rolling levers, at the displayed frame."""
        ctl = self.ctx.controller
        out: list[Handle] = []
        for eid, kind, _ in ctl.selection:
            if kind != ELEMENT or eid not in ctl.scene.ids:
                continue
            el = ctl.scene.element(eid)
            res = ctl.element_result(eid)
            if isinstance(el, Geneva):
                out += geneva_handles(el, res, self._frame(res))
            elif isinstance(el, RollingLever):
                out += rolling_handles(el, res, self._frame(res))
        return out

    def at(self, pos: XY, tol: float) -> Handle | None:
        """The handle within ``tol`` mm of ``pos`` (the nearest), if any."""
        best, dist = None, tol
        for h in self.handles():
            d = math.hypot(h.at[0] - pos[0], h.at[1] - pos[1])
            if d <= dist:
                best, dist = h, d
        return best

    @property
    def busy(self) -> bool:
        return self._grab is not None and self._started

    def overlay(self) -> Overlay:
        return self._overlay

    def route(self, ev: CanvasEvent, tool):
        """The object that should take ``ev``: this layer while it drags or for a press on a handle
        (under the select, Geneva or rolling-lever tool), else ``tool``."""
        if self._grab is not None:
            return self
        if (ev.kind == "press" and ev.button == "left" and tool.name in HANDLE_TOOLS
                and self.at(ev.raw, ev.tolerance) is not None):
            return self
        return tool

    # -- the drag -------------------------------------------------------------------------------
    def handle(self, ev: CanvasEvent) -> None:
        if self._grab is not None and self.stale():
            self.cancel()
            self._explain("the drag was interrupted (an edit, undo or another document): drag again")
            return
        getattr(self, f"_on_{ev.kind}", lambda _ev: None)(ev)

    def stale(self) -> bool:
        """The drag under way lost its ground: its element is gone or was changed by something
        else (an undo, another document), or its preview was ended by an edit."""
        ctl, h = self.ctx.controller, self._grab
        if h is None:
            return False
        if h.element not in ctl.scene.ids:
            return True
        if self._started:
            return not ctl.workspace.previewing
        return ctl.scene.element(h.element) is not self._base

    def forget(self, gone=None) -> bool:
        """Abandon the drag if its element is in ``gone`` (None: the document was replaced)."""
        if self._grab is not None and (gone is None or self._grab.element in gone):
            self.cancel()
            return True
        return False

    def _explain(self, text: str) -> None:
        if text != self._said:
            self._said = text
            self.ctx.say(text)

    def _on_press(self, ev: CanvasEvent) -> None:
        h = self.at(ev.raw, ev.tolerance)
        if h is None:
            return
        ctl = self.ctx.controller
        el = ctl.scene.element(h.element)
        res = ctl.element_result(h.element)
        k = self._frame(res)
        self._grab, self._base, self._good, self._bad, self._started = h, el, el, None, False
        if isinstance(el, Geneva):
            rho = float(res.crank_rotation[k]) if res is not None and res.n_frames else 0.0
            cc, r = el.crank_center, el.crank_radius
            self._grip = {"roller": (cc[0] + r * math.cos(rho), cc[1] + r * math.sin(rho))}
        else:
            fr = getattr(res, "frames", None)
            if fr is not None and len(fr):
                p0 = tuple(fr.P0[k])
            else:   # not synthesised: the drawn contact, or the slider circle's centre if there is none
                try:
                    p0 = el.drawn_contacts()[1]
                except MechsketchError:
                    p0 = el.slider_circle.center if el.slider_circle is not None else el.pin
            self._grip = {"frame": lever_frame(el, res, k), "p0": p0}
        self._explain(f"{h.element}: drag the {h.label.split(' (')[0]}")

    def _on_move(self, ev: CanvasEvent) -> None:
        h = self._grab
        if h is None:
            return
        ctl = self.ctx.controller
        if not self._started:
            if math.hypot(ev.raw[0] - h.at[0], ev.raw[1] - h.at[1]) < 0.4 * ev.tolerance:
                return
            self._started = True
            ctl.begin_preview()
        try:
            cand = moved(self._base, h.name, ev.pos, self._grip)
            why = problems(cand)
        except (ValueError, ZeroDivisionError) as exc:
            cand, why = None, str(exc)
        if why is None and ctl.preview(ReplaceElement(cand, f"drag {h.name}")):
            res = ctl.element_result(h.element)
            why = res.error if res is not None else None
            if why is not None and self._good is not None:   # keep drawing the last valid one
                ctl.preview(ReplaceElement(self._good, f"drag {h.name}"))
        if why is None:
            self._good, self._bad = cand, None
            self._overlay = Overlay()
            self._explain(f"{h.element}: {self._describe(cand)}")
        else:
            self._bad = why
            self._overlay = Overlay(points=[ev.pos], labels=[(ev.pos, "impossible")], bad=True)
            self._explain(f"{h.element}: impossible here: {why}")

    def _on_release(self, ev: CanvasEvent) -> None:
        h = self._grab
        if h is None:
            return
        ctl = self.ctx.controller
        if self._started:
            if self._bad is None and self._good is not None and self._good != self._base:
                ctl.end_preview(ReplaceElement(self._good, f"drag {h.name} of {h.element}"),
                                f"drag {h.name} of {h.element}")
            else:
                ctl.end_preview(None)
                if self._bad is not None:
                    self._explain(f"{h.element} kept as it was: released where it is impossible ({self._bad})")
        self._started = False
        self.cancel()

    def cancel(self) -> None:
        """Abandon a drag (the element stays as it was before it)."""
        if self._grab is not None and self._started:
            self.ctx.controller.end_preview(None)
        self._grab, self._base, self._good, self._bad, self._started = None, None, None, None, False
        self._overlay = Overlay()

    @staticmethod
    def _describe(el) -> str:
        if isinstance(el, Geneva):
            return f"A = {el.center_distance:.2f} mm, roller {el.roller_radius:.2f} mm, direction {el.wheel_direction_deg:.1f}°"
        r2 = (f"R2 = {el.slider_circle.radius:.2f} mm" if el.slider_circle is not None
              else f"slider law ({el.slider_law.kind})")
        return (f"R1 = {el.lever_circle.radius:.2f} mm, {r2}, "
                f"rocker ℓ = {el.rocker_length:.2f} mm, axis {el.slider_axis_deg:.1f}°")
