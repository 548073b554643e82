"""Base of the canvas tools: the context they work in and the event dispatch they share.

:class:`ToolContext` is what a tool reads (the controller, the poses on screen) and how it writes
(one undo command per action, through :meth:`ToolContext.commit`). :class:`Tool` dispatches a
:class:`~mechsketch.gui.canvas.events.CanvasEvent` to ``on_press`` / ``on_move`` / ...,
keeps the preview :class:`~mechsketch.gui.canvas.items.Overlay`, and says each impossible
placement once. The tools themselves are in :mod:`.tools` and :mod:`.build_tools`.
"""
from __future__ import annotations

import math

import numpy as np

from mechsketch.core.model.edits import AddElement, RemoveElement, ReplaceElement
from mechsketch.core.model.linkage import JointKind, Linkage

from . import ops
from .events import XY, CanvasEvent, Hit
from .items import Overlay, short_error
from .pose import ElementPose, PoseCache, pick, rebase, shows_drawn

DRAG_START = 0.4   # of the pick tolerance: how far the mouse moves before a press becomes a drag


class ToolContext:
    """What tools read and change: the controller, the poses on screen, the displayed frame."""

    def __init__(self, controller, cache: PoseCache | None = None) -> None:
        self.controller = controller
        self.cache = cache or PoseCache()
        self.hold_frame = False   # while a geometry drag runs, the canvas shows the drawn pose

    # -- reading ----------------------------------------------------------------------------
    def display_frame(self) -> int:
        return 0 if self.hold_frame else self.controller.frame

    def poses(self) -> list[ElementPose]:
        return self.cache.poses(self.controller, self.display_frame())

    def pose(self, element_id: str) -> ElementPose | None:
        return next((p for p in self.poses() if p.element == element_id), None)

    def pick(self, pos: XY, tol: float) -> Hit | None:
        return pick(self.poses(), pos, tol)

    def linkage(self, element_id: str) -> Linkage:
        return self.controller.scene.element(element_id)

    def has_linkage(self, element_id: str) -> bool:
        """``element_id`` is a linkage of the document (not gone, not an element of another kind
        that took its id)."""
        scene = self.controller.scene
        return element_id in scene.ids and isinstance(scene.element(element_id), Linkage)

    def exists(self, hit: Hit) -> bool:
        """The joint or link ``hit`` is still in the document."""
        if not self.has_linkage(hit.element):
            return False
        lk = self.linkage(hit.element)
        return hit.id in (lk.joint_ids if hit.kind == "joint" else lk.link_ids)

    def at(self, element_id: str, joint_id: str) -> XY:
        """Where the joint is on screen now."""
        pose = self.pose(element_id)
        return pose.at[joint_id] if pose is not None else self.linkage(element_id).joint(joint_id).at

    def editable(self, element_id: str) -> tuple[Linkage, bool]:
        """The linkage drawn as on screen (rebased when a non-zero frame is shown), and whether
        it was rebased."""
        lk = self.linkage(element_id)
        pose = self.pose(element_id)
        if pose is None or pose.arrays is None or pose.index is None or shows_drawn(pose.arrays, pose.index):
            return lk, False
        new = rebase(lk, pose.arrays, pose.index)
        return new, new is not lk

    def active_element(self) -> str | None:
        """The linkage of the first selected item, if any."""
        ids = {lk.id for lk in self.controller.linkages()}
        return next((el for el, _, _ in self.controller.selection if el in ids), None)

    # -- writing ----------------------------------------------------------------------------
    def say(self, text: str) -> None:
        self.controller.message.emit(text)

    def commit(self, old_id: str | None, new: Linkage | None, text: str, rebased: bool = False) -> bool:
        """Push one undo command replacing (adding, removing) a linkage; refuse an edit that
        breaks a linkage that solved before. Shows frame 0 afterwards if the edit was rebased."""
        old = self.linkage(old_id) if old_id is not None and old_id in self.controller.scene.ids else None
        if new is not None and old is not None and ops.structure_error(old) is None:
            err = ops.structure_error(new)
            if err is not None:
                self.say(f"cannot {text}: {err}")
                return False
        if new is None:
            edit = RemoveElement(old_id, text)
        elif old is None:
            edit = AddElement(new, label=text)
        else:
            edit = ReplaceElement(new, text)
        ok = self.controller.push(edit, text)
        if ok and rebased:
            self.controller.set_frame(0)
        return ok

    def status(self, element_id: str) -> str:
        """One line on how the linkage solves now (after an edit)."""
        res = self.controller.result(element_id)
        if res is None:
            return ""
        if res.error:
            return f"{element_id}: {short_error(res.error)}"
        diag = self.controller.diagnostics(element_id)
        if diag is None and res.solution is not None and self.controller.workspace.previewing:
            # a drag preview does not wait for the diagnostics: the share of assemblable samples
            share = float(np.mean(res.solution.valid))
            if share < 1.0:
                return f"{element_id}: the crank reaches only {100.0 * share:.1f}% of its turn (ranges on release)"
        if diag is None or diag.full_turn:
            return f"{element_id} moves through a full turn of its crank"
        ranges = ", ".join(f"{math.degrees(a):.1f}° to {math.degrees(b):.1f}°" for a, b in diag.reachable)
        return f"{element_id}: the crank reaches only {ranges or 'no input'} ({len(diag.dead_points)} dead points)"


