"""Structural analysis: mobility (Chebychev–Grübler–Kutzbach) and Assur-group decomposition.

The linkage is split into the driver (a class-I mechanism: a crank on a ground pivot) and class-II
groups (dyads) of the five kinds RRR, RRP, RPR, PRP, RPP, each attached to links already known.
Guides may belong to the frame or to moving links. The result is a list of :class:`Group` records
in solving order; :mod:`mechsketch.core.solver.plan` compiles them into array kernels.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from enum import StrEnum

from ..errors import StructureError
from ..model.linkage import JointKind, Linkage


class GroupKind(StrEnum):
    """Kind of a class-II group, read as (outer joint of link i, inner joint, outer joint of link j).

    A ``str``: ``GroupKind.RRR == "RRR"``, and ``str``/f-strings/JSON give ``"RRR"``.
    """

    RRR = "RRR"
    RRP = "RRP"
    RPR = "RPR"
    PRP = "PRP"
    RPP = "RPP"


#: kinds we solve
DYAD_KINDS: tuple[GroupKind, ...] = tuple(GroupKind)
#: kinds with two assembly modes, chosen by the drawn pose (PRP, RPP: two lines meet once)
MODAL_KINDS: tuple[GroupKind, ...] = (GroupKind.RRR, GroupKind.RRP, GroupKind.RPR)


@dataclass(frozen=True)
class Group:
    """One class-II group (dyad) in solving order.

    ``link_i``/``link_j`` are the two unknown links, ``inner`` the joint between them,
    ``outer_i``/``outer_j`` their joints to known links ``known_i``/``known_j``. ``kind`` reads
    outer_i + inner + outer_j (e.g. "RRP": link j is a slider on a guide of ``known_j``); a
    :class:`GroupKind` (a string given here is converted).
    """

    name: str
    kind: GroupKind
    link_i: str
    link_j: str
    inner: str
    outer_i: str
    outer_j: str
    known_i: str
    known_j: str
    #: hung on the frame only (directly or through other fixed groups): zero mobility, its links
    #: do not move whatever the driver does; solved once (see :func:`fixed_links`)
    fixed: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.kind, GroupKind):
            object.__setattr__(self, "kind", GroupKind(self.kind))

    @property
    def joints(self) -> tuple[str, str, str]:
        return (self.outer_i, self.inner, self.outer_j)


def joint_count(linkage: Linkage) -> int:
    """Lower pairs counted for mobility: an R joint on k links counts k−1, a P joint 1."""
    total = 0
    for j in linkage.joints:
        k = len(linkage.links_of(j.id))
        total += max(k - 1, 0) if j.kind is JointKind.R else 1
    return total


def mobility(linkage: Linkage) -> int:
    """Degrees of freedom F = 3(n − 1) − 2 p (n links with the frame, p lower pairs)."""
    return 3 * (len(linkage.links) - 1) - 2 * joint_count(linkage)


def _check_driver(linkage: Linkage) -> None:
    """The driver must be a crank (a link of two or more joints) turning about a revolute joint on
    the ground link (actuators are decomposed by :mod:`.drive`)."""
    drv = linkage.driver
    ids = linkage.link_ids
    if linkage.ground not in ids:
        raise StructureError(f"linkage {linkage.id!r} has no ground link {linkage.ground!r}", links=(linkage.ground,))
    if not linkage.has_driver:
        what = "" if not drv.link else f" (driver link {drv.link!r} is not a moving link)"
        raise StructureError(f"linkage {linkage.id!r} has no driver yet{what}: draw a crank with the "
                             "crank tool", links=(drv.link,) if drv.link else ())
    joints = linkage.link(drv.link).joints
    if len(joints) < 2 or drv.pivot not in joints:   # a crank may carry any number of joints
        raise StructureError(f"driver {drv.link!r} must carry its pivot {drv.pivot!r} and at least one "
                             "other joint", joints=joints, links=(drv.link,))
    if drv.pivot not in linkage.link(linkage.ground).joints or linkage.joint(drv.pivot).kind is not JointKind.R:
        raise StructureError(f"driver pivot {drv.pivot!r} must be a revolute joint on the ground link",
                             joints=(drv.pivot,), links=(drv.link,))


def _split(linkage: Linkage, known: set[str], skip: frozenset[str] = frozenset(),
           strict: bool = True) -> list[Group]:
    """Dyads solvable from the links in ``known`` (updated in place), in solving order; links in
    ``skip`` are never used. ``strict``: raise StructureError when links remain that do not split
    into dyads; else return the groups found so far."""
    links = {k.id: k for k in linkage.links if k.id not in skip}
    kinds = {j.id: j.kind for j in linkage.joints}
    members = {j.id: set(linkage.links_of(j.id)) - skip for j in linkage.joints}
    order = [k.id for k in linkage.links]
    groups: list[Group] = []

    def outer(link_id: str) -> list[tuple[str, str]]:
        """(joint, known link) pairs joining ``link_id`` to known links."""
        out = []
        for jid in links[link_id].joints:
            for other in sorted(members[jid] & known, key=order.index):
                if other != link_id:
                    out.append((jid, other))
                    break
        return out

    while len(known & links.keys()) < len(links):
        found = None
        for li in order:
            if li in known or li not in links:
                continue
            oi = outer(li)
            if len(oi) != 1:
                continue
            # the inner joint may carry further unknown links (a compound hinge): they hang on
            # the dyad and are solved after it, so try each unknown partner in turn
            pairs = [(jid, lj) for jid in links[li].joints if not (members[jid] - {li}) & known
                     for lj in sorted(members[jid] - {li}, key=order.index)]
            for jid, lj in pairs:
                oj = outer(lj)
                if len(oj) != 1 or oj[0][0] == jid:
                    continue
                kind = kinds[oi[0][0]].value + kinds[jid].value + kinds[oj[0][0]].value
                if kind in ("PRR", "PPR"):  # mirror to the canonical kinds RRP, RPP
                    li_, lj_, oi_, oj_ = lj, li, oj, oi
                    kind = kind[::-1]
                else:
                    li_, lj_, oi_, oj_ = li, lj, oi, oj
                if kind not in DYAD_KINDS:
                    if not strict:
                        continue
                    raise StructureError(
                        f"links {li!r} and {lj!r} form a PPP group (three prismatic joints "
                        f"{oi[0][0]}, {jid}, {oj[0][0]}): its rotation is undetermined",
                        joints=(oi[0][0], jid, oj[0][0]), links=(li, lj))
                found = Group(f"{kind}({li_},{lj_})", GroupKind(kind), li_, lj_, jid, oi_[0][0], oj_[0][0],
                              oi_[0][1], oj_[0][1])
                break
            if found:
                break
        if found is None:
            if not strict:
                break
            rest = [k for k in order if k not in known]
            rest_joints = sorted({j for k in rest for j in links[k].joints}, key=linkage.joint_ids.index)
            raise StructureError(
                f"linkage {linkage.id!r}: links {', '.join(rest)} do not split into class-II groups "
                f"(dyads) attached to solved links; they form a higher-class group or are "
                f"mis-connected (joints {', '.join(rest_joints)})",
                joints=tuple(rest_joints), links=tuple(rest))
        groups.append(found)
        known.update((found.link_i, found.link_j))
    return groups


def fixed_links(linkage: Linkage) -> set[str]:
    """The frame and the links that cannot move whatever the driver does: those of dyads hung on
    frame joints only (an RRR between two ground pivots, a slider whose rod pivots on the frame and
    whose guide is the frame), directly or through other such dyads. Such a group is a structure
    of zero mobility. Needs no driver (the driver link is never used)."""
    if linkage.ground not in linkage.link_ids:
        return set()
    known = {linkage.ground}
    drv = linkage.driver.link
    skip = frozenset({drv}) if drv and drv != linkage.ground and drv in linkage.link_ids else frozenset()
    _split(linkage, known, skip, strict=False)
    return known


def decompose(linkage: Linkage) -> list[Group]:
    """Split into driver + dyads, in solving order.

    Raises :class:`StructureError` naming the joints and links at fault when the mobility is not 1
    or when what remains after the dyads cannot be split into class-II groups. Groups whose links
    are :func:`fixed_links` (hung on the frame only) have ``fixed`` True.
    """
    _check_driver(linkage)
    f = mobility(linkage)
    if f != 1:
        state = "under-constrained (it can move freely)" if f > 1 else "over-constrained (it cannot move)"
        raise StructureError(
            f"linkage {linkage.id!r} has mobility {f}, needs 1 for one driver: it is {state}. "
            f"{len(linkage.links)} links, {joint_count(linkage)} lower pairs "
            f"(F = 3·({len(linkage.links)}−1) − 2·{joint_count(linkage)})",
            joints=linkage.joint_ids, links=linkage.link_ids)
    groups = _split(linkage, {linkage.ground, linkage.driver.link})
    fixed = fixed_links(linkage)

    def frame_side(joint: str, known: str) -> str:
        """A fixed group's known link on the frame side (the frame, not the crank, at its pivot)."""
        return linkage.ground if known not in fixed and linkage.ground in linkage.links_of(joint) else known

    return [replace(g, fixed=True, known_i=frame_side(g.outer_i, g.known_i),
                    known_j=frame_side(g.outer_j, g.known_j))
            if g.link_i in fixed and g.link_j in fixed else g for g in groups]
