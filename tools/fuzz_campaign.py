"""A seeded fuzz campaign over the command line (issue 20, "Done when"): mutated scenes through
every command, and every table a command writes checked for what must never happen.

    python tools/fuzz_campaign.py --inputs 10000 --seed 2026 --jobs 2 --out fuzz_report.json

Each input is an example scene mutated by one of: ``geometry`` (every coordinate jittered by a
relative noise of 0.1 % to 30 % of the mechanism's size: new linkages, many near toggles and
limits), ``degenerate`` (a joint moved onto another, a guide turned parallel to another, a
Grashof equality, a stroke end on a limit), ``extreme`` (a number replaced by an extreme or a
wrong type, as tests/core/test_fuzz_inputs.py does, with new seeds), or ``parameters`` (samples,
speeds, laws, slot counts, materials). The scene goes through ``validate``, ``analyze --csv`` (with
``--forces`` for a linkage with loads), ``synthesize`` for a rolling lever, and ``export`` for one
input in ten. Findings:

- ``traceback``: anything but exit 0/1 with a message (an uncaught exception);
- ``hang``: a command over its time limit (30 s);
- ``crash``: a worker process that died (a signal);
- ``invalid-row``: a row flagged valid with an empty or non-finite value, a revolute pair of one
  link whose distance differs from the drawn one by more than 1e-6 of the size (an unassembled
  pose flagged valid), two consecutive rows with valid rates whose step goes against their
  velocities with no dead point reported between them (a singular pose passed between samples
  unnoticed: a second method on the rates), a force in a row whose rates are not valid, or a length, path,
  width, deformation, pressure or wear that is negative.

Workers are subprocesses of ``chunk`` inputs each, so a crash loses one chunk and is reported.
"""
from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

if "--worker" in sys.argv:   # one BLAS thread, as the CLI sets it, before numpy loads
    for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

EXAMPLES_DIR = Path(__file__).resolve().parents[1] / "resources" / "examples"
CASES_DIR = Path(__file__).resolve().parents[2] / "shared" / "cases" / "s3"
TIME_LIMIT = 30        # CPU seconds per command before it counts as a hang
WALL_LIMIT = 600       # wall seconds (a blocked read uses no CPU)
FLOATS = [0.0, -0.0, 5e-324, -5e-324, 1e-300, -1e-9, 1e-7, 1.0, -1.0, 1e9, 1e9 + 0.5, 1e10, 1e300,
          1.7976931348623157e308, math.nan, math.inf, -math.inf]
INTS = [0, 1, 2, 3, 4, 12, 16, -1, 360, 361, 100_000, 1_000_000, 10 ** 400]
WRONG = [None, True, "text", [], {}, [1.0], {"a": 1}]
#: columns that are lengths, paths, widths, pressures or wear: never negative where present
NON_NEGATIVE = ("strip_width", "hertz_half_width", "deformation", "slip_path", "wear_invariant",
                "contact_pressure")


class Hang(Exception):
    pass


def _docs() -> dict[str, dict]:
    docs = {p.stem: json.loads(p.read_text()) for p in sorted(EXAMPLES_DIR.glob("*.json"))}
    if CASES_DIR.is_dir():
        docs.update({f"s3_{p.stem}": json.loads(p.read_text()) for p in sorted(CASES_DIR.glob("*.json"))})
    return docs


def _size(el: dict) -> float:
    pts = [j["at"] for j in el.get("joints", []) if isinstance(j, dict) and "at" in j]
    if not pts:
        return float(el.get("center_distance", 100.0) or 100.0)
    a = np.asarray(pts, dtype=float)
    return float(max(np.ptp(a[:, 0]), np.ptp(a[:, 1]), 1.0))


def _numbers(node: Any, path: tuple = ()) -> list[tuple[tuple, Any]]:
    out = []
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for k, v in items:
        out.append((path + (k,), v))
        out.extend(_numbers(v, path + (k,)))
    return out


def _set(doc: Any, path: tuple, value: Any) -> None:
    node = doc
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = json.loads(json.dumps(value, allow_nan=True))


