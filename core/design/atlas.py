"""Building and loading the atlas (records and storage: :mod:`.atlas_store`).

Designs are drawn in the normalised frame of their topology (:data:`~.atlas_store.SPECS`) from a
scrambled Sobol sequence (scipy.stats.qmc; chunk k always takes the same stretch of the sequence,
so the atlas is the same whoever builds which chunk). A first screen in closed form keeps the
designs whose crank can turn fully with a transmission angle above
:data:`~.atlas_store.MIN_MU_DEG` (Grashof's condition and the extreme transmission angles at the
crank's dead-centre lines; for the slider-cranks r + |e| ≤ l and its analogue; a six-bar's
second dyad is sized so that it keeps the angle: :func:`sixbar_lengths`, :func:`slider_lengths`);
the survivors are solved over one crank turn by the product's batch kernels — the studies
engine's :func:`~mechsketch.core.studies.variants.solve_variants` on a template linkage
(:func:`~.atlas_engine.engine_solver`; the closed form of :mod:`.families`,
:func:`closed_form_solver`, is the tested reference and the build of atlas format v1) — and a
design enters only where that solve assembles every sample without a branch jump and keeps the
transmission angle (a slider's: its pressure angle's complement) above the minimum. Each of its
coupler curves gets a Fourier descriptor (:mod:`.descriptors`), its output (the rocker's angle or
the slider's position) the first harmonics over the turn.

:func:`build_atlas` runs the chunks as tasks of the studies engine's runner
(:func:`~mechsketch.core.studies.execute.run_tasks`): in this process (``workers`` threads) or on a
Dask cluster (``client``), with progress and cancel; the results are the same bits.
:func:`load_atlas` returns an atlas from memory, else from the cache folder, else builds and
stores it, reporting progress (and naming an atlas of an older format it rebuilds).
"""
from __future__ import annotations

import math
import os
import time
import uuid
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ..studies.execute import StudyCancelled, connect, run_tasks
from . import families as F
from .atlas_engine import engine_solver, fused_engine_solver
from .atlas_store import (DEFAULT_DESIGNS, FUNC_HARMONICS, MIN_MU_DEG, POINTS, SAMPLES, SPECS, VERSION, VERSION_CHANGES,
                          Atlas, atlas_folder, family_params, read_atlas, read_meta, save_atlas)
from .descriptors import DESC_DIM, fourier_descriptor
from .targets import Cancelled, DesignError, Progress, report

#: designs drawn per chunk (before screening)
CHUNK = 32_768   # a power of 2: the Sobol sequence keeps its balance per chunk
#: screened designs solved per call of the solver (a chunk stops once it has what is wanted);
#: part of the atlas format: numpy's last bits may depend on an array's length
SLICE = 8192
#: atlases of this many designs or more are solved on the engine's fused compiled loop (its
#: compilation, seconds per topology, pays for itself; smaller ones, the tests', use numpy)
FUSED_DESIGNS = 100_000


@dataclass
class Chunk:
    """The designs of one chunk that entered, with their descriptors."""

    shape: np.ndarray
    points: np.ndarray
    desc: np.ndarray
    func: np.ndarray
    turns: np.ndarray
    mu: np.ndarray
    drawn: int


