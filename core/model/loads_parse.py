"""Checks the optional masses, gravity, loads and joint friction of a linkage dict for meaning.

Types and ranges (numbers, minimum 0, two coordinates) are checked first by
``linkage.schema.json``; this module checks what a schema cannot: which kind each load is, that
the links and joints it names exist, that values are finite, that a nonzero value is not below
the physical floor of its unit (``limits.SMALLEST``: 1e-12 N, N·m, kg, kg·m², m/s², N/mm, N·s/mm;
1e-6 mm for a friction radius; a force's and gravity's magnitude; subnormals included — such a
value is refused rather than read as 0, issue 20 item 12), and that a load does something
(not on the ground link, a spring not with both ends on one link). Each problem names its JSON
path (``$.elements[0].loads[2].link``) and what to change.
"""
from __future__ import annotations

import math
from collections import Counter
from typing import Any, Callable

from .limits import tiny_problem
from .loads import (KIND_KEYS, Damper, End, JointFriction, LinkMass, Load, PointForce, Spring, Torque,
                    next_load_id)

Bad = Callable[[str, str, "str | None"], None]


def _finite(values) -> bool:
    return all(math.isfinite(float(v)) for v in values)


def _tiny(bad: Bad, where: str, value: float, unit: str, id: str | None) -> bool:
    """Report a nonzero value below the physical floor of its unit (True if reported)."""
    msg = tiny_problem(value, unit)
    if msg is not None:
        bad(where, msg, id)
    return msg is not None


def parse_dynamics(data: dict[str, Any], bad: Bad, link_ids: list[str], ground: str
                   ) -> tuple[tuple[LinkMass, ...], tuple[float, float] | None, tuple[Load, ...],
                              tuple[JointFriction, ...]]:
    """(masses, gravity, loads, friction) of a structurally valid linkage dict; problems go to
    ``bad(where, message, id)`` with ``where`` relative to the element's path."""
    masses: list[LinkMass] = []
    for k, ld in enumerate(data["links"]):
        if not any(key in ld for key in ("mass", "com", "inertia")):
            continue
        if "mass" not in ld:
            bad(f"links[{k}]", f"link {ld['id']!r} has 'com' or 'inertia' but no 'mass' (kg): add it",
                ld["id"])
            continue
        mass = float(ld["mass"])
        com = ld.get("com")
        inertia = ld.get("inertia")
        if not math.isfinite(mass):
            bad(f"links[{k}].mass", f"must be a finite number of kg, got {ld['mass']}", ld["id"])
            continue
        if com is not None and not _finite(com):
            bad(f"links[{k}].com", f"must be finite numbers (mm), got {com}", ld["id"])
            continue
        if inertia is not None and not math.isfinite(float(inertia)):
            bad(f"links[{k}].inertia", f"must be a finite number of kg·m², got {inertia}", ld["id"])
            continue
        if _tiny(bad, f"links[{k}].mass", mass, "kg", ld["id"]) or (
                inertia is not None and _tiny(bad, f"links[{k}].inertia", float(inertia), "kg·m²", ld["id"])):
            continue
        masses.append(LinkMass(ld["id"], mass, None if com is None else (float(com[0]), float(com[1])),
                               None if inertia is None else float(inertia)))

    friction: list[JointFriction] = []
    for k, jd in enumerate(data["joints"]):
        if "friction_radius" not in jd:
            continue
        radius = float(jd["friction_radius"])
        if jd["kind"] != "R":
            bad(f"joints[{k}].friction_radius", "only a revolute joint has a friction circle "
                "(prismatic joints are frictionless): remove it", jd["id"])
        elif not math.isfinite(radius):
            bad(f"joints[{k}].friction_radius", f"must be a finite number of mm, got {radius}", jd["id"])
        elif _tiny(bad, f"joints[{k}].friction_radius", radius, "mm", jd["id"]):
            continue
        elif radius > 0:
            friction.append(JointFriction(jd["id"], radius))

    gravity = data.get("gravity")
    if gravity is not None:
        if not _finite(gravity):
            bad("gravity", f"must be finite numbers (m/s²), got {gravity}", None)
            gravity = None
        elif _tiny(bad, "gravity", math.hypot(float(gravity[0]), float(gravity[1])), "m/s²", None):
            gravity = None
        else:
            gravity = (float(gravity[0]), float(gravity[1]))

    loads: list[Load] = []
    items = data.get("loads", [])
    given = [ld.get("id") for ld in items if "id" in ld]
    for name, count in Counter(given).items():
        if count > 1:
            k = next(i for i, ld in enumerate(items) if ld.get("id") == name)
            bad(f"loads[{k}].id", f"duplicate load id {name!r}: give each load its own id", name)
    taken = set(given)
    known = set(link_ids)
    for k, ld in enumerate(items):
        load = _load(ld, f"loads[{k}]", bad, known, ground, taken)
        if load is not None:
            loads.append(load)
            taken.add(load.id)
    return tuple(masses), gravity, tuple(loads), tuple(friction)


