"""Cut-ready parts of a linkage: link plates with bores, slotted guides, slider blocks, the frame.

Each link becomes a plate in the drawn pose (world frame, mm):

- a binary link: a stadium around its two joints (end radius = boss radius), or, with a bar
  narrower than its bosses (``width`` < 2·boss), a dog-bone of two boss arcs and two bar lines;
- a ternary or higher link: the rounded hull of its bosses (:func:`~.parts.disc_hull`, exact);
- every revolute joint a bore centred exactly on its drawn position, so hole-centre distances are
  the link lengths;
- a link that carries a prismatic joint's guide gets a stadium slot along the guide axis, long
  enough for the block's whole travel over the cycle plus the block: the slide s of the block
  relative to the guide (``Solution.group_output(g).slides``, 0 in the drawn pose) is swept over
  one driver revolution and its extremes are refined (a fine local grid around each sampled
  extreme, three times), so the slot spans [s_min − L_b/2, s_max + L_b/2] plus the play;
- a link that slides on a guide is a rectangular block (L_b × W_b along the axis) with its pin
  bore (the rounded hull of the block's corners and its bosses when a joint lies outside it);
- the frame (ground link) a plate like any other link (``frame="plate"``) or only the drilling
  pattern of its pivots and slots (``frame="drill"``);
- a joint on one moving link only (a coupler point) also traces its path over the cycle, fitted
  by biarcs within ``tolerance`` on its own layer, kept with the frame in the apart layout.

Defaults scale with the linkage: the boss radius is 12 % of the median joint distance on the
links, the bore 40 % of the boss, blocks 2.5 × 1.6 boss radii, the slot play 0.1 mm per side.
A size may come from the linkage's ``drawing`` block or an export option instead
(:func:`~.build.element_parts` resolves which); a message names it as ``LinkageStyle.names`` says.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from ...errors import GeometryError
from ...model.linkage import JointKind, Linkage
from ...solver.plan import Plan
from ...solver.structure import GroupKind
from ..biarc import fit_biarcs
from ..contour import Contour
from .outline import circle, contour_bounds, disc_hull, rectangle, stadium
from .records import Curve, Part, PartSet

FRAMES = ("plate", "drill")
#: default sizes relative to the median joint distance (boss) and to the boss radius
BOSS_FRACTION = 0.12
BORE_FRACTION = 0.4
BLOCK_LENGTH = 2.5
BLOCK_WIDTH = 1.6
DEFAULT_PLAY = 0.1  # mm per side between block and slot
SWEEP_SAMPLES = 720
#: what sizes a plate (canonical keys, see .keys): the linkage's drawing block
KEYS = ("drawing.boss_radius", "drawing.bore_diameter", "drawing.link_width")
BLOCK_KEYS = ("drawing.block_length", "drawing.block_width")


@dataclass(frozen=True)
class LinkageStyle:
    """Plate sizes (mm); None means the scaled default (see the module docstring). ``names``
    pairs (field, words): how a message names where a size came from (default ``drawing.FIELD``,
    ``width`` as ``drawing.link_width``). ``fasteners``: the diameter of the two holes that fasten
    a separate guide plate to its link (one beyond each end of the slot, through both).
    ``base_plate`` (with ``frame`` "drill"): the frame's drilling pattern on a rectangular plate
    one boss radius around its holes (the pivots and the fasteners of guide plates on it)."""

    boss_radius: float | None = None
    bore_diameter: float | None = None
    width: float | None = None
    block_length: float | None = None
    block_width: float | None = None
    play: float = DEFAULT_PLAY
    frame: str = "plate"
    tolerance: float = 0.01
    names: tuple[tuple[str, str], ...] = ()
    fasteners: float | None = None
    base_plate: bool = False

    def name(self, field: str) -> str:
        """The words for size ``field`` in messages."""
        return dict(self.names).get(field, "drawing.link_width" if field == "width" else f"drawing.{field}")


@dataclass(frozen=True)
class Travel:
    """One prismatic joint: the link carrying the guide, the sliding link, the axis (unit, drawn
    pose) and the slide's extremes over the cycle (mm, 0 in the drawn pose)."""

    joint: str
    guide: str
    slider: str
    axis: tuple[float, float]
    s_min: float
    s_max: float


