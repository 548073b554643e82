"""Batch kinetostatics (core/studies/bforces.py) against the one-design path, design by design.

Each design — its geometry and its masses and loads changed by variables — is solved by
``linkage_forces`` of its own plan, and the batch's driving effort, pin forces, shaking force and
moment must agree to 1e-12 of their size (every group kind, moving guides, a compound hinge, a
slider driven along its guide, cylinders (the rod of an RRP group, the bar of an RRR group, an axis off
the pivots), gravity, point forces, torques, springs, dampers).
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import drive_builders as DB
from mechsketch.core.analyses.forces.kinetostatics import linkage_forces
from mechsketch.core.model.loads import Damper, PointForce, Spring, Torque
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.studies.geometry import build_geometry, design_linkage
from mechsketch.core.studies.keys import variables
from mechsketch.core.studies.variants import solve_variants
from mechsketch.core.workspace import Workspace
from test_forces import KINDS, loaded


def with_values(lk, vals: dict, d: int):
    """The one-design record of design ``d``: masses and loads set from the variables."""
    masses = {m.link: m for m in lk.masses}
    for key, v in vals.items():
        parts, x = key.split(":"), float(v[d])
        if parts[0] in ("mass", "inertia", "com"):
            m = masses[parts[1]]
            if parts[0] == "mass":
                m = replace(m, mass=x)
            elif parts[0] == "inertia":
                m = replace(m, inertia=x)
            else:   # an unset centre of mass is the centroid of the link's joints (drawn)
                pts = [lk.joint(j).at for j in lk.link(parts[1]).joints]
                com = list(m.com) if m.com is not None else [sum(p[0] for p in pts) / len(pts),
                                                             sum(p[1] for p in pts) / len(pts)]
                com["xy".index(parts[2])] = x
                m = replace(m, com=tuple(com))
            masses[parts[1]] = m
    loads = []
    for ld in lk.loads:
        get = lambda name, old: float(vals[f"load:{ld.id}:{name}"][d]) if f"load:{ld.id}:{name}" in vals else old  # noqa: E731
        if isinstance(ld, PointForce):
            ld = replace(ld, force=(get("fx", ld.force[0]), get("fy", ld.force[1])))
        elif isinstance(ld, Torque):
            ld = replace(ld, torque=get("torque", ld.torque))
        elif isinstance(ld, Spring):
            ld = replace(ld, stiffness=get("stiffness", ld.stiffness), free_length=get("free_length", ld.rest_length))
        elif isinstance(ld, Damper):
            ld = replace(ld, damping=get("damping", ld.damping))
        loads.append(ld)
    return replace(lk, masses=tuple(masses[m.link] for m in lk.masses), loads=tuple(loads))


CASES = [loaded(b) for b in KINDS] + [loaded(DB.pushed_crank()),
                                     Workspace.open("resources/examples/fourbar_loaded.json").element("loaded_fourbar"),
                                     loaded(DB.cylinder_slider()), loaded(DB.excavator(axis_off=12.0)),
                                     loaded(Workspace.open("resources/examples/excavator_arm.json").element("arm"))]


@pytest.mark.parametrize("lk", CASES, ids=lambda lk: lk.id)
def test_batch_forces_match_the_one_design_kinetostatics(lk):
    rng = np.random.default_rng(len(lk.id))
    V = variables(lk)
    geo_keys = [v for v in V.values() if v.kind == "dimension"]
    dyn_keys = [v for v in V.values() if v.kind in ("mass", "inertia", "com", "load")]
    pick = [geo_keys[i] for i in rng.choice(len(geo_keys), 2, replace=False)] + \
           [dyn_keys[i] for i in rng.choice(len(dyn_keys), 3, replace=False)]
    D = 3
    vals = {v.key: v.nominal + rng.normal(size=D) * (0.01 * abs(v.nominal) + 0.01) for v in pick}
    for v in pick:
        if v.kind in ("mass", "inertia"):
            vals[v.key] = np.abs(vals[v.key])
    b = solve_variants(lk, vals, samples=48, order=2, fast=False)
    bf = b.forces()
    assert b.assembled.any()
    for d in range(D):
        if not b.assembled[d]:   # an edit that cannot close a link's shape (named by b.message): no forces
            assert b.message(d) and not bf.valid[d].any() and np.isnan(bf.effort[d]).all()
            continue
        geo = build_geometry(lk, b.plan.plan, {k: v[d:d + 1] for k, v in vals.items()}, 1)
        one = with_values(design_linkage(geo, 0), vals, d)
        plan = compile_plan(one)
        sol = plan.sweep(48, 2)
        ref = linkage_forces(plan, sol)
        ok = ref.valid & (np.min([np.abs(c) for c in ref.conditioning.values()], axis=0) > 1e-3)
        assert np.array_equal(ref.valid, bf.valid[d])
        assert ok.sum() >= 10

        def close(got, want, what):
            scale = float(np.nanmax(np.abs(want[ok]))) + 1e-12
            err = float(np.max(np.abs(got[ok] - want[ok]))) / scale
            assert err < 1e-12, (lk.id, d, what, err)

        close(bf.effort[d], ref.driver.values, "effort")
        close(bf.shaking_force[d], ref.shaking_force, "shaking force")
        close(bf.shaking_moment[d], ref.shaking_moment, "shaking moment")
        for j, on in ref.pins.items():
            for link, f in on.items():
                close(bf.pins[j][link][d], f, f"pin {j} on {link}")
        assert bf.peak_effort[d] == pytest.approx(np.nanmax(np.abs(ref.driver.values[ref.valid])), rel=1e-12)
