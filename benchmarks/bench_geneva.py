"""Geneva drive benchmark (a report, not a timed test).

Prints: the time of the whole contact-and-wear analysis (kinematics included) at 3,600 samples for
z = 4, 6, 8 (best of many runs, target ≤ 5 ms); the error of the per-engagement slip path L_s
(trapezoid on the samples with breaks) against the number of samples N, with the observed order,
for the default scene and for a load whose moment changes sign away from φ = 0; the time and
accuracy of the geometry (relief) and of the shapely sweep check. The reference L_s is a
Gauss–Legendre rule with 400 nodes on each smooth piece; a second Gauss rule (48 nodes, the one
the analysis reports) is shown beside it. With matplotlib installed, a PNG of the error curve is
written to benchmarks/out/.

Then the relief search alone (issue 14): CPU time of the search now (only the segments that can
reach the disc, windows of both outlines in one call; geneva/relief.py) against the first version
(every segment, one candidate after another; tests/core/geneva_relief_reference.py), interleaved,
best of 15, for z = 3 … 24; the difference of the exact and touch radii from the first version's,
whether the drawn radius is the same, and the error of both against a dense reference (V on
20,001 angles, then golden-section search on the 5 best local maxima to 1e-15 rad).

Run: ``.venv/bin/python benchmarks/bench_geneva.py [--relief-only]``
"""
from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from mechsketch.core.analyses.geneva.clearance import check_clearances
from mechsketch.core.analyses.geneva.contact import contact
from mechsketch.core.analyses.geneva.contact import slip_path_gauss
from mechsketch.core.analyses.geneva.geometry import geometry as drive_geometry
from mechsketch.core.analyses.geneva.kinematics import kinematics
from mechsketch.core.analyses.geneva.geometry import relief, wheel_outline
from mechsketch.core.model.geneva import ContactModel, Drawing, Geneva, Load

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "core"))
from geneva_relief_reference import relief_old, relief_values_old  # noqa: E402

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


def dense_max(fun, lo: float, hi: float, n: int = 20001, keep: int = 5) -> float:
    """max of ``fun`` on [lo, hi]: a grid of n angles, then golden-section search on ±1 grid step
    around the ``keep`` best local maxima, to 1e-15 rad."""
    x = np.linspace(lo, hi, n)
    v = fun(x)
    v = np.where(np.isfinite(v), v, -np.inf)
    peak = np.r_[True, v[1:] >= v[:-1]] & np.r_[v[:-1] >= v[1:], True] & np.isfinite(v)
    best = -math.inf
    g = (math.sqrt(5.0) - 1.0) / 2.0
    for k in np.nonzero(peak)[0][np.argsort(v[peak])[::-1][:keep]]:
        a, b = max(lo, x[k] - (hi - lo) / (n - 1)), min(hi, x[k] + (hi - lo) / (n - 1))
        while b - a > 1e-15:
            c, d = b - g * (b - a), a + g * (b - a)
            fc, fd = fun(np.array([c, d]))
            if fc >= fd:
                b = d
            else:
                a = c
        best = max(best, v[k], float(fun(np.array([0.5 * (a + b)]))[0]))
    return best


def relief_search() -> None:
    print(f"\nrelief search alone (CPU ms, best of 15, interleaved; load {os.getloadavg()[0]:.2f}): now against "
          "the first version;\nrelative error of the exact (c_l = 0.1 mm) and touch radii against the first version "
          "and against the dense reference (exact = max(search, limit_end))")
    print(f"{'z':>3} {'r_p':>5} {'first ms':>9} {'now ms':>7} {'exact':>11} {'drawn same':>10} {'Δ first':>8} "
          f"{'Δtouch first':>12} {'first-dense':>11} {'now-dense':>9} {'touch now-dense':>15}")
    for z, rp in ((3, 8.0), (4, 8.0), (6, 8.0), (8, 8.0), (12, 2.0), (24, 1.0)):
        d = Geneva("g", z, 100.0, rp).dimensions()
        t_old = t_new = math.inf
        for _ in range(15):
            t0 = time.thread_time()
            old = relief_old(d, 0.1)
            t1 = time.thread_time()
            new = relief(d, 0.1)
            t2 = time.thread_time()
            t_old, t_new = min(t_old, t1 - t0), min(t_new, t2 - t1)
        off = wheel_outline(d).offset(0.1)
        ref = max(dense_max(lambda p: relief_values_old(p, off, d), -d.phi0, d.phi0), old.limit_end)
        outline = wheel_outline(d)
        ref_t = dense_max(lambda p: relief_values_old(p, outline, d), -d.phi0, d.phi0)
        print(f"{z:>3} {rp:>5.1f} {t_old * 1e3:>9.2f} {t_new * 1e3:>7.2f} {new.exact:>11.6f} "
              f"{str(new.drawn == old.drawn):>10} {abs(new.exact - old.exact) / old.exact:>8.1e} "
              f"{abs(new.touch - old.touch) / old.touch:>12.1e} {(old.exact - ref) / ref:>11.1e} "
              f"{(new.exact - ref) / ref:>9.1e} {(new.touch - ref_t) / ref_t:>15.1e}")


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
    if "--relief-only" in sys.argv:
        relief_search()
        sys.exit()
    timing()
    curves = convergence()
    geometry()
    relief_search()
    plot(curves)
