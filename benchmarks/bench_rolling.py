"""Rolling-lever synthesis: speed against error (a report, not a timed test).

    .venv/bin/python benchmarks/bench_rolling.py [--quick] [--out DIR]

Prints (and writes ``DIR/rolling.md``, default ``benchmarks/out``):

1. the exact synthesis of the notes' default scene (stroke θ 0 → −0.5926, N = 200): time (best and
   median of repeated runs, working range included), integration error estimate, error against an
   independent DOP853 solution, and the slip of the computed motion, with the issue's targets
   (slip ≤ 1e-9 mm, ≤ 20 ms) marked met or MISSED;
2. the exact method against its tolerance: adaptive steps, time, true error, slip; beside scipy's
   DOP853 (a generic integrator) on the same ODE;
3. the speed-against-error table of the paper's literal construction, the corrected construction
   and the exact method for N = 4 … 512 (the notes' measures; physical slip over θ ∈ [0, −0.3]
   as in the notes), with the notes' own values to compare;
4. ``DIR/rolling_error_vs_n.png`` when matplotlib is installed.
"""
from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "core"))

from mechsketch.core import load_scene  # noqa: E402
from mechsketch.core.analyses.rolling.exact import exact_path  # noqa: E402
from mechsketch.core.analyses.rolling.geometry import LeverGeometry, pose_state  # noqa: E402
from mechsketch.core.analyses.rolling.synthesis import error_table, synthesize  # noqa: E402
from mechsketch.resources import example_path  # noqa: E402

NOTES = {  # notes, section C, default scene: (literal slip, literal physical, corrected slip, corrected physical)
    4: (1.119, 0.126, 5.9e-2, 6.9e-2), 16: (1.018, 0.079, 3.7e-3, 6.8e-3),
    64: (1.011, 0.0731, 2.3e-4, 4.8e-4), 512: (1.0107, 0.0726, 3.6e-6, 5.9e-6)}


def _scipy_solution(geom, theta, rtol=1e-13):
    from scipy.integrate import solve_ivp

    def f(t, y):
        st = pose_state(geom, np.array([y[0]]), np.array([t]))
        return [st.rate[0], st.k53[0]]

    t0 = time.perf_counter()
    sol = solve_ivp(f, (0.0, float(theta[-1])), [geom.alpha0, 0.0], method="DOP853", rtol=rtol,
                    atol=rtol * 0.1, t_eval=theta)
    return sol.y[0], sol.y[1], time.perf_counter() - t0, sol.nfev


