"""``mechsketch study STUDY.json --out DIR [--workers N | --scheduler ADDRESS]`` and its Python twin
:func:`run_study_file`.

The study file (JSON, see :mod:`mechsketch.core.studies.study`) names its scene (a path relative
to the study file) and element; a ``target`` may give its points inline or as ``{"joint": J,
"csv": "path.csv"}`` (columns ``x,y``, mm). Everything is checked before anything runs, and the
output folder is written only when the study has finished: a bad study, an unreachable scheduler
or a cancelled run leaves nothing. Written (each file atomically):

- ``designs.csv`` (sweep), ``builds.csv`` (montecarlo) or ``evaluations.csv`` (optimize): one
  row per design with its variables and metrics (units in ``summary.json``); with
  ``"output": {"format": "parquet"}`` in the study or ``--format parquet`` (which wins) the tables
  are Parquet files instead (``designs.parquet``…, written by pyarrow: every column in its own
  type — the design index int64, the numbers float64 at full precision — its unit in the field's
  metadata);
- ``summary.json``: counts (designs that do not assemble included), ranges, percentiles,
  sensitivities, the Pareto set, the time and what ran it;
- montecarlo of a linkage: ``envelope.csv`` (or ``.parquet``), per sample the nominal point and the 0.5 %, 50 % and
  99.5 % envelope points of each traced joint;
- optimize: ``pareto/ELEMENT_K.json``, a scene file per Pareto design (the study's scene with the
  element replaced), which opens in the app.

``--workers N`` runs on a local Dask cluster of N processes (one thread each); ``--scheduler``
on the Dask cluster of that scheduler; neither: this process. The numbers are the same either way.
"""
from __future__ import annotations

import argparse
import json
import math
import os
from pathlib import Path

from ..errors import RequestError

HELP = "run a design study (sweep, Monte Carlo, optimisation) described by a study file"


def add_study_parser(sub) -> argparse.ArgumentParser:
    s = sub.add_parser("study", help=HELP, description=HELP)
    s.add_argument("study", help="the study file (JSON)")
    s.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    where = s.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="run on a local Dask cluster of N processes")
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask cluster of this scheduler")
    s.add_argument("--format", metavar="csv|parquet", help="the tables' format (default: the study's "
                   "\"output\": {\"format\": ...}, else csv)")
    return s


def _read_study(path: Path) -> dict:
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise RequestError(f"cannot read the study file {path}: {exc.strerror or exc}") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise RequestError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
    if not isinstance(data, dict):
        raise RequestError(f"{path}: a study is a JSON object")
    return data


def _target(data: dict, folder: Path) -> None:
    import numpy as np

    t = data.get("target")
    if isinstance(t, dict) and "csv" in t:
        p = folder / str(t["csv"])
        try:
            pts = np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2)
        except (OSError, ValueError) as exc:
            raise RequestError(f"study target: cannot read {p} as a CSV of x,y (mm): {exc}") from None
        data["target"] = {k: v for k, v in t.items() if k != "csv"} | {"points": pts[:, :2].tolist()}


def _out_folder(out: str) -> Path:
    p = Path(out)
    if p.exists() and not p.is_dir():
        raise RequestError(f"--out {out}: exists and is not a folder")
    parent = p if p.exists() else p.parent if str(p.parent) else Path(".")
    while not parent.exists():
        parent = parent.parent
    if not os.access(parent, os.W_OK):
        raise RequestError(f"--out {out}: folder {parent} is not writable")
    return p


def prepare(path: str) -> tuple:
    """Read and check a study file: (scene, study) — RequestError/SceneFormatError naming the
    entry at fault; nothing runs."""
    from ..io.scene_file import load_scene
    from ..studies.study import load_study

    sp = Path(path)
    data = _read_study(sp)
    if "scene" not in data:
        raise RequestError(f"{path}: the study names no \"scene\" (a scene file, relative to the study)")
    scene = load_scene(sp.parent / str(data["scene"]))
    eid = data.get("element")
    if eid is None:
        el = next((e for e in scene.elements if e.type in ("linkage", "geneva")), None)
        if el is None:
            raise RequestError(f"{path}: the scene has no linkage or Geneva drive to study")
    else:
        try:
            el = scene.element(eid)
        except KeyError as exc:
            raise RequestError(f"study element: {exc}") from None
    _target(data, sp.parent)
    return scene, load_study(data, el)


def _cluster(workers: int | None, scheduler: str | None):
    """A Dask client (and the local cluster to close, if we made one) or (None, None)."""
    if scheduler:
        from ..studies.execute import connect

        return connect(scheduler), None
    if workers:
        if workers < 1:
            raise RequestError(f"--workers must be at least 1, got {workers}")
        import distributed

        cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                           dashboard_address=":0")
        return distributed.Client(cluster), cluster
    return None, None


