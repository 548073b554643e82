"""The atlas solved by the product's batch engine (:func:`~mechsketch.core.studies.variants.solve_variants`).

Each topology has a template linkage in the atlas's normalised frame, drawn at crank angle 0 in
the assembly modes the atlas uses (σ = +1), with :data:`~.atlas_store.POINTS` coupler points
``P1``, ``P2`` on its link ``coupler``; a chunk of designs is the template with its dimension
values changed (the keys of the studies engine: ``length:LINK:A:B``, ``offset:LINK:P``,
``axis:LINK:P``, ``angle:LINK:A:B:C``, ``point:LINK:J:x|y``, ``x:J``/``y:J``), solved over one
crank turn of N samples in one call. :func:`engine_solver` has the signature of
:data:`~.atlas.Solver` and is the one :func:`~.atlas.build_atlas` uses by default (atlas
format v2); the tests compare it with the closed form (:func:`~.atlas.closed_form_solver`)
design by design, chunk by chunk and atlas by atlas. The six-bars with a slider
(``sixbar_slider``, ``watt_sixbar_slider``) set the guide by ``axis:ground:S`` (its direction)
and ``x:S``/``y:S`` (a point of it).
"""
from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache

import numpy as np

from ..model.linkage import Joint, JointKind, Link, Linkage
from ..studies.variants import solve_variants
from . import families as F
from .atlas_store import POINTS, family_params
from .candidates import build_linkage

#: FAR: how far (normalised units) the template's points lie off their link: a length key keeps
#: the other sides of each triangle a point makes with the link (as SetDimension), so the
#: template's points must close a triangle whatever length a design sets; the point keys, applied
#: after the lengths, then put them where the design has them
FAR = 40.0
#: a design of each topology, assembled at crank angle 0 (the six-bars' E far off its link, the
#: dyad E–G–F closed about it)
_TEMPLATE_SHAPE = {
    F.FOURBAR: [0.4, 1.2, 1.0],
    F.SLIDER_CRANK: [0.3, 2.5],
    F.INVERTED: [0.4, 0.1],
    F.SIXBAR: [0.3, 1.2, 1.0, 0.6, FAR, None, None, 20.0, 20.0],
    F.WATT: [0.3, 1.2, 1.0, 0.5, FAR, None, None, 20.0, 20.0],
    # the slider's guide vertical through F, 10 units beside E; the rod 20 long
    F.SIXBAR_SLIDER: [0.3, 1.2, 1.0, 0.6, FAR, None, None, 20.0, math.pi / 2],
    F.WATT_SLIDER: [0.3, 1.2, 1.0, 0.5, FAR, None, None, 20.0, math.pi / 2],
    # the guided rocker's pivot F 30 units beside E, its guide at offset 2
    F.SIXBAR_GUIDE: [0.3, 1.2, 1.0, 0.6, FAR, None, None, 2.0],
    F.WATT_GUIDE: [0.3, 1.2, 1.0, 0.5, FAR, None, None, 2.0],
}
#: the output link of each topology
OUTPUT_LINK = {F.SLIDER_CRANK: "slider", F.SIXBAR: "rocker2", F.WATT: "rocker2", F.SIXBAR_SLIDER: "slider",
               F.WATT_SLIDER: "slider", F.SIXBAR_GUIDE: "rocker2", F.WATT_GUIDE: "rocker2"}
_POINTS = np.array([[0.0, FAR], [0.0, -FAR]])   # x: half the link's length is added