def scale_of(linkage: Linkage) -> float:
    """Median distance (mm) between two joints of one link (the size defaults scale with)."""
    d = []
    for lk in linkage.links:
        pts = [linkage.joint(j).at for j in lk.joints]
        d += [math.dist(p, q) for i, p in enumerate(pts) for q in pts[i + 1:]]
    d = [x for x in d if x > 0]
    return float(np.median(d)) if d else 10.0


def _slide_index(kind: GroupKind, joint: str, g) -> tuple[int, str, str] | None:
    """(index in DyadOut.slides, guide link, slider link) of a P joint in group g."""
    if kind is GroupKind.RRP and joint == g.outer_j:
        return 0, g.known_j, g.link_j
    if kind is GroupKind.RPR and joint == g.inner:
        return 0, g.link_j, g.link_i
    if kind is GroupKind.PRP:
        if joint == g.outer_i:
            return 0, g.known_i, g.link_i
        if joint == g.outer_j:
            return 1, g.known_j, g.link_j
    if kind is GroupKind.RPP:
        if joint == g.inner:
            return 0, g.link_j, g.link_i
        if joint == g.outer_j:
            return 1, g.known_j, g.link_j
    return None


def travels(plan: Plan, samples: int = SWEEP_SAMPLES) -> list[Travel]:
    """The slide extremes of every prismatic joint over one driver revolution (refined)."""
    lk = plan.linkage
    pjoints = [j for j in lk.joints if j.kind is JointKind.P]
    if not pjoints:
        return []
    sol = plan.sweep(samples, order=0)
    out = []
    for j in pjoints:
        for g in sol.groups:
            hit = _slide_index(g.kind, j.id, g)
            if hit is None:
                continue
            idx, guide, slider = hit
            dy = sol.group_output(g.name)
            s = np.where(dy.ok, dy.slides[idx].s, np.nan)
            if not np.isfinite(s).any():
                raise GeometryError(f"linkage {lk.id!r}: joint {j.id!r} is never assembled over the cycle")
            ext = []
            for pick in (np.nanargmin, np.nanargmax):
                k = int(pick(s))
                x, step = float(sol.input[k]), 2 * math.pi / samples
                best = float(s[k])
                for _ in range(3):
                    xs = x + step * np.linspace(-1, 1, 41)
                    e = plan.evaluate(xs, order=0)
                    o = e.group_output(g.name)
                    v = np.where(o.ok, o.slides[idx].s, np.nan)
                    if not np.isfinite(v).any():
                        break
                    kk = int(pick(v))
                    x, step = float(xs[kk]), step / 20
                    best = min(best, float(v[kk])) if pick is np.nanargmin else max(best, float(v[kk]))
                ext.append(best)
            a = math.radians(j.axis_deg or 0.0)
            out.append(Travel(j.id, guide, slider, (math.cos(a), math.sin(a)), ext[0], ext[1]))
            break
    return out


def _bar(p: np.ndarray, q: np.ndarray, boss: float, width: float) -> Contour:
    """A binary link outline: stadium (width = 2·boss) or dog-bone (narrower bar), CCW."""
    if width >= 2 * boss - 1e-12:
        return stadium(p, q, boss, "plate")
    d = q - p
    length = float(np.hypot(*d))
    alpha = math.asin(width / (2 * boss))
    e = boss * math.cos(alpha)
    hw = width / 2
    local = np.array([[e, -hw], [length - e, -hw], [length - e, hw], [e, hw]])
    sweep = 2 * math.pi - 2 * alpha
    bul = np.array([0.0, math.tan(sweep / 4), 0.0, math.tan(sweep / 4)])
    ang = math.atan2(d[1], d[0])
    return Contour(local, bul, ("plate",) * 4).moved(ang, (float(p[0]), float(p[1])))


def _base_plate(holes: list, margin: float):
    """A rectangle ``margin`` mm around the bounds of ``holes`` (a frame's drilling pattern)."""
    b = np.array([contour_bounds(h) for h in holes])
    x0, y0, x1, y1 = b[:, 0].min() - margin, b[:, 1].min() - margin, b[:, 2].max() + margin, b[:, 3].max() + margin
    return rectangle(((x0 + x1) / 2, (y0 + y1) / 2), x1 - x0, y1 - y0, 0.0, "base")


