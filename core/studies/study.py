"""Design studies of one element: sweeps, Monte Carlo and optimisation, described by a dict (the
study file of ``mechsketch study``) and run here, on threads or on a Dask cluster.

A study (JSON; paths are resolved by the caller, :mod:`mechsketch.core.cli.study_cmds`)::

    {"scene": "fourbar.json", "element": "fourbar", "samples": 360, "seed": 1,
     "variables": {"length:crank:A:B": {"range": [35, 45]},            # sweep and optimize
                   "length:coupler:B:C": {"values": [130, 140, 150]},  # a sweep's own grid values
                   "length:rocker:D:C": {"normal": 0.02}},             # montecarlo: σ (or "uniform")
     "clearance": {"B": "H7/g6"},                                      # montecarlo
     "metrics": ["min_transmission_angle", "peak_torque", "path_error:E"],
     "target": {"joint": "E", "points": [[x, y], ...]},               # for path_error/path_rms
     and one of
     "sweep": {"method": "grid", "points": 5}   or   {"method": "sobol", "designs": 1024},
     "montecarlo": {"builds": 100000, "joints": ["E"], "links": ["rocker"]},
     "optimize": {"objectives": [{"minimize": "peak_torque"}, {"maximize": "min_transmission_angle"}],
                  "constraints": [{"metric": "min_transmission_angle", "min": 40}],
                  "population": 40, "generations": 30, "algorithm": "nsga2" | "de", "pareto_scenes": 10}}

Variables are the keys of :mod:`.keys` (linkages) or the numeric fields of a Geneva drive
(:func:`~.metrics.geneva_keys`); metrics are listed in :mod:`.metrics`. A sweep evaluates every
design of a grid or of a scrambled Sobol sequence; a montecarlo of a linkage is a tolerance run
(:mod:`.tolerance`: deviations, envelope, sensitivity; the metrics of every build too when asked),
of a Geneva drive the metrics of random builds; an optimisation finds the Pareto set of the
objectives under the constraints with pymoo's NSGA-II (several objectives) or scipy's differential
evolution (one). A design that does not assemble is infeasible and counted.

Designs go out in blocks of :data:`BLOCK_DESIGNS` to :func:`~.execute.run_tasks`; a block's
random numbers and results depend only on its index, so the same seed gives the same numbers
whatever the number of workers.
"""
from __future__ import annotations

import itertools
import math
import time
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import RequestError
from ..model.geneva import Geneva
from ..model.linkage import Linkage
from ..model.loads import Damper, LinkMass, PointForce, Spring, Torque
from .budget import check_kept
from .execute import block_rng, run_tasks
from .geometry import build_geometry, design_linkage
from .keys import check_keys, variables
from .metrics import FORCES, PARTS, base, check_metrics, geneva_design, geneva_keys, geneva_metrics, \
    linkage_metrics, unit
from .tolerance import BLOCK as TOL_BLOCK
from .tolerance import _plan as batch_plan
from .tolerance import draw, parse_spec, percentile, tolerance
from .variants import Variants

KINDS = ("sweep", "montecarlo", "optimize")
#: designs per task of a sweep or an optimisation's population
BLOCK_DESIGNS = 2048
#: the largest grid or design count a study accepts (beyond: a Monte Carlo or Sobol sample)
MAX_DESIGNS = 50_000_000
TOP = {"variables", "metrics", "target", "samples", "seed", "scene", "element", "clearance", "output"} | set(KINDS)
#: the formats of a study's tables (``"output": {"format": ...}``; ``mechsketch study --format``)
FORMATS = ("csv", "parquet")


@dataclass
class Study:
    """A checked study (see the module docstring)."""

    element: object
    kind: str
    settings: dict
    variables: dict
    metrics: list
    samples: int
    seed: int
    clearance: dict = field(default_factory=dict)
    target: np.ndarray | None = None
    target_joint: str | None = None
    #: the tables' format, one of :data:`FORMATS`
    format: str = "csv"


def _entry(what: str, msg: str) -> RequestError:
    return RequestError(f"study {what}: {msg}")


