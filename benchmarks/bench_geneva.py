"""Geneva drive benchmark (a report, not a timed test).

Prints: the time of the whole contact-and-wear analysis (kinematics included) at 3,600 samples for
z = 4, 6, 8 (best of many runs, target ≤ 5 ms); the error of the per-engagement slip path L_s
(trapezoid on the samples with breaks) against the number of samples N, with the observed order,
for the default scene and for a load whose moment changes sign away from φ = 0; the time and
accuracy of the geometry (relief) and of the shapely sweep check. The reference L_s is a
Gauss–Legendre rule with 400 nodes on each smooth piece; a second Gauss rule (48 nodes, the one
the analysis reports) is shown beside it. With matplotlib installed, a PNG of the error curve is
written to benchmarks/out/.

Run: ``.venv/bin/python benchmarks/bench_geneva.py``
"""
from __future__ import annotations

import math
import time
from pathlib import Path

from mechsketch.core.analyses.geneva_clearance import check_clearances
from mechsketch.core.analyses.geneva_contact import contact
from mechsketch.core.analyses.geneva_contact import slip_path_gauss
from mechsketch.core.analyses.geneva_geometry import geometry as drive_geometry
from mechsketch.core.analyses.geneva_kinematics import kinematics
from mechsketch.core.model.geneva import ContactModel, Drawing, Geneva, Load

RPM10 = 300.0 / math.pi


def best_time(fn, repeat: int = 200) -> float:
    """Best wall time of ``fn()`` over ``repeat`` runs (s)."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def timing() -> None:
    print("contact + wear analysis at N = 3600 (kinematics included), best of 200 runs")
    print(f"{'z':>3} {'kinematics ms':>14} {'contact ms':>11} {'both ms':>8}  target <= 5 ms")
    for z in (4, 6, 8):
        el = Geneva("g", z, 100.0, 8.0, speed_rpm=RPM10)
        tk = best_time(lambda: kinematics(el, 3600))
        tc = best_time(lambda: contact(el, 3600, el.model))
        tb = best_time(lambda: (kinematics(el, 3600), contact(el, 3600, el.model)))
        print(f"{z:>3} {tk * 1e3:>14.3f} {tc * 1e3:>11.3f} {tb * 1e3:>8.3f}  {'ok' if tb <= 5e-3 else 'SLOW'}")


def convergence() -> list[tuple[str, list[int], list[float]]]:
    cases = [("z=6, default scene (breaks at 0)", Geneva("g", 6, 100.0, 8.0, speed_rpm=RPM10)),
             ("z=4, M_ext = 3 N·m (M changes sign at φ > 0)",
              Geneva("g", 4, 100.0, 8.0, speed_rpm=RPM10, load=Load(external_moment=3.0)))]
    ns = [90, 180, 360, 720, 1440, 3600, 7200, 14400, 36000]
    out = []
    for title, el in cases:
        model = ContactModel()
        ref = slip_path_gauss(el, model, 400)
        g48 = contact(el, 3600, model).slip_path_total
        print(f"\nL_s per engagement, {title}: reference {ref * 1e3:.12f} µm (Gauss 400/piece); "
              f"Gauss 48/piece differs by {abs(g48 - ref) / ref:.1e}")
        print(f"{'N':>7} {'L_s µm':>16} {'rel. error':>11} {'order':>6}")
        errs = []
        for n in ns:
            ls = contact(el, n, model).slip_path_total_trapezoid
            errs.append(abs(ls - ref) / ref)
            order = ""
            if len(errs) > 1 and errs[-1] > 0:
                order = f"{math.log(errs[-2] / errs[-1]) / math.log(n / ns[len(errs) - 2]):.2f}"
            print(f"{n:>7} {ls * 1e3:>16.12f} {errs[-1]:>11.2e} {order:>6}")
        out.append((title, ns, errs))
    return out


def geometry() -> None:
    print("\ngeometry: relief radius (exact search) and the independent shapely sweep (720 angles, tol 5e-4 mm)")
    print(f"{'z':>3} {'R_o':>9} {'relief':>10} {'touch':>10} {'build ms':>9} {'sweep s':>8} "
          f"{'roller gap':>11} {'disc gap':>9}")
    for z in (3, 4, 6, 8, 12):
        el = Geneva("g", z, 100.0, 8.0, drawing=Drawing(wheel_bore_radius=3.0))
        t0 = time.perf_counter()
        geo = drive_geometry(el)
        t1 = time.perf_counter()
        rep = check_clearances(geo, 720)
        t2 = time.perf_counter()
        r = geo.relief
        print(f"{z:>3} {r.classical:>9.4f} {r.exact:>10.5f} {r.touch:>10.5f} {(t1 - t0) * 1e3:>9.1f} "
              f"{t2 - t1:>8.2f} {rep.roller:>11.6f} {rep.disc:>9.6f}")


def plot(curves) -> None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("\n(matplotlib not installed: no plot)")
        return
    out = Path(__file__).parent / "out"
    out.mkdir(exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4))
    for title, ns, errs in curves:
        ax.loglog(ns, errs, "o-", label=title)
    ax.set_xlabel("samples per revolution N")
    ax.set_ylabel("relative error of L_s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "geneva_slip_path_error.png", dpi=120)
    print(f"\nplot: {out / 'geneva_slip_path_error.png'}")


if __name__ == "__main__":
    timing()
    curves = convergence()
    geometry()
    plot(curves)
