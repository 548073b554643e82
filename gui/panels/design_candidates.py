"""The Design dock's candidate list: each synthesised linkage with a thumbnail (its drawn pose, the
path of its coupler point over the cycle, the target's points) and its numbers — largest
deviation, least transmission angle, type and time (the line ``mechsketch design`` prints).

:func:`thumbnail` draws with QPainter from one sweep of the product's solver (no canvas item:
panels never import the canvas).
"""
from __future__ import annotations

import numpy as np
from PySide6.QtCore import QPointF, QRectF, QSize, Qt
from PySide6.QtGui import QColor, QIcon, QPainter, QPen, QPixmap
from PySide6.QtWidgets import QAbstractItemView, QListWidget, QListWidgetItem

from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.linkage import JointKind, Linkage
from mechsketch.core.solver.plan import compile_plan

from .design_runs import candidate_lines

THUMB = QSize(128, 96)
LINK = QColor("#3d5f8f")
CURVE = QColor("#8e44ad")
TARGET = QColor("#0a8a5f")
SAMPLES = 120


def curve_of(linkage: Linkage, samples: int = SAMPLES) -> np.ndarray:
    """(samples, 2) mm: the path of the coupler point ``P`` (else of the output's pin) over a
    cycle by the solver; NaN where it cannot be assembled; empty if it does not solve."""
    joint = "P" if "P" in linkage.joint_ids else next(
        (j for j in ("C", "G") if j in linkage.joint_ids), linkage.joint_ids[-1])
    try:
        return compile_plan(linkage).sweep(samples, order=0, joints=[joint]).position(joint)
    except MechsketchError:
        return np.zeros((0, 2))


def thumbnail(linkage: Linkage, target: np.ndarray | None = None, size: QSize = THUMB) -> QPixmap:
    """A small picture of ``linkage`` (see the module docstring), y up, fitted with a margin."""
    curve = curve_of(linkage)
    joints = np.array([j.at for j in linkage.joints], dtype=float)
    tgt = np.zeros((0, 2)) if target is None else np.asarray(target, dtype=float).reshape(-1, 2)
    pts = np.concatenate([a for a in (curve, joints, tgt) if len(a)])
    pts = pts[np.isfinite(pts).all(axis=1)]
    pix = QPixmap(size)
    pix.fill(QColor("white"))
    if not len(pts):
        return pix
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = max(float(np.max(hi - lo)), 1e-9)
    margin = 6.0
    s = min((size.width() - 2 * margin) / max(hi[0] - lo[0], 1e-9 * span),
            (size.height() - 2 * margin) / max(hi[1] - lo[1], 1e-9 * span))
    cx, cy = (lo + hi) / 2

    def at(p) -> QPointF:
        return QPointF(size.width() / 2 + s * (p[0] - cx), size.height() / 2 - s * (p[1] - cy))

    painter = QPainter(pix)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
    painter.setPen(QPen(CURVE, 1.2))
    ok = np.isfinite(curve).all(axis=1) if len(curve) else np.zeros(0, bool)
    for k in range(len(curve)):
        if ok[k] and ok[k - 1]:
            painter.drawLine(at(curve[k - 1]), at(curve[k]))
    painter.setPen(QPen(LINK, 1.6))
    for link in linkage.links:
        if link.id == linkage.ground:
            continue
        ps = [linkage.joint(j).at for j in link.joints]
        for a in range(len(ps)):
            for b in range(a + 1, len(ps)):
                painter.drawLine(at(ps[a]), at(ps[b]))
    ground = set(linkage.link(linkage.ground).joints)
    for j in linkage.joints:
        painter.setBrush(QColor("#b3661a") if j.id in ground else QColor("white"))
        if j.kind is JointKind.R:
            painter.drawEllipse(at(j.at), 2.2, 2.2)
    painter.setPen(QPen(TARGET, 1.0))
    painter.setBrush(TARGET)
    for p in tgt:
        painter.drawEllipse(at(p), 1.6, 1.6)
    painter.end()
    return pix


class CandidateList(QListWidget):
    """The candidates, best first: a thumbnail and two lines of numbers each."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.setObjectName("designCandidates")
        self.setIconSize(THUMB)
        self.setWordWrap(True)
        self.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.setVerticalScrollMode(QAbstractItemView.ScrollMode.ScrollPerPixel)
        self.setMinimumHeight(THUMB.height() * 2 + 20)
        self.candidates: list = []

    def show_candidates(self, candidates: list, target: np.ndarray | None = None) -> None:
        self.clear()
        self.candidates = list(candidates)
        for k, c in enumerate(self.candidates):
            title, numbers = candidate_lines(c, k + 1)
            item = QListWidgetItem(QIcon(thumbnail(c.linkage, target)), f"{title}\n{numbers}")
            item.setToolTip(c.line(k + 1))
            item.setData(Qt.ItemDataRole.UserRole, k)
            item.setSizeHint(QSize(THUMB.width() + 240, THUMB.height() + 8))
            self.addItem(item)

    def chosen(self):
        """The selected candidate, or None."""
        k = self.currentRow()
        return self.candidates[k] if 0 <= k < len(self.candidates) else None

    def item_rect(self, k: int) -> QRectF:
        return QRectF(self.visualItemRect(self.item(k)))


__all__ = ["CandidateList", "curve_of", "thumbnail"]
