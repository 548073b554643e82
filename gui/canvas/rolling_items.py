"""Canvas items of a rolling lever, built once per synthesis and animated from precomputed frames.

:class:`RollingItem` draws, in world millimetres (y up):

- the frame profile (the fixed centrode, pair D) with the frame's hatched body behind it, and the
  bicentrode (locus of the pair-E contact P0), both static;
- the lever, a rigid plate in its own (drawn-pose) frame: both circles (thin, dashed) with their
  working arcs as true arcs, the pin hole at f and, with a drive, the coupler hole at C; one
  transform per frame, X(p) = F + Rot(θ)(p − f);
- the slider (its synthesised profile on a body) in the slider frame, translated by S5 along the
  slider axis per frame, over a dash-dotted guide;
- painted per frame from the arrays: the rocker G–F, the crank A–B and the coupler B–C (with a
  drive), joints, ground pivots and the two contact points P and P0.

Nothing is solved here: every frame reads the :class:`~mechsketch.core.workspace.results.RollingFrames`
of a :class:`~mechsketch.core.workspace.results.RollingResult`.
"""
from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QBrush, QColor, QPainter, QPainterPath, QPainterPathStroker, QPen, QTransform
from PySide6.QtWidgets import QGraphicsItem, QGraphicsPathItem, QStyleOptionGraphicsItem, QWidget

from mechsketch.core.workspace import RollingResult
from .geneva_items import _Container, _path_item, arc_to
from .items import DRIVER_EDGE, INK, LINK_EDGE, LINK_FILL, MUTED, NOTE, SELECT, _pen, _px, _text, draw_ground
from ..qtsafe import qt_safe

FRAME_EDGE = QColor("#b03a2e")
FRAME_FILL = QColor("#e8d5d2")
LEVER_FILL = QColor(207, 220, 238, 190)
ARC = QColor("#1f4e8c")
SLIDER_EDGE = QColor("#2e7d32")
SLIDER_FILL = QColor("#dcebd5")
BICENTRODE = QColor("#8e44ad")
CONTACT = QColor("#d62728")
JOINT_PX = 4.5


def polyline_path(xy: np.ndarray, close: bool = False) -> QPainterPath:
    """A path through the finite rows of ``xy`` (N, 2) mm; NaN rows break it."""
    path = QPainterPath()
    pen_down = False
    for x, y in np.asarray(xy, dtype=float):
        if not (math.isfinite(x) and math.isfinite(y)):
            pen_down = False
            continue
        if pen_down:
            path.lineTo(x, y)
        else:
            path.moveTo(x, y)
            pen_down = True
    if close:
        path.closeSubpath()
    return path