def run_study_file(path: str, out: str, workers: int | None = None, scheduler: str | None = None,
                   progress=None, cancel=None, fmt: str | None = None):
    """``mechsketch study`` from Python: check, run (``workers`` local Dask processes, a
    ``scheduler`` address, or neither: this process), write ``out`` (tables in ``fmt``, "csv" or
    "parquet"; default the study's ``"output"``); returns the
    :class:`~mechsketch.core.studies.study.StudyResult`. ``progress``/``cancel`` as in
    :mod:`mechsketch.core.studies.execute`."""
    from ..studies.study import FORMATS, run_study

    if fmt is not None and fmt not in FORMATS:
        raise RequestError(f"--format {fmt!r}: not one of {', '.join(FORMATS)}")
    scene, st = prepare(path)
    if fmt is not None:
        st.format = fmt
    folder = _out_folder(out)
    client, cluster = _cluster(workers, scheduler)
    try:
        res = run_study(st, client=client, workers=1, progress=progress, cancel=cancel)
    finally:
        if client is not None and cluster is not None:
            client.close()
            cluster.close()
    res.summary["study"] = str(path)
    res.summary["element"] = getattr(st.element, "id", "")
    write_study(res, scene, folder)
    return res


def _csv(columns: dict) -> str:
    """The columns as CSV text: numbers with 10 significant digits, NaN empty, ±inf as such."""
    import numpy as np

    names = list(columns)
    cols = []
    for n in names:
        a = np.asarray(columns[n], dtype=float)
        txt = np.char.mod("%.10g", a)
        txt = np.where(np.isnan(a), "", txt)
        cols.append(txt)
    rows = [",".join(r) for r in zip(*cols)] if cols else []
    return "\n".join([",".join(names)] + rows) + "\n"


def _table(stem: Path, columns: dict, fmt: str, units: dict) -> Path:
    """Write ``columns`` (name -> (rows,)) atomically as ``stem.csv`` (:func:`_csv`) or
    ``stem.parquet`` (each column in its own dtype, the unit in the field's metadata); returns the
    path."""
    from ..io.atomic import atomic_write, atomic_write_text

    if fmt == "csv":
        path = stem.with_suffix(".csv")
        atomic_write_text(path, _csv(columns))
        return path
    import numpy as np
    import pyarrow as pa
    import pyarrow.parquet as pq

    fields, arrays = [], []
    for name, v in columns.items():
        a = pa.array(np.asarray(v))
        meta = {"unit": units[name]} if units.get(name) else None
        fields.append(pa.field(name, a.type, metadata=meta))
        arrays.append(a)
    table = pa.Table.from_arrays(arrays, schema=pa.schema(fields))
    path = stem.with_suffix(".parquet")
    atomic_write(path, lambda tmp: pq.write_table(table, tmp))
    return path


def _plain(x):
    """``x`` with non-finite floats as strings (JSON has no NaN or Infinity)."""
    import numpy as np

    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, (np.floating, np.integer)):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return x


def write_study(res, scene, folder: Path) -> list[Path]:
    """Write a study's files into ``folder`` (see the module docstring); returns them."""
    import numpy as np

    from ..io.atomic import atomic_write_text
    from ..io.scene_file import dumps_scene

    folder.mkdir(parents=True, exist_ok=True)
    kind = res.study.kind
    fmt = getattr(res.study, "format", "csv")
    name = {"sweep": "designs", "montecarlo": "builds", "optimize": "evaluations"}[kind]
    written = [_table(folder / name, res.columns, fmt, res.units)]
    summary = dict(res.summary)
    summary["columns"] = {k: res.units.get(k, "") for k in res.columns}
    if res.tolerance is not None:
        t = res.tolerance
        env = {}
        for j in t.joints:
            env[f"{j}.x"], env[f"{j}.y"] = t.nominal.pos[j][:, 0], t.nominal.pos[j][:, 1]
            for q in (0.005, 0.5, 0.995):
                e = t.envelope(j, q)
                env[f"{j}.q{q:g}.x"], env[f"{j}.q{q:g}.y"] = e[:, 0], e[:, 1]
        if env:
            written.append(_table(folder / "envelope", {"sample": np.arange(t.samples), **env}, fmt, {}))
    if res.pareto:
        pdir = folder / "pareto"
        pdir.mkdir(exist_ok=True)
        for k, (row, rec) in enumerate(res.pareto):
            p = pdir / f"{rec.id}_{k + 1}.json"
            atomic_write_text(p, dumps_scene(scene.with_element(rec)))
            written.append(p)
        res.summary["pareto_scenes"] = summary["pareto_scenes"] = [str(p.relative_to(folder)) for p in written
                                                                   if p.parent == pdir]
    written.append(folder / "summary.json")
    atomic_write_text(written[-1], json.dumps(_plain(summary), indent=2, ensure_ascii=False) + "\n")
    return written


def run(args: argparse.Namespace) -> int:
    """``mechsketch study`` (parsed); returns the exit status (errors raise MechsketchError)."""
    res = run_study_file(args.study, args.out, workers=args.workers, scheduler=args.scheduler, fmt=args.format)
    s = res.summary
    print(f"study {args.study}: {s['kind']} of {s.get('element', '')!r} in {s['seconds']:.2f} s; wrote {args.out}")
    return 0


__all__ = ["HELP", "add_study_parser", "prepare", "run", "run_study_file", "write_study"]
