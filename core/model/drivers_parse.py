"""Checks a linkage's ``driver`` dict for meaning and builds its :class:`Driver` (kind, stroke, law).

The scene reader has checked the structure against ``linkage.schema.json`` already; this module
checks what a schema cannot: the links and joints named exist and fit the driver's kind, the
speed is finite and not zero, the stroke is increasing, a table law's points are usable. Every
problem is reported through ``bad(where, message, id)`` with the JSON path below ``driver``.
"""
from __future__ import annotations

import math
from typing import Any, Callable

from .drivers import MIN_TABLE_POINTS, DriverKind, LawKind, MotionLaw
from .limits import MAX_LENGTH_MM, speed_problem
from .linkage import Driver, Joint, JointKind, Link

#: driver speed given to a draft linkage (saved with "driver": null) until its crank is drawn
DRAFT_RPM = 60.0

Bad = Callable[..., None]


def _law(ld: dict | None, bad: Bad, who: str) -> MotionLaw:
    """The motion law of ``ld`` (None: constant speed)."""
    if ld is None:
        return MotionLaw()
    kind = LawKind(ld.get("kind", "constant"))
    if kind is not LawKind.TABLE:
        if "points" in ld:
            bad("driver.law.points", f"only a table law has points (this law is {kind.value})", who)
        return MotionLaw(kind)
    pts = [(float(t), float(v)) for t, v in ld.get("points", [])]
    if len(pts) < MIN_TABLE_POINTS:
        bad("driver.law.points", f"a table law needs at least {MIN_TABLE_POINTS} points (cycle fraction, "
            f"value), got {len(pts)}", who)
        return MotionLaw()
    if pts[0][0] != 0.0:
        bad("driver.law.points[0]", f"the first point must be at cycle fraction 0, got {pts[0][0]:g}", who)
    for k in range(1, len(pts)):
        if not pts[k][0] > pts[k - 1][0]:
            bad(f"driver.law.points[{k}]", f"cycle fractions must increase: {pts[k][0]:g} follows "
                f"{pts[k - 1][0]:g}", who)
            return MotionLaw()
    if pts[-1][0] > 1.0:
        bad(f"driver.law.points[{len(pts) - 1}]", f"cycle fractions run from 0 to 1, got {pts[-1][0]:g}", who)
    return MotionLaw(kind, tuple(pts))


