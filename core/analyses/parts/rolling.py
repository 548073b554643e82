"""Cut-ready parts of a rolling lever: the frame plate, the lever plate and the slider plate.

Each part is one closed outline whose working edge is the synthesised profile (mm):

- ``frame`` (ground frame): the fixed centrode of pair D (the frame profile) fitted by biarcs
  within the tolerance, backed by a plate of depth ``depth`` on the side away from the lever
  (straight lines from the profile's ends along their normals, joined by the back edge);
- ``frame_pivots`` (same group as ``frame``, so the apart layout keeps their places): the
  drilling pattern of the frame's pivots, the rocker pivot G and, with a drive, the crank pivot A;
- ``lever`` (lever frame = drawn pose): one outline through the two working arcs (the lever
  circle over the contact angles u1 of the stroke, the slider circle over u2; true arcs kept
  whole) and the bosses of the pin f and, with a drive, of the coupler pin C, taken in angular
  order and joined by outer tangents (:func:`fan_outline`), with their bores;
- ``slider`` (slider frame, the ground at S5 = 0): the slider's conjugate profile fitted by
  biarcs, backed like the frame.

The fitted edges' largest deviation from the exact curve (the integrated centrode; the spline
through the constructed points for the paper's and the corrected constructions) is measured and
kept below the tolerance; for a construction the report also states how far its profile lies
from the exact centrode.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...errors import GeometryError
from ..biarc import BiarcFit, fit_biarcs
from ..contour import Contour
from .outline import ccw, circle, contour_bounds, rectangle
from .records import Part, PartSet
from ..rolling.geometry import pose_state
from ..rolling.synthesis import RollingSynthesis

#: tolerances below this are refused (mm): the biarc count grows like tolerance^(-1/3)
MIN_TOLERANCE = 1e-6
KEYS_PROFILE = ("stroke", "lever_circle", "slider_circle", "option:tolerance", "option:depth")
KEYS_LEVER = ("pin_diameter", "lever_circle", "slider_circle", "pin", "drive.coupler_point")


@dataclass(frozen=True)
class RollingStyle:
    """Sizes (mm): ``depth`` of the frame and slider plates behind their profiles (None: a
    quarter of the profile's chord, at least 3 pin diameters), ``boss`` around the lever's pins
    (None: one pin diameter), ``tolerance`` of the fitted profiles; ``depth_name``: how messages
    name the depth (the front end's option). ``fasteners``: the diameter (mm) of the fastener
    holes of the frame and slider plates (None: none; see :func:`fastener_centres`), matched in the
    frame's drilling pattern or, with ``base_plate``, in a base plate carrying every pivot."""

    depth: float | None = None
    boss: float | None = None
    tolerance: float = 0.001
    depth_name: str = "the plate depth"
    fasteners: float | None = None
    base_plate: bool = False


def _fit(curve_range, tolerance: float, what: str) -> BiarcFit:
    curve, t0, t1 = curve_range
    try:
        return fit_biarcs(curve, t0, t1, tolerance)
    except (ValueError, GeometryError) as exc:
        raise GeometryError(f"cannot fit the {what} within {tolerance:g} mm: {exc}") from None


def _backed(fit: BiarcFit, away: np.ndarray, depth: float, kind: str) -> Contour:
    """The profile (a biarc chain) closed by a plate of ``depth`` mm on the side of ``away``."""
    pts = [np.array(a.start) for a in fit.arcs] + [np.array(fit.arcs[-1].end)]
    bul = [a.bulge for a in fit.arcs]
    p0, p1 = pts[0], pts[-1]
    chord = p1 - p0
    n = np.array([-chord[1], chord[0]]) / np.hypot(*chord)
    if n @ away < 0:
        n = -n
    back1, back0 = p1 + depth * n, p0 + depth * n
    verts = np.array(pts + [back1, back0])
    bulges = np.array(bul + [0.0, 0.0, 0.0])
    return ccw(Contour(verts, bulges, (kind,) * (len(bulges) - 2) + ("back", kind)))


def fastener_centres(plate: Contour, depth: float, diameter: float) -> list[np.ndarray]:
    """The fastener pattern of a backed plate (:func:`_backed`: its last two vertices are the back
    edge): two holes of ``diameter`` mm at a quarter and three quarters of the back edge, their
    centres one diameter in from it (a web of half a diameter to the edge), mm."""
    pts = np.asarray(plate.points, float)
    kinds = plate.kinds
    back = [k for k in range(len(pts)) if kinds and kinds[k] == "back"]
    b0, b1 = pts[back[0]], pts[(back[0] + 1) % len(pts)]
    inward = np.array([-(b1 - b0)[1], (b1 - b0)[0]]) / np.hypot(*(b1 - b0))   # CCW: the inside is on the left
    return [b0 + f * (b1 - b0) + diameter * inward for f in (0.25, 0.75)]


def _with_fasteners(parts: tuple[Part, ...], style: RollingStyle, r_pin: float, depth: float) -> tuple[tuple[Part, ...], list[str]]:
    """``parts`` with the fastener holes (and the base plate) of ``style``, and their report notes."""
    d = style.fasteners
    if d is None and not style.base_plate:
        return parts, []
    if d is not None and not (math.isfinite(d) and 0 < d < 0.5 * depth):
        raise GeometryError(f"the fastener diameter must be a positive number of millimetres below half the plate "
                            f"depth ({0.5 * depth:g} mm); got {d:g}")
    by = {p.name: p for p in parts}
    holes = {n: [circle(c, 0.5 * d, "fastener") for c in fastener_centres(by[n].outer, depth, d)] if d else []
             for n in ("frame", "slider")}
    out = {n: replace(by[n], holes=by[n].holes + tuple(holes[n]), keys=by[n].keys + ("option:fasteners",))
           for n in ("frame", "slider")} if d else {}
    pivots = by["frame_pivots"]
    notes = [f"fasteners: 2 × Ø{d:g} mm in the frame and slider plates, at 1/4 and 3/4 of the back edge, "
             f"{d:g} mm in from it; the frame's pair matched in the "
             + ("base plate" if style.base_plate else "frame's drilling pattern (frame_pivots)")] if d else []
    if style.base_plate:
        d = d or 0.0
        rings = [by["frame"].outer] + list(pivots.holes)
        b = np.array([contour_bounds(c) for c in rings])
        m = max(4 * r_pin, 2 * d)
        x0, y0, x1, y1 = b[:, 0].min() - m, b[:, 1].min() - m, b[:, 2].max() + m, b[:, 3].max() + m
        outline = rectangle(((x0 + x1) / 2, (y0 + y1) / 2), x1 - x0, y1 - y0, 0.0, "base")
        out["frame_pivots"] = Part("base_plate", outline, pivots.holes + tuple(holes["frame"]), group="base_plate",
                                   keys=pivots.keys + ("option:base_plate", "option:fasteners"))
        notes.append(f"base_plate: {x1 - x0:.3f} × {y1 - y0:.3f} mm carrying the pivots and the frame plate's "
                     f"fasteners, {m:g} mm around them")
    else:
        out["frame_pivots"] = replace(pivots, holes=pivots.holes + tuple(holes["frame"]),
                                      keys=pivots.keys + ("option:fasteners",))
    return tuple(out.get(p.name, p) for p in parts), notes


def rolling_parts(res: RollingSynthesis, style: RollingStyle = RollingStyle()) -> PartSet:
    """The plates of a synthesised rolling lever (see the module docstring). Raises
    :class:`GeometryError` for a tolerance that is not finite or below what is exported
    faithfully, or a profile that cannot be fitted."""
    tol = style.tolerance
    if not (math.isfinite(tol) and tol > 0.0):
        raise GeometryError(f"the tolerance must be a positive number of millimetres, got {tol}")
    floor = max(MIN_TOLERANCE, 10.0 * (res.error_mm if math.isfinite(res.error_mm) else 0.0))
    if tol < floor:
        raise GeometryError(f"a tolerance of {tol:g} mm is below what is exported faithfully ({floor:g} mm)")
    el = res.element
    r_pin = 0.5 * el.pin_diameter
    boss = style.boss if style.boss is not None else el.pin_diameter
    frame_fit = _fit(res.frame_profile(), tol, "frame profile")
    slider_fit = _fit(res.slider_profile(), tol, "slider profile")
    chord = max(float(np.hypot(*(res.P[-1] - res.P[0]))), float(np.hypot(*(res.Q[-1] - res.Q[0]))))
    depth = style.depth if style.depth is not None else max(0.25 * chord, 3 * el.pin_diameter)
    if not (math.isfinite(depth) and depth > 0):
        raise GeometryError(f"{style.depth_name} must be a positive number of millimetres; got {depth:g}")
    # the lever is on one side of each profile: the material goes to the other
    ends = pose_state(res.geom, res.alpha[[0, -1]], res.theta[[0, -1]])
    away_f = 0.5 * (res.P[0] + res.P[-1]) - 0.5 * (ends.C1[0] + ends.C1[-1])
    lever_side = el.slider_circle.center if el.slider_circle is not None else el.pin
    away_s = 0.5 * (res.Q[0] + res.Q[-1]) - np.asarray(lever_side, float)
    frame = _backed(frame_fit, away_f, depth, "frame")
    slider = _backed(slider_fit, away_s, depth, "slider")
    pivots = [circle(el.rocker_pivot, r_pin)]
    if el.drive is not None:
        pivots.append(circle(el.drive.crank_pivot, r_pin))
    pins = [el.pin] + ([el.drive.coupler_point] if el.drive is not None else [])
    u1 = (float(np.min(res.u1)), float(np.max(res.u1)))
    lc, sc = el.lever_circle, el.slider_circle
    lever_fit = None
    if sc is not None:
        u2 = (float(np.min(res.u2)), float(np.max(res.u2)))
        pair_e = (sc.center, sc.radius, u2)
        e_note = f"u2 {math.degrees(u2[0]):.4f}° … {math.degrees(u2[1]):.4f}° on the slider circle (true arcs)"
    else:   # a slider law: the lever element Π30 is a derived curve, fitted by biarcs
        lever_fit = _fit(res.lever_profile_e(), tol, "lever element Π30")
        pair_e = (None, None, lever_fit)
        e_note = (f"the lever element Π30 (slider law) {len(lever_fit.arcs)} arcs, max deviation "
                  f"{lever_fit.max_deviation:.3e} mm")
    lever_outline = fan_outline([(lc.center, lc.radius, u1), pair_e] + [(q, r_pin + boss, None) for q in pins])
    lever = Part("lever", lever_outline, tuple(circle(p, r_pin) for p in pins), group="lever", keys=KEYS_LEVER)
    parts = (
        Part("frame", frame, (), group="frame", deviation=frame_fit.max_deviation, keys=KEYS_PROFILE),
        Part("frame_pivots", None, tuple(pivots), group="frame", keys=("rocker_pivot", "drive.crank_pivot")),
        lever if lever_fit is None else Part("lever", lever_outline, lever.holes, group="lever",
                                             deviation=lever_fit.max_deviation, keys=KEYS_LEVER),
        Part("slider", slider, (), group="slider", deviation=slider_fit.max_deviation, keys=KEYS_PROFILE),
    )
    src = ("the exact curve (integrated centrode)" if res.method == "exact" else
           "the constructed profile (natural cubic spline through the points)")
    notes = [f"frame profile: {len(frame_fit.arcs)} arcs ({frame_fit.spans} biarcs), max deviation "
             f"{frame_fit.max_deviation:.3e} mm from {src} (tolerance {tol:g} mm); plate depth {depth:.3f} mm",
             f"slider profile: {len(slider_fit.arcs)} arcs ({slider_fit.spans} biarcs), max deviation "
             f"{slider_fit.max_deviation:.3e} mm (tolerance {tol:g} mm)",
             f"lever: working arcs u1 {math.degrees(u1[0]):.4f}° … {math.degrees(u1[1]):.4f}° on the lever circle, "
             f"{e_note}, pin bores Ø{el.pin_diameter:g} mm, bosses {boss:g} mm",
             "frame_pivots: the rocker pivot" + (" and the crank pivot" if el.drive is not None else "")
             + " drilled in the base plate, placed with the frame profile"]
    if res.method != "exact":
        dev = float(np.max(res.reference().distance(res.P)))
        notes.append(f"note: the {res.method} construction itself deviates {dev:.4g} mm from the exact centrode")
    parts, more = _with_fasteners(parts, style, r_pin, depth)
    return PartSet(el.id, parts, (), tuple(notes + more))


def _tangent(ci: np.ndarray, ri: float, cj: np.ndarray, rj: float) -> tuple[np.ndarray, np.ndarray]:
    """The outer tangent from disc i to disc j with both on its left (radius 0: a point): the
    points where it leaves i and meets j (mm)."""
    d = ci - cj
    rho = float(np.hypot(*d))
    x = (rj - ri) / rho
    if abs(x) > 1.0:
        raise GeometryError("a pin boss and a working arc (or two bosses) overlap too much to be joined")
    beta, a = math.atan2(d[1], d[0]), math.acos(x)
    for th in (beta + a, beta - a):
        n = np.array([math.cos(th), math.sin(th)])  # outward normal, right of travel
        travel = np.array([-n[1], n[0]])
        if travel @ (cj - ci) > 0:
            return ci + ri * n, cj + rj * n
    raise GeometryError("cannot join the lever's features by a tangent")


def _chain(fit: BiarcFit, o: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A biarc chain's vertices (M + 1, 2) and bulges (M,), turned to run counter-clockwise about ``o``."""
    pts = np.array([a.start for a in fit.arcs] + [fit.arcs[-1].end], dtype=float)
    bul = np.array([a.bulge for a in fit.arcs])
    a, b = pts[0] - o, pts[-1] - o
    if a[0] * b[1] - a[1] * b[0] < 0.0:
        pts, bul = pts[::-1].copy(), -bul[::-1]
    return pts, bul


def fan_outline(items: list[tuple]) -> Contour:
    """A closed CCW outline through features taken in angular order about their mean point:
    working arcs (centre, radius, (a, b)) kept whole, working curves (None, None, a
    :class:`~..biarc.BiarcFit`: a slider law's lever element) kept whole and run counter-clockwise,
    bosses (centre, radius, None) wrapped from the incoming to the outgoing tangent, consecutive
    features joined by outer tangents (an arc's or a curve's end counts as a point). It may be
    concave; the part check judges its validity."""
    refs = []
    for c, r, span in items:
        if isinstance(span, BiarcFit):
            mid = span.arcs[len(span.arcs) // 2]
            refs.append(np.asarray(mid.start, float))
            continue
        c = np.asarray(c, float)
        refs.append(c + r * np.array([math.cos(0.5 * (span[0] + span[1])), math.sin(0.5 * (span[0] + span[1]))])
                    if span is not None else c)
    o = np.mean(refs, axis=0)
    order = sorted(range(len(items)), key=lambda k: math.atan2(*(refs[k] - o)[::-1]))
    feats = [items[k] if not isinstance(items[k][2], BiarcFit) else (None, None, _chain(items[k][2], o))
             for k in order]

    def ends(f):  # (start disc, end disc) as (centre, radius): an arc's ends are points
        c, r, span = f
        if isinstance(span, tuple) and len(span) == 2 and isinstance(span[0], np.ndarray):
            return (span[0][0], 0.0), (span[0][-1], 0.0)
        c = np.asarray(c, float)
        if span is None:
            return (c, r), (c, r)
        return ((c + r * np.array([math.cos(span[0]), math.sin(span[0])]), 0.0),
                (c + r * np.array([math.cos(span[1]), math.sin(span[1])]), 0.0))

    n = len(feats)
    joins = []  # (leave point of feature k, arrive point at feature k+1)
    for k in range(n):
        (_, (ce, re)), ((cs, rs), _) = ends(feats[k]), ends(feats[(k + 1) % n])
        joins.append(_tangent(ce, re, cs, rs))
    pts, bul = [], []
    for k, (c, r, span) in enumerate(feats):
        arrive = joins[k - 1][1]
        leave = joins[k][0]
        if isinstance(span, tuple) and len(span) == 2 and isinstance(span[0], np.ndarray):
            cpts, cbul = span   # a working curve: its vertices and bulges, then the join onwards
            pts += list(cpts)
            bul += list(cbul) + [0.0]
            continue
        if span is not None:
            sweep = span[1] - span[0]
        else:
            c = np.asarray(c, float)
            a0 = math.atan2(arrive[1] - c[1], arrive[0] - c[0])
            a1 = math.atan2(leave[1] - c[1], leave[0] - c[0])
            sweep = (a1 - a0) % (2 * math.pi)
        if sweep > 1e-12:
            pts += [arrive, leave]
            bul += [math.tan(sweep / 4), 0.0]
        else:
            pts.append(arrive)
            bul.append(0.0)
    pts_a, bul_a = np.array(pts), np.array(bul)
    keep = np.hypot(*(np.roll(pts_a, -1, axis=0) - pts_a).T) > 1e-12 * (1.0 + float(np.max(np.abs(pts_a))))
    return Contour(pts_a[keep], bul_a[keep], ("lever",) * int(keep.sum()))
