"""The atlas's records and storage: what a design of each topology is (:data:`SPECS`, normalised
frames), the :class:`Atlas` arrays, and where and how they are kept.

An atlas holds, per design, its normalised shape, :data:`POINTS` coupler points, the Fourier
descriptors of their coupler curves (:mod:`.descriptors`) and the first harmonics of its output
over one crank turn. It is stored versioned in the user cache folder (:func:`cache_dir`:
``$MECHSKETCH_CACHE_DIR``, else the platform's cache folder) under
``atlas-v{VERSION}/{topology}-{designs}/`` as ``.npy`` arrays and a ``meta.json``, written to a
temporary folder and then renamed, so that a killed build leaves nothing that loads; it is read
memory-mapped. Nearest-neighbour queries use scipy's ``cKDTree`` over the descriptors (built on
first query and kept with the atlas). Building and loading: :mod:`.atlas`.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import families as F
from .descriptors import DESC_DIM

VERSION = 2
#: what each format version changed (the message when an older cached atlas is rebuilt)
VERSION_CHANGES = {1: "closed-form build",
                   2: "built by the studies engine's batch kernels; six-bars with a slider (RRP) or a guided "
                      "rocker (RPR) as the second dyad added"}
#: coupler points per design
POINTS = 2
#: crank-angle samples per turn when building
SAMPLES = 96
#: harmonics of the output function kept
FUNC_HARMONICS = 4
#: designs whose transmission angle drops below this anywhere on the turn are left out, °
MIN_MU_DEG = 15.0
#: the default atlas size (designs per topology) and a small one for tests and quick starts
DEFAULT_DESIGNS = 1_000_000
SMALL_DESIGNS = 20_000


@dataclass(frozen=True)
class Spec:
    """How a topology is sampled: ``names`` of its shape parameters, their ``ranges`` (lo, hi)
    and whether each is sampled ``log``-uniformly; the coupler point's box (u, v ranges, in
    units of ``point_unit``: "b" the coupler length, "1" the frame's unit, "l1" a six-bar's
    rod, "r" the least distance of a guided rocker's pivot from E; the last two set by
    :func:`~.atlas.sixbar_lengths`, :func:`~.atlas.slider_lengths`, :func:`~.atlas.guide_lengths`)."""

    names: tuple[str, ...]
    ranges: tuple[tuple[float, float], ...]
    log: tuple[bool, ...]
    u: tuple[float, float]
    v: tuple[float, float]
    point_unit: str


SPECS: dict[str, Spec] = {
    F.FOURBAR: Spec(("a", "b", "c"), ((0.12, 3.0), (0.2, 5.0), (0.2, 5.0)), (True, True, True),
                    (-1.0, 2.0), (-1.5, 1.5), "b"),
    F.SLIDER_CRANK: Spec(("h", "b"), ((-2.5, 2.5), (1.05, 8.0)), (False, True), (-0.5, 1.5), (-1.0, 1.0), "b"),
    F.INVERTED: Spec(("a", "e"), ((0.1, 5.0), (-1.0, 1.0)), (True, False), (-2.0, 2.0), (-1.0, 1.0), "1"),
    # drawn as a, b, c, E (units of b), F, l2/l1 and where l1 falls in its feasible range (0..1):
    # :func:`~.atlas.sixbar_lengths` turns them into a, b, c, ex, ey, Fx, Fy, l1, l2
    F.SIXBAR: Spec(("a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "l2"),
                   ((0.12, 1.0), (0.3, 3.0), (0.3, 3.0), (-0.5, 1.5), (-1.0, 1.0), (-1.5, 2.5), (-2.0, 2.0),
                    (0.3, 3.0), (0.0, 1.0)),
                   (True, True, True, False, False, False, False, True, False), (-0.5, 1.5), (-1.0, 1.0), "l1"),
    # the same, E on the rocker (units of c)
    F.WATT: Spec(("a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "l2"),
                 ((0.12, 1.0), (0.3, 3.0), (0.3, 3.0), (-0.5, 1.5), (-1.0, 1.0), (-1.5, 2.5), (-2.0, 2.0),
                  (0.3, 3.0), (0.0, 1.0)),
                 (True, True, True, False, False, False, False, True, False), (-0.5, 1.5), (-1.0, 1.0), "l1"),
    # with a slider (RRP) as the second dyad: a, b, c, E (units of b; of c on a Watt), a point F
    # of the guide, where the rod l1 falls in its range (0..1, :func:`~.atlas.slider_lengths`)
    # and the guide's direction g (rad; the other sense is the other assembly mode)
    F.SIXBAR_SLIDER: Spec(("a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "g"),
                          ((0.12, 1.0), (0.3, 3.0), (0.3, 3.0), (-0.5, 1.5), (-1.0, 1.0), (-1.5, 2.5), (-2.0, 2.0),
                           (0.0, 1.0), (0.0, math.pi)),
                          (True, True, True, False, False, False, False, False, False), (-0.5, 1.5), (-1.0, 1.0),
                          "l1"),
    F.WATT_SLIDER: Spec(("a", "b", "c", "ex", "ey", "Fx", "Fy", "l1", "g"),
                        ((0.12, 1.0), (0.3, 3.0), (0.3, 3.0), (-0.5, 1.5), (-1.0, 1.0), (-1.5, 2.5), (-2.0, 2.0),
                         (0.0, 1.0), (0.0, math.pi)),
                        (True, True, True, False, False, False, False, False, False), (-0.5, 1.5), (-1.0, 1.0), "l1"),
    # with a guided rocker (RPR) as the second dyad: a, b, c, E (units of b; of c on a Watt), the
    # rocker's pivot F and the guide's offset as a fraction −1..1 of the largest it may have
    # (:func:`~.atlas.guide_lengths`); the points in units of the least distance |E − F|
    F.SIXBAR_GUIDE: Spec(("a", "b", "c", "ex", "ey", "Fx", "Fy", "e"),
                         ((0.12, 1.0), (0.3, 3.0), (0.3, 3.0), (-0.5, 1.5), (-1.0, 1.0), (-1.5, 2.5), (-2.0, 2.0),
                          (-1.0, 1.0)),
                         (True, True, True, False, False, False, False, False), (-1.0, 1.0), (-1.0, 1.0), "r"),
    F.WATT_GUIDE: Spec(("a", "b", "c", "ex", "ey", "Fx", "Fy", "e"),
                       ((0.12, 1.0), (0.3, 3.0), (0.3, 3.0), (-0.5, 1.5), (-1.0, 1.0), (-1.5, 2.5), (-2.0, 2.0),
                        (-1.0, 1.0)),
                       (True, True, True, False, False, False, False, False), (-1.0, 1.0), (-1.0, 1.0), "r"),
}


def family_params(topology: str, shape: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(D, K) :mod:`.families` parameters of normalised designs: ``shape`` (D, S), ``points``
    (D, 2) one coupler point each (normalised units)."""
    d = shape.shape[0]
    z, one = np.zeros(d), np.ones(d)
    px, py = points[:, 0], points[:, 1]
    if topology == F.FOURBAR:
        return np.stack([z, z, one, z, shape[:, 0], shape[:, 1], shape[:, 2], px, py], axis=1)
    if topology == F.SLIDER_CRANK:
        return np.stack([z, z, z, shape[:, 0], one, shape[:, 1], px, py], axis=1)
    if topology in F.ALL_SIXBARS:
        return np.concatenate([np.stack([z, z, one, z], axis=1), shape, np.stack([px, py], axis=1)], axis=1)
    return np.stack([z, z, one, z, shape[:, 0], shape[:, 1], px, py], axis=1)