def _load(ld: dict, where: str, bad: Bad, links: set[str], ground: str, taken: set[str]) -> Load | None:
    """One load dict as a record, or None (problems reported)."""
    kinds = [KIND_KEYS[key] for key in KIND_KEYS if key in ld]
    lid = ld.get("id")
    if len(kinds) != 1:
        what = "none" if not kinds else " and ".join(repr(k) for k in kinds)
        bad(where, f"a load is one of: a force (with 'force'), a torque ('torque'), a spring "
            f"('stiffness') or a damper ('damping'); this one has {what}", lid)
        return None
    kind = kinds[0]
    allowed = {"force": {"id", "link", "at", "force"}, "torque": {"id", "link", "torque"},
               "spring": {"id", "ends", "stiffness", "free_length"}, "damper": {"id", "ends", "damping"}}[kind]
    extra = sorted(set(ld) - allowed)
    if extra:
        bad(where, f"a {kind} load has no field(s) {', '.join(extra)}: remove them", lid)
        return None
    lid = lid or next_load_id(kind, taken)
    if kind in ("force", "torque"):
        if "link" not in ld:
            bad(where, f"the {kind} {lid!r} needs 'link' (the link it acts on)", lid)
            return None
        link = ld["link"]
        if link not in links:
            bad(f"{where}.link", f"{kind} {lid!r} names unknown link {link!r}", lid)
            return None
        if link == ground:
            bad(f"{where}.link", f"{kind} {lid!r} is on the ground link {link!r}, which does not move: "
                "put it on a moving link", lid)
            return None
        if kind == "torque":
            if not math.isfinite(float(ld["torque"])):
                bad(f"{where}.torque", f"must be a finite number of N·m, got {ld['torque']}", lid)
                return None
            if _tiny(bad, f"{where}.torque", float(ld["torque"]), "N·m", lid):
                return None
            return Torque(lid, link, float(ld["torque"]))
        if "at" not in ld:
            bad(where, f"the force {lid!r} needs 'at' (the drawn point of {link!r} it acts at, mm)", lid)
            return None
        for key, unit in (("at", "mm"), ("force", "N")):
            if not _finite(ld[key]):
                bad(f"{where}.{key}", f"must be finite numbers ({unit}), got {ld[key]}", lid)
                return None
        if _tiny(bad, f"{where}.force", math.hypot(float(ld["force"][0]), float(ld["force"][1])), "N", lid):
            return None
        return PointForce(lid, link, (float(ld["at"][0]), float(ld["at"][1])),
                          (float(ld["force"][0]), float(ld["force"][1])))
    if "ends" not in ld:
        bad(where, f"the {kind} {lid!r} needs 'ends': [{{link, at}}, {{link, at}}]", lid)
        return None
    ends = []
    for m, e in enumerate(ld["ends"]):
        if e["link"] not in links:
            bad(f"{where}.ends[{m}].link", f"{kind} {lid!r} names unknown link {e['link']!r}", lid)
            return None
        if not _finite(e["at"]):
            bad(f"{where}.ends[{m}].at", f"must be finite numbers (mm), got {e['at']}", lid)
            return None
        ends.append(End(e["link"], (float(e["at"][0]), float(e["at"][1]))))
    if ends[0].link == ends[1].link:
        bad(f"{where}.ends", f"both ends of {kind} {lid!r} are on link {ends[0].link!r}: it does "
            "nothing; attach the ends to two different links", lid)
        return None
    if kind == "spring":
        k, free = float(ld["stiffness"]), ld.get("free_length")
        if not math.isfinite(k) or (free is not None and not math.isfinite(float(free))):
            bad(where, f"spring {lid!r}: stiffness and free length must be finite numbers", lid)
            return None
        if _tiny(bad, f"{where}.stiffness", k, "N/mm", lid):
            return None
        return Spring(lid, (ends[0], ends[1]), k, None if free is None else float(free))
    c = float(ld["damping"])
    if not math.isfinite(c):
        bad(f"{where}.damping", f"must be a finite number of N·s/mm, got {ld['damping']}", lid)
        return None
    if _tiny(bad, f"{where}.damping", c, "N·s/mm", lid):
        return None
    return Damper(lid, (ends[0], ends[1]), c)
