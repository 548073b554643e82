"""Solution.residual (stacked and reduced once) against a plain pass per link and per joint written
here, bit for bit: every example linkage and test linkages with a moving guide, a P joint and a
32-dyad chain, over sweeps that assemble everywhere, that do not (NaN samples), and at NaN inputs."""
from __future__ import annotations

import glob
import math

import numpy as np
import pytest

import chains
import linkage_builders as LB
from mechsketch.core import load_scene
from mechsketch.core.model.linkage import JointKind, Linkage
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


def reference_residual(sol) -> float:
    """The greatest loop-closure gap, mm, one link and one joint at a time over the valid samples."""
    lk, n, valid = sol.plan.linkage, len(sol), np.asarray(sol.valid, dtype=bool)
    worst = 0.0
    for link_id, st in sol._states.items():
        drawn = [complex(*lk.joint(j).at) for j in lk.link(link_id).joints]
        reach = max([abs(p - st.a0) for p in drawn], default=0.0)
        # the same array operations for every sample (numpy's scalar |z| may round differently)
        drift = np.abs(np.abs(np.broadcast_to(st.rot, (n,))) - 1.0) * reach
        for i in np.flatnonzero(valid):
            if drift[i] == drift[i]:    # NaN samples do not count
                worst = max(worst, float(drift[i]))
    for j in lk.joints:
        carriers = [c for c in lk.links_of(j.id) if c in sol._states]
        if len(carriers) < 2:
            continue
        p0 = complex(*j.at)
        pts = [np.broadcast_to(sol._states[c].point(p0), (n,)) for c in carriers]
        for other in pts[1:] if j.kind is JointKind.R else pts[1:2]:
            if j.kind is JointKind.R:
                gap = np.abs(other - pts[0])
            else:
                a = math.radians(j.axis_deg or 0.0)
                u = np.broadcast_to(sol._states[carriers[0]].rot, (n,)) * complex(math.cos(a), math.sin(a))
                gap = np.abs((u.conjugate() * (other - pts[0])).imag)
            for i in np.flatnonzero(valid):
                if gap[i] == gap[i]:
                    worst = max(worst, float(gap[i]))
    return worst


def _linkages() -> list[Linkage]:
    out = []
    for f in sorted(glob.glob(str(example_path("double_rocker").parent / "*.json"))):
        out += [e for e in load_scene(f).elements if isinstance(e, Linkage)]
    return out + [LB.sixbar_guide(), LB.rrp_guide_on_coupler(), LB.eight_bar(), chains.dyad_chain(32)]


@pytest.mark.parametrize("lk", _linkages(), ids=lambda lk: lk.id)
def test_residual_equals_a_per_joint_pass(lk):
    plan = compile_plan(lk)
    sweep = plan.sweep(samples=360)
    assert sweep.residual() == reference_residual(sweep)
    assert sweep.residual() < 1e-6 * max(1.0, LB.size_of(lk))   # it closes
    # beyond the cycle's range and at NaN inputs: samples that do not assemble
    q = np.concatenate((np.linspace(-4 * math.pi, 4 * math.pi, 301) if not lk.driver.linear
                        else np.linspace(-1e3, 1e3, 301), [math.nan, math.nan]))
    wide = plan.evaluate(q, order=0)
    assert not wide.valid[-2:].any()
    assert wide.residual() == reference_residual(wide)
    assert wide.residual() is wide.residual()   # computed once per Solution