@lru_cache(maxsize=None)
def template(topology: str, samples: int) -> Linkage:
    """The template linkage of ``topology`` (see the module docstring)."""
    shape = list(_TEMPLATE_SHAPE[topology])
    if topology in F.ALL_SIXBARS:     # F beside E, so that the dyad closes (its mode +1, as the atlas's)
        four = family_params(F.FOURBAR, np.array([shape[:3]]), np.array([shape[3:5]]))
        if topology in F.WATTS:
            ev4 = F.evaluate(F.FOURBAR, four, np.zeros((1, 1)), 1.0)
            E = 1.0 + complex(shape[3], shape[4]) * (ev4.joints["C"][0, 0] - 1.0) / shape[2]
        else:
            E = complex(F.evaluate(F.FOURBAR, four, np.zeros((1, 1)), 1.0).P[0, 0])
        shape[5], shape[6] = E.real + (10.0 if topology in F.SLIDER_SIXBARS else 30.0), E.imag
    x = family_params(topology, np.array([shape], dtype=float), _POINTS[:1])[0]
    lk = build_linkage(topology, x, 1.0, 0.0, f"atlas_{topology}", samples=samples)
    ev = F.evaluate(topology, x[None], np.zeros((1, 1)), 1.0)
    B = ev.joints["E" if topology in F.ALL_SIXBARS else "B"][0, 0]
    extra = []
    if topology == F.INVERTED or topology in F.GUIDE_SIXBARS:   # a helper joint H one unit along the guide:
        # the block's frame is the guide's
        frame, half = ev.joints["u"][0, 0], 0.0
        extra = [Joint("H", JointKind.R, ((B + frame).real, (B + frame).imag))]
    elif topology in F.ALL_SIXBARS:
        frame, half = (ev.joints["G"][0, 0] - B) / x[11], x[11] / 2
    else:
        frame, half = (ev.joints["C"][0, 0] - B) / x[5], x[5] / 2
    pts = [B + complex(p[0] + half, p[1]) * frame for p in _POINTS[:POINTS]]
    joints = [j for j in lk.joints if j.id != "P"] + extra + [Joint(f"P{k + 1}", JointKind.R, (p.real, p.imag))
                                                             for k, p in enumerate(pts)]
    more = tuple(j.id for j in extra) + tuple(f"P{i + 1}" for i in range(POINTS))
    links = tuple(Link(k.id, tuple(j for j in k.joints if j != "P") + (more if k.id == "coupler" else ()))
                  for k in lk.links)
    return replace(lk, joints=tuple(joints), links=links)


def _values(topology: str, shape: np.ndarray, points: np.ndarray) -> dict[str, np.ndarray]:
    """The engine's keys and values of designs ``shape`` (D, S), ``points`` (D, P, 2)."""
    v: dict[str, np.ndarray] = {}
    if topology == F.FOURBAR:
        v = {"length:crank:A:B": shape[:, 0], "length:coupler:B:C": shape[:, 1], "length:rocker:D:C": shape[:, 2]}
    elif topology == F.SLIDER_CRANK:
        v = {"length:coupler:B:C": shape[:, 1], "offset:ground:S": -shape[:, 0]}
    elif topology == F.INVERTED:
        v = {"length:crank:A:B": shape[:, 0], "offset:rocker:Q": -shape[:, 1]}
    elif topology in F.GUIDE_SIXBARS:    # the guide's offset from F, then F moved
        host = "rocker" if topology in F.WATTS else "connector"
        v = {"length:crank:A:B": shape[:, 0], "length:connector:B:C": shape[:, 1], "length:rocker:D:C": shape[:, 2],
             f"point:{host}:E:x": shape[:, 3], f"point:{host}:E:y": shape[:, 4], "offset:rocker2:Q": -shape[:, 7],
             "x:F": shape[:, 5], "y:F": shape[:, 6]}
    elif topology in F.SLIDER_SIXBARS:   # the guide turned to g, then moved through F
        host = "rocker" if topology in F.WATTS else "connector"
        v = {"length:crank:A:B": shape[:, 0], "length:connector:B:C": shape[:, 1], "length:rocker:D:C": shape[:, 2],
             f"point:{host}:E:x": shape[:, 3], f"point:{host}:E:y": shape[:, 4],
             "axis:ground:S": np.degrees(shape[:, 8]), "x:S": shape[:, 5], "y:S": shape[:, 6],
             "length:coupler:E:G": shape[:, 7]}
    else:
        host = "rocker" if topology == F.WATT else "connector"
        v = {"length:crank:A:B": shape[:, 0], "length:connector:B:C": shape[:, 1], "length:rocker:D:C": shape[:, 2],
             f"point:{host}:E:x": shape[:, 3], f"point:{host}:E:y": shape[:, 4], "x:F": shape[:, 5],
             "y:F": shape[:, 6], "length:coupler:E:G": shape[:, 7], "length:rocker2:F:G": shape[:, 8]}
    for k in range(POINTS):
        v[f"point:coupler:P{k + 1}:x"] = points[:, k, 0]
        v[f"point:coupler:P{k + 1}:y"] = points[:, k, 1]
    return v


