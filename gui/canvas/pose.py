"""What the canvas shows and picks: each linkage at the current frame, read from precomputed arrays.

Qt-free helpers shared by the view, the items, the tools and the animation player:

- :class:`SolutionArrays` - joint positions, slider axes and guide segments of one solution,
  extracted once per solve (arrays of shape (N, 2) mm or (N,) deg; NaN where not assemblable);
- :class:`PoseCache` / :class:`ElementPose` - a linkage at one sample, or at its drawn pose when it
  has no solution (a linkage still being drawn) or the sample cannot be assembled;
- :func:`pick` - the joint or link under a world point;
- :func:`rebase` - the same linkage drawn at another sample (editing at an animation frame);
- frames and walking through valid samples: :mod:`mechsketch.gui.frames`.

Nothing here calls the solver.
"""
from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field, replace
from typing import Iterable

import numpy as np

from mechsketch.core.model.linkage import Joint, JointKind, Linkage
from mechsketch.core.solver.diagnostics import sampled_dead_points
from mechsketch.core.solver.plan import Solution

from ..frames import dead_samples, input_value_text, map_frame
from .events import XY, Hit

#: the guide of a slider is drawn this much beyond the block's stroke (fraction of the stroke, mm)
GUIDE_MARGIN = (0.15, 8.0)


def slider_roles(linkage: Linkage, joint_id: str) -> tuple[str, str]:
    """``(guide link, block link)`` of the P joint ``joint_id``.

    The frame is always the guide; otherwise the block is the carrier whose pin (another joint)
    sits closest to the P joint in the drawn pose.
    """
    carriers = linkage.links_of(joint_id)
    if len(carriers) != 2:
        return (carriers[0] if carriers else "", "")
    a, b = carriers
    if linkage.ground in carriers:
        return (linkage.ground, b if a == linkage.ground else a)
    at = complex(*linkage.joint(joint_id).at)

    def pin_gap(link_id: str) -> float:
        others = [complex(*linkage.joint(j).at) for j in linkage.link(link_id).joints if j != joint_id]
        return min((abs(p - at) for p in others), default=math.inf)

    return (b, a) if pin_gap(a) <= pin_gap(b) else (a, b)


class SolutionArrays:
    """Everything the canvas draws from one solution, extracted once (no solving).

    ``pos[j]`` (N, 2) mm; ``axis[j]`` (N,) deg for P joints; ``guide[j]`` two (N, 2) arrays, the
    ends of the guide segment of P joint ``j``; ``valid`` (N,) bool; ``dead`` sample indices of
    the dead points (nearest valid sample); ``dead_points`` the DeadPoints they mark, when given.
    """

    def __init__(self, linkage: Linkage, sol: Solution, dead_inputs: Iterable[float] = ()) -> None:
        self.solution = sol
        self.diagnostics = None   # the diagnostics the dead samples came from (None: not yet)
        self.dead_points: list = []   # the DeadPoints of ``dead`` (refined, or sampled during a drag)
        self.n = len(sol)
        self.valid = np.asarray(sol.valid, dtype=bool)
        self.pos: dict[str, np.ndarray] = {j.id: sol.position(j.id) for j in linkage.joints}
        self.axis: dict[str, np.ndarray] = {}
        self.guide: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        for j in linkage.joints:
            if j.kind is JointKind.P:
                self._slider(linkage, sol, j)
        self.dead = dead_samples(sol, self.valid, dead_inputs)

    def _slider(self, linkage: Linkage, sol: Solution, j: Joint) -> None:
        guide, block = slider_roles(linkage, j.id)
        rot = sol.rotation(sol.plan.reporter[j.id])
        self.axis[j.id] = (j.axis_deg or 0.0) + np.degrees(rot)
        if not guide or not block:
            return
        self.pos[j.id] = sol.point(block, j.at)   # shown where the block is, whichever link reports it
        u0 = cmath.exp(1j * math.radians(j.axis_deg or 0.0))
        with np.errstate(invalid="ignore"):
            d = sol.point(block, j.at) - sol.point(guide, j.at)
            ug = sol.rotation(guide)
            s = d[:, 0] * np.cos(ug) * u0.real - d[:, 0] * np.sin(ug) * u0.imag
            s = s + d[:, 1] * (np.sin(ug) * u0.real + np.cos(ug) * u0.imag)
        fin = s[np.isfinite(s)]
        lo, hi = (float(fin.min()), float(fin.max())) if fin.size else (0.0, 0.0)
        margin = max(GUIDE_MARGIN[0] * (hi - lo), GUIDE_MARGIN[1])
        p0 = complex(*j.at)
        ends = [p0 + u0 * (lo - margin), p0 + u0 * (hi + margin)]
        self.guide[j.id] = tuple(sol.point(guide, (e.real, e.imag)) for e in ends)  # type: ignore[assignment]

    def sample_of(self, x: float) -> int:
        """The valid sample nearest to driver input ``x`` (rad, the sweep's unwrapped convention)."""
        return dead_samples(self.solution, self.valid, [x])[0]

    def extent(self) -> tuple[float, float, float, float] | None:
        """(xmin, ymin, xmax, ymax) of every joint over the whole cycle, mm."""
        pts = [p for p in self.pos.values()] + [e for g in self.guide.values() for e in g]
        if not pts:
            return None
        allp = np.concatenate(pts)
        allp = allp[np.isfinite(allp).all(axis=1)]
        if not allp.size:
            return None
        return (float(allp[:, 0].min()), float(allp[:, 1].min()), float(allp[:, 0].max()), float(allp[:, 1].max()))