def _guide_fasteners(a, b, u, r_slot: float, margin: float, d: float | None, name: str, min_web: float) -> list:
    """The fastener holes (Ø ``d`` mm) of a separate guide plate, one beyond each end of its slot
    midway across the plate's rim (the same holes go through the link below); none if ``d`` is None."""
    if d is None:
        return []
    if not (math.isfinite(d) and 0 < d <= margin - 2.2 * min_web):
        raise GeometryError(f"the fasteners of {name} (Ø{d:g} mm) must fit its rim of {margin:.4g} mm with 10 % over "
                            f"the minimum web {min_web:g} mm each side: at most Ø{margin - 2.2 * min_web:.4g} mm")
    off = (r_slot + 0.5 * margin) * u
    return [circle(a - off, 0.5 * d, "fastener"), circle(b + off, 0.5 * d, "fastener")]


def linkage_parts(linkage: Linkage, plan: Plan, style: LinkageStyle = LinkageStyle(),
                  min_web: float = 1.0, traces: bool = True) -> PartSet:
    """The plates of ``linkage`` (compiled ``plan``) in the drawn pose; see the module docstring.
    ``traces=False`` leaves out the traced coupler curves (drawn, never cut nor checked: a
    cut check needs only the plates).

    Raises :class:`GeometryError` for sizes that cannot make a plate (naming the option)."""
    if style.frame not in FRAMES:
        raise GeometryError(f"frame must be one of {', '.join(FRAMES)}; got {style.frame!r}")
    scale = scale_of(linkage)
    boss = style.boss_radius if style.boss_radius is not None else BOSS_FRACTION * scale
    bore = 0.5 * style.bore_diameter if style.bore_diameter is not None else BORE_FRACTION * boss
    width = style.width if style.width is not None else 2 * boss
    blen = style.block_length if style.block_length is not None else BLOCK_LENGTH * boss
    bwid = style.block_width if style.block_width is not None else BLOCK_WIDTH * boss
    for field, v in (("boss_radius", boss), ("width", width), ("block_length", blen), ("block_width", bwid)):
        if not (math.isfinite(v) and v > 0):
            raise GeometryError(f"{style.name(field)} must be a positive number of millimetres; got {v:g}")
    if not (math.isfinite(bore) and 0 <= bore < boss):
        raise GeometryError(f"the bore (Ø{2 * bore:g} mm) must be smaller than the boss (radius {boss:g} mm): "
                            f"change {style.name('bore_diameter')} or {style.name('boss_radius')}")
    if width > 2 * boss + 1e-12:
        raise GeometryError(f"the link width {width:g} mm ({style.name('width')}) is wider than the bosses "
                            f"(2 × {boss:g} mm): raise {style.name('boss_radius')} or narrow the link")
    margin = boss - bore
    trav = travels(plan)
    guides: dict[str, list[Travel]] = {}
    sliders: dict[str, list[Travel]] = {}
    for t in trav:
        guides.setdefault(t.guide, []).append(t)
        sliders.setdefault(t.slider, []).append(t)
    at = {j.id: np.array(j.at, float) for j in linkage.joints}
    kinds = {j.id: j.kind for j in linkage.joints}
    parts, notes = [], []
    for lk in linkage.links:
        rj = [j for j in lk.joints if kinds[j] is JointKind.R]
        holes = [circle(at[j], bore) for j in rj] if bore > 0 else []
        discs = [(at[j], boss) for j in rj]
        for t in guides.get(lk.id, []):
            u = np.array(t.axis)
            a = at[t.joint] + (t.s_min - blen / 2) * u
            b = at[t.joint] + (t.s_max + blen / 2) * u
            r_slot = bwid / 2 + style.play
            slot = stadium(a, b, r_slot, "slot")
            where = f"{lk.id}: slot for {t.joint} ({t.slider}): travel s ∈ [{t.s_min:.4f}, {t.s_max:.4f}] mm " \
                    f"({t.s_max - t.s_min:.4f} mm) + block {blen:.3f} mm, width {2 * r_slot:.3f} mm"
            sp = shapely.Polygon(slot.polyline(1e-3))
            clash = [j for j in rj if sp.distance(shapely.Point(*at[j])) < bore + min_web]
            if clash:
                # the block's travel passes over a pin of this link: the guide is a plate of its own,
                # stacked on the link (fastened where they overlap)
                name = f"{lk.id}_guide_{t.joint}"
                guide = stadium(a, b, r_slot + margin, "plate")
                pins = _guide_fasteners(a, b, u, r_slot, margin, style.fasteners, name, min_web)
                holes += pins
                parts.append(Part(name, guide, (slot,) + tuple(pins), group=name, keys=KEYS + BLOCK_KEYS[1:]
                                  + (("option:fasteners",) if pins else ())))
                notes.append(where + f"; it passes over the pin at {', '.join(clash)}, so the guide is the "
                                     f"separate plate {name}, stacked on {lk.id}"
                             + (f", fastened to it by 2 × Ø{style.fasteners:g} mm beyond the slot's ends" if pins else ""))
                discs += [(a, r_slot + margin), (b, r_slot + margin)]
                continue
            holes.append(slot)
            discs += [(a, r_slot + margin), (b, r_slot + margin)]
            notes.append(where)
        keys = KEYS
        if lk.id in sliders:
            t = sliders[lk.id][0]
            u = np.array(t.axis)
            ang = math.atan2(u[1], u[0])
            block = rectangle(at[t.joint], blen, bwid, ang)
            inside = all(abs((at[j] - at[t.joint]) @ u) + bore + min_web <= blen / 2 and
                         abs((at[j] - at[t.joint]) @ np.array([-u[1], u[0]])) + bore + min_web <= bwid / 2
                         for j in rj)
            if inside and len(discs) == len(rj):
                outer = block
            else:
                corners = np.asarray(block.points)
                cs = np.vstack([corners] + [d[0][None] for d in discs])
                outer = disc_hull(cs, np.r_[np.zeros(4), [d[1] for d in discs]])
            keys = KEYS + BLOCK_KEYS
        elif len(discs) == 0:
            continue
        elif len(discs) == 2 and len(rj) == 2:
            outer = _bar(discs[0][0], discs[1][0], boss, width)
        else:
            outer = disc_hull(np.array([d[0] for d in discs]), np.array([d[1] for d in discs]))
        if lk.id == linkage.ground and style.frame == "drill":
            outer = _base_plate(holes, boss) if style.base_plate else None
        parts.append(Part(lk.id, outer, tuple(holes), group=lk.id, keys=keys))
    curves = _traces(linkage, plan, style.tolerance, notes) if traces else []
    notes.insert(0, f"plates: boss radius {boss:.3f} mm, bores Ø{2 * bore:.3f} mm, bar width {width:.3f} mm"
                    + (f", blocks {blen:.3f} × {bwid:.3f} mm, play {style.play:g} mm per side" if trav else "")
                    + f"; frame as a {'drilling pattern' if style.frame == 'drill' else 'plate'}; drawn pose")
    return PartSet(linkage.id, tuple(parts), tuple(curves), tuple(notes), web_key="drawing.min_web")


