"""What a linkage reports in words: the head line (links, joints, driver, drawn input) and its
diagnostics (what ``mechsketch analyze SCENE --element ID --summary`` prints)."""
from __future__ import annotations

import math

from ..model.linkage import Linkage
from ..solver.diagnostics import Diagnostics
from ..solver.plan import Plan


def linkage_summary(linkage: Linkage, plan: Plan, diagnostics: Diagnostics) -> str:
    """The head line of ``linkage`` (driver, its sense and the drawn input angle of ``plan``) and
    the text of ``diagnostics`` (dead points, infeasible ranges, transmission, modes) below it."""
    d = linkage.driver
    head = (f"linkage {linkage.id!r}: {len(linkage.links)} links, {len(linkage.joints)} joints, driver "
            f"{d.link!r} at {d.speed_rpm:g} rpm ({'CCW' if d.speed_rpm > 0 else 'CW'}), drawn input "
            f"{math.degrees(plan.theta0):.4f}°")
    return head + "\n" + str(diagnostics)
