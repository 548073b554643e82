"""Tolerances shared by the plan and the branch-point search (a leaf module: imports nothing of
the solver, so :mod:`.plan` and :mod:`.branches` can both import it at module level)."""
from __future__ import annotations

import numpy as np

#: below this conditioning (|sin| of the velocity system's column angle) a sample is near a toggle
TOGGLE_COND = 1e-3
#: an assembly margin within TOUCH_REL · (group size + coordinate size) of zero is a toggle
#: touched exactly (rounding, not geometry): it assembles, and may be a branch point
TOUCH_REL = 64 * np.finfo(float).eps

__all__ = ["TOGGLE_COND", "TOUCH_REL"]
