"""Pure linkage operations behind the canvas tools: fresh ids, deletion, placement checks.

Qt-free and solver-free (except :func:`structure_error`, which only compiles the plan). Each
function returns a new immutable :class:`Linkage` (or a message), never mutates.
"""
from __future__ import annotations

import math
import string
from typing import Iterable

from mechsketch.core.errors import MechsketchError
from mechsketch.core.model.linkage import Driver, Joint, JointKind, Link, Linkage
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.solver.structure import fixed_links

from .events import XY

#: two points closer than this (mm) are the same point
SAME_POINT = 1e-6
#: |sin| of the angle at a new dyad joint below which it is "on the line" (a toggle when drawn)
COLLINEAR_SIN = 2e-3
DEFAULT_RPM = 60.0


def fresh_joint_id(linkage: Linkage | None, taken: Iterable[str] = ()) -> str:
    """The first unused joint id of A, B, ..., Z, A1, ..., Z1, A2, ..."""
    used = set(taken) | (set(linkage.joint_ids) if linkage else set())
    for n in range(0, 10_000):
        for c in string.ascii_uppercase:
            cand = c if n == 0 else f"{c}{n}"
            if cand not in used:
                return cand
    raise RuntimeError("no free joint id")  # pragma: no cover - 260 000 joints


def fresh_link_id(linkage: Linkage | None, stem: str = "link", taken: Iterable[str] = (),
                  bare: bool = False) -> str:
    """``stem`` itself if ``bare`` and free, else the first free ``stem1``, ``stem2``, ..."""
    used = set(taken) | (set(linkage.link_ids) if linkage else set())
    if bare and stem not in used:
        return stem
    n = 1
    while f"{stem}{n}" in used:
        n += 1
    return f"{stem}{n}"


def fresh_element_id(ids: Iterable[str], stem: str = "linkage") -> str:
    used = set(ids)
    n = 1
    while f"{stem}{n}" in used:
        n += 1
    return f"{stem}{n}"


#: samples per cycle of a linkage the tools start (Edit › Preferences sets it)
NEW_LINKAGE_SAMPLES = 360


def new_linkage(element_id: str, pivot: Joint, ground: str = "ground") -> Linkage:
    """A linkage being drawn: a frame with one ground pivot and no driver yet.

    The driver record names the crank the crank tool will add; until then the solver reports
    "no driver yet" (a message, not an error of the app).
    """
    return Linkage(element_id, (pivot,), (Link(ground, (pivot.id,)),), ground,
                   Driver("crank", pivot.id, DEFAULT_RPM), samples=NEW_LINKAGE_SAMPLES)


def has_driver(linkage: Linkage) -> bool:
    """The linkage has a working crank (the driver link exists, with its pivot on the frame)."""
    drv = linkage.driver
    return (drv.link in linkage.link_ids and drv.link != linkage.ground
            and drv.pivot in linkage.link(drv.link).joints)


def on_ground(linkage: Linkage, joint_id: str) -> bool:
    return linkage.ground in linkage.links_of(joint_id)


def fixed_point(linkage: Linkage, joint_id: str) -> bool:
    """``joint_id`` cannot move: it is on the frame or on a link fixed to it (a dyad hung on frame
    joints only), whatever the driver does (the crank's pivot included)."""
    fixed = fixed_links(linkage)
    return any(k in fixed for k in linkage.links_of(joint_id))


def fixed_dyad(linkage: Linkage, joint_a: str, joint_b: str) -> str | None:
    """Why a dyad from ``joint_a`` to ``joint_b`` would be a structure (zero mobility), or None."""
    if fixed_point(linkage, joint_a) and fixed_point(linkage, joint_b):
        return (f"{joint_a} and {joint_b} are both fixed to the frame: a dyad between them would not "
                f"move (zero mobility); pick a joint of a moving link (the crank tip, a coupler or "
                f"rocker joint)")
    return None


def structure_error(linkage: Linkage) -> str | None:
    """The message of compiling ``linkage`` (None if it compiles)."""
    try:
        compile_plan(linkage)
    except MechsketchError as exc:
        return str(exc)
    return None


def delete_items(linkage: Linkage, joints: Iterable[str] = (), links: Iterable[str] = ()) -> Linkage | None:
    """Remove joints and links, then whatever is left dangling.

    Moving links left with fewer than two joints, P joints left on fewer than two links and joints
    left on no link go too (repeatedly). The driver record stays (the solver then says "no driver
    yet" until a crank is drawn again). Returns None when no joint remains (remove the element).
    """
    lk = linkage
    for link_id in links:
        if link_id in lk.link_ids and link_id != lk.ground:
            lk = lk.without_link(link_id)
    for jid in joints:
        if jid in lk.joint_ids:
            lk = lk.without_joint(jid)
    changed = True
    while changed:
        changed = False
        for link in lk.links:
            if link.id != lk.ground and len(link.joints) < 2:
                lk = lk.without_link(link.id)
                changed = True
        for j in lk.joints:
            carriers = lk.links_of(j.id)
            if not carriers or (j.kind is JointKind.P and len(carriers) < 2):
                lk = lk.without_joint(j.id)
                changed = True
                break
    return lk if lk.joints else None


def dist(a: XY, b: XY) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