@dataclass
class ElementPose:
    """One linkage as the canvas shows it: at sample ``index``, or drawn (``index`` None)."""

    linkage: Linkage
    at: dict[str, XY]
    axis: dict[str, float] = field(default_factory=dict)          # P joint -> axis, deg
    guide: dict[str, tuple[XY, XY]] = field(default_factory=dict)  # P joint -> guide segment ends
    index: int | None = None
    arrays: SolutionArrays | None = None
    error: str | None = None

    @property
    def element(self) -> str:
        return self.linkage.id


def drawn_pose(linkage: Linkage, error: str | None = None) -> ElementPose:
    """The linkage at its drawn positions (guides a short segment through each P joint)."""
    at = {j.id: (float(j.at[0]), float(j.at[1])) for j in linkage.joints}
    axis = {j.id: float(j.axis_deg or 0.0) for j in linkage.joints if j.kind is JointKind.P}
    guide = {}
    for jid, a in axis.items():
        u = cmath.exp(1j * math.radians(a)) * 30.0
        p = complex(*at[jid])
        guide[jid] = ((p - u).real, (p - u).imag), ((p + u).real, (p + u).imag)
    return ElementPose(linkage, at, axis, guide, None, None, error)


def sample_pose(arrays: SolutionArrays, linkage: Linkage, k: int) -> ElementPose | None:
    """The linkage at sample ``k`` of its solution, or None if that sample is not assemblable."""
    if not (0 <= k < arrays.n) or not arrays.valid[k]:
        return None
    at = {j: (float(p[k, 0]), float(p[k, 1])) for j, p in arrays.pos.items()}
    axis = {j: float(a[k]) for j, a in arrays.axis.items()}
    guide = {j: ((float(a[k, 0]), float(a[k, 1])), (float(b[k, 0]), float(b[k, 1])))
             for j, (a, b) in arrays.guide.items()}
    return ElementPose(linkage, at, axis, guide, k, arrays, None)