def mutate(doc: dict, rng: np.random.Generator) -> tuple[str, dict]:
    """(strategy, a mutated deep copy of ``doc``)."""
    doc = json.loads(json.dumps(doc))
    el = doc["elements"][0]
    kind = str(rng.choice(["geometry", "geometry", "degenerate", "extreme", "parameters"]))
    size = _size(el)
    if kind == "geometry":
        sigma = float(rng.choice([1e-3, 1e-2, 0.05, 0.1, 0.3])) * size
        for path, v in _numbers(el):
            if isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) for x in v) \
                    and path[-1] in ("at", "center", "pin", "rocker_pivot", "crank_pivot", "coupler_point",
                                     "crank_center", "com"):
                _set(el, path, [float(v[0] + rng.normal(0, sigma)), float(v[1] + rng.normal(0, sigma))])
        for key in ("center_distance", "roller_radius", "roller_length"):
            if isinstance(el.get(key), (int, float)):
                el[key] = float(el[key] * math.exp(rng.normal(0, 0.2)))
    elif kind == "degenerate":
        joints = [j for j in el.get("joints", []) if isinstance(j, dict) and "at" in j]
        op = int(rng.integers(0, 4))
        if joints and op == 0 and len(joints) > 1:
            a, b = rng.choice(len(joints), 2, replace=False)
            joints[a]["at"] = list(joints[b]["at"])
        elif op == 1:
            ps = [j for j in joints if j.get("kind") == "P"]
            if len(ps) > 1:
                ps[1]["axis_deg"] = ps[0]["axis_deg"] + float(rng.choice([0.0, 180.0, 1e-9, 90.0]))
            elif ps:
                ps[0]["axis_deg"] = float(rng.choice([0.0, 90.0, 180.0, 45.0]))
        elif op == 2 and len(joints) > 2:
            a, b = rng.choice(len(joints), 2, replace=False)
            t = float(rng.choice([0.5, 1.0, 1e-9, 1 - 1e-12]))
            pa, pb = np.asarray(joints[a]["at"], float), np.asarray(joints[b]["at"], float)
            joints[a]["at"] = list(map(float, pa + t * (pb - pa) * 0.999999))
        elif "slots" in el:
            el["slots"] = int(rng.choice([3, 4, 12, 16, 24]))
        elif isinstance(el.get("driver"), dict) and "stroke" in el["driver"]:
            s = el["driver"]["stroke"]
            el["driver"]["stroke"] = [s[0], s[0] + (s[1] - s[0]) * float(rng.choice([1e-9, 2.0, 10.0]))]
    elif kind == "extreme":
        leaves = _numbers(el, ("elements", 0))
        path, v = leaves[int(rng.integers(0, len(leaves)))]
        if isinstance(v, bool) or v is None:
            new = WRONG[int(rng.integers(0, len(WRONG)))]
        elif isinstance(v, int):
            new = (INTS + FLOATS)[int(rng.integers(0, len(INTS) + len(FLOATS)))]
        elif isinstance(v, float):
            new = FLOATS[int(rng.integers(0, len(FLOATS)))]
        else:
            new = WRONG[int(rng.integers(0, len(WRONG)))]
        _set(doc, path, new)
    else:
        if "samples" in el:
            el["samples"] = int(rng.choice([2, 3, 7, 36, 360, 3600, 36000]))
        drv = el.get("driver")
        if isinstance(drv, dict):
            drv["speed_rpm"] = float(rng.choice([-1e5, -60, -0.001, 0.001, 1, 60, 1e5]))
            drv["law"] = {"kind": str(rng.choice(["constant", "cycloidal", "harmonic", "modified_trapezoid"]))}
        if "slots" in el:
            el["slots"] = int(rng.integers(3, 25))
        if isinstance(el.get("material"), dict):
            for part in el["material"].values():
                if isinstance(part, dict):
                    part["E"] = float(rng.choice([0.001, 1, 100, 210000, 1e7]))
    return kind, doc


def _run(main, argv: list[str]) -> tuple[int, str]:
    out, err = io.StringIO(), io.StringIO()
    signal.setitimer(signal.ITIMER_PROF, TIME_LIMIT)   # CPU seconds: a loaded machine is no hang
    signal.alarm(WALL_LIMIT)                           # and a blocked read (no CPU) still is one
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
    finally:
        signal.alarm(0)
        signal.setitimer(signal.ITIMER_PROF, 0)
    return code, out.getvalue() + err.getvalue()


def _float(s: str) -> float | None:
    if s == "":
        return None
    try:
        return float(s)
    except ValueError:
        return None


