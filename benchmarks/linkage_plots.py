"""The figures of the linkage benchmark: time per sample against error (mechsketch, Newton,
pylinkage) and the error at the toggle against the gap δ (needs matplotlib, the 'bench' extra).
"""
from __future__ import annotations

from pathlib import Path


def plot(rows, py_rows, scan, out_dir: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    markers = {"four-bar": "o", "slider-crank (offset)": "s", "six-bar (moving guide)": "^",
               "near-change-point four-bar": "D"}
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharex=True)
    for ax, order in zip(axes, (0, 2)):
        for mech, mk in markers.items():
            sel = [r for r in rows if r.mech == mech and r.order == order]
            if not sel:
                continue
            e_ms = [r.ms_err.pos if order == 0 else max(r.ms_err.pos, r.ms_err.vel, r.ms_err.acc) for r in sel]
            e_nt = [r.nt.err.pos if order == 0 else max(r.nt.err.pos, r.nt.err.vel, r.nt.err.acc) for r in sel]
            ax.plot([r.ms_us for r in sel], e_ms, mk + "-", color="C0", label=f"mechsketch: {mech}")
            ax.plot([r.nt.us for r in sel], e_nt, mk + "--", color="C3", mfc="none",
                    label=f"Newton: {mech}")
            for r, e in zip(sel, e_ms):
                ax.annotate(f"{r.N:,}", (r.ms_us, e), fontsize=6, xytext=(3, 3), textcoords="offset points")
        if py_rows:
            sel = [p for p in py_rows if p[1] == order]
            e = [p[3].pos if order == 0 else max(p[3].pos, p[3].vel, p[3].acc) for p in sel]
            ax.plot([p[2] for p in sel], e, "x:", color="C2", label="pylinkage: four-bar")
        ax.axhline(1e-13 if order == 0 else 1e-12, color="grey", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("µs per sample (log)")
        ax.set_ylabel("max position error / size" if order == 0 else
                      "max of position/size, velocity and acceleration relative errors")
        ax.set_title("positions only" if order == 0 else "with velocities and accelerations")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=6, loc="best")
    fig.suptitle("Linkage solving: time per sample against error (50-digit reference); "
                 "labels: N; dotted: error targets")
    fig.tight_layout()
    fig.savefig(out_dir / "linkage_speed_error.png", dpi=130)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    d = [s["delta_rel"] for s in scan]
    for w, (lab, c) in enumerate((("position / size", "C0"), ("velocity rel.", "C1"), ("acceleration rel.", "C2"))):
        ax.plot(d, [s["ms"][w] for s in scan], "o-", color=c, label=f"mechsketch {lab}")
        ax.plot(d, [s["nt"][w] for s in scan], "s--", color=c, mfc="none", label=f"Newton {lab}")
    ax.plot(d, [s["cond"] for s in scan], "k:", label="sin μ at toggle")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("δ / size (gap to the change point)")
    ax.set_ylabel("error at the sample nearest the toggle")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Near-change-point four-bar, N = 3,600")
    fig.tight_layout()
    fig.savefig(out_dir / "linkage_near_toggle.png", dpi=130)
    plt.close(fig)
