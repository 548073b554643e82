"""Checks a linkage element dict for meaning and builds a :class:`Linkage`.

Structure (types, required keys) is checked first against ``linkage.schema.json`` by the scene
reader; this module checks what a schema cannot: ids, membership, coincident joints, the driver.
"""
from __future__ import annotations

import math
from collections import Counter
from typing import Any

from ..errors import Problem
from .drawing import parse_linkage_drawing
from .drivers_parse import DRAFT_RPM, parse_driver  # noqa: F401  (DRAFT_RPM re-exported)
from .linkage import Joint, JointKind, Link, Linkage
from .loads_parse import parse_dynamics

SCHEMA = "linkage.schema.json"
#: two revolute joints of one link closer than this (mm, relative to the link's own span, at
#: least 1 mm) coincide
COINCIDENT_REL = 1e-9
#: drawn coordinates beyond this (mm) are refused: the kinematics would lose all precision
MAX_COORD = 1e9


def parse(data: dict[str, Any], path: str) -> tuple[Linkage | None, list[Problem]]:
    """Validate a structurally valid linkage dict; return the linkage (or None) and problems."""
    problems: list[Problem] = []
    eid = data["id"]

    def bad(where: str, msg: str, id: str | None = None) -> None:
        problems.append(Problem(f"{path}.{where}", msg, id))

    joints: list[Joint] = []
    for k, jd in enumerate(data["joints"]):
        x, y = (float(v) for v in jd["at"])
        if math.isfinite(x) and math.isfinite(y) and max(abs(x), abs(y)) > MAX_COORD:
            bad(f"joints[{k}].at", f"position {jd['at']} is beyond ±{MAX_COORD:g} mm", jd["id"])
            continue
        if not (math.isfinite(x) and math.isfinite(y)):
            bad(f"joints[{k}].at", f"position must be finite numbers, got {jd['at']}", jd["id"])
            continue
        kind = JointKind(jd["kind"])
        axis = jd.get("axis_deg")
        if kind is JointKind.P:
            if axis is None:
                bad(f"joints[{k}]", "a P joint needs 'axis_deg' (the slide direction, degrees)", jd["id"])
                axis = 0.0
            elif not math.isfinite(float(axis)):
                bad(f"joints[{k}].axis_deg", f"must be a finite number, got {axis}", jd["id"])
                axis = 0.0
            axis = float(axis)
        elif axis is not None:
            bad(f"joints[{k}].axis_deg", "only a P joint has an axis", jd["id"])
            axis = None
        joints.append(Joint(jd["id"], kind, (x, y), axis))

    for what, items, key in (("joint", data["joints"], "joints"), ("link", data["links"], "links")):
        counts = Counter(it["id"] for it in items)
        for k, it in enumerate(items):
            if counts[it["id"]] > 1:
                bad(f"{key}[{k}].id", f"duplicate {what} id {it['id']!r}", it["id"])
                counts[it["id"]] = 0  # report once
    joint_by_id = {j.id: j for j in joints}
    known_joints = {jd["id"] for jd in data["joints"]}

    links: list[Link] = []
    for k, ld in enumerate(data["links"]):
        ids = tuple(ld["joints"])
        for m, jid in enumerate(ids):
            if jid not in known_joints:
                bad(f"links[{k}].joints[{m}]", f"link {ld['id']!r} names unknown joint {jid!r}", ld["id"])
        dup = [j for j, c in Counter(ids).items() if c > 1]
        if dup:
            bad(f"links[{k}].joints", f"link {ld['id']!r} lists joint(s) {', '.join(dup)} twice", ld["id"])
        links.append(Link(ld["id"], ids))

    member: dict[str, list[str]] = {j: [] for j in known_joints}
    for lk in links:
        for jid in set(lk.joints):
            if jid in member:
                member[jid].append(lk.id)
    for k, jd in enumerate(data["joints"]):
        jid = jd["id"]
        if not member.get(jid):
            bad(f"joints[{k}]", f"joint {jid!r} is on no link", jid)
        elif jd["kind"] == "P" and len(member[jid]) != 2:
            bad(f"joints[{k}]", f"P joint {jid!r} must join exactly two links, it is on "
                f"{len(member[jid])} ({', '.join(member[jid])})", jid)

    for k, lk in enumerate(links):
        revs = [joint_by_id[j] for j in lk.joints if j in joint_by_id and joint_by_id[j].kind is JointKind.R]
        scale = max((math.hypot(p.at[0] - q.at[0], p.at[1] - q.at[1]) for p in revs for q in revs), default=1.0)
        for a in range(len(revs)):
            for b in range(a + 1, len(revs)):
                p, q = revs[a].at, revs[b].at
                if math.hypot(p[0] - q[0], p[1] - q[1]) <= COINCIDENT_REL * max(scale, 1.0):
                    bad(f"links[{k}]", f"revolute joints {revs[a].id!r} and {revs[b].id!r} of link "
                        f"{lk.id!r} are at the same point {list(p)}", lk.id)

    link_ids = {lk.id for lk in links}
    ground = data["ground"]
    if ground not in link_ids:
        bad("ground", f"ground names unknown link {ground!r}", ground)
    driver = parse_driver(data["driver"], bad, links, joint_by_id, ground)

    masses, gravity, loads, friction = parse_dynamics(
        data, bad, [lk.id for lk in links], ground)
    drawing = parse_linkage_drawing(data.get("drawing"), lambda where, msg: bad(where, msg, eid))

    if problems:
        return None, problems
    linkage = Linkage(eid, tuple(joints), tuple(links), ground,
                      driver, int(data.get("samples", 360)),
                      masses, gravity, loads, friction, drawing)
    return linkage, problems
