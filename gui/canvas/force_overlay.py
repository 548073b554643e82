"""The forces View overlay: joint reactions and the driving torque at the displayed frame.

For every linkage with masses or loads, each revolute joint's reaction (the force on its
later-listed link, N) is an arrow from the joint to a stated scale (``1 mm ≙ … N``, chosen once
per result from the largest reaction of the cycle), labelled with its size; the driving torque
(N·m, counter-clockwise positive; a linear actuator's force, N, positive extending) is written
at the driver's joint. For every Geneva drive the
crank torque from its contact model is written at the crank centre the same way. The forces are
the workspace's (``Workspace.forces``: computed when the overlay is first shown, then cached);
a frame change only indexes arrays.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from PySide6.QtGui import QBrush, QColor, QPainter
from PySide6.QtWidgets import QStyleOptionGraphicsItem, QWidget

from mechsketch.core.analyses.geneva.torque import crank_torque
from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.geneva import Geneva

from .arrows import arrow, nice_scale
from .items import INK, _Item, _pen, _px, _rect_of, _text
from ..frames import map_frame
from ..qtsafe import qt_safe

REACTION = QColor("#e8590c")
TORQUE = QColor("#a61e4d")
#: the largest reaction arrow of the cycle is about this fraction of the linkage's size
ARROW_FRACTION = 0.25


@qt_safe
class ForcesItem(_Item):
    """Reaction arrows (records: at, tip, text), torque texts (at, torque) and legends."""

    PAD_PX = 160.0

    def __init__(self, z: float = 63) -> None:
        super().__init__()
        self.records: list[dict[str, Any]] = []
        self.setZValue(z)
        self.setCacheMode(_Item.CacheMode.NoCache)

    def set_records(self, records: list[dict[str, Any]], points: list) -> None:
        self.records = records
        self._bounds(_rect_of(points))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for r in self.records:
            if "legend" in r:
                _text(painter, r["legend"], r["text"], px, 0.0, 0.0, INK, 11, True)
            elif "torque" in r:
                _text(painter, r["at"], r["torque"], px, 10.0, -22.0, TORQUE, 11, True)
            else:
                painter.setPen(_pen(REACTION, 2.4))
                painter.setBrush(QBrush(REACTION))
                arrow(painter, r["at"], r["tip"], px)
                _text(painter, r["tip"], r["text"], px, 4.0, 4.0, REACTION, 10)


def _size(pose) -> float:
    ext = pose.arrays.extent() if pose.arrays is not None else None
    return max(ext[2] - ext[0], ext[3] - ext[1], 1.0) if ext else 100.0


def force_records(overlays) -> tuple[list[dict[str, Any]], list]:
    """The forces overlay at the displayed frame (``overlays`` an :class:`OverlaySet`)."""
    ctl = overlays.controller
    records: list[dict[str, Any]] = []
    points: list = []
    for pose in overlays.ctx.poses():
        lk = pose.linkage
        if not lk.has_dynamics or pose.arrays is None or pose.index is None:
            continue
        try:
            res = ctl.workspace.forces(lk.id)
        except MechsketchError as exc:
            ctl.message.emit(f"forces of {lk.id}: {exc}")
            continue
        if len(res) != pose.arrays.n:
            continue
        k = pose.index
        biggest = max((float(np.nanmax(np.hypot(f[:, 0], f[:, 1]))) for on in res.pins.values()
                       for f in on.values() if np.isfinite(f).any()), default=0.0)
        scale = nice_scale(biggest / (ARROW_FRACTION * _size(pose))) if biggest > 0 else 1.0
        for j, on in res.pins.items():
            f = next(iter(on.values()))[k]
            if j not in pose.at or not np.all(np.isfinite(f)):
                continue
            at = pose.at[j]
            tip = (at[0] + float(f[0]) / scale, at[1] + float(f[1]) / scale)
            records.append({"at": at, "tip": tip, "text": f"{j} {math.hypot(*f):.3g} N"})
            points += [at, tip]
        t = float(res.driver.values[k])
        pivot = pose.at[lk.driver.pivot]
        if math.isfinite(t):
            sym = "T" if res.driver.kind == "torque" else "F"   # a crank's torque, an actuator's force
            records.append({"at": pivot, "torque": f"{lk.driver.link}: {sym} = {t:.4g} {res.driver.unit}"})
        ext = pose.arrays.extent()
        corner = (ext[0], ext[1] - 0.1 * _size(pose)) if ext else pivot
        records.append({"legend": corner, "text": f"{lk.id}: joint forces on the later-listed link, "
                                                  f"1 mm ≙ {scale:g} N"})
        points += [pivot, corner]
    total = ctl.sample_count()
    for eid, res in ctl.element_results().items():
        el = res.element
        if not isinstance(el, Geneva) or res.contact is None or not res.n_frames:
            continue
        k = map_frame(overlays.ctx.display_frame(), total, res.n_frames)
        tq = crank_torque(el, res.contact)
        records.append({"at": el.crank_center, "torque": f"{el.id}: crank torque {tq.torque[k]:.4g} N·m"})
        points.append(el.crank_center)
    return records, points
