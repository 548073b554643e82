"""The authored rolling-lever element (pure-rolling profiles after Dvornikov & Maksimova).

Everything is given in the drawn pose ("position 1"), in millimetres; the lever's rotation θ is 0
there and the stroke runs over θ (rad, counter-clockwise positive). The lever carries two circles:
``lever_circle`` (Π3п, rolling on the frame profile, pair D) and ``slider_circle`` (Π30, rolling on
the slider profile, pair E), the pin ``pin`` of the rocker whose ground pivot is ``rocker_pivot``.
The profiles themselves are derived (synthesised), never stored: see
:mod:`mechsketch.core.analyses.rolling.synthesis`.

``parse`` checks what the schema cannot: the rocker line meets the lever circle in the drawn pose,
the chosen contact lies on the ray from the pivot and is neither the pin nor the pivot itself (both
make the lever a mere pivoting body, see :func:`coincidence_tolerance`), the normal to the slider
axis through the contact reaches the slider circle, the stroke is not empty, the drive points are
distinct; with a slider law (instead of the slider circle), that the law covers the stroke and the
drawn pose lies within it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ..errors import GeometryError, Problem

SCHEMA = "rolling_lever.schema.json"

XYTuple = tuple[float, float]

#: defaults of the optional keys
DEFAULT_METHOD = "exact"
DEFAULT_POINTS = 200
DEFAULT_TOLERANCE = 1e-10  # mm, integration tolerance of the exact method
DEFAULT_PIN_DIAMETER = 10.0  # mm, holes drawn in the DXF
METHODS = ("exact", "paper", "corrected")


@dataclass(frozen=True)
class Circle:
    """A circle of the lever in the drawn pose: centre (mm) and radius (mm)."""

    center: XYTuple
    radius: float

    def to_dict(self) -> dict:
        return {"center": [self.center[0], self.center[1]], "radius": self.radius}


@dataclass(frozen=True)
class Stroke:
    """The lever rotation θ (rad) from ``start`` to ``end``; θ = 0 is the drawn pose."""

    start: float
    end: float

    @property
    def span(self) -> float:
        """Signed θ span of the stroke (rad)."""
        return self.end - self.start

    def to_dict(self) -> dict:
        return {"from": self.start, "to": self.end}


#: the rise laws a slider law may name (mechsketch.core.solver.motion_law.profile)
SLIDER_LAWS = ("cycloidal", "harmonic", "modified_trapezoid", "constant")


@dataclass(frozen=True)
class SliderLaw:
    """A prescribed slider displacement S5(θ) over the stroke (mm), instead of a slider circle.

    Either ``table`` ((θ rad, S5 mm), …; θ strictly monotone, covering the stroke; interpolated by
    a quintic spline, cubic below 6 points) or a rise law ``kind`` (``cycloidal``, ``harmonic``,
    ``modified_trapezoid``, ``constant``) taking S5 from 0 at ``stroke.from`` to ``travel`` at
    ``stroke.to``. The lever's pair-E element and the slider profile are then the exact centrodes
    of the lever/slider relative motion (:mod:`mechsketch.core.analyses.rolling.law`).
    """

    kind: str = "table"
    travel: float = 0.0
    table: tuple[tuple[float, float], ...] = ()

    def to_dict(self) -> dict:
        if self.kind == "table":
            return {"table": [[t, s] for t, s in self.table]}
        return {"law": self.kind, "travel": self.travel}


@dataclass(frozen=True)
class Drive:
    """The crank drive: ground pivot A of the crank and the lever point C (drawn pose) of the coupler."""

    crank_pivot: XYTuple
    coupler_point: XYTuple

    def to_dict(self) -> dict:
        return {"crank_pivot": [self.crank_pivot[0], self.crank_pivot[1]],
                "coupler_point": [self.coupler_point[0], self.coupler_point[1]]}


@dataclass(frozen=True)
class RollingLever:
    """A rolling-lever element of a scene (type ``"rolling_lever"``); all lengths mm, angles rad.

    ``contact_branch`` ``"near"``/``"far"``: which intersection of the rocker line (from the pivot)
    with the lever circle is the contact of pair D. ``slider_side`` +1/−1: the intersection of the
    normal to the slider axis with the slider circle on the side of the axis rotated by ±90°.
    ``points``: the stroke is divided into ``points`` intervals (``points + 1`` samples).
    Exactly one of ``slider_circle`` and ``slider_law`` (:class:`SliderLaw`) is set; with a law the
    method is ``exact`` and ``slider_side`` says on which side of the pair-D contact, along
    n = J d_s, the pair-E contact lies (its working side: side·(P0 − P)·n ≥ 0 over the stroke).
    """

    id: str
    lever_circle: Circle
    pin: XYTuple
    rocker_pivot: XYTuple
    slider_circle: Circle | None
    stroke: Stroke
    contact_branch: str = "near"
    slider_axis_deg: float = 0.0
    slider_side: int = 1
    method: str = DEFAULT_METHOD
    points: int = DEFAULT_POINTS
    tolerance: float = DEFAULT_TOLERANCE
    pin_diameter: float = DEFAULT_PIN_DIAMETER
    drive: Drive | None = None
    slider_law: SliderLaw | None = None
    type: str = field(default="rolling_lever", init=False)

    # -- derived constants of the drawn pose ------------------------------------------------
    @property
    def rocker_length(self) -> float:
        """ℓ = |pin − rocker_pivot| (mm)."""
        return math.hypot(self.pin[0] - self.rocker_pivot[0], self.pin[1] - self.rocker_pivot[1])

    @property
    def rocker_angle0(self) -> float:
        """α0, the rocker angle in the drawn pose (rad, atan2)."""
        return math.atan2(self.pin[1] - self.rocker_pivot[1], self.pin[0] - self.rocker_pivot[0])

    @property
    def slider_axis(self) -> XYTuple:
        """Unit vector of the slider motion d_s."""
        a = math.radians(self.slider_axis_deg)
        return (math.cos(a), math.sin(a))

    def drawn_contacts(self) -> tuple[XYTuple, XYTuple]:
        """The contacts P (pair D) and P0 (pair E) in the drawn pose (mm).

        Raises :class:`~mechsketch.core.errors.GeometryError` if either cannot be built.
        """
        msgs, p, p0 = _drawn_geometry(self)
        if msgs:
            raise GeometryError(f"rolling lever {self.id!r}: {msgs[0][1]}")
        assert p is not None
        if p0 is None:   # a slider law: the contact of pair E lies on the normal, k53 = dS5/dθ from P
            raise GeometryError(f"rolling lever {self.id!r}: with a slider law the contact of pair E comes "
                                "from the synthesis (RollingSynthesis.P0)")
        return p, p0

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "type": "rolling_lever",
            "id": self.id,
            "lever_circle": self.lever_circle.to_dict(),
            "contact_branch": self.contact_branch,
            "pin": [self.pin[0], self.pin[1]],
            "rocker_pivot": [self.rocker_pivot[0], self.rocker_pivot[1]],
            **({"slider_circle": self.slider_circle.to_dict()} if self.slider_circle is not None else {}),
            "slider_axis_deg": self.slider_axis_deg,
            "slider_side": self.slider_side,
            "stroke": self.stroke.to_dict(),
            "method": self.method,
            "points": self.points,
            "tolerance": self.tolerance,
            "pin_diameter": self.pin_diameter,
        }
        if self.slider_law is not None:
            d["slider_law"] = self.slider_law.to_dict()
        if self.drive is not None:
            d["drive"] = self.drive.to_dict()
        return d


def _xy(v: Any) -> XYTuple:
    return (float(v[0]), float(v[1]))


#: two points of the drawing closer than this, relative to its size, count as one (see below)
COINCIDENCE_REL = 1e-9


def coincidence_tolerance(ell: float, r1: float, pivot: XYTuple, center: XYTuple) -> float:
    """κ (mm): the contact of pair D closer than κ to the pin (g = ℓ) or to the rocker pivot (g = 0)
    counts as that point; ``COINCIDENCE_REL`` times the largest of ℓ, R1 and |G − c1|.

    Why it matters (the ODE dα/dθ = 1 − g/ℓ): the pin is a lever point, so if it lies on the lever
    circle it lies on the moved circle and on the rocker line in every pose: g = ℓ is then always a
    root. If it is the chosen contact, dα/dθ = 0 for all θ: the rocker stands still, the lever only
    turns about the pin, and both centrodes of pair D shrink to that one point; there is no rolling
    profile to synthesise. If the other intersection is the contact, the motion is regular until
    the contact reaches the pin, where the rocker line touches the moved circle (a double root the
    discriminant only touches, never crosses): the end of the working range. In the same way a
    rocker pivot on the lever circle as the chosen contact gives g = 0, dα/dθ = 1 for all θ: lever
    and rocker turn about the pivot as one body.
    """
    return COINCIDENCE_REL * max(ell, r1, math.hypot(pivot[0] - center[0], pivot[1] - center[1]))


def _drawn_geometry(el: RollingLever) -> tuple[list[tuple[str, str]], XYTuple | None, XYTuple | None]:
    """Check the drawn pose; returns ([(json key, message)], P, P0)."""
    msgs: list[tuple[str, str]] = []
    gx, gy = el.rocker_pivot
    ell = el.rocker_length
    scale = max(1.0, *(abs(c) for c in (*el.pin, *el.rocker_pivot, *el.lever_circle.center)))
    if ell <= 1e-9 * scale:
        msgs.append(("rocker_pivot", f"rocker_pivot {list(el.rocker_pivot)} coincides with the pin "
                                     f"{list(el.pin)}: the rocker has no length"))
        return msgs, None, None
    ex, ey = (el.pin[0] - gx) / ell, (el.pin[1] - gy) / ell
    cx, cy = el.lever_circle.center
    r1 = el.lever_circle.radius
    b = (cx - gx) * ex + (cy - gy) * ey
    miss = abs((cx - gx) * ey - (cy - gy) * ex) - r1  # distance of the centre from the line − R1
    disc = b * b - ((cx - gx) ** 2 + (cy - gy) ** 2 - r1 * r1)
    if disc <= 0.0:
        msgs.append(("lever_circle", f"the rocker line from rocker_pivot {list(el.rocker_pivot)} through "
                                     f"the pin misses the lever circle by {max(miss, 0.0):.6g} mm in the "
                                     "drawn pose"))
        return msgs, None, None
    # both roots without cancellation: q and c0/q (c0 = |c1 − G|² − R1², the product of the roots)
    c0 = (cx - gx) ** 2 + (cy - gy) ** 2 - r1 * r1
    q = b + math.copysign(math.sqrt(disc), b)
    roots = sorted((q, c0 / q))
    t = roots[1] if el.contact_branch == "far" else roots[0]
    kappa = coincidence_tolerance(ell, r1, el.rocker_pivot, el.lever_circle.center)
    if abs(t - ell) <= kappa:
        off = math.hypot(el.pin[0] - cx, el.pin[1] - cy) - r1
        msgs.append(("pin", f"the pin {list(el.pin)} lies on the lever circle ({off:+.3g} mm from it) and is "
                            f"the {el.contact_branch} intersection of the rocker line, i.e. the contact "
                            "itself: g = ℓ, so dα/dθ = 1 − g/ℓ = 0, and it stays 0 because the pin stays on "
                            "the moved circle and on the rocker line in every pose; the rocker never moves, "
                            "the lever only turns about the pin and both centrodes of pair D shrink to that "
                            "point (no profile to roll on). Move the pin off the lever circle or use the "
                            f"'{'near' if el.contact_branch == 'far' else 'far'}' branch"))
        return msgs, None, None
    if abs(t) <= kappa:
        msgs.append(("rocker_pivot", f"rocker_pivot {list(el.rocker_pivot)} lies on the lever circle and is the "
                                     f"{el.contact_branch} intersection of the rocker line, i.e. the contact "
                                     "itself: g = 0, so dα/dθ = 1 − g/ℓ = 1 for every θ; lever and rocker turn "
                                     "about the pivot as one body and both centrodes of pair D shrink to the "
                                     "pivot (no profile to roll on). Move the pivot off the lever circle or "
                                     "use the 'far' branch"))
        return msgs, None, None
    if t < 0.0:
        msgs.append(("contact_branch", f"the {el.contact_branch} intersection of the rocker line with the "
                                       f"lever circle lies behind rocker_pivot (t = {t:.6g} mm): the "
                                       "pivot is inside the lever circle; use the 'far' branch or move it"))
        return msgs, None, None
    p = (gx + t * ex, gy + t * ey)
    if el.slider_circle is None:   # a slider law: pair E is derived from it (analyses.rolling.law)
        return msgs, p, None
    dsx, dsy = el.slider_axis
    nx, ny = -dsy, dsx
    zx, zy = p[0] - el.slider_circle.center[0], p[1] - el.slider_circle.center[1]
    zn = zx * nx + zy * ny
    r2 = el.slider_circle.radius
    disc2 = zn * zn - (zx * zx + zy * zy) + r2 * r2
    if disc2 < 0.0:
        dist = abs(zx * dsx + zy * dsy)
        msgs.append(("slider_circle", f"the normal to the slider axis through the contact point "
                                      f"({p[0]:.6g}, {p[1]:.6g}) cannot reach the slider circle: it "
                                      f"passes {dist - r2:.6g} mm outside it in the drawn pose"))
        return msgs, p, None
    t2 = -zn + el.slider_side * math.sqrt(disc2)
    return msgs, p, (p[0] + t2 * nx, p[1] + t2 * ny)


def _slider_law(data: dict[str, Any], stroke: Stroke, bad) -> SliderLaw | None:
    """The ``slider_law`` of a rolling-lever dict (None without one); problems go to ``bad``."""
    sl = data.get("slider_law")
    if sl is None:
        return None
    if ("table" in sl) == ("law" in sl):
        bad("slider_law", "give either 'table' ([[θ rad, S5 mm], ...]) or 'law' with 'travel' (mm)")
        return None
    lo, hi = sorted((stroke.start, stroke.end))
    if not lo <= 0.0 <= hi:
        bad("stroke", f"with a slider law the drawn pose (θ = 0) must lie within the stroke (from {stroke.start:g} "
                      f"to {stroke.end:g} rad): the slider's displacement is counted from it")
    if "law" in sl:
        if "travel" not in sl:
            bad("slider_law.travel", f"the {sl['law']} law needs 'travel' (mm, S5 at stroke.to)")
            return None
        travel = float(sl["travel"])
        if travel == 0.0:
            bad("slider_law.travel", "the travel is 0: the slider would not move (the profiles would be the "
                                     "lever's pair-D centrodes)")
        return SliderLaw(sl["law"], travel)
    pts = tuple((float(a), float(b)) for a, b in sl["table"])
    th = [a for a, _ in pts]
    steps = [b - a for a, b in zip(th, th[1:])]
    if not (all(d > 0 for d in steps) or all(d < 0 for d in steps)):
        k = next(i for i, d in enumerate(steps) if d == 0 or (d > 0) != (steps[0] > 0))
        bad(f"slider_law.table[{k + 1}]", f"θ must be strictly increasing or decreasing; θ = {th[k + 1]:g} rad "
                                          f"after {th[k]:g} rad")
        return None
    if min(th) > lo or max(th) < hi:
        bad("slider_law.table", f"the table covers θ from {min(th):g} to {max(th):g} rad; the stroke needs "
                                f"{lo:g} to {hi:g} rad")
    return SliderLaw("table", 0.0, pts)


def parse(data: dict[str, Any], path: str) -> tuple[RollingLever | None, list[Problem]]:
    """Check a schema-valid rolling-lever dict for meaning; return the element (or None) and problems."""
    problems: list[Problem] = []
    eid = data["id"]

    def bad(where: str, msg: str) -> None:
        problems.append(Problem(f"{path}.{where}", msg, eid))

    lc, sc, st = data["lever_circle"], data.get("slider_circle"), data["stroke"]
    drive = None
    if "drive" in data:
        dd = data["drive"]
        drive = Drive(_xy(dd["crank_pivot"]), _xy(dd["coupler_point"]))
        if math.dist(drive.crank_pivot, drive.coupler_point) <= 1e-9:
            bad("drive.coupler_point", f"coupler_point {list(drive.coupler_point)} coincides with the crank "
                                       "pivot: the coupler has no length")
    stroke = Stroke(float(st["from"]), float(st["to"]))
    if stroke.start == stroke.end:
        bad("stroke", f"the stroke is empty (from = to = {stroke.start} rad)")
    el = RollingLever(
        id=eid,
        lever_circle=Circle(_xy(lc["center"]), float(lc["radius"])),
        pin=_xy(data["pin"]),
        rocker_pivot=_xy(data["rocker_pivot"]),
        slider_circle=Circle(_xy(sc["center"]), float(sc["radius"])) if sc is not None else None,
        stroke=stroke,
        contact_branch=data.get("contact_branch", "near"),
        slider_axis_deg=float(data.get("slider_axis_deg", 0.0)),
        slider_side=int(data.get("slider_side", 1)),
        method=data.get("method", DEFAULT_METHOD),
        points=int(data.get("points", DEFAULT_POINTS)),
        tolerance=float(data.get("tolerance", DEFAULT_TOLERANCE)),
        pin_diameter=float(data.get("pin_diameter", DEFAULT_PIN_DIAMETER)),
        drive=drive,
        slider_law=_slider_law(data, stroke, bad),
    )
    if (sc is None) == (el.slider_law is None):
        bad("slider_circle", "give exactly one of slider_circle (pair E rolls on a circle of the lever) and "
                             "slider_law (the slider's displacement S5(θ) prescribed)"
                             + (", not both" if sc is not None else ""))
        return None, problems
    if el.slider_law is not None and el.method != "exact":
        bad("method", f"a slider law is synthesised by the exact method only (the paper's construction "
                      f"needs a slider circle); got {el.method!r}")
    for key, msg in _drawn_geometry(el)[0]:
        bad(key, msg)
    if problems:
        return None, problems
    return el, problems
