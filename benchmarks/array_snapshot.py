"""Every array of every linkage example, for checking that a change keeps results bit for bit.

    python benchmarks/array_snapshot.py save OUT.npz        # this checkout's arrays
    python benchmarks/array_snapshot.py compare A.npz B.npz  # which arrays differ, and by how much

For every linkage of ``resources/examples`` (and of the scenes given with ``--scene``), at
N = 8, 360 and 3,600 samples and orders 0, 1, 2: every joint's position, velocity and
acceleration, every moving link's angle, ω and α, ``valid`` and ``rates_valid``, every group's
conditioning; at order 2 with masses or loads, every force column (``force_columns``) and every
slide's normal force and moment. Arrays are compared with NaN equal to NaN; ``compare`` prints
each differing array with its largest relative difference and exits 1 if any differs.
"""
from __future__ import annotations

import argparse
import glob
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def collect(scenes: list[str]) -> dict[str, np.ndarray]:
    from mechsketch.core import Workspace
    from mechsketch.core.analyses.forces.kinetostatics import linkage_forces
    from mechsketch.core.analyses.forces.report import force_columns
    from mechsketch.core.model.linkage import Linkage

    out: dict[str, np.ndarray] = {}
    for path in scenes:
        ws = Workspace.open(path)
        name = os.path.splitext(os.path.basename(path))[0]
        for el in ws.scene.elements:
            if not isinstance(el, Linkage):
                continue
            plan = ws.plan(el.id)
            for n in (8, 360, 3600):
                for order in (0, 1, 2):
                    sol = plan.sweep(n, order=order)
                    key = f"{name}/{el.id}/{n}/{order}"
                    for j in el.joint_ids:
                        out[f"{key}/{j}.p"] = sol.position(j)
                        if order >= 1:
                            out[f"{key}/{j}.v"] = sol.velocity(j)
                        if order >= 2:
                            out[f"{key}/{j}.a"] = sol.acceleration(j)
                    for k in el.moving_links:
                        out[f"{key}/{k}.angle"] = sol.angle(k)
                        if order >= 1:
                            out[f"{key}/{k}.omega"] = sol.omega(k)
                        if order >= 2:
                            out[f"{key}/{k}.alpha"] = sol.alpha(k)
                    out[f"{key}/valid"] = sol.valid
                    out[f"{key}/rates_valid"] = sol.rates_valid
                    for g in sol.groups:
                        out[f"{key}/{g.name}.cond"] = np.broadcast_to(sol.conditioning(g.name), (n,)).copy()
                    if order == 2 and el.has_dynamics:
                        res = linkage_forces(plan, sol)
                        for c, v in force_columns(res).items():
                            out[f"{key}/F/{c}"] = v
                        for jid, s in res.slides.items():
                            out[f"{key}/F/{jid}.normal"] = s.normal
                            out[f"{key}/F/{jid}.moment"] = s.moment
    return out


def compare(a: dict, b: dict) -> int:
    bad = 0
    for k in sorted(set(a) | set(b)):
        if k not in a or k not in b:
            print(f"only in {'second' if k not in a else 'first'}: {k}")
            bad += 1
            continue
        x, y = a[k], b[k]
        if x.shape != y.shape or not np.array_equal(x, y, equal_nan=True):
            with np.errstate(invalid="ignore", divide="ignore"):
                d = np.nanmax(np.abs(x.astype(float) - y.astype(float))) if x.shape == y.shape else np.nan
                s = np.nanmax(np.abs(y.astype(float))) if y.size else 0.0
            print(f"differs: {k}  max |diff| {d:.3g} (relative {d / s if s else d:.3g})")
            bad += 1
    print(f"{len(set(a) | set(b))} arrays, {bad} differ")
    return 1 if bad else 0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("save")
    s.add_argument("out")
    s.add_argument("--scene", action="append", default=[])
    c = sub.add_parser("compare")
    c.add_argument("a")
    c.add_argument("b")
    args = p.parse_args()
    if args.cmd == "save":
        scenes = sorted(glob.glob(os.path.join(ROOT, "resources", "examples", "*.json"))) + args.scene
        np.savez_compressed(args.out, **collect(scenes))
        return 0
    return compare(dict(np.load(args.a)), dict(np.load(args.b)))


if __name__ == "__main__":
    sys.exit(main())
