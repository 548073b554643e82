"""Tolerance and pin-clearance Monte Carlo of a linkage, and its first-order (linearised) band.

``tolerance(linkage, spec, builds=B, samples=N, seed=S)`` builds B copies of the linkage whose
dimensions are drawn from ``spec`` and whose pins have the play their ISO 286 fits give, solves
each over the cycle with the batch engine, and reports per build the largest distance of each
traced point from the nominal at the same input (:meth:`ToleranceResult.deviation`, mm), of each
link's angle (:meth:`ToleranceResult.angle_deviation`, °), and per sample the quantiles of the
deviation across the path (:meth:`ToleranceResult.envelope`). ``spec``::

    {"length:crank:A:B": {"normal": 0.0167},        # σ, mm (or ° for an angle key)
     "length:coupler:B:C": {"uniform": 0.05},       # half-width
     "x:D": {"normal": 0.02, "bias": 0.01},         # optional shift of the mean
     "clearance": {"B": "H7/g6", "C": {"fit": "H8/f7", "diameter": 10.0, "distribution": "normal"}}}

Variables are the keys of :mod:`.keys`; a clearance names a revolute joint on two or more links
and a fit on its bore diameter (default: the drawn bore of the exported parts, 40 % of the boss
radius, which is 12 % of the median link length). Its radial play per build is half the clearance
of a hole and a shaft drawn within their limits (:meth:`~.iso286.Fit.radial_play`); the pin's
play direction is the worst at every sample (:mod:`.tol_kernels`). Builds that do not assemble
(at the drawn input or anywhere the nominal does) count with an infinite deviation: they are never
dropped from a percentile, and :attr:`ToleranceResult.failed` says how many there are.

The same seed gives the same numbers whatever runs the builds (:mod:`.execute`: blocks of
:data:`BLOCK` builds with their own random stream). A block runs as one generated compiled loop
(:mod:`.tol_fused`) where the plan has one and the run is large (``fast``), else by the reference
path: the batch engine's arrays reduced by :func:`.tol_kernels.reduce_point` (the tests compare
the two).
"""
from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import numpy as np

from ..analyses.parts.linkage import BORE_FRACTION, BOSS_FRACTION, scale_of
from ..errors import RequestError
from ..model.linkage import JointKind, Linkage
from ..solver.plan import compile_plan
from .budget import check_kept, size_text
from .engine import BatchPlan
from .execute import block_rng, run_tasks
from .fused import fusable
from .geometry import build_geometry
from .iso286 import Fit, fit
from .keys import check_keys, variables
from .linearised import Nominal, _normals, derivatives
from .tol_fused import TolFused
from .tol_kernels import reduce_angle, reduce_point, scan_table
from .variants import Variants

#: builds per block: the unit of random numbers and of work handed to a worker (below 2¹⁶: a
#: block's histogram counts are sent as 16-bit integers)
BLOCK = 4096
#: histogram bins per sample of the envelope
BINS = 512


@dataclass(frozen=True)
class Spec:
    """A parsed tolerance spec: ``variables`` [(key, "normal"|"uniform", σ or half-width, bias)],
    ``clearances`` [(joint, Fit, distribution)]."""

    variables: tuple
    clearances: tuple

    @property
    def keys(self) -> list[str]:
        return [v[0] for v in self.variables]

    @property
    def pins(self) -> list[str]:
        return [c[0] for c in self.clearances]


def bore_diameter(linkage: Linkage) -> float:
    """The drawn bore diameter of the exported parts (mm): 2 · 0.4 · (0.12 · median link length)."""
    return 2.0 * BORE_FRACTION * BOSS_FRACTION * scale_of(linkage)


