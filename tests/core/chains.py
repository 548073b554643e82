"""A long linkage for the workspace tests and the drag benchmark: a crank driving a chain of n
RRR dyads, dyad k hanging on the previous dyad's coupler and on its own ground pivot, so every
group depends on the one before it (moving the last joint touches one group, the first all)."""
from __future__ import annotations

import math

from linkage_builders import build


def dyad_chain(n: int, eid: str = "chain", samples: int = 360, crank: float = 10.0, span: float = 100.0
               ) -> "Linkage":  # noqa: F821
    """Crank A-P0 (``crank`` mm) then dyads k = 1..n: coupler P(k-1)-Pk, rocker Pk-Gk with Gk on
    the ground at x = k·``span``, y = 0; Pk drawn at (k·span - span/2, span·0.8) so every dyad is
    far from its toggles for a whole crank turn (rocker 0.94·span, coupler ~span)."""
    joints = [("A", "R", (0.0, 0.0)), ("P0", "R", (crank * math.cos(1.0), crank * math.sin(1.0)))]
    links: dict[str, list[str]] = {"ground": ["A"], "crank": ["A", "P0"]}
    for k in range(1, n + 1):
        joints.append((f"G{k}", "R", (k * span, 0.0)))
        joints.append((f"P{k}", "R", (k * span - 0.5 * span, 0.8 * span)))
        links["ground"].append(f"G{k}")
        links[f"c{k}"] = [f"P{k - 1}", f"P{k}"]
        links[f"r{k}"] = [f"P{k}", f"G{k}"]
    return build(eid, joints, links, "ground", "crank", "A", rpm=60.0, samples=samples)