def check_linkage_csv(path: Path, el: dict, dead: list[float] = ()) -> list[str]:
    """What must never be in a linkage table (see the module docstring)."""
    rows = list(csv.DictReader(path.open(newline="")))
    if not rows:
        return []
    bad: list[str] = []
    cols = list(rows[0])
    joints = {j["id"]: j for j in el.get("joints", []) if isinstance(j, dict)}
    size = _size(el)
    pairs = []
    for link in el.get("links", []):
        rs = [j for j in link.get("joints", []) if joints.get(j, {}).get("kind") == "R"]
        for a, b in zip(rs, rs[1:]):
            d0 = math.dist(joints[a]["at"], joints[b]["at"])
            pairs.append((a, b, d0))
    pos = [c for c in cols if c.endswith((".x", ".y", ".angle"))]
    rates = [c for c in cols if c.endswith((".vx", ".vy", ".ax", ".ay", ".omega", ".alpha"))]
    known = set(pos) | set(rates) | {"t", "input", "valid", "rates_valid"}
    forces = [c for c in cols if c not in known and not c.endswith(("_valid", "_error", ".error"))]
    for k, r in enumerate(rows):
        valid, rv = r.get("valid") == "1", r.get("rates_valid") == "1"
        if valid:
            for c in pos:
                v = _float(r[c])
                if v is None or not math.isfinite(v):
                    bad.append(f"row {k}: valid but {c} = {r[c]!r}")
                    break
            for a, b, d0 in pairs:
                try:
                    d = math.hypot(float(r[f"{a}.x"]) - float(r[f"{b}.x"]), float(r[f"{a}.y"]) - float(r[f"{b}.y"]))
                except (KeyError, ValueError):
                    continue
                if not abs(d - d0) <= 1e-6 * max(size, d0, 1.0):
                    bad.append(f"row {k}: valid but |{a}{b}| = {d!r} against the drawn {d0!r}")
                    break
        if valid and rv:
            for c in rates:
                v = _float(r[c])
                if v is None or not math.isfinite(v):
                    bad.append(f"row {k}: rates_valid but {c} = {r[c]!r}")
                    break
        if not (valid and rv):
            filled = [c for c in forces if r.get(c, "") not in ("", None)]
            if filled:
                bad.append(f"row {k}: rates not valid but forces given ({filled[0]} = {r[filled[0]]})")
        if len(bad) > 5:
            break
    drv = el.get("driver") if isinstance(el.get("driver"), dict) else {}
    return bad + check_continuity(rows, cols, size, dead, drv.get("kind", "crank") == "crank")


def dead_points(summary: str) -> list[float]:
    """The inputs of the dead points a linkage summary reports (rad for a crank, mm else)."""
    out = []
    for m in re.finditer(r"^dead point: (-?[0-9.]+)(°| mm)", summary, re.M):
        v = float(m.group(1))
        out.append(math.radians(v) if m.group(2) == "°" else v)
    return out


def _between(a: float, b: float, x: float, crank: bool) -> bool:
    if crank:   # the table's input is unwrapped; the summary's dead points are not
        lo, hi = min(a, b), max(a, b)
        k = math.floor((lo - x) / (2 * math.pi))
        return any(lo <= x + 2 * math.pi * j <= hi for j in range(k, k + 3))
    return min(a, b) <= x <= max(a, b)


def check_continuity(rows: list[dict], cols: list[str], size: float, dead: list[float] = (),
                     crank: bool = True) -> list[str]:
    """A second method on the rates: between two consecutive rows with valid rates, the change of
    every coordinate must go the way the trapezoid of its velocities says. A singular pose passed
    between two samples that the summary does not report (a guide turning parallel: the blocks
    come back from the other side of infinity) shows as a step against the velocities, while each
    row alone looks assembled. Only the direction is judged: near an assembly limit or a pole the
    velocity grows without bound and the trapezoid's size is legitimately off. Tables of fewer
    than 180 rows are skipped."""
    if len(rows) < 180 or "t" not in cols:
        return []
    joints = [c[:-2] for c in cols if c.endswith(".x") and f"{c[:-2]}.vx" in cols]
    for k in range(len(rows) - 1):
        a, b = rows[k], rows[k + 1]
        if not (a.get("rates_valid") == b.get("rates_valid") == "1"):
            continue
        dt = float(b["t"]) - float(a["t"])
        lo, hi = sorted((float(a["input"]), float(b["input"])))
        step = hi - lo   # a reported dead point between these rows or within a step of them: near an
        if not dt > 0 or any(_between(lo - step, hi + step, x, crank) for x in dead):   # assembly limit
            continue     # the motion goes as the root of the distance to it, far under-sampled
        for j in joints:
            for ax in ("x", "y"):
                dx = float(b[f"{j}.{ax}"]) - float(a[f"{j}.{ax}"])
                trap = 0.5 * dt * (float(a[f"{j}.v{ax}"]) + float(b[f"{j}.v{ax}"]))
                if dx * trap < 0 and min(abs(dx), abs(trap)) > 1e-2 * size:
                    return [f"rows {k}-{k + 1}: {j}.{ax} moves {dx:.6g} mm, its velocities say {trap:.6g} mm"]
    return []


