"""The diagnostics panel: for each linkage, mobility, the Assur groups found (kind, mode), reachable
input ranges, dead points, transmission-angle range, and the solve's time and loop-closure error;
when it has masses or loads, the forces summary too (peak and RMS driving effort, peak reaction of
each joint, shaking force and moment, power-balance residual, the result with friction).

Each element shows its result's summary: the text of ``mechsketch analyze --summary`` for a
linkage or a Geneva drive (``analyze --forces --summary`` for a linkage with masses or loads), of
``mechsketch synthesize --summary`` for a rolling lever (one text, in core/analyses, shared by CLI
and GUI), so every number here can be reproduced headless. An element that cannot be solved shows
the core's message.
"""
from __future__ import annotations

import html

from PySide6.QtWidgets import QTextBrowser, QVBoxLayout, QWidget

from mechsketch.core import MechsketchError
from mechsketch.core.model.linkage import Linkage
from mechsketch.core.model.underlay import Underlay

from ..controller import SceneController
from .lazy import LazyRefresh
from ..qtsafe import qt_safe


class SummaryCache:
    """Each element's summary text by the identity of its result (the text of a result never
    changes): a panel refresh after an edit of another element, or an undo or redo that brings a
    cached result back, shows its text without classifying the outputs again (for a chain of 32
    dyads the classification and the text take ~50 ms). Keeps the last ``keep`` results of each
    element (they are the workspace's, held here only while cached)."""

    def __init__(self, keep: int = 2) -> None:
        self.keep = keep
        self._texts: dict[str, list[tuple[object, str]]] = {}

    def summary(self, element_id: str, result) -> str:
        """``result.summary()``, computed once per result."""
        seen = self._texts.setdefault(element_id, [])
        for res, text in seen:
            if res is result:
                return text
        text = result.summary()
        seen.insert(0, (result, text))
        del seen[self.keep:]
        return text

    def forget_others(self, element_ids) -> None:
        """Drop the texts of elements not in ``element_ids`` (removed from the scene)."""
        for eid in set(self._texts) - set(element_ids):
            del self._texts[eid]


def diagnostics_lines(controller: SceneController, cache: SummaryCache | None = None) -> list[tuple[str, str]]:
    """(style, text) lines: style is "head", "error" or "" (pure: reads the controller; the
    summaries through ``cache`` when given)."""
    cache = cache or SummaryCache()
    out: list[tuple[str, str]] = []
    els = controller.scene.elements
    if not els:
        return [("", "The scene is empty.")]
    for el in els:
        if not isinstance(el, Linkage):
            out.extend(_element_lines(controller, el, cache))
            continue
        res = controller.result(el.id)
        if res is None or res.solution is None:
            out.append(("head", f"linkage {el.id}: {len(el.links)} links, {len(el.joints)} joints"))
            out.append(("error", "not solved yet" if res is None else f"cannot solve: {res.error}"))
            continue
        head, *rest = cache.summary(el.id, res).splitlines()   # the text of `mechsketch analyze --summary`
        out.append(("head", head))
        out.extend(("", line) for line in rest)
        out.append(("", f"solve + diagnostics in the app: {res.seconds * 1e3:.2f} ms"))
        if el.has_dynamics:
            out.extend(force_lines(controller, el.id))
    return out


def force_lines(controller: SceneController, element_id: str) -> list[tuple[str, str]]:
    """The forces summary of a linkage (the text ``analyze --forces --summary`` adds), computed
    when first asked and cached by the workspace; the core's message if it cannot be computed."""
    from mechsketch.core.analyses.forces.report import force_summary

    try:
        head, *rest = force_summary(controller.workspace.forces(element_id)).splitlines()
    except MechsketchError as exc:
        return [("error", f"forces: {exc}")]
    return [("head", head), *(("", line.strip()) for line in rest)]


def _element_lines(controller: SceneController, el, cache: SummaryCache) -> list[tuple[str, str]]:
    """The summary (or the error) of a Geneva drive or rolling lever; what an underlay is."""
    if isinstance(el, Underlay):
        return underlay_lines(el)
    res = controller.element_result(el.id)
    if res is None:   # a type this version of the app does not solve
        return [("head", f"{el.type} {el.id}"),
                ("", f"no diagnostics for this element type in the app yet (try: mechsketch analyze SCENE "
                     f"--element {el.id})")]
    kind = {"geneva": "Geneva drive", "rolling_lever": "rolling lever"}.get(el.type, el.type)
    out = [("head", f"{kind} {el.id}")]
    if res.error is not None:
        out.append(("error", res.error))
    if res.error is None or getattr(res, "kinematics", None) is not None:
        out.extend(("", line) for line in cache.summary(el.id, res).splitlines())
    out.append(("", f"computed in the app: {res.seconds * 1e3:.1f} ms"))
    return out


def underlay_lines(u: Underlay) -> list[tuple[str, str]]:
    """An underlay: what it holds, its placement and size (mm), whether it is shown."""
    x0, y0, x1, y1 = u.world_bounds()
    pl = u.placement
    what = (f"picture {u.image.width}×{u.image.height} px" if u.image is not None else
            f"drawing: {len(u.paths)} paths, {sum(len(p) for p in u.paths):,} points")
    return [("head", f"underlay {u.id}: {u.name}"), ("", what),
            ("", f"placed at {pl.scale:.6g} mm per unit, turned {pl.angle_deg:.4g}°: {x1 - x0:.4g} × {y1 - y0:.4g} mm "
                 f"from ({x0:.4g}, {y0:.4g})"),
            ("", "shown; its points snap" if u.visible else "hidden (its points do not snap)")]


@qt_safe
class DiagnosticsPanel(LazyRefresh, QWidget):
    """Read-only text of :func:`diagnostics_lines`, refreshed when the solutions change — during a
    drag only on the release (the text needs the full diagnostics and the motion classification,
    which a drag preview does not compute)."""

    preview_interval_ms = None

    def __init__(self, controller: SceneController, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.controller = controller
        self.text = QTextBrowser()
        self.text.setObjectName("diagnosticsText")
        self.text.setOpenLinks(False)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(self.text)
        self._stale = True
        self.summaries = SummaryCache()   # the texts of the results shown lately
        controller.changed.connect(self._invalidate)
        self.refresh()

    def refresh(self) -> None:
        self._stale = False
        parts = []
        self.summaries.forget_others(self.controller.scene.ids)
        for style, line in diagnostics_lines(self.controller, self.summaries):
            text = html.escape(line)
            if style == "head":
                parts.append(f"<p style='margin-top:6px; margin-bottom:2px'><b>{text}</b></p>")
            elif style == "error":
                parts.append(f"<p style='color:#b00020; margin:0'>{text}</p>")
            else:
                parts.append(f"<p style='margin:0; margin-left:10px'>{text}</p>")
        self.text.setHtml("".join(parts))

    def plain_text(self) -> str:
        """What the panel shows, as plain text."""
        self.refresh_if_stale()
        return self.text.toPlainText()