def cache_dir() -> Path:
    """The user cache folder of mechsketch: ``$MECHSKETCH_CACHE_DIR``, else ``$XDG_CACHE_HOME``
    or ``~/.cache`` on Linux, ``~/Library/Caches`` on macOS, ``%LOCALAPPDATA%`` on Windows."""
    env = os.environ.get("MECHSKETCH_CACHE_DIR")
    if env:
        return Path(env)
    if sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    elif os.name == "nt":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "mechsketch"


def atlas_folder(topology: str, designs: int, version: int = VERSION) -> Path:
    """Where the atlas of ``topology`` with ``designs`` designs of format ``version`` is kept."""
    return cache_dir() / f"atlas-v{version}" / f"{topology}-{designs}"


def read_meta(folder: Path) -> dict | None:
    """The ``meta.json`` of the atlas in ``folder`` (any version), or None."""
    try:
        return json.loads((folder / "meta.json").read_text())
    except (OSError, ValueError):
        return None


@dataclass
class Atlas:
    """One topology's atlas. ``shape`` (D, S) float32 normalised shape parameters; ``points``
    (D, POINTS, 2) float32 coupler points; ``desc`` (D·POINTS, DESC_DIM) float16 curve
    descriptors (row = design·POINTS + point); ``func`` (D, 2·FUNC_HARMONICS + 1) float16 the
    output's harmonics; ``turns`` (D,) int8 the output's turns per crank turn; ``mu`` (D,)
    float16 the least transmission angle, °; ``meta`` what was built, how and when."""

    topology: str
    shape: np.ndarray
    points: np.ndarray
    desc: np.ndarray
    func: np.ndarray
    turns: np.ndarray
    mu: np.ndarray
    meta: dict = field(default_factory=dict)
    _tree: object = field(default=None, repr=False)

    def __len__(self) -> int:
        return int(self.shape.shape[0])

    def tree(self):
        """The cKDTree over the curve descriptors (built on first use)."""
        if self._tree is None:
            from scipy.spatial import cKDTree

            self._tree = cKDTree(np.asarray(self.desc, dtype=np.float64), leafsize=32, balanced_tree=False)
        return self._tree

    def params(self, rows: np.ndarray) -> np.ndarray:
        """(R, K) family parameters of curve rows (design·POINTS + point)."""
        rows = np.asarray(rows)
        d, p = rows // POINTS, rows % POINTS
        return family_params(self.topology, np.asarray(self.shape[d], float), np.asarray(self.points[d, p], float))

    def nearest(self, queries: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
        """(distances (Q, k), curve rows (Q, k)) of the ``k`` nearest descriptors to each query."""
        dist, idx = self.tree().query(np.asarray(queries, float), k=min(k, self.desc.shape[0]))
        return np.atleast_2d(dist), np.atleast_2d(idx)


_ARRAYS = ("shape", "points", "desc", "func", "turns", "mu")


def save_atlas(atlas: Atlas, folder: Path) -> None:
    """Write ``atlas`` to ``folder`` atomically (a temporary sibling folder, then a rename)."""
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{folder.name}.", dir=folder.parent))
    try:
        for name in _ARRAYS:
            np.save(tmp / f"{name}.npy", np.ascontiguousarray(getattr(atlas, name)))
        (tmp / "meta.json").write_text(json.dumps(atlas.meta, indent=1))
        if folder.exists():
            shutil.rmtree(folder)
        os.replace(tmp, folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def read_atlas(folder: Path) -> Atlas | None:
    """The atlas stored in ``folder`` (memory-mapped), or None if it is missing, of another
    version or incomplete."""
    try:
        meta = json.loads((folder / "meta.json").read_text())
        if meta.get("version") != VERSION:
            return None
        arrays = {name: np.load(folder / f"{name}.npy", mmap_mode="r") for name in _ARRAYS}
    except (OSError, ValueError):
        return None
    return Atlas(meta["topology"], meta=meta, **arrays)


def disk_bytes(folder: Path) -> int:
    """Bytes the atlas in ``folder`` takes on disk."""
    return sum(p.stat().st_size for p in folder.iterdir() if p.is_file())


def function_values(atlas: Atlas, rows: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(R, N) the output (normalised units: rad or crank lengths) of designs ``rows`` at crank
    angles ``theta`` (R, N) or (N,), rebuilt from the stored harmonics (an approximation good
    for retrieval only)."""
    f = np.asarray(atlas.func[rows], dtype=float)
    th = np.broadcast_to(theta, (len(rows),) + np.shape(theta)[-1:])
    out = f[:, :1] + np.asarray(atlas.turns[rows], float)[:, None] * th
    for k in range(1, FUNC_HARMONICS + 1):
        out = out + f[:, 2 * k - 1:2 * k] * np.cos(k * th) + f[:, 2 * k:2 * k + 1] * np.sin(k * th)
    return out


__all__ = ["Atlas", "DEFAULT_DESIGNS", "DESC_DIM", "FUNC_HARMONICS", "MIN_MU_DEG", "POINTS", "SAMPLES", "SMALL_DESIGNS",
           "SPECS", "Spec", "VERSION", "VERSION_CHANGES", "atlas_folder", "cache_dir", "disk_bytes", "family_params",
           "function_values", "read_atlas", "read_meta", "save_atlas"]