def check_any_csv(path: Path) -> list[str]:
    rows = list(csv.DictReader(path.open(newline="")))
    bad = []
    for k, r in enumerate(rows):
        for c, s in r.items():
            v = _float(s or "")
            if s and v is None and c not in ("engaged",):
                continue
            if v is not None and not math.isfinite(v):
                bad.append(f"row {k}: {c} = {s!r}")
            if v is not None and v < 0 and c in NON_NEGATIVE:
                bad.append(f"row {k}: {c} = {s} is negative")
        if len(bad) > 5:
            break
    return bad


def _finer(main, argv: list[str], table: Path, el: dict) -> list[str]:
    """A step against the velocities, judged again at 36,000 samples: a motion that turns a link
    by most of a turn between two samples (a crank pin passing a hair from a guide's pivot) is
    under-sampled, not wrong, and the finer table connects its rows; an unreported singular pose
    stays a step however fine the samples."""
    fine = table.parent / "fine" / "fine.csv"   # not beside the tables being walked
    fine.parent.mkdir(exist_ok=True)
    run = [a for a in argv if a != "--summary"]
    run[run.index("--csv") + 1] = str(fine)
    try:
        code, text_out = _run(main, run + ["--samples", "36000", "--summary"])
    except Hang:
        return [f"{table.name}: step against the velocities; the 36,000-sample check hung"]
    if code != 0:
        return [f"{table.name}: step against the velocities; at 36,000 samples exit {code}: {text_out[-200:]}"]
    try:
        return check_linkage_csv(fine, dict(el, samples=36000), dead_points(text_out))
    finally:
        fine.unlink(missing_ok=True)


def _list(value: Any) -> list:
    return value if isinstance(value, list) else []


def one_input(main, name: str, doc: dict, rng: np.random.Generator, folder: Path,
              keep: str | None = None) -> tuple[str, list[dict]]:
    kind, doc = mutate(doc, rng)
    text = json.dumps(doc, allow_nan=True)
    scene = folder / "scene.json"
    scene.write_text(text)
    inflight = Path(keep) / f"inflight.{os.getpid()}.{name}.json" if keep else None
    if inflight is not None:   # stays behind if the worker dies on this input (a crash's repro)
        inflight.write_text(text)
    el = doc["elements"][0] if isinstance(doc.get("elements"), list) and doc["elements"] else {}
    typ = el.get("type") if isinstance(el, dict) else None
    cmds = [["validate", str(scene)], ["analyze", str(scene), "--csv", str(folder / "a.csv"), "--summary"]]
    if typ == "linkage" and (el.get("loads") or any(isinstance(lk, dict) and "mass" in lk for lk in _list(el.get("links")))):
        cmds.append(["analyze", str(scene), "--forces", "--csv", str(folder / "f.csv"), "--summary"])
    if typ == "rolling_lever":
        cmds.append(["synthesize", str(scene), "--csv", str(folder / "s.csv"), "--summary"])
    if rng.random() < 0.1:
        cmds.append(["export", str(scene), "--dxf", str(folder / "e.dxf")])
    findings = []
    for argv in cmds:
        for f in folder.glob("*.csv"):
            f.unlink()
        try:
            code, text_out = _run(main, argv)
        except Hang:
            findings.append({"kind": "hang", "argv": argv[0]})
            continue
        except BaseException as exc:   # the finding itself: anything escaping the CLI
            findings.append({"kind": "traceback", "argv": argv[0], "error": f"{type(exc).__name__}: {exc}"[:300]})
            continue
        if code not in (0, 1) or (code == 1 and not text_out.strip()) or "Traceback" in text_out:
            findings.append({"kind": "traceback", "argv": argv[0], "error": text_out[-300:]})
        if code != 0:
            continue
        dead = dead_points(text_out)
        for f in folder.glob("*.csv"):
            bad = check_linkage_csv(f, el, dead) if typ == "linkage" else check_any_csv(f)
            if bad and typ == "linkage" and all("its velocities say" in b for b in bad):
                bad = _finer(main, argv, f, el)
            if bad:
                findings.append({"kind": "invalid-row", "argv": " ".join(argv[:1] + argv[2:3]), "rows": bad[:3]})
    if inflight is not None:
        inflight.unlink()
    for fd in findings:
        fd.update(example=name, strategy=kind)
    if findings:
        (folder / f"{name}.{rng.integers(1 << 30)}.json").write_text(text)
    return kind, findings


