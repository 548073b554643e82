"""What a linkage reports in words: the head line (links, joints, driver, drawn input), what kind
of linkage it is (:mod:`.classify`: Grashof, four-bar type, slider-crank kind, actuator stroke,
the outputs' strokes and time ratios) and its diagnostics (what ``mechsketch analyze SCENE
--element ID --summary`` prints, and the GUI's diagnostics panel shows)."""
from __future__ import annotations

from ..model.drivers import input_text
from ..model.linkage import Linkage
from ..solver.diagnostics import Diagnostics
from ..solver.plan import Plan, Solution
from .classify import classification


def linkage_summary(linkage: Linkage, plan: Plan, diagnostics: Diagnostics, solution: Solution | None = None) -> str:
    """The head line of ``linkage`` (driver, its sense and the drawn input of ``plan``), its
    classification (the outputs' strokes and time ratios need ``solution``, the cycle's sweep) and
    the text of ``diagnostics`` (dead points, infeasible ranges, transmission, modes) below it."""
    d = linkage.driver
    if d.linear:
        how = f"({d.kind.value}) at {abs(d.speed_rpm):g} cycles/min"
    else:
        how = f"at {d.speed_rpm:g} rpm ({'CCW' if d.speed_rpm > 0 else 'CW'})"
    head = (f"linkage {linkage.id!r}: {len(linkage.links)} links, {len(linkage.joints)} joints, driver "
            f"{d.link!r} {how}, drawn input {input_text(plan.theta0, plan.input_unit, 4)}")
    full = diagnostics.full_turn if diagnostics is not None else None
    return "\n".join([head, *classification(linkage, plan, solution, full), str(diagnostics)])