def _traces(linkage: Linkage, plan: Plan, tol: float, notes: list[str]) -> list[Curve]:
    """Biarc fits of the paths of the joints that sit on one moving link only (coupler points)."""
    out = []
    tracers = [j for j in linkage.joints if j.kind is JointKind.R and len(linkage.links_of(j.id)) == 1
               and linkage.links_of(j.id)[0] != linkage.ground]
    if not tracers:
        return out
    if not (math.isfinite(tol) and tol > 0):
        raise GeometryError(f"the curve tolerance must be a positive number of millimetres, got {tol}")
    sol = plan.sweep(SWEEP_SAMPLES, order=0)
    for j in tracers:
        ok = np.isfinite(sol.position(j.id)).all(axis=1)
        if not ok.all():
            notes.append(f"trace of {j.id}: not drawn, the linkage is not assembled over the whole revolution")
            continue
        t0 = float(sol.input[0])
        t1 = t0 + plan.direction * 2 * math.pi

        def curve(t, jid=j.id):
            return plan.evaluate(np.asarray(t, float), order=0, joints=[jid]).position(jid)

        try:
            fit = fit_biarcs(curve, t0, t1, tol)
        except GeometryError as exc:
            notes.append(f"trace of {j.id}: not drawn ({exc})")
            continue
        pts = np.array([a.start for a in fit.arcs])
        bul = np.array([a.bulge for a in fit.arcs])
        out.append(Curve(j.id, pts, bul, True, fit.max_deviation, tol, group=linkage.ground))
    return out