def worker(seed: int, count: int, keep: str) -> None:
    """Run ``count`` inputs from ``seed``; print one JSON line per input."""
    os.environ.setdefault("MECHSKETCH_MEMORY_MB", "400")

    def on_alarm(*_):
        raise Hang()

    signal.signal(signal.SIGALRM, on_alarm)
    signal.signal(signal.SIGPROF, on_alarm)
    from mechsketch.core.cli import main

    docs = _docs()
    names = sorted(docs)
    rng = np.random.default_rng(seed)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for _ in range(count):
            name = names[int(rng.integers(0, len(names)))]
            t0 = time.perf_counter()
            kind, findings = one_input(main, name, docs[name], rng, folder, keep)
            for kept in folder.glob(f"{name}.*.json"):
                kept.replace(Path(keep) / kept.name)
            line = json.dumps({"example": name, "strategy": kind, "seconds": time.perf_counter() - t0,
                               "findings": findings})
            print(line, flush=True)
            if findings:   # seen at once, not only when the chunk ends
                with open(Path(keep) / f"findings.{os.getpid()}.jsonl", "a") as log:
                    log.write(line + "\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--inputs", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--chunk", type=int, default=250)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default="fuzz_report.json")
    ap.add_argument("--keep", default="fuzz_findings", help="folder for the scenes with findings")
    ap.add_argument("--worker", nargs=2, type=int, metavar=("SEED", "COUNT"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    Path(args.keep).mkdir(exist_ok=True)
    if args.worker:
        worker(args.worker[0], args.worker[1], args.keep)
        return 0
    chunks = [(args.seed * 100_003 + k, min(args.chunk, args.inputs - k * args.chunk))
              for k in range((args.inputs + args.chunk - 1) // args.chunk)]
    done, findings, crashes, strategies = 0, [], [], {}
    t0 = time.time()
    running: list[tuple[subprocess.Popen, tuple[int, int]]] = []
    while chunks or running:
        while chunks and len(running) < args.jobs:
            seed, count = chunks.pop(0)
            env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
            p = subprocess.Popen([sys.executable, __file__, "--worker", str(seed), str(count), "--keep", args.keep],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
            running.append((p, (seed, count)))
        p, (seed, count) = running.pop(0)
        out, err = p.communicate()
        lines = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
        done += len(lines)
        for rec in lines:
            strategies[rec["strategy"]] = strategies.get(rec["strategy"], 0) + 1
            findings.extend(rec["findings"])
        if p.returncode != 0 or len(lines) < count:
            crashes.append({"seed": seed, "returncode": p.returncode, "inputs_done": len(lines),
                            "stderr": err[-500:]})
            print(f"crash: worker seed {seed} exit {p.returncode} after {len(lines)} of {count} inputs; "
                  f"stderr: {err[-1500:]}", file=sys.stderr)
        print(f"{done}/{args.inputs} inputs, {len(findings)} findings, {len(crashes)} crashes, "
              f"{time.time() - t0:.0f} s", file=sys.stderr)
    kinds: dict[str, int] = {}
    for f in findings:
        kinds[f["kind"]] = kinds.get(f["kind"], 0) + 1
    report = {"inputs": done, "seed": args.seed, "strategies": strategies, "findings_by_kind": kinds,
              "crashes": crashes, "findings": findings, "seconds": time.time() - t0,
              "load_average": os.getloadavg()}
    Path(args.out).write_text(json.dumps(report, indent=1))
    print(json.dumps({k: report[k] for k in ("inputs", "strategies", "findings_by_kind", "seconds")}))
    print(f"crashes: {len(crashes)}")
    return 0 if not findings and not crashes else 1


if __name__ == "__main__":
    sys.exit(main())
