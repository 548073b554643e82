"""Copy, paste and duplicate (Ctrl+C, Ctrl+V, Ctrl+D) as scene JSON on the system clipboard, so
elements move within a window and between windows (and apps) of mechsketch.

What is copied: the selected elements (Geneva drives, rolling levers, underlays, linkages picked
as a whole); joints or links of a linkage picked on the canvas copy that linkage whole when they
cover all of its joints, else the selected joints — and the links among them — as a new linkage
(:func:`sub_linkage`: its masses, loads and friction on what is kept; its driver if the crank is
kept, else a draft without one). Nothing selected: every element. The clipboard holds the scene
text (``application/x-mechsketch-scene`` and plain text); a paste reads any scene JSON text.

Pasted elements land where the pointer is over the canvas (else offset from where they were),
renamed where their ids are taken, as one undo step, and become the selection. Duplicate pastes
a copy beside the original without touching the clipboard.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any

from PySide6.QtCore import QMimeData, QObject
from PySide6.QtGui import QAction, QClipboard, QCursor, QGuiApplication, QKeySequence

from mechsketch.core import MechsketchError, SceneFormatError
from mechsketch.core.io.scene_file import dumps_scene, element_problems, loads_scene
from mechsketch.core.model.edits import AddElement
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.scene import Scene
from mechsketch.core.model.transform import extent, placed, translated

from .selection import ELEMENT

MIME = "application/x-mechsketch-scene"
#: the clipboard text is read only up to this size (a scene file's own limit)
MAX_TEXT = 10 * 1024 * 1024


def sub_linkage(lk: Linkage, joints: set[str]) -> Linkage:
    """The part of ``lk`` made of ``joints`` and the links among them (a link keeps the selected
    ones of its joints, if two or more, or one for the frame). Raises :class:`MechsketchError`
    when they do not make a linkage a file may hold (the reader's message)."""
    keep_joints = tuple(j for j in lk.joints if j.id in joints)
    links = []
    for k in lk.links:
        kept = tuple(j for j in k.joints if j in joints)
        if len(kept) >= 2 or (k.id == lk.ground and kept):
            links.append(replace(k, joints=kept))
    ground = lk.ground if any(k.id == lk.ground for k in links) else None
    if ground is None:                      # no frame joint picked: the frame holds none of them
        raise MechsketchError(f"the selected joints of {lk.id} hold no frame joint: pick a ground pivot too "
                              "(or copy the whole linkage)")
    names = {k.id for k in links}
    drv = lk.driver
    driver = drv if drv.link in names and drv.pivot in joints else replace(drv, link=ground, pivot=keep_joints[0].id)
    new = Linkage(lk.id, keep_joints, tuple(links), ground, driver, lk.samples,
                  tuple(m for m in lk.masses if m.link in names and m.link != ground), lk.gravity,
                  tuple(ld for ld in lk.loads if _load_kept(ld, names, joints)),
                  tuple(f for f in lk.friction if f.joint in joints))
    problems = element_problems(new)
    if problems:
        raise MechsketchError(f"the selected joints of {lk.id} do not make a linkage: {problems[0].message}")
    return new


def _load_kept(load: Any, links: set[str], joints: set[str]) -> bool:
    """A force or torque on a kept link; a spring or damper with both ends on kept links (an end
    on the frame counts when the frame is kept)."""
    names = [load.link] if hasattr(load, "link") else [end.link for end in getattr(load, "ends", ())]
    return all(n in links for n in names)


def selected_elements(controller) -> tuple[list[Any], str]:
    """What a copy takes from ``controller``'s selection, and words for it."""
    scene = controller.scene
    whole: list[str] = []
    parts: dict[str, set[str]] = {}
    for eid, kind, ident in controller.selection:
        if eid not in scene.ids:
            continue
        if kind == ELEMENT:
            whole.append(eid)
            continue
        lk = scene.element(eid)
        if not isinstance(lk, Linkage):
            continue
        picked = parts.setdefault(eid, set())
        picked.update([ident] if kind == "joint" else lk.link(ident).joints if ident in lk.link_ids else ())
    out: list[Any] = []
    for el in scene.elements:
        if el.id in whole:
            out.append(el)
        elif el.id in parts:
            out.append(el if parts[el.id] >= set(el.joint_ids) else sub_linkage(el, parts[el.id]))
    if not controller.selection:
        out = list(scene.elements)
    what = ", ".join(e.id if e in scene.elements else f"{len(e.joints)} joints of {e.id}" for e in out)
    return out, what


def scene_text(elements: list[Any]) -> str:
    return dumps_scene(Scene(tuple(elements)))


def read_text(text: str) -> list[Any]:
    """The elements of scene JSON ``text`` (:class:`SceneFormatError` if it is none)."""
    if len(text) > MAX_TEXT:
        raise SceneFormatError([], f"the clipboard holds {len(text) / 1e6:.1f} MB; scenes are limited to 10 MB")
    return list(loads_scene(text, "the clipboard").elements)


class ClipboardCommands(QObject):
    """Edit › Copy, Paste, Duplicate for one window (``window``: read for its controller and canvas)."""

    def __init__(self, window: Any, clipboard: QClipboard | None = None) -> None:
        super().__init__(window)
        self.window = window
        self.controller = window.controller
        self.clipboard = clipboard or QGuiApplication.clipboard()
        self.actions: dict[str, QAction] = {}
        K = QKeySequence.StandardKey
        for name, text, slot, key, tip in (
                ("copy", "&Copy", self.copy, K.Copy, "Copy the selected elements (or joints) as scene JSON"),
                ("paste", "&Paste", self.paste, K.Paste, "Paste elements from the clipboard where the pointer is"),
                ("duplicate", "D&uplicate", self.duplicate, QKeySequence("Ctrl+D"),
                 "Add a copy of the selected elements beside them")):
            act = QAction(text, window)
            act.setObjectName(name)
            act.setShortcut(QKeySequence(key))
            act.setStatusTip(tip)
            act.triggered.connect(lambda _c=False, s=slot: s())
            self.actions[name] = act

    def _say(self, text: str) -> None:
        self.controller.message.emit(text)

    def _take(self) -> list[Any] | None:
        try:
            elements, what = selected_elements(self.controller)
        except MechsketchError as exc:
            self._say(f"cannot copy: {exc}")
            return None
        if not elements:
            self._say("nothing to copy: the scene is empty")
            return None
        self._what = what
        return elements

    def copy(self) -> bool:
        """Put the selection on the clipboard as scene JSON."""
        elements = self._take()
        if elements is None:
            return False
        text = scene_text(elements)
        data = QMimeData()
        data.setData(MIME, text.encode("utf-8"))
        data.setText(text)
        self.clipboard.setMimeData(data)
        self._say(f"copied {self._what}")
        return True

    def clipboard_text(self) -> str:
        data = self.clipboard.mimeData()
        if data is None:
            return ""
        if data.hasFormat(MIME):
            return bytes(data.data(MIME)).decode("utf-8", errors="replace")
        return data.text() if data.hasText() else ""

    def paste(self) -> bool:
        """Add the clipboard's elements where the pointer is over the canvas (else beside where
        they were), as one undo step."""
        text = self.clipboard_text()
        if not text.strip():
            self._say("nothing to paste: copy elements first (Ctrl+C)")
            return False
        try:
            elements = read_text(text)
        except (SceneFormatError, MechsketchError) as exc:
            first = exc.problems[0] if isinstance(exc, SceneFormatError) and exc.problems else exc
            self._say(f"the clipboard does not hold mechsketch elements: {first}")
            return False
        at = self._pointer()
        return self._add(elements, at, "paste")

    def duplicate(self) -> bool:
        """A copy of the selection beside it (the clipboard is left alone)."""
        elements = self._take()
        return elements is not None and self._add(elements, None, "duplicate")

    def _pointer(self):
        view = getattr(self.window, "canvas", None)
        if not hasattr(view, "viewport"):
            return None
        vp = view.viewport()
        local = vp.mapFromGlobal(QCursor.pos())
        if not vp.rect().contains(local):
            return None
        p = view.mapToScene(local)
        return (p.x(), p.y())

    def _offset(self) -> float:
        view = getattr(self.window, "canvas", None)
        px = view.px() if hasattr(view, "px") else 0.5
        return 24.0 * px                      # 24 pixels down and right on screen

    def _add(self, elements: list[Any], at, verb: str) -> bool:
        ctl = self.controller
        try:
            if at is not None:
                new = placed(elements, at, ctl.scene.ids)
            else:
                d = self._offset()
                moved = [translated(e, d, -d) for e in elements]
                new = placed(moved, _centre(moved), ctl.scene.ids)
        except MechsketchError as exc:
            self._say(f"cannot {verb}: {exc}")
            return False
        stack = ctl.undo_stack
        text = f"{verb} {', '.join(e.id for e in new)}"
        stack.beginMacro(text)
        try:
            done = [ctl.push(AddElement(e, label=text), text) for e in new]
        finally:
            stack.endMacro()
        if not all(done):
            return False
        ctl.set_selection([(e.id, ELEMENT, e.id) for e in new])
        renamed = [f"{o.id} → {n.id}" for o, n in zip(elements, new) if o.id != n.id]
        self._say(f"{verb}: {', '.join(e.id for e in new)}" + (f" (renamed {', '.join(renamed)})" if renamed else ""))
        return True


def _centre(elements: list[Any]) -> tuple[float, float]:
    boxes = [extent(e) for e in elements]
    return ((min(b[0] for b in boxes) + max(b[2] for b in boxes)) / 2,
            (min(b[1] for b in boxes) + max(b[3] for b in boxes)) / 2)