def _draw(topology: str, start: int, count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Designs ``start`` .. ``start + count`` of the Sobol sequence: (shape (n, S), points (n, P, 2))."""
    from scipy.stats import qmc

    spec = SPECS[topology]
    dim = len(spec.names) + 2 * POINTS
    sob = qmc.Sobol(dim, scramble=True, seed=seed)
    if start:
        sob.fast_forward(start)
    u = sob.random(count)
    cols = []
    for k, ((lo, hi), lg) in enumerate(zip(spec.ranges, spec.log)):
        cols.append(np.exp(math.log(lo) + u[:, k] * math.log(hi / lo)) if lg else lo + u[:, k] * (hi - lo))
    shape = np.stack(cols, axis=1)
    pu = u[:, len(spec.names):].reshape(count, POINTS, 2)
    unit = shape[:, spec.names.index("b")][:, None] if spec.point_unit == "b" else 1.0   # "l1": set later
    px = (spec.u[0] + pu[..., 0] * (spec.u[1] - spec.u[0])) * unit
    py = (spec.v[0] + pu[..., 1] * (spec.v[1] - spec.v[0])) * unit
    return shape, np.stack([px, py], axis=-1)


def screen(topology: str, shape: np.ndarray, min_mu_deg: float = MIN_MU_DEG) -> np.ndarray:
    """(n,) bool: the crank can turn fully and the transmission angle stays above the minimum,
    in closed form (the batch solve confirms it)."""
    s = math.sin(math.radians(min_mu_deg))
    with np.errstate(invalid="ignore"):
        if topology in (F.FOURBAR,) + F.ALL_SIXBARS:
            a, b, c = shape[:, 0], shape[:, 1], shape[:, 2]
            L = np.sort(np.stack([a, b, c, np.ones_like(a)], axis=1), axis=1)
            grashof = L[:, 0] + L[:, 3] < L[:, 1] + L[:, 2]
            crank = grashof & ((a <= L[:, 0]) | (L[:, 0] == 1.0))        # crank-rocker or double crank
            cos1 = (b * b + c * c - (1 - a) ** 2) / (2 * b * c)           # μ at the crank's two dead-centre lines
            cos2 = (b * b + c * c - (1 + a) ** 2) / (2 * b * c)
            return crank & (np.maximum(np.abs(cos1), np.abs(cos2)) <= math.cos(math.radians(min_mu_deg)))
        if topology == F.SLIDER_CRANK:
            h, b = shape[:, 0], shape[:, 1]
            reach = np.abs(h) + 1.0
            return (b > reach) & (np.sqrt(np.maximum(b * b - reach * reach, 0.0)) / b >= s)
        a, e = shape[:, 0], shape[:, 1]
        near = np.abs(a - 1.0)
        return (near > np.abs(e)) & (np.sqrt(np.maximum(1.0 - (e / np.maximum(near, 1e-300)) ** 2, 0.0)) >= s)


#: solve(topology, shape (D, S), points (D, P, 2), theta (N,)) -> (coupler points (D, P, N) complex,
#: output (D, N), sin μ (D, N), assembled (D, N)) in the normalised frame
Solver = Callable[[str, np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]


def sixbar_lengths(shape: np.ndarray, points: np.ndarray, min_mu_deg: float = MIN_MU_DEG, watt: bool = False
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drawn six-bars (a, b, c, E in units of b — of c on a Watt's rocker —, F, l2/l1, l1's
    place 0..1) made concrete:
    l1 is chosen where the dyad E–G–F keeps its transmission angle above the minimum at every
    distance |E − F| over the turn (from the law of cosines: d² = l1²(1 + r² − 2r·cos μ)), and
    the coupler points scaled by l1. Returns (shape (n, 9), points, kept (n,) bool)."""
    shape = shape.copy()
    unit = shape[:, 2] if watt else shape[:, 1]
    shape[:, 3] *= unit
    shape[:, 4] *= unit
    th = 2 * math.pi * np.arange(48) / 48
    four = np.stack([np.zeros(len(shape)), np.zeros(len(shape)), np.ones(len(shape)), np.zeros(len(shape)),
                     shape[:, 0], shape[:, 1], shape[:, 2], shape[:, 3], shape[:, 4]], axis=1)
    ev = F.evaluate(F.FOURBAR, four, th[None, :], 1.0)
    E = ev.P
    if watt:    # the point on the rocker D C, in its frame
        C, D = ev.joints["C"], 1.0
        E = D + (shape[:, 3] + 1j * shape[:, 4])[:, None] * (C - D) / shape[:, 2][:, None]
    d = np.abs(E - (shape[:, 5] + 1j * shape[:, 6])[:, None])
    dmin, dmax = d.min(axis=1), d.max(axis=1)
    r = shape[:, 7]
    cm = math.cos(math.radians(min_mu_deg + 2.0))
    lo_q, hi_q = 1 + r * r - 2 * r * cm, 1 + r * r + 2 * r * cm
    with np.errstate(invalid="ignore", divide="ignore"):
        lo, hi = dmax / np.sqrt(hi_q), dmin / np.sqrt(lo_q)
    ok = ev.ok.all(axis=1) & (lo < hi) & (dmin > 0)
    l1 = np.where(ok, lo * (hi / np.where(ok, lo, 1.0)) ** shape[:, 8], np.nan)
    shape[:, 7], shape[:, 8] = l1, r * l1
    return shape, points * l1[:, None, None], ok


def slider_lengths(shape: np.ndarray, points: np.ndarray, min_mu_deg: float = MIN_MU_DEG, watt: bool = False
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drawn six-bars with a slider (a, b, c, E in units of b — of c on a Watt —, F, the rod's
    place 0..1, g) made concrete: the rod l1 is at least the largest distance d of E from the
    guide over the turn divided by cos(μ_min + 2°) (so that the slider's transmission angle,
    asin √(1 − (d/l1)²), stays above the minimum) and at most four times that (log-uniform
    by the drawn place); the coupler points are scaled by l1. Returns (shape (n, 9), points,
    kept (n,) bool)."""
    shape = shape.copy()
    unit = shape[:, 2] if watt else shape[:, 1]
    shape[:, 3] *= unit
    shape[:, 4] *= unit
    E, ok = _sixbar_e(shape, watt)
    e = np.exp(1j * shape[:, 8])[:, None]
    d = np.abs(np.imag(np.conj(e) * (E - (shape[:, 5] + 1j * shape[:, 6])[:, None])))
    lo = d.max(axis=1) / math.cos(math.radians(min_mu_deg + 2.0))
    ok &= lo > 0
    l1 = np.where(ok, lo * 4.0 ** shape[:, 7], np.nan)
    shape[:, 7] = l1
    return shape, points * l1[:, None, None], ok


def guide_lengths(shape: np.ndarray, points: np.ndarray, min_mu_deg: float = MIN_MU_DEG, watt: bool = False
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drawn six-bars with a guided rocker (a, b, c, E in units of b — of c on a Watt —, F, the
    guide's offset as a fraction −1..1) made concrete: the offset e is that fraction of
    r_min·cos(μ_min + 2°), r_min the least distance |E − F| over the turn (so that the block's
    transmission angle, acos(|e|/|E − F|), stays above the minimum); the coupler points are
    scaled by r_min. Returns (shape (n, 8), points, kept (n,) bool)."""
    shape = shape.copy()
    unit = shape[:, 2] if watt else shape[:, 1]
    shape[:, 3] *= unit
    shape[:, 4] *= unit
    E, ok = _sixbar_e(shape, watt)
    rmin = np.abs(E - (shape[:, 5] + 1j * shape[:, 6])[:, None]).min(axis=1)
    ok &= rmin > 1e-3
    shape[:, 7] = np.where(ok, shape[:, 7] * rmin * math.cos(math.radians(min_mu_deg + 2.0)), np.nan)
    return shape, points * rmin[:, None, None], ok


def _sixbar_e(shape: np.ndarray, watt: bool) -> tuple[np.ndarray, np.ndarray]:
    """(n, 48) the point E over one turn of the six-bars ``shape`` (E in absolute units) and
    (n,) whether their four-bar assembles all the turn."""
    n = len(shape)
    th = 2 * math.pi * np.arange(48) / 48
    four = np.stack([np.zeros(n), np.zeros(n), np.ones(n), np.zeros(n),
                     shape[:, 0], shape[:, 1], shape[:, 2], shape[:, 3], shape[:, 4]], axis=1)
    ev = F.evaluate(F.FOURBAR, four, th[None, :], 1.0)
    E = ev.P
    if watt:    # the point on the rocker D C, in its frame
        E = 1.0 + (shape[:, 3] + 1j * shape[:, 4])[:, None] * (ev.joints["C"] - 1.0) / shape[:, 2][:, None]
    return E, ev.ok.all(axis=1)


def closed_form_solver(topology: str, shape: np.ndarray, points: np.ndarray, theta: np.ndarray):
    """The closed form of :mod:`.families` (tested equal to the product's solver to 1e-12): one
    evaluation per design, every coupler point carried by the coupler it gives."""
    ev = F.evaluate(topology, family_params(topology, shape, points[:, 0]), theta, 1.0)
    B = ev.joints["B"]
    if topology == F.INVERTED:
        frame = ev.joints["u"]
    elif topology in F.GUIDE_SIXBARS:     # the block's frame: its guide
        B, frame = ev.joints["E"], ev.joints["u"]
    elif topology in F.ALL_SIXBARS:
        B = ev.joints["E"]
        frame = (ev.joints["G"] - B) / shape[:, 7][:, None]
    else:
        frame = (ev.joints["C"] - B) / shape[:, SPECS[topology].names.index("b")][:, None]
    p = points[..., 0] + 1j * points[..., 1]
    P = B[:, None, :] + p[:, :, None] * frame[:, None, :]
    return P, ev.out, ev.sin_mu, ev.ok


def describe_chunk(topology: str, index: int, seed: int = 0, chunk: int = CHUNK, min_mu_deg: float = MIN_MU_DEG,
                   solver: Solver | None = None, limit: int | None = None) -> dict[str, np.ndarray]:
    """Chunk ``index`` of the atlas in float64: draw, screen, solve (``solver``, default the
    studies engine's :func:`~.atlas_engine.engine_solver`), keep, describe. Returns the kept
    designs' ``shape`` (K, S), ``points`` (K, P, 2), ``desc`` (K·P, DESC_DIM), ``func``
    (K, 2·H + 1), ``turns`` (K,), ``mu`` (K,) °, and ``drawn`` (the indices, among the
    chunk's draws, of the kept designs). ``limit``: stop once that many are kept (the screened
    designs are solved :data:`SLICE` at a time, in order; each design's numbers do not depend
    on the others', so the first ``limit`` are those of the whole chunk)."""
    solver = solver or engine_solver
    shape, points = _draw(topology, index * chunk, chunk, seed)
    rows = np.flatnonzero(screen(topology, shape, min_mu_deg))
    shape, points = shape[rows], points[rows]
    if topology in F.ALL_SIXBARS:
        lengths = (slider_lengths if topology in F.SLIDER_SIXBARS else
                   guide_lengths if topology in F.GUIDE_SIXBARS else sixbar_lengths)
        shape, points, keep = lengths(shape, points, min_mu_deg, topology in F.WATTS)
        shape, points, rows = shape[keep], points[keep], rows[keep]
    theta = 2 * math.pi * np.arange(SAMPLES) / SAMPLES
    parts, kept = [], 0
    for lo in range(0, len(rows), SLICE):
        sl = slice(lo, lo + SLICE)
        curves, out, sin_mu, good = solver(topology, shape[sl], points[sl], theta)
        ok = good.all(axis=1) & np.isfinite(curves).all(axis=(1, 2))
        mu = np.degrees(np.arcsin(np.clip(np.min(np.where(good, sin_mu, 0.0), axis=1), 0.0, 1.0)))
        ok &= mu >= min_mu_deg
        parts.append((np.flatnonzero(ok) + lo, curves[ok], out[ok], mu[ok]))
        kept += int(ok.sum())
        if limit is not None and kept >= limit:
            break
    at = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0, int)
    curves = np.concatenate([p[1] for p in parts]) if parts else np.zeros((0, POINTS, SAMPLES), complex)
    out = np.concatenate([p[2] for p in parts]) if parts else np.zeros((0, SAMPLES))
    desc = fourier_descriptor(curves, compiled=True, min_rows=0).reshape(-1, DESC_DIM)
    func, turns = _harmonics(topology, out, theta)
    return {"shape": shape[at], "points": points[at], "desc": desc, "func": func, "turns": turns,
            "mu": np.concatenate([p[3] for p in parts]) if parts else np.zeros(0), "drawn": rows[at]}


def solve_chunk(topology: str, index: int, seed: int = 0, chunk: int = CHUNK, min_mu_deg: float = MIN_MU_DEG,
                solver: Solver | None = None, limit: int | None = None) -> Chunk:
    """Chunk ``index`` of the atlas as stored (:func:`describe_chunk` in the atlas's dtypes; a
    pure function of its arguments: a Dask task)."""
    c = describe_chunk(topology, index, seed, chunk, min_mu_deg, solver, limit)
    return Chunk(c["shape"].astype(np.float32), c["points"].astype(np.float32), c["desc"].astype(np.float16),
                 c["func"].astype(np.float16), c["turns"].astype(np.int8), c["mu"].astype(np.float16), chunk)


def _harmonics(topology: str, out: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The output over the turn as its turns per crank turn and the harmonics 0..FUNC_HARMONICS
    (a0, a1, b1, a2, b2, ...) of what is left: (D, 2·H + 1), (D,)."""
    if F.OUTPUT_UNIT[topology] == "mm":       # a slider's position
        turns = np.zeros(out.shape[0])
        g = out
    else:
        u = np.unwrap(np.concatenate([out, out[:, :1]], axis=1), axis=1)
        turns = np.round((u[:, -1] - u[:, 0]) / (2 * math.pi))
        g = u[:, :-1] - turns[:, None] * theta[None, :]
    c = np.fft.rfft(g, axis=1) / g.shape[1]
    cols = [c[:, 0].real]
    for k in range(1, FUNC_HARMONICS + 1):
        cols += [2 * c[:, k].real, -2 * c[:, k].imag]
    return np.stack(cols, axis=1), turns


@dataclass(frozen=True)
class _Round:
    """One round of chunks of an atlas build (the context of its tasks: one object, so that Dask
    scatters it whole; ``nonce`` keeps two builds' rounds apart on one cluster)."""

    topology: str
    seed: int
    chunk: int
    first: int
    solver: Solver
    min_mu_deg: float
    nonce: str
    #: designs still wanted: no chunk of the round need keep more (:func:`describe_chunk`)
    limit: int | None = None


def _chunk_task(ctx: _Round, i: int) -> Chunk:
    """Chunk ``ctx.first + i`` of the atlas (a task of :func:`~mechsketch.core.studies.execute.run_tasks`)."""
    return solve_chunk(ctx.topology, ctx.first + i, ctx.seed, ctx.chunk, ctx.min_mu_deg, ctx.solver, ctx.limit)


def _cluster_size(client) -> int:
    try:
        return max(len(client.scheduler_info().get("workers", {})), 1)
    except (AttributeError, OSError):
        return 1


def _stop(cancel) -> bool:
    if cancel is None:
        return False
    return bool(cancel.is_set() if hasattr(cancel, "is_set") else cancel())


def _gather_chunks(job: _Round, designs: int, client, lanes: int, progress: Progress | None, cancel) -> list[Chunk]:
    """Chunks 0, 1, ... of ``job`` until they hold ``designs`` designs, run in rounds by
    :func:`~mechsketch.core.studies.execute.run_tasks` (see :func:`build_atlas`)."""
    topology, chunk = job.topology, job.chunk
    parts: list[Chunk] = []
    have, index = 0, 0
    asked, shown = [False], [0.0]
    while have < designs:
        per = have / (index * chunk) if index else 0.0        # designs kept per design drawn so far
        need = math.ceil((designs - have) / (per * chunk)) if per > 0 else 1
        n = max(min(need, 4 * lanes), lanes if index else 1)

        def tick(done: int, total: int, have=have, n=n, per=per, index=index) -> None:
            est = have + (done / max(total, 1)) * n * chunk * per
            msg = f"{topology} atlas: {min(int(est), designs):,} of {designs:,} designs (chunk {index + done})"
            shown[0] = max(shown[0], min(est / designs, 0.999))      # an estimate: never shown going back
            asked[0] = asked[0] or bool(progress is not None and progress(shown[0], msg))

        ctx = replace(job, first=index, nonce=uuid.uuid4().hex, limit=designs - have)
        try:
            got = run_tasks(_chunk_task, ctx, n, client=client, workers=lanes if client is None else 1,
                            progress=tick, cancel=lambda: asked[0] or _stop(cancel))
        except StudyCancelled as exc:
            raise Cancelled(f"the {topology} atlas: {exc}") from None
        index += n
        for c in got:
            if have < designs:
                parts.append(c)
                have += c.shape.shape[0]
        if index > 10_000:
            raise DesignError(f"the {topology} atlas: too few designs pass the screen")
    return parts


def build_atlas(topology: str, designs: int, seed: int = 0, progress: Progress | None = None, client=None,
                solver: Solver | None = None, chunk: int = CHUNK, workers: int = 1, cancel=None) -> Atlas:
    """An atlas of ``designs`` designs of ``topology`` (see the module docstring), solved by the
    studies engine (:func:`~.atlas_engine.engine_solver`; ``solver``: another, e.g.
    :func:`closed_form_solver`). The chunks run as tasks of the studies engine's runner
    (:func:`~mechsketch.core.studies.execute.run_tasks`; from :data:`FUSED_DESIGNS` designs on
    its fused compiled loop, :func:`~.atlas_engine.fused_engine_solver`): in this process
    (``workers`` threads) or on the Dask cluster of ``client`` (a ``distributed.Client`` or a scheduler address), in
    rounds sized from the share of designs that passed so far; the atlas is chunks 0, 1, ... in
    order, cut at ``designs``, so it is the same bits whoever ran which chunk. ``progress``
    (fraction, message) may return True to cancel, as may ``cancel`` (an Event or a callable):
    :class:`~.targets.Cancelled` is raised and nothing is returned."""
    if topology not in SPECS:
        raise DesignError(f"no atlas for topology {topology!r} (atlases: {', '.join(SPECS)})")
    if designs < 1:
        raise DesignError(f"an atlas needs at least one design, got {designs}")
    solve = solver or (fused_engine_solver if designs >= FUSED_DESIGNS else engine_solver)
    start = time.perf_counter()
    own = isinstance(client, str)          # a scheduler address: our client, closed when done
    if client is not None:
        client = connect(client)
    lanes = _cluster_size(client) if client is not None else max(int(workers), 1)
    try:
        parts = _gather_chunks(_Round(topology, seed, chunk, 0, solve, MIN_MU_DEG, ""), designs, client, lanes,
                               progress, cancel)
    finally:
        if own:
            client.close()
    report(progress, 1.0, f"{topology} atlas: {designs:,} of {designs:,} designs")
    cat = {name: np.concatenate([getattr(c, name) for c in parts])[:designs] for name in
           ("shape", "points", "func", "turns", "mu")}
    cat["desc"] = np.concatenate([c.desc for c in parts])[: designs * POINTS]
    drawn = sum(c.drawn for c in parts)
    meta = {"version": VERSION, "topology": topology, "designs": designs, "points": POINTS, "samples": SAMPLES,
            "seed": seed, "drawn": drawn, "min_mu_deg": MIN_MU_DEG, "seconds": time.perf_counter() - start,
            "solver": SOLVER_NAMES.get(getattr(solve, "__name__", ""), getattr(solve, "__name__", "custom")),
            "built": time.strftime("%Y-%m-%dT%H:%M:%S"), "dask": client is not None, "lanes": lanes}
    return Atlas(topology, meta=meta, **cat)


#: how the meta data names the solvers
SOLVER_NAMES = {"engine_solver": "studies engine (solve_variants)", "closed_form_solver": "closed form",
                "fused_engine_solver": "studies engine (solve_variants, fused loop)"}


_LOADED: dict[tuple[str, int], Atlas] = {}


def load_atlas(topology: str, designs: int | None = None, progress: Progress | None = None,
               build: bool = True, client=None, workers: int = 1) -> Atlas:
    """The atlas of ``topology`` with ``designs`` designs (default ``$MECHSKETCH_ATLAS_DESIGNS``
    or :data:`~.atlas_store.DEFAULT_DESIGNS`): from memory, else from the cache folder, else built
    now (with ``progress``; on a Dask cluster with ``client``) and stored. ``build=False``
    raises DesignError instead of building."""
    if topology not in SPECS:
        raise DesignError(f"no atlas for topology {topology!r} (atlases: {', '.join(SPECS)})")
    n = int(designs or os.environ.get("MECHSKETCH_ATLAS_DESIGNS") or DEFAULT_DESIGNS)
    key = (topology, n)
    if key in _LOADED:
        return _LOADED[key]
    folder = atlas_folder(topology, n)
    atlas = read_atlas(folder)
    if atlas is None:
        stale = older_atlas(topology, n)
        if not build:
            raise DesignError(f"the {topology} atlas ({n:,} designs) is not built yet (cache folder {folder.parent})"
                              + (f"; {stale}" if stale else ""))
        if stale:
            report(progress, 0.0, stale)
        atlas = build_atlas(topology, n, progress=progress, client=client, workers=workers)
        if stale:
            atlas.meta["replaces"] = stale
        try:
            save_atlas(atlas, folder)
        except OSError as exc:   # a read-only cache: keep it in memory for this session
            atlas.meta["not_stored"] = f"{folder}: {exc}"
    _LOADED[key] = atlas
    return atlas


def older_atlas(topology: str, designs: int) -> str:
    """A message naming an atlas of ``topology`` and ``designs`` of an older format in the cache
    folder (it is left there, unread, and rebuilt in the current format), or ""."""
    found = [v for v in range(1, VERSION) if read_meta(atlas_folder(topology, designs, v)) is not None]
    if not found:
        return ""
    return (f"the cached {topology} atlas is of format v{found[-1]} (older than v{VERSION}: "
            f"{VERSION_CHANGES[VERSION]}); rebuilding it (the old one, "
            f"{atlas_folder(topology, designs, found[-1])}, may be deleted)")


def forget_loaded() -> None:
    """Drop the atlases kept in memory (tests; a changed cache folder)."""
    _LOADED.clear()


__all__ = ["CHUNK", "Chunk", "FUSED_DESIGNS", "SLICE", "SOLVER_NAMES", "build_atlas", "closed_form_solver",
           "describe_chunk", "forget_loaded", "guide_lengths", "load_atlas", "older_atlas", "screen", "sixbar_lengths",
           "slider_lengths", "solve_chunk"]