def _num(what: str, v, integer: bool = False, positive: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise _entry(what, f"must be a finite number, got {v!r}")
    if integer and int(v) != v:
        raise _entry(what, f"must be a whole number, got {v!r}")
    if positive and not v > 0:
        raise _entry(what, f"must be positive, got {v!r}")
    return int(v) if integer else float(v)


def output_format(output) -> str:
    """The tables' format of a study's ``"output"`` entry (``{"format": "csv" | "parquet"}``; default
    csv); RequestError naming a wrong entry."""
    if not isinstance(output, dict) or set(output) - {"format"}:
        raise _entry("output", f"give {{\"format\": \"csv\"}} or {{\"format\": \"parquet\"}}, got {output!r}")
    fmt = output.get("format", "csv")
    if fmt not in FORMATS:
        raise _entry("output format", f"{fmt!r} is not one of {', '.join(FORMATS)}")
    return fmt


def load_study(data: dict, element) -> Study:
    """Check a study dict against its element; RequestError naming the first entry at fault."""
    if not isinstance(data, dict):
        raise RequestError("a study is a JSON object")
    unknown = set(data) - TOP
    if unknown:
        raise _entry(f"key {sorted(unknown)[0]!r}", f"unknown (a study has {', '.join(sorted(TOP))})")
    kinds = [k for k in KINDS if k in data]
    if len(kinds) != 1:
        raise RequestError(f"a study has exactly one of {', '.join(KINDS)}; this one has "
                           f"{', '.join(kinds) or 'none'}")
    kind = kinds[0]
    settings = data[kind]
    if not isinstance(settings, dict):
        raise _entry(kind, "must be an object")
    if not isinstance(element, (Linkage, Geneva)):
        raise _entry("element", f"{getattr(element, 'id', '?')!r} is a {getattr(element, 'type', '?')}; studies "
                                "apply to linkages and Geneva drives")
    var = data.get("variables", {})
    if not isinstance(var, dict) or (not var and kind != "montecarlo") or (not var and "clearance" not in data):
        raise _entry("variables", "give at least one variable {key: {...}}")
    if isinstance(element, Linkage):
        check_keys(element, list(var), "study variable")
    else:
        known = geneva_keys(element)
        for k in var:
            if k not in known:
                raise _entry(f"variable {k!r}", f"not a field of Geneva drive {element.id!r} (its fields: "
                                                f"{', '.join(known)})")
    for k, d in var.items():
        _check_variable(kind, k, d)
    metrics = data.get("metrics", [])
    if not isinstance(metrics, list) or not all(isinstance(m, str) for m in metrics):
        raise _entry("metrics", "give a list of metric names")
    tgt, tjoint = _target(data.get("target"))
    st = Study(element, kind, dict(settings), dict(var), list(metrics),
               int(_num("samples", data.get("samples", getattr(element, "samples", 360)), True, True)),
               int(_num("seed", data.get("seed", 0), True)), dict(data.get("clearance", {})), tgt, tjoint)
    st.format = output_format(data.get("output", {}))
    if st.samples < 2 or st.samples > 100_000:
        raise _entry("samples", f"from 2 to 100,000, got {st.samples}")
    {"sweep": _check_sweep, "montecarlo": _check_mc, "optimize": _check_optimize}[kind](st)
    return st


def _check_variable(kind: str, key: str, d) -> None:
    what = f"variable {key!r}"
    if not isinstance(d, dict):
        raise _entry(what, "must be an object such as {\"range\": [lo, hi]}")
    if kind == "montecarlo":
        return            # checked by the tolerance spec (normal/uniform, σ ≥ 0)
    if "values" in d and kind == "sweep":
        vals = d["values"]
        if not isinstance(vals, list) or not vals:
            raise _entry(what, "\"values\" must be a non-empty list")
        for v in vals:
            _num(what, v)
        return
    r = d.get("range")
    if not (isinstance(r, list) and len(r) == 2):
        raise _entry(what, "give \"range\": [lo, hi]" + (" or \"values\": [...]" if kind == "sweep" else ""))
    lo, hi = _num(what, r[0]), _num(what, r[1])
    if not lo < hi:
        raise _entry(what, f"the range's low end must be below its high end, got [{lo:g}, {hi:g}]")


def _target(t) -> tuple[np.ndarray | None, str | None]:
    if t is None:
        return None, None
    if not isinstance(t, dict) or "points" not in t:
        raise _entry("target", "give {\"joint\": J, \"points\": [[x, y], ...]}")
    pts = np.asarray(t["points"], dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2 or not np.isfinite(pts).all():
        raise _entry("target", "points must be at least two [x, y] pairs of finite numbers (mm)")
    return pts, t.get("joint")


def _check_sweep(st: Study) -> None:
    s = st.settings
    method = s.get("method", "grid")
    if method not in ("grid", "sobol"):
        raise _entry("sweep.method", f"'grid' or 'sobol', got {method!r}")
    if method == "grid":
        pts = int(_num("sweep.points", s.get("points", 5), True, True))
        n = 1
        for d in st.variables.values():
            n *= len(d["values"]) if "values" in d else pts
        if n > MAX_DESIGNS:
            raise _entry("sweep", f"the grid has {n:,} designs, more than {MAX_DESIGNS:,}: use fewer points or Sobol")
    else:
        n = int(_num("sweep.designs", s.get("designs", 1024), True, True))
        if any("values" in d for d in st.variables.values()):
            raise _entry("sweep", "a Sobol sweep takes ranges, not lists of values")
        if n > MAX_DESIGNS:
            raise _entry("sweep.designs", f"at most {MAX_DESIGNS:,}, got {n:,}")
    if not st.metrics:
        raise _entry("metrics", "a sweep reports metrics: list at least one")
    check_metrics(st.element, st.metrics, st.target)
    check_kept(8.0 * n * (len(st.variables) + len(st.metrics) + 2), f"a sweep of {n:,} designs",
               "use fewer designs")


def _check_mc(st: Study) -> None:
    s = st.settings
    _num("montecarlo.builds", s.get("builds", 10_000), True, True)
    spec = dict(st.variables)
    if st.clearance:
        spec["clearance"] = st.clearance
    if isinstance(st.element, Linkage):
        parse_spec(st.element, spec)
    else:
        for k, d in st.variables.items():
            if len(set(d) & {"normal", "uniform"}) != 1:
                raise _entry(f"variable {k!r}", "give {\"normal\": σ} or {\"uniform\": half-width}")
            w = _num(f"variable {k!r}", d.get("normal", d.get("uniform")))
            if w < 0:
                raise _entry(f"variable {k!r}", f"σ and half-widths must not be negative, got {w:g}")
        if st.clearance:
            raise _entry("clearance", "pin clearances apply to linkages")
    check_metrics(st.element, st.metrics, st.target)


def _objectives(st: Study) -> list[tuple[str, float]]:
    out = []
    for o in st.settings.get("objectives", []):
        if isinstance(o, str):
            o = {"minimize": o}
        if not isinstance(o, dict) or len(o) != 1 or next(iter(o)) not in ("minimize", "maximize"):
            raise _entry("optimize.objectives", f"each is \"metric\", {{\"minimize\": m}} or {{\"maximize\": m}}; got {o!r}")
        (sense, m), = o.items()
        out.append((m, 1.0 if sense == "minimize" else -1.0))
    if not out:
        raise _entry("optimize.objectives", "give at least one objective")
    return out


def _constraints(st: Study) -> list[tuple[str, float, float]]:
    out = []
    for c in st.settings.get("constraints", []):
        if not isinstance(c, dict) or "metric" not in c or not set(c) - {"metric"} <= {"min", "max"} or len(c) < 2:
            raise _entry("optimize.constraints", f"each is {{\"metric\": m, \"min\": a, \"max\": b}}; got {c!r}")
        out.append((c["metric"], _num("constraint min", c.get("min", -math.inf)) if "min" in c else -math.inf,
                    _num("constraint max", c.get("max", math.inf)) if "max" in c else math.inf))
    return out


def _check_optimize(st: Study) -> None:
    objs, cons = _objectives(st), _constraints(st)
    check_metrics(st.element, [m for m, _ in objs] + [m for m, _, _ in cons] + st.metrics, st.target)
    alg = st.settings.get("algorithm", "nsga2" if len(objs) > 1 else "de")
    if alg not in ("nsga2", "de"):
        raise _entry("optimize.algorithm", f"'nsga2' or 'de', got {alg!r}")
    if alg == "de" and len(objs) > 1:
        raise _entry("optimize.algorithm", "differential evolution optimises one objective; use 'nsga2'")
    for k in ("population", "generations", "pareto_scenes"):
        if k in st.settings:
            _num(f"optimize.{k}", st.settings[k], True, True)


# -- evaluating designs --------------------------------------------------------------------------
class _Eval:
    """What a task needs to evaluate designs (picklable)."""

    def __init__(self, st: Study, metrics: list[str], columns: dict | None = None, blocks: int = 0) -> None:
        self.element, self.metrics, self.samples = st.element, metrics, st.samples
        self.target, self.columns, self.blocks = st.target, columns, blocks
        self.variables, self.seed, self.spec = st.variables, st.seed, None


def evaluate(element, values: dict, n: int, metrics: list[str], samples: int, target=None) -> dict[str, np.ndarray]:
    """The metrics of n designs of ``element`` (``values`` key -> (n,))."""
    if isinstance(element, Geneva):
        return geneva_metrics(element, values, n, metrics)
    bp = batch_plan(element)
    order = 2 if any(base(m) in FORCES for m in metrics) else 0
    joints = sorted({m.split(":", 1)[1] for m in metrics if base(m) in ("path_error", "path_rms")})
    links = sorted({m.split(":", 1)[1] for m in metrics if base(m) == "swing"})
    b = Variants(bp, values, n, bp.inputs(samples), order)
    b._compute([(j, 0) for j in joints], [(k, 0) for k in links], summary=True)
    designs = None
    if any(base(m) in PARTS for m in metrics):
        geo = build_geometry(element, bp.plan, values, n)
        designs = lambda d: design_linkage(geo, d)   # noqa: E731
    return linkage_metrics(b, metrics, target, designs)


def _block_task(ev: _Eval, i: int) -> dict:
    lo = i * BLOCK_DESIGNS
    cols = {k: v[lo:lo + BLOCK_DESIGNS] for k, v in ev.columns.items()}
    n = len(next(iter(cols.values())))
    return evaluate(ev.element, cols, n, ev.metrics, ev.samples, ev.target)


def _run_blocks(ev: _Eval, n: int, **run) -> dict[str, np.ndarray]:
    parts = run_tasks(_block_task, ev, -(-n // BLOCK_DESIGNS), **run)
    return {m: np.concatenate([p[m] for p in parts]) if parts else np.empty(0) for m in ev.metrics}


@dataclass
class StudyResult:
    """What a study found: ``columns`` name -> (rows,) in order (the CSV's columns: the design's
    index, its variables, then its metrics), ``units`` per column, ``summary`` (the JSON), and
    for an optimisation the Pareto designs ``pareto`` [(row, element record)]; ``tolerance`` the
    Monte Carlo of a linkage's montecarlo study."""

    study: Study
    columns: dict
    units: dict
    summary: dict
    pareto: list = field(default_factory=list)
    tolerance: object = None


def design_record(element, values: dict, d: int):
    """Design ``d`` of ``values`` as an element record (for scene files)."""
    if isinstance(element, Geneva):
        return geneva_design(element, values, d)
    geo = build_geometry(element, batch_plan(element).plan, {k: np.asarray(v)[d:d + 1] for k, v in values.items()}, 1)
    if not geo.ok[0]:
        raise RequestError(f"design {d} does not assemble: {geo.message(0)}")
    rec = design_linkage(geo, 0)
    return _dynamic(rec, {k: np.asarray(v)[d] for k, v in values.items()})


def _dynamic(lk: Linkage, vals: dict) -> Linkage:
    """Masses and loads of a linkage set from mass/inertia/com/load variables (scene files)."""
    masses = {m.link: m for m in lk.masses}
    for k, v in vals.items():
        p = k.split(":")
        if p[0] in ("mass", "inertia", "com"):
            m = masses.get(p[1], LinkMass(p[1], 0.0))
            if p[0] == "mass":
                m = replace(m, mass=float(v))
            elif p[0] == "inertia":
                m = replace(m, inertia=float(v))
            else:
                pts = [lk.joint(j).at for j in lk.link(p[1]).joints]
                c = list(m.com or (sum(q[0] for q in pts) / len(pts), sum(q[1] for q in pts) / len(pts)))
                c["xy".index(p[2])] = float(v)
                m = replace(m, com=tuple(c))
            masses[p[1]] = m
    loads = []
    for ld in lk.loads:
        def get(name: str, old: float) -> float:
            key = f"load:{ld.id}:{name}"
            return float(vals[key]) if key in vals else old
        if isinstance(ld, PointForce):
            ld = replace(ld, force=(get("fx", ld.force[0]), get("fy", ld.force[1])))
        elif isinstance(ld, Torque):
            ld = replace(ld, torque=get("torque", ld.torque))
        elif isinstance(ld, Spring):
            ld = replace(ld, stiffness=get("stiffness", ld.stiffness), free_length=get("free_length", ld.rest_length))
        elif isinstance(ld, Damper):
            ld = replace(ld, damping=get("damping", ld.damping))
        loads.append(ld)
    order = lk.link_ids
    return replace(lk, masses=tuple(sorted(masses.values(), key=lambda m: order.index(m.link))), loads=tuple(loads))


def _units(st: Study, names) -> dict:
    vs = variables(st.element) if isinstance(st.element, Linkage) else {}
    out = {}
    for n in names:
        out[n] = vs[n].unit if n in vs else unit(n)
    return out


def run_study(st: Study, client=None, workers: int = 1, progress=None, cancel=None) -> StudyResult:
    """Run a checked study (see the module docstring and :mod:`.execute` for the callbacks)."""
    start = time.perf_counter()
    run = {"client": client, "workers": workers, "progress": progress, "cancel": cancel}
    res = {"sweep": _sweep, "montecarlo": _montecarlo, "optimize": _optimize}[st.kind](st, run)
    res.summary["seconds"] = round(time.perf_counter() - start, 3)
    res.summary["workers"] = "cluster" if client is not None else workers
    return res


def _design_table(st: Study) -> dict[str, np.ndarray]:
    s = st.settings
    if s.get("method", "grid") == "grid":
        pts = int(s.get("points", 5))
        axes = [np.asarray(d["values"], float) if "values" in d else np.linspace(d["range"][0], d["range"][1], pts)
                for d in st.variables.values()]
        grid = np.array(list(itertools.product(*axes))) if axes else np.empty((0, 0))
        return {k: grid[:, i].copy() for i, k in enumerate(st.variables)}
    from scipy.stats import qmc   # noqa: PLC0415 (scipy: only a Sobol sweep pays for it)

    n = int(s.get("designs", 1024))
    sob = qmc.Sobol(len(st.variables), scramble=True, seed=st.seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = sob.random(n)
    lo = np.array([d["range"][0] for d in st.variables.values()])
    hi = np.array([d["range"][1] for d in st.variables.values()])
    x = lo + u * (hi - lo)
    return {k: x[:, i].copy() for i, k in enumerate(st.variables)}


def _sweep(st: Study, run: dict) -> StudyResult:
    table = _design_table(st)
    n = len(next(iter(table.values())))
    metrics = _with_assembled(st.metrics)
    got = _run_blocks(_Eval(st, metrics, table), n, **run)
    cols = {"design": np.arange(n), **table, **got}
    ok = got["assembled"] > 0
    summary = {"kind": "sweep", "method": st.settings.get("method", "grid"), "designs": n,
               "assembled": int(ok.sum()), "not_assembled": int(n - ok.sum()), "metrics": {}}
    for m in st.metrics:
        v = got[m]
        fin = np.isfinite(v)
        if fin.any():
            i, j = int(np.nanargmin(v)), int(np.nanargmax(v))
            summary["metrics"][m] = {"unit": unit(m), "min": float(v[i]), "min_design": i, "max": float(v[j]),
                                     "max_design": j, "mean": float(np.nanmean(v)), "nan": int((~fin).sum())}
    return StudyResult(st, cols, _units(st, cols), summary)


def _with_assembled(metrics: list[str]) -> list[str]:
    return ["assembled"] + [m for m in metrics if m != "assembled"]


def _mc_block(ev: _Eval) -> int:
    """Builds per task: a linkage's are the tolerance run's blocks (the same builds, row by row)."""
    return TOL_BLOCK if ev.spec is not None else BLOCK_DESIGNS


def _mc_task(ev: _Eval, i: int) -> dict:
    size = _mc_block(ev)
    n = min(size, ev.blocks - i * size)
    return evaluate(ev.element, _mc_draw(ev, i, n), n, ev.metrics, ev.samples, ev.target)


def _mc_draw(ev: _Eval, i: int, n: int) -> dict:
    if ev.spec is not None:     # a linkage: the tolerance run's own draws
        nominal = {k: v.nominal for k, v in variables(ev.element).items()}
        values, _ = draw(ev.spec, nominal, ev.seed, i, n)
        return values
    rng = block_rng(ev.seed, i)
    known = geneva_keys(ev.element)
    out = {}
    for k, d in ev.variables.items():
        x = rng.normal(0.0, d["normal"], n) if "normal" in d else rng.uniform(-d["uniform"], d["uniform"], n)
        out[k] = known[k] + d.get("bias", 0.0) + x
    return out


def _montecarlo(st: Study, run: dict) -> StudyResult:
    builds = int(st.settings.get("builds", 10_000))
    cols: dict = {"build": np.arange(builds)}
    summary: dict = {"kind": "montecarlo", "builds": builds, "seed": st.seed}
    tol = None
    if isinstance(st.element, Linkage):
        spec = dict(st.variables)
        if st.clearance:
            spec["clearance"] = st.clearance
        tol = tolerance(st.element, spec, builds=builds, samples=st.samples, seed=st.seed,
                        joints=st.settings.get("joints"), links=st.settings.get("links"), **run)
        for j in tol.joints:
            d = tol.deviation(j)
            cols[f"deviation:{j}"] = d
            summary.setdefault("deviation", {})[j] = {
                "unit": "mm", **{f"p{q:g}": percentile(d, q) for q in (50, 90, 95, 99, 99.9)}, "max": float(np.max(d))}
            summary.setdefault("sensitivity", {})[j] = tol.sensitivity(j)
        for k in tol.links:
            a = tol.angle_deviation(k)
            cols[f"angle_deviation:{k}"] = a
            summary.setdefault("angle_deviation", {})[k] = {"unit": "°", **{f"p{q:g}": percentile(a, q)
                                                                           for q in (50, 95, 99)}}
        summary["failed"] = tol.failed
        summary["assembled"] = int(tol.assembled.sum())
    if st.metrics or not isinstance(st.element, Linkage):
        ev = _Eval(st, _with_assembled(st.metrics), blocks=builds)
        if isinstance(st.element, Linkage):
            ev.spec = parse_spec(st.element, {**st.variables, **({"clearance": st.clearance} if st.clearance else {})})
        parts = run_tasks(_mc_task, ev, -(-builds // _mc_block(ev)), **run)
        got = {m: np.concatenate([p[m] for p in parts]) for m in ev.metrics}
        cols.update(got)
        summary["metrics"] = {m: {"unit": unit(m), **{f"p{q:g}": percentile(np.where(np.isfinite(got[m]), got[m],
                                                                                      np.inf), q)
                                                       for q in (5, 50, 95)}} for m in st.metrics}
        summary.setdefault("assembled", int((got["assembled"] > 0).sum()))
    return StudyResult(st, cols, _units(st, cols), summary, tolerance=tol)


# -- optimisation -------------------------------------------------------------------------------
class _Population:
    """Evaluates populations in blocks (the same numbers whatever runs them) and keeps them."""

    def __init__(self, st: Study, run: dict) -> None:
        self.st, self.run = st, run
        self.objs, self.cons = _objectives(st), _constraints(st)
        names = [m for m, _ in self.objs] + [m for m, _, _ in self.cons] + st.metrics
        self.metrics = _with_assembled(list(dict.fromkeys(names)))
        self.keys = list(st.variables)
        self.rows: list[dict] = []
        self.generation = 0

    def __call__(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Objectives (P, n_obj) to minimise and constraint violations (P, 1 + n_cons) ≤ 0."""
        table = {k: X[:, i].copy() for i, k in enumerate(self.keys)}
        got = _run_blocks(_Eval(self.st, self.metrics, table), len(X), **self.run)
        F = np.column_stack([s * got[m] for m, s in self.objs])
        G = [np.where(got["assembled"] > 0, -1.0, 1.0)]
        for m, lo, hi in self.cons:
            v = got[m]
            g = np.maximum(lo - v if math.isfinite(lo) else -np.inf, v - hi if math.isfinite(hi) else -np.inf)
            G.append(np.where(np.isfinite(v), g, 1.0))
        bad = ~np.isfinite(F).all(axis=1)
        F[bad] = 1e30
        G = np.column_stack(G)
        for i in range(len(X)):
            self.rows.append({"generation": self.generation, **{k: X[i, j] for j, k in enumerate(self.keys)},
                              **{m: got[m][i] for m in self.metrics}, "feasible": float((G[i] <= 0).all())})
        self.generation += 1
        return F, G


def _pareto(F: np.ndarray) -> np.ndarray:
    """Indices of the non-dominated rows of F (minimisation)."""
    keep = []
    for i in range(len(F)):
        dominated = np.any(np.all(F <= F[i], axis=1) & np.any(F < F[i], axis=1))
        if not dominated:
            keep.append(i)
    return np.array(keep, dtype=int)


def _optimize(st: Study, run: dict) -> StudyResult:
    pop = _Population(st, run)
    lo = np.array([st.variables[k]["range"][0] for k in pop.keys], float)
    hi = np.array([st.variables[k]["range"][1] for k in pop.keys], float)
    size = int(st.settings.get("population", 40))
    gens = int(st.settings.get("generations", 30))
    alg = st.settings.get("algorithm", "nsga2" if len(pop.objs) > 1 else "de")
    if alg == "nsga2":
        _nsga2(pop, lo, hi, size, gens, st.seed)
    else:
        _de(pop, lo, hi, size, gens, st.seed)
    rows = pop.rows
    cols = {"evaluation": np.arange(len(rows))}
    for name in rows[0]:
        cols[name] = np.array([r[name] for r in rows], dtype=float)
    feas = cols["feasible"] > 0
    F = np.column_stack([s * cols[m] for m, s in pop.objs])
    idx = np.flatnonzero(feas & np.isfinite(F).all(axis=1))
    front = idx[_pareto(F[idx])] if idx.size else idx
    # one design per distinct point of the front, best first by the first objective
    front = front[np.argsort(F[front, 0], kind="stable")]
    _, first = np.unique(np.round(F[front], 12), axis=0, return_index=True)
    front = front[np.sort(first)]
    front = front[np.argsort(F[front, 0], kind="stable")]
    nscenes = int(st.settings.get("pareto_scenes", 10))
    table = {k: cols[k] for k in pop.keys}
    pareto = []
    for r in front[:nscenes]:
        pareto.append((int(r), design_record(st.element, table, int(r))))
    cols["pareto"] = np.isin(np.arange(len(rows)), front).astype(float)
    summary = {"kind": "optimize", "algorithm": alg, "evaluations": len(rows), "feasible": int(feas.sum()),
               "objectives": [{"metric": m, "sense": "minimize" if s > 0 else "maximize", "unit": unit(m)}
                              for m, s in pop.objs],
               "constraints": [{"metric": m, "min": a, "max": b} for m, a, b in pop.cons],
               "pareto": [{"evaluation": int(r), **{k: float(cols[k][r]) for k in pop.keys},
                           **{m: float(cols[m][r]) for m, _ in pop.objs}} for r in front]}
    return StudyResult(st, cols, _units(st, cols), summary, pareto)


def _nsga2(pop: _Population, lo, hi, size: int, gens: int, seed: int) -> None:
    from pymoo.algorithms.moo.nsga2 import NSGA2   # noqa: PLC0415 (pymoo: only an optimisation pays)
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    class _P(Problem):
        def __init__(self) -> None:
            super().__init__(n_var=len(lo), n_obj=len(pop.objs), n_ieq_constr=1 + len(pop.cons), xl=lo, xu=hi)

        def _evaluate(self, X, out, *args, **kwargs):
            out["F"], out["G"] = pop(np.asarray(X, float))

    minimize(_P(), NSGA2(pop_size=size), ("n_gen", gens), seed=seed, verbose=False)


def _de(pop: _Population, lo, hi, size: int, gens: int, seed: int) -> None:
    from scipy.optimize import differential_evolution   # noqa: PLC0415

    def f(x: np.ndarray) -> np.ndarray:      # x (n_var, S): the population at once
        F, G = pop(np.asarray(x, float).T)
        viol = np.maximum(G, 0.0).sum(axis=1)
        return np.where(viol > 0, 1e12 * (1.0 + viol), F[:, 0])

    differential_evolution(f, list(zip(lo, hi)), maxiter=gens, popsize=max(1, size // max(len(lo), 1)),
                           rng=np.random.default_rng(seed), vectorized=True, updating="deferred", polish=False)


__all__ = ["BLOCK_DESIGNS", "FORMATS", "KINDS", "Study", "StudyResult", "design_record", "evaluate", "load_study", "output_format", "run_study"]