def sin_angle(o: XY, a: XY, b: XY) -> float:
    """|sin| of the angle between o->a and o->b (0 when collinear)."""
    ax, ay, bx, by = a[0] - o[0], a[1] - o[1], b[0] - o[0], b[1] - o[1]
    na, nb = math.hypot(ax, ay), math.hypot(bx, by)
    if na < SAME_POINT or nb < SAME_POINT:
        return 0.0
    return abs(ax * by - ay * bx) / (na * nb)


def coincidence(linkage: Linkage, moved: Iterable[str]) -> str | None:
    """Why the moved joints make a link degenerate (two revolute joints of one link at one point)."""
    moved = set(moved)
    for link in linkage.links:
        revs = [linkage.joint(j) for j in link.joints if linkage.joint(j).kind is JointKind.R]
        for a in range(len(revs)):
            for b in range(a + 1, len(revs)):
                ja, jb = revs[a], revs[b]
                if (ja.id in moved or jb.id in moved) and dist(ja.at, jb.at) <= SAME_POINT:
                    return (f"joints {ja.id} and {jb.id} of link {link.id!r} would be at the same point: "
                            f"the link would have zero length")
    return None


def coincident_partners(linkage: Linkage, joint_id: str) -> list[str]:
    """Joints drawn at the same point as ``joint_id`` (a slider's pin and its P joint)."""
    at = linkage.joint(joint_id).at
    return [j.id for j in linkage.joints if j.id != joint_id and dist(j.at, at) <= SAME_POINT]


def add_coupler_point(linkage: Linkage, link_id: str, at: XY) -> tuple[Linkage, str]:
    """Add a revolute point at drawn position ``at`` to ``link_id``; returns (linkage, joint id)."""
    jid = fresh_joint_id(linkage)
    link = linkage.link(link_id)
    lk = linkage.with_joint(Joint(jid, JointKind.R, (float(at[0]), float(at[1]))))
    return lk.with_link(Link(link.id, link.joints + (jid,))), jid


def add_ground_pivot(linkage: Linkage, at: XY) -> tuple[Linkage, str]:
    jid = fresh_joint_id(linkage)
    lk = linkage.with_joint(Joint(jid, JointKind.R, (float(at[0]), float(at[1]))))
    ground = lk.link(lk.ground) if lk.ground in lk.link_ids else Link(lk.ground, ())
    return lk.with_link(Link(ground.id, ground.joints + (jid,))), jid


def add_crank(linkage: Linkage, pivot: str, tip_at: XY) -> tuple[Linkage, str, str]:
    """A crank from ground pivot ``pivot`` to a new tip; it becomes the driver."""
    tip = fresh_joint_id(linkage)
    cid = fresh_link_id(linkage, "crank", bare=True)
    speed = linkage.driver.speed_rpm or DEFAULT_RPM
    lk = linkage.with_joint(Joint(tip, JointKind.R, (float(tip_at[0]), float(tip_at[1]))))
    lk = lk.with_link(Link(cid, (pivot, tip))).with_driver(Driver(cid, pivot, speed))
    return lk, cid, tip


def add_rrr(linkage: Linkage, m: str, h: str, at: XY) -> tuple[Linkage, str, tuple[str, str]]:
    """Links M-L and H-L with a new inner joint L at ``at``."""
    jl = fresh_joint_id(linkage)
    la = fresh_link_id(linkage)
    lb = fresh_link_id(linkage, taken=(la,))
    lk = linkage.with_joint(Joint(jl, JointKind.R, (float(at[0]), float(at[1]))))
    lk = lk.with_link(Link(la, (m, jl))).with_link(Link(lb, (h, jl)))
    return lk, jl, (la, lb)


def add_rrp(linkage: Linkage, m: str, guide: str, at: XY, axis_deg: float) -> tuple[Linkage, str, str]:
    """A rod from M to a new pin L at ``at``, a block on L sliding along ``guide`` (the frame or a
    moving link) on a new P joint at L with axis ``axis_deg``. Returns (linkage, pin, P joint)."""
    jl = fresh_joint_id(linkage)
    js = fresh_joint_id(linkage, taken=(jl,))
    rod = fresh_link_id(linkage)
    block = fresh_link_id(linkage, "block", taken=(rod,))
    p = (float(at[0]), float(at[1]))
    lk = linkage.with_joint(Joint(jl, JointKind.R, p)).with_joint(Joint(js, JointKind.P, p, float(axis_deg)))
    g = lk.link(guide) if guide in lk.link_ids else Link(guide, ())
    lk = lk.with_link(Link(rod, (m, jl))).with_link(Link(block, (jl, js))).with_link(Link(g.id, g.joints + (js,)))
    return lk, jl, js


def add_rpr(linkage: Linkage, m: str, h: str) -> tuple[Linkage, str]:
    """A block pivoting at M sliding on a bar pivoting at H (axis through H and M, P joint at M)."""
    pm, ph = linkage.joint(m).at, linkage.joint(h).at
    axis = math.degrees(math.atan2(pm[1] - ph[1], pm[0] - ph[0]))
    jq = fresh_joint_id(linkage)
    block = fresh_link_id(linkage, "block")
    bar = fresh_link_id(linkage, taken=(block,))
    lk = linkage.with_joint(Joint(jq, JointKind.P, (float(pm[0]), float(pm[1])), axis))
    lk = lk.with_link(Link(block, (m, jq))).with_link(Link(bar, (h, jq)))
    return lk, jq
