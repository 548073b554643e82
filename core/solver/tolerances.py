"""Tolerances shared by the plan and the branch-point search (a leaf module: imports nothing of
the solver, so :mod:`.plan` and :mod:`.branches` can both import it at module level)."""
from __future__ import annotations

import numpy as np

#: below this conditioning (|sin| of the velocity system's column angle) a sample is near a toggle
TOGGLE_COND = 1e-3
#: an assembly margin within TOUCH_REL · (group size + coordinate size) of zero is a toggle
#: touched exactly (rounding, not geometry): it assembles, and may be a branch point
TOUCH_REL = 64 * np.finfo(float).eps
#: a local minimum of a group's assembly margin within BRANCH_REL · (group size + coordinate size,
#: both taken about the driver pivot) of zero is a branch point (a toggle passed *through*); a
#: larger one is a near miss (the mode is kept). The margin's rounding at a true touch, measured on
#: the test linkages, is ≤ 2 eps of that size; a gap of 1e-12 mm at 300 mm is resolved
BRANCH_REL = 8 * np.finfo(float).eps
#: outer joints of an RRR (or the pins of an RPR) closer than SINGULAR_REL · (group size +
#: coordinate size) leave the direction between them, hence the pose, undetermined: the sample is
#: singular (reported, not solved; its position error would be ~eps·size²/distance)
SINGULAR_REL = 1.5e-8

#: velocities and accelerations of a sample are given (``rates_valid``) where their estimated
#: relative error stays below RATE_REL: 8·eps·(1 + coordinates/size)/cond² for the two-mode groups
#: near a toggle (rates lose eps·size/gap and gap ≈ size·cond²/8), /cond for PRP and RPP
RATE_REL = 1e-6
#: the factor of eps in that estimate
RATE_EPS = 8.0

__all__ = ["BRANCH_REL", "RATE_EPS", "RATE_REL", "SINGULAR_REL", "TOGGLE_COND", "TOUCH_REL"]
