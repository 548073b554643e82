"""An output's extreme that lies just before the drawn pose (between the last sample and the
first, so its search bracket starts at a negative time) is found where it is, not mirrored to
the positive side: the rocker of a crank-rocker four-bar, drawn a fraction of a sample past its
extreme, in both turning directions. Reference: the rocker's closed-form extreme, where crank
and coupler are collinear (|AC| = coupler ± crank), solved at that crank angle."""
from __future__ import annotations

import math

import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core.analyses.classify import output_motions
from mechsketch.core.solver.plan import compile_plan

CRANK, COUPLER, ROCKER, GROUND = 40.0, 140.0, 120.0, 160.0
N = 360


def _extreme_crank_angles() -> list[float]:
    """Crank angles (rad) at the rocker's two extremes (C above the ground line, mode +1): the
    crank along A→C with |AC| = coupler + crank (extended) and against it (folded, coupler − crank)."""
    out = []
    for L, along in ((COUPLER + CRANK, 1.0), (COUPLER - CRANK, -1.0)):
        # C: |AC| = L, |DC| = rocker, D = (ground, 0), above the x axis
        x = (L * L - ROCKER * ROCKER + GROUND * GROUND) / (2 * GROUND)
        c = complex(x, math.sqrt(L * L - x * x))
        out.append(math.atan2((along * c).imag, (along * c).real))
    return out


@pytest.mark.parametrize("rpm", [60.0, -60.0])
@pytest.mark.parametrize("which", [0, 1])
@pytest.mark.parametrize("past", [0.3, 0.7])
def test_an_extreme_just_before_the_drawn_pose(rpm, which, past):
    theta_ext = _extreme_crank_angles()[which]
    step = 2 * math.pi / N
    theta0 = theta_ext + math.copysign(past * step, rpm)     # the extreme is `past` samples back
    lk = LB.fourbar(CRANK, COUPLER, ROCKER, GROUND, theta0=math.degrees(theta0), rpm=rpm, samples=N)
    plan = compile_plan(lk)
    sol = plan.sweep(order=0)
    ref = plan.evaluate(np.array([theta_ext]), order=0)
    exact = float(ref.angle("rocker")[0])
    exact = exact + 2 * math.pi * round((float(sol.angle("rocker")[0]) - exact) / (2 * math.pi))
    y = sol.angle("rocker")
    assert np.argmin(y) in (0, N - 1) or np.argmax(y) in (0, N - 1)   # the bracket straddles t = 0
    (mo,) = [m for m in output_motions(lk, plan, sol) if m.link == "rocker"]
    got = mo.low if abs(mo.low - exact) < abs(mo.high - exact) else mo.high
    assert got == pytest.approx(exact, abs=1e-9)