def parse_driver(dd: dict[str, Any] | None, bad: Bad, links: list[Link], joints: dict[str, Joint],
                 ground: str) -> Driver:
    """The :class:`Driver` of the (schema-valid) dict ``dd`` — None: a draft whose crank is not
    drawn yet — reporting every problem through ``bad``."""
    if dd is None:   # the linkage is being drawn: no crank yet (saved as "driver": null)
        return Driver("", "", DRAFT_RPM)
    kind = DriverKind(dd.get("kind", "crank"))
    who = dd["link"]
    speed = float(dd.get("speed_rpm", 60.0))
    if not math.isfinite(speed):
        bad("driver.speed_rpm", f"must be a finite number, got {speed}", who)
        speed = 60.0
    elif speed_problem(speed) is not None:
        bad("driver.speed_rpm", speed_problem(speed), who)
    law = _law(dd.get("law"), bad, who)
    stroke = dd.get("stroke")
    if stroke is not None:
        stroke = (float(stroke[0]), float(stroke[1]))
        if max(abs(stroke[0]), abs(stroke[1])) > MAX_LENGTH_MM:
            bad("driver.stroke", f"the stroke must lie within ±{MAX_LENGTH_MM:g} mm, got "
                f"[{stroke[0]:g}, {stroke[1]:g}]", who)
            stroke = None
    by_id = {lk.id: lk for lk in links}
    link = by_id.get(dd["link"])
    pivot = joints.get(dd["pivot"])
    if link is None:
        bad("driver.link", f"driver names unknown link {dd['link']!r}", dd["link"])
    elif dd["link"] == ground:
        bad("driver.link", "the driver cannot be the ground link", dd["link"])
    if pivot is None:
        bad("driver.pivot", f"driver pivot names unknown joint {dd['pivot']!r}", dd["pivot"])
    elif link is not None and pivot.id not in link.joints:
        bad("driver.pivot", f"pivot {pivot.id!r} is not a joint of driver {link.id!r}", pivot.id)
    ok = link is not None and pivot is not None and link.id != ground and pivot.id in link.joints
    if kind is DriverKind.CRANK:
        if stroke is not None:
            bad("driver.stroke", "a crank has no stroke (it turns); give a stroke to a cylinder or slider", who)
            stroke = None
        if ok:
            if len(link.joints) < 2:
                bad("driver.link", f"crank {link.id!r} needs a joint besides its pivot (its tip)", link.id)
            if pivot.kind is not JointKind.R:
                bad("driver.pivot", f"pivot {pivot.id!r} must be a revolute joint", pivot.id)
            if ground in by_id and pivot.id not in by_id[ground].joints:
                bad("driver.pivot", f"pivot {pivot.id!r} is not on the ground link {ground!r}", pivot.id)
    else:
        if stroke is None:
            bad("driver", f"a {kind.value} driver needs a 'stroke' [start, end] in mm", who)
        elif not stroke[0] < stroke[1]:
            bad("driver.stroke", f"the stroke must increase (start < end), got [{stroke[0]:g}, {stroke[1]:g}] mm", who)
        elif kind is DriverKind.CYLINDER and stroke[0] <= 0.0:
            bad("driver.stroke", f"a cylinder's length must stay positive, got a start of {stroke[0]:g} mm", who)
        if ok and pivot.kind is not JointKind.P:
            bad("driver.pivot", f"a {kind.value} is driven along a prismatic joint; {pivot.id!r} is revolute",
                pivot.id)
        elif ok and kind is DriverKind.SLIDER:
            if ground in by_id and pivot.id not in by_id[ground].joints:
                bad("driver.pivot", f"the slider's guide {pivot.id!r} must be on the ground link {ground!r} "
                    "(a slider is driven along a fixed guide)", pivot.id)
        elif ok:
            _check_cylinder(link, pivot, links, joints, ground, bad)
    if law.kind is LawKind.TABLE and kind is not DriverKind.CRANK and law.points and stroke is not None:
        last = law.points[-1]
        if last[0] == 1.0 and last[1] != law.points[0][1]:
            bad("driver.law.points", f"an actuator's cycle closes on its first point: the point at 1 must "
                f"repeat {law.points[0][1]:g} mm, got {last[1]:g}", who)
    elif law.kind is LawKind.TABLE and law.points and law.points[-1][0] == 1.0:
        turns = (law.points[-1][1] - law.points[0][1]) / 360.0
        if turns != round(turns):
            bad("driver.law.points", f"a crank's table closes after whole turns: the point at 1 must differ from "
                f"the first by a multiple of 360°, got {law.points[-1][1] - law.points[0][1]:g}°", who)
    return Driver(dd["link"], dd["pivot"], speed, kind, stroke, law)


def _check_cylinder(barrel: Link, slide: Joint, links: list[Link], joints: dict[str, Joint], ground: str,
                    bad: Bad) -> None:
    """A cylinder: barrel and rod binary, each with a revolute end pivot besides the slide."""
    others = [lk for lk in links if slide.id in lk.joints and lk.id != barrel.id]
    if len(others) != 1:
        return   # the joint check reports a P joint not on exactly two links
    rod = others[0]
    for part, lk in (("barrel", barrel), ("rod", rod)):
        if lk.id == ground:
            bad("driver.link", f"the cylinder's {part} {lk.id!r} cannot be the ground link", lk.id)
            continue
        ends = [j for j in lk.joints if j != slide.id]
        if len(ends) != 1:
            bad("driver.link", f"the cylinder's {part} {lk.id!r} must carry exactly its slide {slide.id!r} and "
                f"one end pivot, it has joints {', '.join(lk.joints)}", lk.id)
        elif ends[0] in joints and joints[ends[0]].kind is not JointKind.R:
            bad("driver.link", f"the cylinder's {part} {lk.id!r} must end in a revolute pivot; "
                f"{ends[0]!r} is prismatic", lk.id)


__all__ = ["DRAFT_RPM", "parse_driver"]