def arc_path(centre: tuple[float, float], radius: float, a0: float, a1: float,
             path: QPainterPath | None = None) -> QPainterPath:
    """A circular arc from angle ``a0`` to ``a1`` (rad, CCW, y-up world) as a curve
    (:func:`~.geneva_items.arc_to`), appended to ``path``."""
    path = QPainterPath() if path is None else path
    cx, cy = centre
    path.moveTo(cx + radius * math.cos(a0), cy + radius * math.sin(a0))
    arc_to(path, centre, radius, a0, a1 - a0)
    return path


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise convex hull (M, 2) of points (N, 2) (monotone chain)."""
    pts = sorted({(float(x), float(y)) for x, y in points if math.isfinite(x) and math.isfinite(y)})
    if len(pts) < 3:
        return np.asarray(pts, dtype=float).reshape(-1, 2)

    def cross(o, a, b) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.asarray(lower[:-1] + upper[:-1], dtype=float)


def _normals(xy: np.ndarray) -> np.ndarray:
    """Unit left normals (N, 2) of a polyline (central differences)."""
    d = np.gradient(xy, axis=0)
    n = np.stack([-d[:, 1], d[:, 0]], axis=-1)
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def body_behind(profile: np.ndarray, away_from: tuple[float, float], depth: float) -> np.ndarray:
    """A band (closed polygon, (2N, 2) mm) of ``depth`` mm behind ``profile``, on the side away
    from the point ``away_from`` (the mating body is on the other side)."""
    n = _normals(profile)
    mid = len(profile) // 2
    side = -1.0 if float(np.dot(np.asarray(away_from) - profile[mid], n[mid])) > 0 else 1.0
    back = profile + side * depth * n
    return np.concatenate([profile, back[::-1]])


def lever_transform(F: np.ndarray, theta: float, f: tuple[float, float]) -> QTransform:
    """X(p) = F + Rot(θ)(p − f): the lever frame (drawn pose) into the ground at one frame."""
    t = QTransform()
    t.translate(float(F[0]), float(F[1]))
    t.rotateRadians(float(theta))
    t.translate(-f[0], -f[1])
    return t


@qt_safe
class _Moving(QGraphicsItem):
    """The per-frame drawing of a :class:`RollingItem` (bars, joints, contacts), above its parts."""

    def __init__(self, owner: "RollingItem") -> None:
        super().__init__(owner)
        self.owner = owner
        self.setZValue(10)

    def boundingRect(self) -> QRectF:
        return self.owner.boundingRect()

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem, widget: QWidget | None = None) -> None:
        self.owner.paint_frame(painter)


class RollingItem(_Container):
    """One rolling lever; ``lever`` and ``slider`` are the moving groups, ``paths`` the path items
    by name ("frame_profile", "frame_body", "bicentrode", "guide", "lever_plate", "lever_arc",
    "slider_arc", "lever_circles", "slider_profile", "slider_body")."""

    def __init__(self, result: RollingResult) -> None:
        super().__init__()
        self.setZValue(5)
        self.result = result
        self.paths: dict[str, QGraphicsPathItem] = {}
        self.lever = _Container()
        self.slider = _Container()
        self.lever.setParentItem(self)
        self.slider.setParentItem(self)
        self.lever.setZValue(3)
        self.slider.setZValue(2)
        self.index = 0
        self.selected = False
        self._moving = _Moving(self)
        self._build()
        self.set_frame(0)

    @property
    def element_id(self) -> str:
        return self.result.element_id

    @property
    def n_frames(self) -> int:
        return self.result.n_frames

    # -- building ---------------------------------------------------------------------------
    def _build(self) -> None:
        res, el = self.result, self.result.element
        if res.synthesis is None or res.frames is None:
            self._set_core(QRectF(el.pin[0] - 10, el.pin[1] - 10, 20, 20))
            self.label_at, self.label_color = el.pin, NOTE
            self.label_text = f"{el.id}: {res.error or 'not synthesised'}"
            return
        fr = res.frames
        lc, sc = el.lever_circle, el.slider_circle
        law = sc is None   # a slider law: the lever's pair-E element is the derived curve Π30
        depth = 0.12 * (lc.radius if law else max(lc.radius, sc.radius))
        lever_side = el.pin if law else sc.center
        # the frame: profile and its body (away from the lever circle's centre in the drawn pose)
        self.paths["frame_body"] = _path_item(polyline_path(body_behind(res.frame_profile, lc.center, depth), True),
                                              self, FRAME_FILL, FRAME_FILL, 0.5, 0.5, "frame_body")
        self.paths["frame_body"].setBrush(QBrush(FRAME_EDGE, Qt.BrushStyle.BDiagPattern))
        self.paths["frame_profile"] = _path_item(polyline_path(res.frame_profile), self, None, FRAME_EDGE, 2.6,
                                                 1.0, "frame_profile")
        self.paths["bicentrode"] = _path_item(polyline_path(res.bicentrode), self, None, BICENTRODE, 1.4, 1.1,
                                              "bicentrode", Qt.PenStyle.DashLine)
        # the slider guide (static) and the slider (moves by S5 along the axis)
        ds = np.asarray(el.slider_axis)
        p0 = fr.P0[0] - fr.S5[0] * ds
        s_lo, s_hi = float(np.nanmin(fr.S5)), float(np.nanmax(fr.S5))
        ext = float(np.ptp(res.slider_profile @ ds)) if len(res.slider_profile) else 0.0
        margin = 0.6 * ext + depth
        guide = QPainterPath()
        a, b = p0 + (s_lo - margin) * ds, p0 + (s_hi + margin) * ds
        guide.moveTo(*a)
        guide.lineTo(*b)
        self.paths["guide"] = _path_item(guide, self, None, MUTED, 1.0, 0.8, "guide", Qt.PenStyle.DashDotLine)
        sbody = body_behind(res.slider_profile, lever_side, depth)
        self.paths["slider_body"] = _path_item(polyline_path(sbody, True), self.slider, SLIDER_FILL, SLIDER_FILL,
                                               0.5, 0.0, "slider_body")
        self.paths["slider_profile"] = _path_item(polyline_path(res.slider_profile), self.slider, None,
                                                  SLIDER_EDGE, 2.6, 1.0, "slider_profile")
        # the lever in its own frame: plate, dashed circles, working arcs, holes
        (u1a, u1b), (u2a, u2b) = res.lever_arc, res.slider_arc
        t1, t2 = np.linspace(u1a, u1b, 60), np.linspace(u2a, u2b, 60)
        pair_e = (res.lever_profile_e if law else
                  np.asarray(sc.center) + sc.radius * np.stack([np.cos(t2), np.sin(t2)], axis=-1))
        pts = [np.asarray(lc.center) + lc.radius * np.stack([np.cos(t1), np.sin(t1)], axis=-1), pair_e,
               np.asarray([el.pin])]
        if el.drive is not None:
            pts.append(np.asarray([el.drive.coupler_point]))
        plate = polyline_path(convex_hull(np.concatenate(pts)), True)
        r_pin = 0.5 * el.pin_diameter
        holes = [el.pin] + ([el.drive.coupler_point] if el.drive is not None else [])
        for h in holes:
            plate.addEllipse(QPointF(*h), r_pin, r_pin)
        plate.setFillRule(Qt.FillRule.OddEvenFill)
        self.paths["lever_plate"] = _path_item(plate, self.lever, LEVER_FILL, LINK_EDGE, 1.2, 0.0, "lever_plate")
        circles = QPainterPath()
        circles.addEllipse(QPointF(*lc.center), lc.radius, lc.radius)
        if not law:
            circles.addEllipse(QPointF(*sc.center), sc.radius, sc.radius)
        self.paths["lever_circles"] = _path_item(circles, self.lever, None, LINK_EDGE, 0.8, 0.5, "lever_circles",
                                                 Qt.PenStyle.DashLine)
        self.paths["lever_arc"] = _path_item(arc_path(lc.center, lc.radius, u1a, u1b), self.lever, None, ARC, 3.2,
                                             1.0, "lever_arc")
        e_path = polyline_path(res.lever_profile_e) if law else arc_path(sc.center, sc.radius, u2a, u2b)
        self.paths["slider_arc"] = _path_item(e_path, self.lever, None, SLIDER_EDGE, 3.2, 1.0, "slider_arc")
        self._ticks(res, depth)
        # extent over the whole cycle: every moving point, the lever plate at each end of the stroke
        moving = [fr.F, fr.P, fr.P0, res.frame_profile, res.bicentrode, np.asarray([el.rocker_pivot, a, b])]
        if fr.A is not None:
            moving += [fr.A, fr.B, fr.C]
        rect = _rect(np.concatenate(moving))
        for k in (0, len(fr) // 2):
            rect = rect.united(lever_transform(fr.F[k], float(fr.theta[k]), el.pin).mapRect(plate.boundingRect()))
        self._set_core(rect)
        self.label_at = (rect.left(), rect.bottom())
        self.label_text = f"{el.id}  (rolling lever, {res.synthesis.method})"

    def _ticks(self, res: RollingResult, depth: float) -> None:
        """Matching marks on both bodies of each pair, at the same synthesis samples θ_k: on the frame
        profile at P_k and on the lever circle at u1_k, on the slider profile at Q_k and on the
        slider circle at u2_k. Rolling without slip brings each pair of marks together exactly when
        the contact passes them, so the rolling is visible during the animation."""
        syn = res.synthesis
        el = self.result.element
        n = len(syn.theta)
        idx = np.unique(np.linspace(0, n - 1, min(n, 13)).round().astype(int))
        size = 0.5 * depth

        def marks(points: np.ndarray, normals: np.ndarray) -> QPainterPath:
            path = QPainterPath()
            for p, d in zip(points[idx], normals[idx]):
                if np.isfinite(p).all() and np.isfinite(d).all():
                    path.moveTo(float(p[0] - size * d[0]), float(p[1] - size * d[1]))
                    path.lineTo(float(p[0] + size * d[0]), float(p[1] + size * d[1]))
            return path

        def radial(centre, radius: float, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            d = np.stack([np.cos(u), np.sin(u)], axis=-1)
            return np.asarray(centre) + radius * d, d

        if el.slider_circle is not None:
            e_marks = radial(el.slider_circle.center, el.slider_circle.radius, syn.u2)
        else:   # a slider law: marks on the lever element Π30 at the same samples
            lev = syn.lever_e_points
            e_marks = (lev, _normals(lev))
        specs = (("frame_ticks", self, np.asarray(syn.P), _normals(np.asarray(syn.P)), FRAME_EDGE),
                 ("lever_ticks", self.lever, *radial(el.lever_circle.center, el.lever_circle.radius, syn.u1), ARC),
                 ("slider_ticks", self.slider, np.asarray(syn.Q), _normals(np.asarray(syn.Q)), SLIDER_EDGE),
                 ("slider_arc_ticks", self.lever, *e_marks, SLIDER_EDGE))
        for name, parent, pts, normals, colour in specs:
            self.paths[name] = _path_item(marks(pts, normals), parent, None, colour, 1.6, 1.2, name)

    # -- animation --------------------------------------------------------------------------
    def set_frame(self, index: int) -> None:
        """Show frame ``index`` of the precomputed cycle (no solving)."""
        fr = self.result.frames
        if fr is None or len(fr) == 0 or self.result.synthesis is None:
            return
        self.index = k = int(index) % len(fr)
        el = self.result.element
        self.lever.setTransform(lever_transform(fr.F[k], float(fr.theta[k]), el.pin))
        ds = el.slider_axis
        s5 = float(fr.S5[k])
        self.slider.setTransform(QTransform.fromTranslate(s5 * ds[0], s5 * ds[1]))
        self._moving.update()

    def lever_rotation(self) -> float:
        """The lever's rotation shown now (rad; θ of the frame)."""
        t = self.lever.transform()
        return math.atan2(t.m12(), t.m11())

    def slider_offset(self) -> tuple[float, float]:
        """The slider's translation shown now (mm)."""
        t = self.slider.transform()
        return (t.dx(), t.dy())

    # -- per-frame painting (bars, joints, contacts) -------------------------------------------
    def paint_frame(self, painter: QPainter) -> None:
        """Bars, joints, ground pivots and contact points at the current frame."""
        fr = self.result.frames
        if fr is None or self.result.synthesis is None:
            return
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        px = _px(painter)
        k = self.index
        el = self.result.element
        G = el.rocker_pivot
        bars = [((G[0], G[1]), tuple(fr.F[k]), LINK_FILL, LINK_EDGE)]
        grounds = [G]
        joints = [tuple(fr.F[k])]
        if fr.A is not None:
            A, B, C = tuple(fr.A[k]), tuple(fr.B[k]), tuple(fr.C[k])
            bars += [(A, B, QColor("#f5d9b8"), DRIVER_EDGE), (B, C, LINK_FILL, LINK_EDGE)]
            grounds.append(A)
            joints += [B, C]
        edge_w = 10.0 if not self.selected else 12.0
        for a, b, fill, edge in bars:
            pa, pb = QPointF(*a), QPointF(*b)
            painter.setPen(_pen(SELECT if self.selected else edge, edge_w))
            painter.drawLine(pa, pb)
            painter.setPen(_pen(fill, edge_w - 3.0))
            painter.drawLine(pa, pb)
        for g in grounds:
            draw_ground(painter, g, px)
        painter.setPen(_pen(INK, 1.6))
        painter.setBrush(QBrush(QColor("white")))
        r = JOINT_PX * px
        for j in joints + grounds:
            painter.drawEllipse(QPointF(*j), r, r)
        if fr.u1 is not None:   # the contact as a point of the lever (its circles), carried by the lever
            lt = self.lever.transform()
            lc, sc = el.lever_circle, el.slider_circle
            on_lever = [(lc.center[0] + lc.radius * math.cos(fr.u1[k]), lc.center[1] + lc.radius * math.sin(fr.u1[k]))]
            if sc is not None:
                on_lever.append((sc.center[0] + sc.radius * math.cos(fr.u2[k]),
                                 sc.center[1] + sc.radius * math.sin(fr.u2[k])))
            else:   # the contact on the lever element Π30: P0 carried back into the lever frame
                d = fr.P0[k] - fr.F[k]
                c, s_ = math.cos(-fr.theta[k]), math.sin(-fr.theta[k])
                on_lever.append((el.pin[0] + c * d[0] - s_ * d[1], el.pin[1] + s_ * d[0] + c * d[1]))
            for x, y in on_lever:
                q = lt.map(QPointF(x, y))
                painter.setPen(_pen(CONTACT, 2.0))
                painter.setBrush(Qt.BrushStyle.NoBrush)
                painter.drawEllipse(q, 6.5 * px, 6.5 * px)
        painter.setPen(Qt.PenStyle.NoPen)
        painter.setBrush(QBrush(CONTACT))
        for c in (fr.P[k], fr.P0[k]):
            if np.isfinite(c).all():
                painter.drawEllipse(QPointF(float(c[0]), float(c[1])), 3.5 * px, 3.5 * px)
        for c, name in ((fr.P[k], "P"), (fr.P0[k], "P0")):
            if np.isfinite(c).all():
                _text(painter, (float(c[0]), float(c[1])), name, px, 6.0, -14.0, CONTACT, 10)
        _text(painter, G, "G", px, 8.0, 7.0, INK, 11, True)
        _text(painter, tuple(fr.F[k]), "F", px, 8.0, 7.0, INK, 11, True)
        if fr.A is not None:
            for p, name in ((fr.A[k], "A"), (fr.B[k], "B"), (fr.C[k], "C")):
                _text(painter, (float(p[0]), float(p[1])), name, px, 8.0, 7.0, INK, 11, True)

    # -- selection and picking --------------------------------------------------------------
    def set_selected(self, on: bool) -> None:
        """Outline the lever and the slider in the selection colour."""
        if on == self.selected:
            return
        self.selected = on
        for name, colour in (("lever_plate", LINK_EDGE), ("slider_body", SLIDER_FILL), ("frame_profile", FRAME_EDGE)):
            item = self.paths.get(name)
            if item is not None:
                pen = QPen(item.pen())
                pen.setColor(SELECT if on else colour)
                item.setPen(pen)
        self._moving.update()

    def hit(self, pos: tuple[float, float], tol: float) -> bool:
        """True if the world point ``pos`` is on the lever, the slider, a profile or the rocker."""
        p = QPointF(*pos)
        stroker = QPainterPathStroker()
        stroker.setWidth(2 * tol)
        for name in ("lever_plate", "slider_body", "frame_body"):
            item = self.paths.get(name)
            if item is not None and item.path().contains(item.mapFromScene(p)):
                return True
        for name in ("frame_profile", "slider_profile", "bicentrode", "lever_arc", "slider_arc"):
            item = self.paths.get(name)
            if item is not None and stroker.createStroke(item.path()).contains(item.mapFromScene(p)):
                return True
        fr = self.result.frames
        if fr is not None and self.result.synthesis is not None:
            seg = QPainterPath()
            seg.moveTo(*self.result.element.rocker_pivot)
            seg.lineTo(*fr.F[self.index])
            return stroker.createStroke(seg).contains(p)
        return False

    def extent(self) -> QRectF:
        """The area swept by the mechanism over its cycle (mm)."""
        return QRectF(self._core)


def _rect(xy: np.ndarray) -> QRectF:
    fin = xy[np.isfinite(xy).all(axis=1)]
    if not len(fin):
        return QRectF()
    lo, hi = fin.min(axis=0), fin.max(axis=0)
    return QRectF(float(lo[0]), float(lo[1]), float(hi[0] - lo[0]), float(hi[1] - lo[1]))