class Tool:
    """Base of the canvas tools: event dispatch, overlay, de-duplicated status messages."""

    name = "tool"
    title = "Tool"
    shortcut = ""
    hint = ""
    in_toolbar = True   # False: made active by a command (e.g. Insert), not from the toolbar

    def __init__(self, ctx: ToolContext) -> None:
        self.ctx = ctx
        self._overlay = Overlay()
        self._said: str | None = None
        self.reset()

    def reset(self) -> None:
        """Forget a half-finished placement."""
        self._overlay = Overlay()

    def activate(self) -> None:
        self.reset()
        self._said = None
        if self.hint:
            self.ctx.say(self.hint)

    def deactivate(self) -> None:
        self.cancel()

    def cancel(self) -> None:
        self.reset()

    @property
    def busy(self) -> bool:
        """A drag is in progress (the view reports it and holds the frame)."""
        return False

    def overlay(self) -> Overlay:
        return self._overlay

    def explain(self, text: str) -> None:
        """Say ``text`` once (repeated moves over the same impossible spot say it once)."""
        if text != self._said:
            self._said = text
            self.ctx.say(text)

    def ok(self) -> None:
        self._said = None

    def handle(self, ev: CanvasEvent) -> None:
        """Dispatch ``ev``; a half-done placement whose joints or linkage are gone starts again
        first (checked here, on every event, whatever signal may have been missed)."""
        why = self.stale()
        if why:
            self.cancel()
            self.explain(f"{self.title}: {why}; start again")
        getattr(self, f"on_{ev.kind}")(ev)

    def picks(self) -> list[Hit]:
        """Joints (and links) this tool has picked and still refers to."""
        return []

    def refers_to(self) -> set[str]:
        """The linkages this tool's half-done work refers to (empty when it holds nothing)."""
        return {h.element for h in self.picks()}

    def stale(self) -> str | None:
        """Why the half-done work cannot go on (a linkage or a picked joint is gone), or None."""
        if any(not self.ctx.has_linkage(e) for e in self.refers_to()):
            return "the linkage it was placing on is gone (undone, deleted or another document)"
        if any(not self.ctx.exists(h) for h in self.picks()):
            return "a picked joint is gone (undone or deleted)"
        return None

    def forget(self, gone: set[str] | frozenset[str] | None = None) -> bool:
        """Drop the half-done work if it refers to an element in ``gone`` (None: the whole
        document was replaced, so everything goes). True if the tool started again."""
        if gone is None or self.refers_to() & set(gone):
            self.cancel()
            self._said = None
            return True
        return False

    def on_press(self, ev: CanvasEvent) -> None:
        pass

    def on_move(self, ev: CanvasEvent) -> None:
        pass

    def on_release(self, ev: CanvasEvent) -> None:
        pass

    def on_double(self, ev: CanvasEvent) -> None:
        """A double click arrives after its press/release pair; tools ignore the extra event."""

    def key(self, text: str) -> bool:
        """A key typed on the canvas (its text, e.g. "6"); True if the tool used it."""
        return False

    def anchor(self) -> XY | None:
        """The point the next one is measured from (typed length and angle, Shift-snapping), if
        the tool has one."""
        return None

    # -- helpers ----------------------------------------------------------------------------
    def _joint_hit(self, ev: CanvasEvent, revolute: bool = True) -> Hit | None:
        h = ev.hit
        if h is None or h.kind != "joint":
            return None
        if revolute and self.ctx.linkage(h.element).joint(h.id).kind is not JointKind.R:
            return None
        return h

    def _select(self, element: str, kind: str, id_: str) -> None:
        self.ctx.controller.set_selection([(element, kind, id_)])