def _c(a: np.ndarray) -> np.ndarray:
    return a[..., 0] + 1j * a[..., 1]


def engine_solver(topology: str, shape: np.ndarray, points: np.ndarray, theta: np.ndarray, fast: bool = False):
    """Coupler points (D, P, N) complex, output (D, N), sin μ (D, N), assembled (D, N) of the
    designs, solved by the studies engine (the atlas's :data:`~.atlas.Solver`); ``fast``: by
    its fused compiled loop where the plan has one (:func:`fused_engine_solver`), else its
    numpy path (the same bits)."""
    n = len(theta)
    lk = template(topology, n)
    out_link = OUTPUT_LINK.get(topology, "rocker")
    wanted = [f"P{k + 1}" for k in range(POINTS)] + [j for j in ("B", "C", "E", "G", "H") if j in lk.joint_ids]
    v = solve_variants(lk, _values(topology, shape, points), samples=n, order=0, joints=wanted, links=[out_link],
                       fast=fast)
    P = np.stack([_c(v.position(f"P{k + 1}")) for k in range(POINTS)], axis=1)
    ok = v.valid & v.assembled[:, None]
    B, C = _c(v.position("B")), _c(v.position("C"))
    with np.errstate(invalid="ignore", divide="ignore"):
        if topology == F.SLIDER_CRANK:
            out = C.real
            sin_mu = np.abs(C.real - B.real) / shape[:, 1:2]
        elif topology == F.INVERTED:
            out = np.angle(_c(v.position("H")) - B)        # the guide's direction, as the closed form's
            sin_mu = np.sqrt(np.maximum(1.0 - shape[:, 1:2] ** 2 / np.abs(B - 1.0) ** 2, 0.0))
        else:
            out = v.angle(out_link)
            sin_mu = np.abs(np.imag(np.conj(C - B) * (C - 1.0))) / (shape[:, 1:2] * shape[:, 2:3])
            if topology in F.GUIDE_SIXBARS:      # the guide's direction; the block's transmission
                E = _c(v.position("E"))
                out = np.angle(_c(v.position("H")) - E)
                r2 = np.abs(E - (shape[:, 5] + 1j * shape[:, 6])[:, None]) ** 2
                sin_mu = np.minimum(sin_mu, np.sqrt(np.maximum(1.0 - shape[:, 7:8] ** 2 / r2, 0.0)))
            elif topology in F.ALL_SIXBARS:
                E, G = _c(v.position("E")), _c(v.position("G"))
                Fp = (shape[:, 5] + 1j * shape[:, 6])[:, None]
                if topology in F.SLIDER_SIXBARS:     # the slider's place on its guide, from F; the rod's angle
                    e = np.exp(-1j * shape[:, 8:9])
                    out = np.real(e * (G - Fp))
                    mu2 = np.abs(np.real(e * (G - E))) / shape[:, 7:8]
                else:
                    mu2 = np.abs(np.imag(np.conj(G - E) * (G - Fp))) / (shape[:, 7:8] * shape[:, 8:9])
                sin_mu = np.minimum(sin_mu, mu2)
    return P, out, sin_mu, ok


def fused_engine_solver(topology: str, shape: np.ndarray, points: np.ndarray, theta: np.ndarray):
    """:func:`engine_solver` on the studies engine's fused compiled loop (numba; crank-driven RRR
    and RRP groups: all but the inverted slider-crank, which stays on the numpy path): the same
    bits, about three times faster on a six-bar once compiled (compiled once per topology and
    cached on disk), so the large atlases use it."""
    return engine_solver(topology, shape, points, theta, fast=True)


__all__ = ["OUTPUT_LINK", "engine_solver", "fused_engine_solver", "template"]