def _number(entry: str, name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise RequestError(f"tolerance {entry!r}: {name} must be a finite number, got {v!r}")
    return float(v)


def parse_spec(linkage: Linkage, spec: dict) -> Spec:
    """Check ``spec`` (see the module docstring); RequestError naming the entry at fault."""
    if not isinstance(spec, dict):
        raise RequestError("a tolerance spec is a dict {key: {\"normal\": σ} | {\"uniform\": w}, "
                           "\"clearance\": {joint: \"H7/g6\"}}")
    keys = [k for k in spec if k != "clearance"]
    check_keys(linkage, keys, "tolerance")
    var = []
    for k in keys:
        d = spec[k]
        if not isinstance(d, dict) or len(set(d) & {"normal", "uniform"}) != 1 or set(d) - {"normal", "uniform", "bias"}:
            raise RequestError(f"tolerance {k!r}: give one of {{\"normal\": σ}} or {{\"uniform\": half-width}} "
                               f"(and optionally \"bias\"), got {d!r}")
        kind = "normal" if "normal" in d else "uniform"
        width = _number(k, "σ" if kind == "normal" else "the half-width", d[kind])
        if width < 0:
            raise RequestError(f"tolerance {k!r}: {'σ' if kind == 'normal' else 'the half-width'} must not be "
                               f"negative, got {width:g}")
        var.append((k, kind, width, _number(k, "bias", d.get("bias", 0.0))))
    cl = []
    clear = spec.get("clearance", {})
    if not isinstance(clear, dict):
        raise RequestError("tolerance 'clearance': give {joint: \"H7/g6\"} or {joint: {\"fit\": ..., \"diameter\": ...}}")
    for j, entry in clear.items():
        if j not in linkage.joint_ids:
            raise RequestError(f"clearance {j!r}: linkage {linkage.id!r} has no joint {j!r} (its joints: "
                               f"{', '.join(linkage.joint_ids)})")
        if linkage.joint(j).kind is not JointKind.R or len(linkage.links_of(j)) < 2:
            raise RequestError(f"clearance {j!r}: a clearance is a pin's: {j!r} must be a revolute joint on two or "
                               "more links")
        drv = linkage.driver
        if drv.kind == "cylinder":
            raise RequestError(f"clearance {j!r}: pin play is not modelled in cylinder-driven linkages")
        e = entry if isinstance(entry, dict) else {"fit": entry}
        if set(e) - {"fit", "diameter", "distribution"}:
            raise RequestError(f"clearance {j!r}: unknown fields {sorted(set(e) - {'fit', 'diameter', 'distribution'})}")
        dia = _number(f"clearance {j}", "diameter", e.get("diameter", bore_diameter(linkage)))
        dist = e.get("distribution", "uniform")
        if dist not in ("uniform", "normal"):
            raise RequestError(f"clearance {j!r}: distribution must be 'uniform' or 'normal', got {dist!r}")
        try:
            f = fit(e.get("fit"), dia)
        except RequestError as exc:
            raise RequestError(f"clearance {j!r}: {exc}") from None
        cl.append((j, f, dist))
    return Spec(tuple(var), tuple(cl))


def draw(spec: Spec, nominal: dict, seed: int, block: int, n: int) -> tuple[dict, np.ndarray]:
    """The values (key -> (n,)) and radial plays (n, pins) of block ``block``'s n builds."""
    rng = block_rng(seed, block)
    values = {}
    for key, kind, w, bias in spec.variables:
        x = rng.normal(0.0, w, n) if kind == "normal" else rng.uniform(-w, w, n)
        values[key] = nominal[key] + bias + x
    plays = np.zeros((n, len(spec.clearances)))
    for m, (_, f, dist) in enumerate(spec.clearances):
        plays[:, m] = f.radial_play(rng, n, dist)
    return values, plays


@functools.lru_cache(maxsize=8)
def _plan(linkage: Linkage) -> BatchPlan:
    """The batch plan of a linkage, made once per process (a worker keeps it between tasks)."""
    return BatchPlan(linkage)


class _Context:
    """What a task needs (picklable: sent once to each Dask worker)."""

    def __init__(self, linkage: Linkage, spec: Spec, samples: int, seed: int, builds: int, joints: list,
                 links: list, nominal: dict, arrays: dict, fast: bool | None) -> None:
        self.linkage, self.spec, self.samples, self.seed, self.builds = linkage, spec, samples, seed, builds
        self.joints, self.links, self.nominal, self.arrays, self.fast = joints, links, nominal, arrays, fast


def _accumulators(joints: list, links: list, n: int, N: int) -> dict:
    """A block's empty results: per traced joint the histograms, extremes, moments, failures and
    deviations, per followed link the deviations."""
    return {"joints": {j: {"hist_up": np.zeros((N, BINS + 2), dtype=np.uint16),
                           "hist_lo": np.zeros((N, BINS + 2), dtype=np.uint16),
                           "ext": np.tile(np.array([np.inf, -np.inf, np.inf, -np.inf]), (N, 1)),
                           "mom": np.zeros((N, 2)), "fails": np.zeros(N, dtype=np.int64), "dev": np.empty(n)}
                       for j in joints},
            "links": {k: np.empty(n) for k in links}}


def _reference(ctx: _Context, values: dict, plays: np.ndarray, n: int, out: dict, idx=None) -> np.ndarray:
    """Builds ``idx`` (default all n) by the reference path — the batch engine's (B, N, 2) arrays,
    then :func:`.tol_kernels.reduce_point` — added to ``out``; returns whether each assembled."""
    bp = _plan(ctx.linkage)
    if idx is not None:
        values, plays, n = {k: v[idx] for k, v in values.items()}, plays[idx], idx.size
    b = Variants(bp, values, n, bp.inputs(ctx.samples), 0)
    b.fast = False if ctx.fast is False else None
    b._compute([(j, 0) for j in ctx.joints], [(k, 0) for k in ctx.links], summary=True)
    ok = b._status & 1
    A = ctx.arrays
    for j in ctx.joints:
        a, o = A["joints"][j], out["joints"][j]
        dev = np.empty(n)
        reduce_point(b.position(j), ok, a["pos"], a["normal"], A["valid"], a["S"], a["T"], a["smax"], a["g"], plays,
                     a["lo"], a["width"], o["hist_up"], o["hist_lo"], o["ext"], o["mom"], o["fails"], dev)
        o["dev"][slice(None) if idx is None else idx] = dev
    for k in ctx.links:
        dev = np.empty(n)
        reduce_angle(b.angle(k), ok, A["links"][k]["ang"], A["valid"], A["links"][k]["t"], plays, dev)
        out["links"][k][slice(None) if idx is None else idx] = dev
    return b.assembled.copy()


@functools.lru_cache(maxsize=8)
def _tol_kernel(linkage: Linkage, joints: tuple, links: tuple) -> TolFused:
    return TolFused(_plan(linkage), joints, links)


def _fused(ctx: _Context, values: dict, plays: np.ndarray, n: int, out: dict) -> np.ndarray:
    """The block by the fused tolerance kernel (:mod:`.tol_fused`); builds near a toggle by the
    reference path. Returns whether each build assembled."""
    bp = _plan(ctx.linkage)
    tf = _tol_kernel(ctx.linkage, tuple(ctx.joints), tuple(ctx.links))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        geo = build_geometry(bp.linkage, bp.plan, values, n)
        K = bp.constants(geo)
        C = tf.columns(K)
    ok = np.ascontiguousarray(geo.ok)
    th = bp.inputs(ctx.samples).q - bp.plan.theta0
    A = ctx.arrays
    redo = np.zeros(n, dtype=bool)
    jargs = []
    for j in ctx.joints:
        a, o = A["joints"][j], out["joints"][j]
        jargs += [a["pos"], a["normal"], a["S"], a["T"], a["Q"], a["smax"], a["g"], a["lo"], a["width"], o["hist_up"],
                  o["hist_lo"], o["ext"], o["mom"], o["fails"], o["dev"]]
    for k in ctx.links:
        jargs += [A["links"][k]["ang"], A["links"][k]["t"], out["links"][k]]
    tf.kernel(C, tf.angle0(K), np.cos(th), np.sin(th), ok, A["valid"], np.ascontiguousarray(plays), redo, *jargs)
    if redo.any():
        _reference(ctx, values, plays, n, out, np.flatnonzero(redo))
    return ok


def _task(ctx: _Context, block: int) -> dict:
    """The builds of one block: per build the deviations, per sample the histograms and moments."""
    n = min(BLOCK, ctx.builds - block * BLOCK)
    values, plays = draw(ctx.spec, ctx.nominal, ctx.seed, block, n)
    out = _accumulators(ctx.joints, ctx.links, n, ctx.samples)
    bp = _plan(ctx.linkage)
    if ctx.fast and fusable(bp):
        out["assembled"] = _fused(ctx, values, plays, n, out)
    else:
        out["assembled"] = _reference(ctx, values, plays, n, out)
    for o in out["joints"].values():
        # a block's counts fit 16 bits (BLOCK < 2¹⁶): a quarter of the bytes a worker sends back
        o["hist_up"], o["hist_lo"] = o["hist_up"].astype(np.uint16, copy=False), o["hist_lo"].astype(np.uint16, copy=False)
    return out


def _total(arrays: list) -> np.ndarray:
    """The sum of the blocks' arrays in block order (counts in 64 bits, moments in float64)."""
    out = np.zeros(arrays[0].shape, dtype=np.int64 if arrays[0].dtype.kind in "iu" else np.float64)
    for a in arrays:
        out += a
    return out


class ToleranceResult:
    """The Monte Carlo of :func:`tolerance` (see the module docstring)."""

    def __init__(self, linkage: Linkage, spec: Spec, builds: int, samples: int, seed: int, nominal: Nominal,
                 parts: list, seconds: float) -> None:
        self.linkage, self.spec, self.builds, self.samples, self.seed = linkage, spec, builds, samples, seed
        self.nominal, self.seconds = nominal, seconds
        self.assembled = np.concatenate([p["assembled"] for p in parts])
        self._dev = {j: np.concatenate([p["joints"][j]["dev"] for p in parts]) for j in parts[0]["joints"]}
        self._ang = {k: np.degrees(np.concatenate([p["links"][k] for p in parts])) for k in parts[0]["links"]}
        self._acc = {}
        for j in self._dev:
            acc = {x: _total([p["joints"][j][x] for p in parts]) for x in ("hist_up", "hist_lo", "mom", "fails")}
            ext = np.stack([p["joints"][j]["ext"] for p in parts])
            acc["ext"] = np.stack([ext[:, :, 0].min(0), ext[:, :, 1].max(0), ext[:, :, 2].min(0), ext[:, :, 3].max(0)], 1)
            self._acc[j] = acc

    @property
    def joints(self) -> list[str]:
        return list(self._dev)

    @property
    def links(self) -> list[str]:
        return list(self._ang)

    @property
    def failed(self) -> int:
        """Builds that do not assemble at their drawn input or lose assembly where the nominal is
        assembled (their deviations are infinite)."""
        first = next(iter(self._dev.values()), None)
        return int(np.sum(~np.isfinite(first))) if first is not None else int(np.sum(~self.assembled))

    def _joint(self, joint: str) -> str:
        if joint not in self._dev:
            raise RequestError(f"joint {joint!r} was not traced by this tolerance run (traced: {', '.join(self._dev)}); "
                               "ask for it with joints=[...]")
        return joint

    def deviation(self, joint: str) -> np.ndarray:
        """(B,) per build the largest distance of ``joint`` from its nominal position at the same
        input over the cycle, mm, pins at their worst (inf: the build fails somewhere)."""
        return self._dev[self._joint(joint)]

    def angle_deviation(self, link: str) -> np.ndarray:
        """(B,) per build the largest |angle − nominal| of ``link`` over the cycle, degrees."""
        if link not in self._ang:
            raise RequestError(f"link {link!r} was not followed by this tolerance run (followed: "
                               f"{', '.join(self._ang)}); ask for it with links=[...]")
        return self._ang[link]

    def percentile(self, joint: str, q: float) -> float:
        """The q-th percentile (0-100) of :meth:`deviation` (linear between the two nearest builds),
        failed builds counted at +inf: inf once the percentile reaches them."""
        return percentile(self.deviation(joint), q)

    def envelope(self, joint: str, q: float) -> np.ndarray:
        """(N, 2) per sample the point at the q-quantile (0 < q < 1) of the builds' signed deviation
        along the nominal path's normal (the velocity turned +90°), pins at their worst that way for q ≥
        0.5 and the other way below; the envelope(j, 0.995) and (j, 0.005) curves bound a 99 % band.
        Builds that fail at a sample count at the far side; where they reach the quantile, and
        where the nominal itself does not assemble, the point is NaN."""
        j = self._joint(joint)
        if not 0.0 < q < 1.0:
            raise RequestError(f"q is a quantile between 0 and 1, got {q!r}")
        acc, a = self._acc[j], self.nominal
        hist = acc["hist_up"] if q >= 0.5 else acc["hist_lo"]
        ext = acc["ext"][:, 2:4] if q >= 0.5 else acc["ext"][:, 0:2]
        lo, w = self._bins[j]
        s = np.full(self.samples, np.nan)
        for k in np.flatnonzero(a.valid):
            s[k] = _quantile(hist[k], acc["fails"][k], q, self.builds, lo[k], w[k], ext[k])
        return a.pos[j] + s[:, None] * a.normal[j]

    def sigma(self, joint: str) -> np.ndarray:
        """(N,) the standard deviation of the dimensions' normal deviation over the builds
        assembled at each sample (pins excluded), mm."""
        acc = self._acc[self._joint(joint)]
        n = self.builds - acc["fails"]
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = acc["mom"][:, 0] / n
            var = acc["mom"][:, 1] / n - mean * mean
        return np.where(self.nominal.valid, np.sqrt(np.maximum(var, 0.0) * n / np.maximum(n - 1, 1)), np.nan)

    def sensitivity(self, joint: str | None = None) -> dict[str, float]:
        """Each variable's and pin's share (sum 1) of the first-order variance of ``joint``'s
        displacement over the cycle (default the first traced joint), from the exact derivatives."""
        return sensitivity(self.nominal, self.spec, joint or self.joints[0])

    def summary(self, joint: str | None = None) -> str:
        j = joint or self.joints[0]
        d = self.deviation(j)
        fin = np.isfinite(d)
        head = (f"tolerance of {self.linkage.id!r}: {self.builds:,} builds × {self.samples} samples in "
                f"{self.seconds:.2f} s, seed {self.seed}")
        lines = [head, f"builds that do not assemble over the cycle: {self.failed:,} "
                       f"({self.failed / max(self.builds, 1):.3%}; counted at +inf in the percentiles)"]
        if fin.any():
            p = [percentile(d, q) for q in (50, 95, 99, 99.9)]
            lines.append(f"deviation of {j} (mm): median {p[0]:.6g}, p95 {p[1]:.6g}, p99 {p[2]:.6g}, p99.9 {p[3]:.6g}, "
                         f"max {np.max(d):.6g}")
        shares = self.sensitivity(j)
        lines.append("first-order shares: " + ", ".join(f"{k} {v:.1%}" for k, v in
                                                        sorted(shares.items(), key=lambda kv: -kv[1])))
        return "\n".join(lines)


def percentile(values: np.ndarray, q: float) -> float:
    """The q-th percentile (0-100) of ``values`` with linear interpolation, +inf values at the top
    (inf where the interpolation reaches one: never inf − inf)."""
    v = np.sort(np.asarray(values, dtype=float))
    if v.size == 0:
        return math.nan
    x = q / 100.0 * (v.size - 1)
    lo, hi = int(math.floor(x)), int(math.ceil(x))
    if not math.isfinite(v[hi]):
        return math.inf
    return float(v[lo] + (x - lo) * (v[hi] - v[lo]))


def _quantile(h: np.ndarray, fails: int, q: float, total: int, lo: float, w: float, ext) -> float:
    """The q-quantile of a histogram h (under, bins…, over) of total − fails values, the failed
    ones at +inf (q ≥ 0.5) or −inf (below): linear within a bin, the extremes bounding the ends."""
    nb = h.size - 2
    target = q * total
    if q < 0.5:
        target -= fails
        if target <= 0:
            return -np.inf
    elif target > total - fails:
        return np.inf
    cum = np.cumsum(h)
    i = int(np.searchsorted(cum, target))
    i = min(i, h.size - 1)
    before = cum[i - 1] if i else 0
    frac = (target - before) / h[i] if h[i] else 0.0
    if i == 0:
        a, b = ext[0], lo
    elif i == nb + 1:
        a, b = lo + nb * w, ext[1]
    else:
        a, b = lo + (i - 1) * w, lo + i * w
    return float(a + frac * (b - a))


def sensitivity(nom: Nominal, spec: Spec, joint: str) -> dict[str, float]:
    """First-order variance shares of ``joint``'s displacement summed over the cycle."""
    v = nom.valid
    var = {}
    for i, (key, kind, w, _bias) in enumerate(spec.variables):
        s2 = w * w if kind == "normal" else w * w / 3.0
        var[key] = s2 * float(np.sum(nom.dpos[joint][i][v] ** 2))
    for m, (j, f, _dist) in enumerate(spec.clearances):
        var[f"clearance:{j}"] = 0.5 * f.mean_square_play * float(np.sum(nom.S[joint][m][v] ** 2))
    total = sum(var.values())
    return {k: (x / total if total > 0 else 0.0) for k, x in var.items()}


class LinearBand:
    """The first-order band of :func:`linearised_tolerance`: per sample the standard deviation of
    each traced point along its path's normal, σ_n(k) = √Σ σ_i²·(ν·∂p/∂x_i)², and the pins' worst
    case Σ r_max·|S_Jᵀ ν| (mm)."""

    def __init__(self, nominal: Nominal, spec: Spec) -> None:
        self.nominal, self.spec = nominal, spec

    def sigma(self, joint: str) -> np.ndarray:
        """(N,) mm."""
        n = self.nominal
        nu = n.normal[joint]
        var = np.zeros(n.N)
        for i, (_k, kind, w, _b) in enumerate(self.spec.variables):
            s2 = w * w if kind == "normal" else w * w / 3.0
            var += s2 * (n.dpos[joint][i] * nu).sum(axis=1) ** 2
        return np.where(n.valid, np.sqrt(var), np.nan)

    def clearance(self, joint: str) -> np.ndarray:
        """(N,) mm: the pins at their largest play, each in its worst direction along the normal."""
        n = self.nominal
        nu = n.normal[joint]
        out = np.zeros(n.N)
        for m, (_j, f, _d) in enumerate(self.spec.clearances):
            t = np.einsum("kab,ka->kb", n.S[joint][m], nu)
            out += 0.5 * max(f.clearance_max, 0.0) * np.hypot(t[:, 0], t[:, 1])
        return np.where(n.valid, out, np.nan)

    def band(self, joint: str, k: float = 3.0) -> np.ndarray:
        """(N,) k·σ_n + the pins' worst case, mm."""
        return k * self.sigma(joint) + self.clearance(joint)

    def envelope(self, joint: str, k: float = 3.0, side: float = 1.0) -> np.ndarray:
        """(N, 2) the nominal path moved by ``side``·band along its normal."""
        return self.nominal.pos[joint] + side * self.band(joint, k)[:, None] * self.nominal.normal[joint]

    def sensitivity(self, joint: str) -> dict[str, float]:
        return sensitivity(self.nominal, self.spec, joint)

    def agreement(self, mc: ToleranceResult, joint: str, k: float = 3.0) -> float:
        """The largest relative difference, over the samples, between this band's k·σ_n and the
        Monte Carlo's k × standard deviation of the dimensions' normal deviation (samples where
        the band is below 1e-9 of the largest are skipped)."""
        a, b = k * self.sigma(joint), k * mc.sigma(joint)
        big = np.nanmax(a)
        m = np.isfinite(a) & np.isfinite(b) & (a > 1e-9 * big)
        return float(np.max(np.abs(b[m] - a[m]) / a[m])) if m.any() else 0.0


def _setup(linkage: Linkage, spec: Spec, samples: int, joints: list, links: list) -> tuple[Nominal, dict]:
    """The nominal motion, its derivatives and the per-sample arrays the reducers read."""
    bp = _plan(linkage)
    inp = bp.inputs(samples)
    nom = derivatives(bp, inp, spec.keys, spec.pins, joints, links)
    sol = compile_plan(linkage).sweep(samples, 1, joints=joints or None)
    arrays = {"valid": nom.valid.copy(), "joints": {}, "links": {}}
    for j in joints:
        nom.normal[j] = _normals(nom.pos[j], sol.velocity(j) if sol.order >= 1 else None)
        S = nom.S[j]
        smax = np.sqrt(np.maximum(np.linalg.eigvalsh(S @ np.swapaxes(S, -1, -2))[..., -1], 0.0)) if S.size else \
            np.zeros((0, samples))
        g = np.hypot(*np.einsum("pkab,ka->pkb", S, nom.normal[j]).transpose(2, 0, 1)) if S.size else np.zeros((0, samples))
        band = LinearBand(nom, spec)
        sig = np.nan_to_num(band.sigma(j))
        gmax = np.nan_to_num(band.clearance(j))
        size = float(np.nanmax(np.abs(nom.pos[j]))) + 1.0
        R = 8.0 * sig + 2.0 * gmax + 1e-9 * size
        arrays["joints"][j] = {"pos": np.ascontiguousarray(nom.pos[j]), "normal": np.ascontiguousarray(nom.normal[j]),
                               "S": np.ascontiguousarray(S), "T": scan_table(np.ascontiguousarray(S)),
                               "Q": np.ascontiguousarray(np.stack([(S[..., 0, :] ** 2).sum(-1), (S[..., 0, :] * S[..., 1, :]).sum(-1),
                                                                   (S[..., 1, :] ** 2).sum(-1)], -1)),
                               "smax": np.ascontiguousarray(smax), "g": np.ascontiguousarray(g),
                               "lo": -R, "width": 2.0 * R / BINS}
    for k in links:
        T = nom.T[k]
        arrays["links"][k] = {"ang": nom.ang[k], "t": np.hypot(T[..., 0], T[..., 1]) if T.size else np.zeros((0, samples))}
    return nom, arrays


def default_joints(linkage: Linkage) -> list[str]:
    """The traced points of a tolerance run: the joints on one moving link only (coupler points),
    else every joint not on the frame."""
    ground = set(linkage.link(linkage.ground).joints)
    single = [j for j in linkage.joint_ids if len(linkage.links_of(j)) == 1 and j not in ground
              and linkage.joint(j).kind is JointKind.R]
    return single or [j for j in linkage.joint_ids if j not in ground]


def tolerance(linkage: Linkage, spec: dict, builds: int = 10_000, samples: int | None = None, seed: int = 0,
              joints=None, links=None, client=None, workers: int = 1, progress=None, cancel=None,
              fast: bool | None = None) -> ToleranceResult:
    """The Monte Carlo of the module docstring; ``joints`` the traced points (default
    :func:`default_joints`), ``links`` the links whose angles are followed (default every moving
    link); ``client``/``workers``/``progress``/``cancel`` as in :mod:`.execute`; ``fast``: True the
    fused tolerance kernel (:mod:`.tol_fused`, where the plan has one), False the numpy reference
    path, None the kernel from 2,000,000 build-samples on."""
    start = time.perf_counter()
    sp = parse_spec(linkage, spec)
    builds = int(builds)
    if builds < 1:
        raise RequestError(f"builds must be at least 1, got {builds}")
    N = int(samples or linkage.samples)
    js = list(default_joints(linkage) if joints is None else joints)
    ls = list(linkage.moving_links if links is None else links)
    for j in js:
        if j not in linkage.joint_ids:
            raise RequestError(f"joint {j!r}: linkage {linkage.id!r} has no such joint")
    for k in ls:
        if k not in linkage.link_ids:
            raise RequestError(f"link {k!r}: linkage {linkage.id!r} has no such link")
    kept = builds * 8.0 * (len(js) + len(ls) + 1) + len(js) * N * (BINS + 2) * 16.0
    work = max(workers, 1) * min(builds, BLOCK) * N * (18.0 * len(js) + 10.0 * len(ls) + 2.0)
    check_kept(kept + work, f"a tolerance run of {builds:,} builds × {N} samples",
               f"use fewer builds, samples or traced joints (each block of {BLOCK} builds needs "
               f"{size_text(work / max(workers, 1))})")
    nom, arrays = _setup(linkage, sp, N, js, ls)
    nominal = {k: v.nominal for k, v in variables(linkage).items() if k in sp.keys}
    if fast is None:
        fast = True if builds * N >= 2_000_000 else None
    ctx = _Context(linkage, sp, N, int(seed), builds, js, ls, nominal, arrays, fast)
    parts = run_tasks(_task, ctx, -(-builds // BLOCK), client=client, workers=workers, progress=progress,
                      cancel=cancel)
    res = ToleranceResult(linkage, sp, builds, N, int(seed), nom, parts, time.perf_counter() - start)
    res._bins = {j: (arrays["joints"][j]["lo"], arrays["joints"][j]["width"]) for j in js}
    return res


def linearised_tolerance(linkage: Linkage, spec: dict, samples: int | None = None, joints=None,
                         links=None) -> LinearBand:
    """The first-order band of ``spec`` from the exact derivatives (one solve; see
    :class:`LinearBand`); compare it with a Monte Carlo by :meth:`LinearBand.agreement`."""
    sp = parse_spec(linkage, spec)
    N = int(samples or linkage.samples)
    js = list(default_joints(linkage) if joints is None else joints)
    ls = list(linkage.moving_links if links is None else links)
    nom, _arrays = _setup(linkage, sp, N, js, ls)
    return LinearBand(nom, sp)


__all__ = ["BLOCK", "LinearBand", "percentile", "Spec", "ToleranceResult", "bore_diameter", "default_joints", "draw",
           "linearised_tolerance", "parse_spec", "sensitivity", "tolerance"]
