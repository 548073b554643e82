"""View overlays of the canvas, each a graphics item painting from precomputed arrays.

- :class:`HandlesItem` - the handles of the selected Geneva drives and rolling levers;
- :class:`VectorsItem` - velocity (green) and acceleration (red) of the selected joints, to a
  stated scale (``1 mm ≙ … mm/s``), chosen once per solution from the largest value in the cycle;
- :class:`CentresItem` - instant centres of the selected links relative to the frame and to every
  other link (Kennedy's theorem draws itself: three centres of three links on one line);
- :class:`TransmissionItem` - the transmission angle μ of every RRR group, an arc at the inner
  joint, red outside 40°-140°;
- :class:`GenevaOverlayItem` - for each Geneva drive the phase (indexing or dwell), the contact
  force on the roller as an arrow to a stated scale, and the most loaded place on every slot.

:class:`OverlaySet` holds them, the switches (View menu) and the per-solution array caches
(velocities, centres): a frame change only indexes arrays.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QBrush, QColor, QFont, QFontMetricsF, QPainter, QPainterPath
from PySide6.QtWidgets import QStyleOptionGraphicsItem, QWidget

from mechsketch.core.analyses.centrodes import linkage_centrodes
from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.geneva import Geneva

from .arrows import arrow, nice_scale
from .centrode_view import CentrodeView
from .force_overlay import ForcesItem, force_records
from .items import BAD, INK, MUTED, _Item, _pen, _px, _rect_of, _text
from ..frames import map_frame
from ..qtsafe import qt_safe

HANDLE = QColor("#0b7285")
VEL = QColor("#2b8a3e")
ACC = QColor("#c92a2a")
IC = QColor("#7048e8")
MU = QColor("#1c7ed6")
FORCE = QColor("#d9480f")
#: a vector's longest arrow over the cycle is about this fraction of the linkage's size
VECTOR_FRACTION = 0.3
MU_RANGE = (40.0, 140.0)   # degrees: a transmission angle outside is drawn in red


@qt_safe
class HandlesItem(_Item):
    """Squares at the handle positions with short labels."""

    PAD_PX = 120.0

    def __init__(self) -> None:
        super().__init__()
        self.handles: list = []
        self.placed: list[QRectF] = []   # the labels' boxes at the last paint (screen px)
        self.setZValue(90)
        self.setCacheMode(_Item.CacheMode.NoCache)

    def set_handles(self, handles: list) -> None:
        self.handles = list(handles)
        self._bounds(_rect_of([h.at for h in self.handles]))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for h in self.handles:
            s = 5 * px
            painter.setPen(_pen(HANDLE, 1.6))
            painter.setBrush(QBrush(QColor("white")))
            painter.drawRect(QRectF(h.at[0] - s, h.at[1] - s, 2 * s, 2 * s))
        font = QFont(painter.font())
        font.setPixelSize(LABEL_SIZE)
        metrics = QFontMetricsF(font)
        offsets, self.placed = place_labels([(h.at[0] / px, -h.at[1] / px) for h in self.handles],
                                            [(metrics.horizontalAdvance(h.label), metrics.height()) for h in self.handles],
                                            metrics.ascent())
        for h, (dx, dy) in zip(self.handles, offsets):
            _text(painter, h.at, h.label, px, dx, dy, HANDLE, LABEL_SIZE)


#: a handle's label, px
LABEL_SIZE = 10
#: where a handle's label may go (dx, dy: px right and up of its handle, baseline start), by
#: preference; the text's width is subtracted from the dx of the left-hand ones
LABEL_PLACES = ((9.0, -16.0), (9.0, 8.0), (-9.0, -16.0), (-9.0, 8.0), (9.0, -30.0), (9.0, 22.0),
                (-9.0, -30.0), (-9.0, 22.0))


def place_labels(points: list[tuple[float, float]], sizes: list[tuple[float, float]],
                 ascent: float) -> tuple[list[tuple[float, float]], list[QRectF]]:
    """Offsets (dx, dy) in px of labels beside ``points`` (screen px, y down) whose texts are
    ``sizes`` (width, height px): each takes the first of :data:`LABEL_PLACES` where its box meets
    no label placed before it nor a handle's square (greedy, in order; the first place if none is
    free). Returns the offsets and the boxes (screen px) — two handles close together (the
    rolling lever's lever and slider circle centres) no longer print their labels over each other."""
    squares = [QRectF(x - 6.0, y - 6.0, 12.0, 12.0) for x, y in points]
    placed: list[QRectF] = []
    offsets = []
    for k, ((x, y), (w, h)) in enumerate(zip(points, sizes)):
        choice = None
        for dx, dy in LABEL_PLACES:
            dx = dx - w if dx < 0 else dx
            box = QRectF(x + dx, y - dy - ascent, w, h)
            if not any(box.intersects(r) for r in placed) and not any(
                    box.intersects(q) for j, q in enumerate(squares) if j != k):
                choice = (dx, dy, box)
                break
        if choice is None:
            dx, dy = LABEL_PLACES[0]
            choice = (dx, dy, QRectF(x + dx, y - dy - ascent, w, h))
        offsets.append(choice[:2])
        placed.append(choice[2])
    return offsets, placed


class _ArraysItem(_Item):
    """Base of the overlay items: a list of drawing records rebuilt by :class:`OverlaySet`."""

    PAD_PX = 160.0

    def __init__(self, z: float) -> None:
        super().__init__()
        self.records: list[dict[str, Any]] = []
        self.setZValue(z)
        self.setCacheMode(_Item.CacheMode.NoCache)

    def set_records(self, records: list[dict[str, Any]], points: list) -> None:
        self.records = records
        self._bounds(_rect_of(points))


@qt_safe
class VectorsItem(_ArraysItem):
    """Velocity and acceleration arrows of joints (records: at, v_tip, a_tip) and a legend."""

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for r in self.records:
            if "legend" in r:
                _text(painter, r["legend"], r["text"], px, 0.0, 0.0, INK, 11, True)
                continue
            for key, colour in (("v_tip", VEL), ("a_tip", ACC)):
                tip = r.get(key)
                if tip is not None:
                    painter.setPen(_pen(colour, 2.2))
                    painter.setBrush(QBrush(colour))
                    arrow(painter, r["at"], tip, px)


@qt_safe
class CentresItem(_ArraysItem):
    """Instant centres (records: at, label, far)."""

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for r in self.records:
            if r.get("far"):
                _text(painter, r["at"], f"{r['label']} at infinity (translation)", px, 8.0, -30.0, IC, 10)
                continue
            x, y = r["at"]
            s = 6 * px
            painter.setPen(_pen(IC, 2.0))
            painter.setBrush(Qt.BrushStyle.NoBrush)
            painter.drawEllipse(QPointF(x, y), s, s)
            painter.drawLine(QPointF(x - 1.6 * s, y), QPointF(x + 1.6 * s, y))
            painter.drawLine(QPointF(x, y - 1.6 * s), QPointF(x, y + 1.6 * s))
            _text(painter, (x, y), r["label"], px, 9.0, 8.0, IC, 10, True)


@qt_safe
class TransmissionItem(_ArraysItem):
    """Transmission-angle arcs (records: at, a0, sweep, mu)."""

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        for r in self.records:
            mu = r["mu"]
            colour = MU if MU_RANGE[0] <= mu <= MU_RANGE[1] else BAD
            painter.setPen(_pen(colour, 2.0))
            x, y = r["at"]
            rad = 22 * px
            path = QPainterPath()
            path.moveTo(x + rad * math.cos(r["a0"]), y + rad * math.sin(r["a0"]))
            for t in np.linspace(0.0, 1.0, 24)[1:]:
                a = r["a0"] + t * r["sweep"]
                path.lineTo(x + rad * math.cos(a), y + rad * math.sin(a))
            painter.drawPath(path)
            mid = r["a0"] + 0.5 * r["sweep"]
            _text(painter, (x + 1.5 * rad * math.cos(mid), y + 1.5 * rad * math.sin(mid)), f"μ {mu:.1f}°", px,
                  -14.0, -4.0, colour, 10, True)


@qt_safe
class GenevaOverlayItem(_ArraysItem):
    """Geneva phase text, contact-force arrow, most-loaded marks (records per drive)."""

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        px = _px(painter)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for r in self.records:
            _text(painter, r["label_at"], r["phase"], px, 0.0, 0.0, INK, 12, True)
            _text(painter, r["label_at"], r["scale"], px, 0.0, -16.0, MUTED, 10)
            if r.get("force") is not None:
                a, b = r["force"]
                painter.setPen(_pen(FORCE, 2.6))
                painter.setBrush(QBrush(FORCE))
                arrow(painter, a, b, px)
                _text(painter, a, r["force_text"], px, 10.0, 10.0, FORCE, 10, True)
            painter.setPen(_pen(BAD, 2.0))
            painter.setBrush(Qt.BrushStyle.NoBrush)
            for x, y in r["loaded"]:
                s = 5 * px
                painter.drawLine(QPointF(x - s, y - s), QPointF(x + s, y + s))
                painter.drawLine(QPointF(x - s, y + s), QPointF(x + s, y - s))
                painter.drawEllipse(QPointF(x, y), 1.5 * s, 1.5 * s)
            if r["loaded"]:
                _text(painter, r["label_at"], r["loaded_text"], px, 0.0, -32.0, BAD, 10)


def _rot(v: np.ndarray, a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


class OverlaySet:
    """The overlays of one canvas: switches, caches, and the records drawn at the displayed frame."""

    #: (name, menu text, shortcut, status tip) of the View switches, in menu order
    ACTIONS = (
        ("vectors", "Velocity && Acceleration of Selected Joints", "",
         "arrows of the selected joints' velocity (green) and acceleration (red), scale stated on the canvas"),
        ("centres", "Instant Centres of Selected Links", "",
         "the instant centres of the selected links relative to the frame and to every other link"),
        ("transmission", "Transmission Angles", "", "the transmission angle μ of every RRR group"),
        ("geneva", "Geneva Phase && Contact Force", "",
         "Geneva drives: dwell or indexing, the contact force on the roller, the most loaded place"),
        ("forces", "Joint Forces && Driving Torque", "",
         "linkages with masses or loads: joint reactions as arrows and the driving torque; Geneva drives: "
         "the crank torque from the contact model"),
        ("centrodes", "Centrodes of Selected Link", "",
         "fixed centrode on the frame (or on a second selected link), moving centrode on the link, rolling"),
    )

    def __init__(self, view) -> None:
        self.view = view
        self.ctx = view.ctx
        self.controller = view.controller
        self.shown: dict[str, bool] = {name: False for name, *_ in self.ACTIONS}
        self.items = {"vectors": VectorsItem(60), "centres": CentresItem(61), "transmission": TransmissionItem(59),
                      "geneva": GenevaOverlayItem(62), "forces": ForcesItem(63)}
        for it in self.items.values():
            view.scene().addItem(it)
        self.centrodes = CentrodeView(view)
        self._cache: dict[tuple, Any] = {}

    def set_shown(self, name: str, on: bool) -> None:
        """Switch overlay ``name`` on or off."""
        if name == "centrodes":
            self.shown[name] = self.centrodes.set_enabled(on)
            return
        self.shown[name] = bool(on)
        self.refresh()

    def set_px(self, px: float) -> None:
        for it in self.items.values():
            it.set_px(px)
        self.centrodes.set_px(px)

    # -- caches (per solution, by identity) ------------------------------------------------------
    def _cached(self, key: tuple, make) -> Any:
        hit = self._cache.get(key)
        if hit is None or hit[0] is not key[0]:
            if len(self._cache) > 256:
                self._cache.clear()
            hit = (key[0], make())
            self._cache[key] = hit
        return hit[1]

    def _va(self, sol, joint: str) -> tuple[np.ndarray, np.ndarray, float, float]:
        """Velocity (N, 2) mm/s and acceleration (N, 2) mm/s² of ``joint`` and their largest norms."""
        def make():
            v, a = sol.velocity(joint), sol.acceleration(joint)
            vm = np.linalg.norm(v, axis=1)
            am = np.linalg.norm(a, axis=1)
            return v, a, float(np.nanmax(vm)) if np.isfinite(vm).any() else 0.0, \
                float(np.nanmax(am)) if np.isfinite(am).any() else 0.0
        return self._cached((sol, "va", joint, id(sol)), make)

    def _centre(self, sol, lk, link: str, rel: str | None):
        return self._cached((sol, "ic", link, rel, id(sol)), lambda: linkage_centrodes(sol, lk, link, rel))

    # -- records at the displayed frame ----------------------------------------------------------
    def refresh(self) -> None:
        """Rebuild every shown overlay's records at the displayed frame."""
        for name, item in self.items.items():
            if not self.shown[name]:
                item.set_records([], [])
                continue
            try:
                records, points = getattr(self, f"_{name}")()
            except MechsketchError as exc:   # a request the core refuses: say it, draw nothing
                self.controller.message.emit(f"{name}: {exc}")
                records, points = [], []
            item.set_records(records, points)
        self.centrodes.refresh()

    def _selected(self, kind: str) -> dict[str, list[str]]:
        out: dict[str, list[str]] = {}
        for el, k, i in self.controller.selection:
            if k == kind:
                out.setdefault(el, []).append(i)
        return out

    def _size(self, pose) -> float:
        ext = pose.arrays.extent() if pose.arrays is not None else None
        return max(ext[2] - ext[0], ext[3] - ext[1], 1.0) if ext else 100.0

    def _vectors(self):
        sel = self._selected("joint")
        records, points = [], []
        for pose in self.ctx.poses():
            joints = sel.get(pose.element, [])
            if not joints or pose.arrays is None or pose.index is None:
                continue
            sol, k = pose.arrays.solution, pose.index
            data = {j: self._va(sol, j) for j in joints if j in pose.at}
            vmax = max((d[2] for d in data.values()), default=0.0)
            amax = max((d[3] for d in data.values()), default=0.0)
            length = VECTOR_FRACTION * self._size(pose)
            sv = nice_scale(vmax / length) if vmax > 0 else 1.0     # mm/s per mm of arrow
            sa = nice_scale(amax / length) if amax > 0 else 1.0
            for j, (v, a, _, _) in data.items():
                at = pose.at[j]
                rec = {"at": at}
                if np.all(np.isfinite(v[k])):
                    rec["v_tip"] = (at[0] + float(v[k, 0]) / sv, at[1] + float(v[k, 1]) / sv)
                    points.append(rec["v_tip"])
                if np.all(np.isfinite(a[k])):
                    rec["a_tip"] = (at[0] + float(a[k, 0]) / sa, at[1] + float(a[k, 1]) / sa)
                    points.append(rec["a_tip"])
                records.append(rec)
                points.append(at)
            if data:
                ext = pose.arrays.extent()
                corner = (ext[0], ext[3] + 0.12 * self._size(pose)) if ext else pose.at[joints[0]]
                records.append({"legend": corner, "text": f"{pose.element}: v (green) 1 mm ≙ {sv:g} mm/s,  "
                                                          f"a (red) 1 mm ≙ {sa:g} mm/s²"})
                points.append(corner)
        return records, points

    def _centres(self):
        sel = self._selected("link")
        records, points = [], []
        for pose in self.ctx.poses():
            links = [l for l in sel.get(pose.element, []) if l != pose.linkage.ground]
            if not links or pose.arrays is None or pose.index is None:
                continue
            sol, lk, k = pose.arrays.solution, pose.linkage, pose.index
            limit = 50.0 * self._size(pose)
            for link in links:
                for other in [lk.ground] + [m for m in lk.moving_links if m != link]:
                    c = self._centre(sol, lk, link, None if other == lk.ground else other)
                    label = f"I({link},{other})"
                    w = c.world[k]
                    anchor = pose.at[lk.link(link).joints[0]]
                    if c.translation[k] or not np.all(np.isfinite(w)) or np.hypot(*(w - anchor)) > limit:
                        if other == lk.ground:
                            records.append({"at": anchor, "label": label, "far": True})
                        continue
                    records.append({"at": (float(w[0]), float(w[1])), "label": label})
                    points.append((float(w[0]), float(w[1])))
        return records, points

    def _transmission(self):
        records, points = [], []
        for pose in self.ctx.poses():
            if pose.arrays is None or pose.index is None:
                continue
            sol, k = pose.arrays.solution, pose.index
            for g in sol.groups:
                if str(g.kind) != "RRR":
                    continue
                mu = self._cached((sol, "mu", g.name, id(sol)), lambda g=g: np.degrees(sol.transmission_angle(g.name)))
                if not math.isfinite(mu[k]):
                    continue
                L = np.asarray(pose.at[g.inner])
                a = np.asarray(pose.at[g.outer_i]) - L
                b = np.asarray(pose.at[g.outer_j]) - L
                a0 = math.atan2(a[1], a[0])
                sweep = math.remainder(math.atan2(b[1], b[0]) - a0, 2 * math.pi)
                records.append({"at": (float(L[0]), float(L[1])), "a0": a0, "sweep": sweep, "mu": float(mu[k])})
                points.append((float(L[0]), float(L[1])))
        return records, points

    def _forces(self):
        return force_records(self)

    def _geneva(self):
        records, points = [], []
        ctl = self.controller
        total = ctl.sample_count()
        for eid, res in ctl.element_results().items():
            el = res.element
            if not isinstance(el, Geneva) or res.kinematics is None or res.contact is None or not res.n_frames:
                continue
            k = map_frame(self.ctx.display_frame(), total, res.n_frames)
            records.append(self._geneva_record(el, res, k))
            points += records[-1]["loaded"] + [records[-1]["label_at"]]
        return records, points

    def _geneva_record(self, el: Geneva, res, k: int) -> dict[str, Any]:
        kin, con = res.kinematics, res.contact
        cc, wc = np.asarray(el.crank_center), np.asarray(el.wheel_center)
        r, rp, a = el.crank_radius, el.roller_radius, el.center_distance
        rn = con.Rn
        rn_max = float(np.nanmax(rn)) if np.isfinite(rn).any() else 0.0
        scale = nice_scale(rn_max / (0.35 * a)) if rn_max > 0 else 1.0   # N per mm of arrow

        def contact_at(j: int) -> tuple[np.ndarray, np.ndarray] | None:
            """(contact point, unit force on the roller) at sample j, None outside the engagement."""
            if not (kin.engaged[j] and math.isfinite(rn[j]) and rn[j] > 0):
                return None
            rho = float(res.crank_rotation[j])
            roller = cc + r * np.array([math.cos(rho), math.sin(rho)])
            er = (roller - wc) / np.linalg.norm(roller - wc)
            tang = np.sign(kin.omega[j] or 1.0) * np.array([-er[1], er[0]])
            sgn = np.sign(con.moment[j]) or 1.0
            return roller + rp * sgn * tang, -sgn * tang

        rec: dict[str, Any] = {"label_at": (float(wc[0] - a * 0.2), float(wc[1] + 1.05 * a)),
                               "scale": f"force arrow: 1 mm ≙ {scale:g} N", "force": None, "loaded": []}
        hit = contact_at(k)
        rec["phase"] = f"{el.id}: indexing" if kin.engaged[k] else f"{el.id}: dwell (wheel locked)"
        if hit is not None:
            p, u = hit
            tail = p - u * float(rn[k]) / scale
            rec["force"] = ((float(tail[0]), float(tail[1])), (float(p[0]), float(p[1])))
            rec["force_text"] = f"Rn {float(rn[k]):.0f} N"
        if rn_max > 0:
            j = int(np.nanargmax(rn))
            hit = contact_at(j)
            if hit is not None:
                local = _rot(hit[0] - wc, -float(res.wheel_rotation[j]))
                now = float(res.wheel_rotation[k])
                rec["loaded"] = [tuple(float(v) for v in wc + _rot(_rot(local, 2 * math.pi * i / el.slots), now))
                                 for i in range(el.slots)]
                p_text = (f"p max {con.pressure_max:.0f} MPa" if math.isfinite(con.pressure_max)
                          else "p max not computed (outside the contact model's validity range)")
                rec["loaded_text"] = (f"most loaded: Rn max {rn_max:.0f} N at φ {math.degrees(con.phi_Rn_max):.1f}°, "
                                      + p_text)
        return rec