class PoseCache:
    """Extracts :class:`SolutionArrays` once per solution and hands out poses at a frame."""

    def __init__(self) -> None:
        self._arrays: dict[str, SolutionArrays] = {}
        self._poses: dict[str, tuple] = {}   # id -> (linkage, result, arrays, frame, total, pose)

    def arrays(self, linkage: Linkage, result, diagnose: bool = True) -> SolutionArrays | None:
        """Arrays of ``result.solution`` (``result`` a workspace LinkageResult), cached by identity,
        with the dead-point samples of its diagnostics (computed unless ``diagnose`` is False:
        then only if they were already; a drag preview does not wait for them)."""
        if result is None or result.solution is None:
            self._arrays.pop(linkage.id, None)
            return None
        cached = self._arrays.get(linkage.id)
        diag = result.diagnostics if diagnose else result.diagnostics_if_computed
        if cached is None or cached.solution is not result.solution or cached.diagnostics is not diag:
            # without the diagnostics (a drag preview), the dead points at the samples' resolution
            points = diag.dead_points if diag is not None else sampled_dead_points(result.solution)
            cached = SolutionArrays(linkage, result.solution, [d.input for d in points])
            cached.diagnostics = diag
            cached.dead_points = list(points)
            self._arrays[linkage.id] = cached
        return cached

    def poses(self, controller, frame: int | None = None) -> list[ElementPose]:
        """Every linkage of ``controller.scene`` at ``frame`` (default ``controller.frame``)."""
        frame = controller.frame if frame is None else frame
        total = controller.sample_count()
        out = []
        live = set()
        for el in controller.linkages():
            live.add(el.id)
            res = controller.result(el.id)
            arrays = self.arrays(el, res, diagnose=not controller.workspace.previewing)
            hit = self._poses.get(el.id)
            if (hit is not None and hit[0] is el and hit[1] is res and hit[2] is arrays
                    and hit[3:5] == (frame, total)):
                out.append(hit[5])   # an element the last change did not touch: the same pose
                continue
            pose = None
            note = res.error if res is not None else None
            if arrays is not None:
                k = map_frame(frame, total, arrays.n)
                pose = sample_pose(arrays, el, k)
                if pose is None:
                    note = (f"cannot be assembled at input {input_value_text(arrays.solution, k)} - showing "
                            "the drawn pose")
            if pose is None:
                pose = drawn_pose(el, note)
                pose.arrays = arrays
            self._poses[el.id] = (el, res, arrays, frame, total, pose)
            out.append(pose)
        for gone in set(self._arrays) - live:
            del self._arrays[gone]
        for gone in set(self._poses) - live:
            del self._poses[gone]
        return out


# -- picking ---------------------------------------------------------------------------------

def _abs(z: complex) -> float:
    """|z|, or inf where it overflows (coordinates near the float limit)."""
    try:
        return abs(z)
    except OverflowError:
        return math.inf


def _seg_dist(p: complex, a: complex, b: complex) -> float:
    """Distance (mm) from ``p`` to the segment ``a``–``b``; inf where it overflows (never raises)."""
    try:
        d = b - a
        length = _abs(d)
        if length < 1e-12:
            return _abs(p - a)
        u = d / length                         # no |d|²: far coordinates cannot overflow it
        t = max(0.0, min(length, ((p - a) * u.conjugate()).real))
        dist = _abs(p - (a + t * u))
    except (OverflowError, ZeroDivisionError):
        return math.inf
    return dist if math.isfinite(dist) else math.inf


def _inside(p: complex, poly: list[complex]) -> bool:
    inside = False
    for k in range(len(poly)):
        a, b = poly[k], poly[k - 1]
        if (a.imag > p.imag) != (b.imag > p.imag):
            x = a.real + (p.imag - a.imag) * (b.real - a.real) / (b.imag - a.imag)
            if x > p.real:
                inside = not inside
    return inside


def link_outline(pose: ElementPose, link_id: str) -> list[complex]:
    """Displayed corner points of a link, in drawing order (angle-sorted for three or more).

    A P joint counts for its block; on the link that carries its guide (drawn as a slot or rail)
    it counts as the guide's end nearest the link's other joints, so that the link is drawn
    joined to its guide (a cylinder's barrel from its pivot to the slide, a guide on a rocker)."""
    lk = pose.linkage
    pts = []
    guides = []
    for j in lk.link(link_id).joints:
        if j not in pose.at:
            continue
        if lk.joint(j).kind is JointKind.P and slider_roles(lk, j)[0] == link_id:
            guides.append(j)
        else:
            pts.append(complex(*pose.at[j]))
    for j in guides:
        ends = [complex(*e) for e in pose.guide.get(j, ())]
        ends = [e for e in ends if math.isfinite(e.real) and math.isfinite(e.imag)]
        if ends and pts and lk.ground != link_id:
            c = sum(pts) / len(pts)
            pts.append(min(ends, key=lambda e: _abs(e - c)))
    uniq: list[complex] = []
    for p in pts:
        if all(_abs(p - q) > 1e-9 for q in uniq):
            uniq.append(p)
    if len(uniq) <= 2:
        return uniq
    c = sum(uniq) / len(uniq)
    return sorted(uniq, key=lambda z: math.atan2((z - c).imag, (z - c).real))   # cmath.phase raises on subnormals