def _err_mm(geom, theta, a, s, a_ref, s_ref):
    p, r = pose_state(geom, a, theta), pose_state(geom, a_ref, theta)
    q = p.P0 - s[:, None] * np.asarray(geom.ds)
    qr = r.P0 - s_ref[:, None] * np.asarray(geom.ds)
    return float(max(np.abs(p.P - r.P).max(), np.abs(q - qr).max()))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions and N values")
    ap.add_argument("--out", default=str(HERE / "out"))
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    lines: list[str] = []

    def say(s=""):
        print(s)
        lines.append(s)

    el = load_scene(example_path("rolling_lever_press")).element("press")
    geom = LeverGeometry.from_element(el)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    say("# Rolling lever: speed against error")
    say()
    say(f"Default scene of the notes (section C), stroke θ 0 → {el.stroke.end} rad, N = {el.points}, "
        f"tolerance {el.tolerance:g} mm. Load average {load:.2f} on {os.cpu_count()} CPUs.")
    say()

    # 1. the exact synthesis against the targets
    reps = 10 if args.quick else 50
    for _ in range(3):
        synthesize(el, measures=False)  # warm up
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        res = synthesize(el, measures=False)
        times.append(time.perf_counter() - t0)
    full = synthesize(el)
    c = full.slip.continuous
    a_ref, s_ref, _, _ = _scipy_solution(geom, res.theta)
    true_err = _err_mm(geom, res.theta, res.alpha, res.S5, a_ref, s_ref)
    slip = max(c.worst, true_err)
    best, med = min(times) * 1e3, statistics.median(times) * 1e3
    say("## 1. Exact synthesis of the example stroke")
    say()
    say("| quantity | value |")
    say("|---|---|")
    say(f"| synthesis time, best / median of {reps} (ms) | {best:.2f} / {med:.2f} |")
    say(f"| adaptive RK4 steps, evaluations | {len(res.path.theta) - 1}, {res.path.evaluations} |")
    say(f"| integration error estimate (mm) | {res.error_mm:.2e} |")
    say(f"| error of P and Q against DOP853 at rtol 1e-13 (mm) | {true_err:.2e} |")
    say(f"| pair D slip of the computed motion (mm) | {c.slip_d:.2e} |")
    say(f"| pair E slip of the computed motion (mm) | {c.slip_e:.2e} |")
    say(f"| centrode lengths, frame / lever (mm) | {c.length_fixed:.10f} / {c.length_moving:.10f} |")
    say(f"| arc-length mismatch, pair D / pair E (mm) | {c.mismatch_d:.2e} / {c.mismatch_e:.2e} |")
    say(f"| S5 at the stroke end (mm) | {res.S5[-1]:.6f} |")
    say()
    say(f"Target slip ≤ 1e-9 mm: {'met' if slip <= 1e-9 else 'MISSED'} ({slip:.2e} mm, the worst of the slip "
        "figures and the true error). "
        f"Target ≤ 20 ms: {'met' if med <= 20 else 'MISSED'} (median {med:.2f} ms).")
    say()

    # 2. tolerance sweep and a generic integrator
    say("## 2. Exact method against its tolerance (N = 200 samples from the dense output)")
    say()
    say("| tolerance (mm) | steps | evaluations | time (ms) | true error (mm) | estimate (mm) | slip (mm) |")
    say("|---|---|---|---|---|---|---|")
    theta = res.theta
    for tol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-11):
        best_t = math.inf
        for _ in range(3 if args.quick else 10):
            t0 = time.perf_counter()
            path = exact_path(geom, 0.0, el.stroke.end, tol)
            a, s = path.at(theta)
            best_t = min(best_t, time.perf_counter() - t0)
        from mechsketch.core.analyses.rolling.slip import continuous_measures

        cm = continuous_measures(path, 0.0, el.stroke.end)
        say(f"| {tol:.0e} | {len(path.theta) - 1} | {path.evaluations} | {best_t * 1e3:.2f} | "
            f"{_err_mm(geom, theta, a, s, a_ref, s_ref):.1e} | {path.error_mm:.1e} | {cm.worst:.1e} |")
    say()
    say("Generic baseline, scipy `solve_ivp` DOP853 on the same ODE (numpy right-hand side):")
    say()
    say("| rtol | evaluations | time (ms) | error against rtol 1e-13 (mm) |")
    say("|---|---|---|---|")
    for rtol in (1e-6, 1e-9, 1e-12):
        a, s, t, nfev = _scipy_solution(geom, theta, rtol)
        say(f"| {rtol:.0e} | {nfev} | {t * 1e3:.1f} | {_err_mm(geom, theta, a, s, a_ref, s_ref):.1e} |")
    say()

    # 3. error against N for the three methods
    ns = (4, 16, 64, 512) if args.quick else (4, 8, 16, 32, 64, 128, 256, 512)
    rows = error_table(el, ns=ns, physical_range=(0.0, -0.3), repeat=3 if args.quick else 7)
    say("## 3. Speed against error, N = 4 … 512")
    say()
    say("Time is the synthesis alone (best of several runs; for the constructions without the exact motion "
        "that fixes the stroke's lever arc). Measures of the notes: arc-length mismatch of the polygon, "
        "kinematic slip of the lever material, IC offset from the rocker line, deviation from the exact "
        "centrode (a 1e-12 mm reference), physical slip of the mechanism run on a cubic spline through the "
        "points over θ ∈ [0, −0.3]; for the exact method also the slip of the computed continuous motion. "
        "In brackets: the notes' values.")
    say()
    say("| method | N | time (ms) | arc mismatch | kinematic slip | IC offset | deviation | physical slip | "
        "continuous slip |")
    say("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        note_slip = note_phys = ""
        if r.n in NOTES and r.method in ("paper", "corrected"):
            k = 0 if r.method == "paper" else 2
            note_slip = f" ({NOTES[r.n][k]:g})"
            note_phys = f" ({NOTES[r.n][k + 1]:g})"
        cont = "" if math.isnan(r.continuous_slip) else f"{r.continuous_slip:.1e}"
        say(f"| {r.method} | {r.n} | {r.time_s * 1e3:.2f} | {abs(r.arc_mismatch):.2e} | {r.kinematic_slip:.5g}{note_slip} | "
            f"{r.ic_offset:.3g} | {r.deviation:.3g} | {r.physical_slip:.3g}{note_phys} | {cont} |")
    say()
    lit = [r.kinematic_slip for r in rows if r.method == "paper"]
    say(f"The paper's construction levels off: its kinematic slip goes from {lit[0]:.4f} mm (N = {ns[0]}) to "
        f"{lit[-1]:.4f} mm (N = {ns[-1]}) and no number of points removes it (flaw C1: the rays G–π_k are drawn "
        "through the lever in position 1). The corrected construction and the exact profile's discrete measures "
        "fall as N⁻²; the exact method's curve itself is exact to its tolerance for every N.")
    (out / "rolling.md").write_text("\n".join(lines) + "\n", encoding="utf-8")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not installed: no plot)")
        return 0
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for m, style in (("paper", "o-"), ("corrected", "s-"), ("exact", "^-")):
        rr = [r for r in rows if r.method == m]
        ax[0].loglog([r.n for r in rr], [r.kinematic_slip for r in rr], style, label=f"{m}: kinematic slip")
        ax[1].loglog([r.time_s * 1e3 for r in rr], [max(r.deviation, 1e-13) for r in rr], style,
                     label=f"{m}: deviation")
    ax[0].set_xlabel("N")
    ax[0].set_ylabel("mm")
    ax[1].set_xlabel("synthesis time (ms)")
    ax[1].set_ylabel("deviation from the exact centrode (mm)")
    for a in ax:
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "rolling_error_vs_n.png", dpi=120)
    print(f"wrote {out / 'rolling.md'} and {out / 'rolling_error_vs_n.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