def pick(poses: Iterable[ElementPose], pos: XY, tol: float) -> Hit | None:
    """The joint (preferred) or moving link within ``tol`` mm of ``pos``, nearest first.

    Where joints coincide (a slider's pin and its P joint), the revolute joint wins.
    """
    p = complex(*pos)
    best: tuple[float, Hit] | None = None
    for pose in poses:
        for j in pose.linkage.joints:
            q = pose.at.get(j.id)
            if q is None:
                continue
            d = _abs(p - complex(*q)) + (1e-6 * tol if j.kind is JointKind.P else 0.0)
            if d <= tol and (best is None or d < best[0]):
                best = (d, Hit(pose.element, "joint", j.id))
    if best is not None:
        return best[1]
    for pose in poses:
        for lk in pose.linkage.links:
            if lk.id == pose.linkage.ground:
                continue
            poly = link_outline(pose, lk.id)
            if len(poly) < 2:
                continue
            d = min(_seg_dist(p, poly[k - 1], poly[k]) for k in range(1 if len(poly) == 2 else 0, len(poly)))
            if len(poly) > 2 and _inside(p, poly):
                d = 0.0
            if d <= tol and (best is None or d < best[0]):
                best = (d, Hit(pose.element, "link", lk.id))
    return best[1] if best else None


# -- editing at a frame ---------------------------------------------------------------------

def shows_drawn(arrays: SolutionArrays, k: int | None) -> bool:
    """Sample ``k`` is the drawn pose: sample 0 of a sweep that starts at the drawn input (a crank;
    an actuator whose stroke starts at its drawn length or place)."""
    sol = arrays.solution
    return k == 0 and float(sol.input[0]) == sol.plan.theta0


def rebase(linkage: Linkage, arrays: SolutionArrays, k: int) -> Linkage:
    """The same mechanism drawn at sample ``k``: every joint at its position there, slider axes
    turned with their links. Lengths, assembly modes and the driver are unchanged; only the drawn
    input moves (a slider driver's stroke, counted from its drawn place, moves with it). Returns
    ``linkage`` itself if sample ``k`` is not assemblable or shows the drawn pose."""
    if shows_drawn(arrays, k) or not (0 <= k < arrays.n) or not arrays.valid[k]:
        return linkage
    joints = []
    for j in linkage.joints:
        p = arrays.pos[j.id][k]
        if not np.isfinite(p).all():
            return linkage
        axis = j.axis_deg
        if j.kind is JointKind.P:
            axis = math.remainder(float(arrays.axis[j.id][k]), 360.0)
        joints.append(replace(j, at=(float(p[0]), float(p[1])), axis_deg=axis))
    drv = linkage.driver
    if drv.kind == "slider" and drv.stroke is not None:   # its input is measured from the drawn place
        s = float(arrays.solution.input[k])
        law = drv.law
        if law.points:
            law = replace(law, points=tuple((t, v - s) for t, v in law.points))
        drv = replace(drv, stroke=(drv.stroke[0] - s, drv.stroke[1] - s), law=law)
    return replace(linkage, joints=tuple(joints), driver=drv)


def to_drawn(arrays: SolutionArrays | None, linkage: Linkage, link_id: str, k: int | None, p: XY) -> XY:
    """The drawn-pose position of the point of ``link_id`` shown at ``p`` at sample ``k``."""
    if arrays is None or k is None or shows_drawn(arrays, k) or link_id == linkage.ground:
        return p
    sol = arrays.solution
    anchor = next((j for j in linkage.link(link_id).joints if linkage.joint(j).kind is JointKind.R), None)
    if anchor is None:
        return p
    rho = float(sol.rotation(link_id)[k])
    f = complex(*arrays.pos[anchor][k])
    d = complex(*linkage.joint(anchor).at)
    z = d + cmath.exp(-1j * rho) * (complex(*p) - f)
    return (z.real, z.imag)
