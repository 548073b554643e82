"""The quantities a study reports per design and optimises: names, units and how each is computed.

Linkages (from the batch engine, chunk by chunk):

- ``assembled``, ``full_cycle``, ``dead_point`` (1/0), ``min_transmission_angle`` (°);
- ``path_error:J`` / ``path_rms:J`` (mm): the largest / root-mean-square distance of the target
  path's points (the study's ``target``) from joint J's coupler curve (the closed polyline of its
  samples); ``swing:LINK`` (°): the range of a link's angle over the cycle;
- ``peak_torque``, ``rms_torque`` (N·m; an actuator's force, N), ``peak_shaking_force`` (N),
  ``peak_shaking_moment`` (N·m): the kinetostatics (:mod:`.bforces`);
- ``thinnest_web`` (mm), ``part_envelope`` (mm, the longest side of any part's bounding box): the
  cut-ready parts of each design (one design at a time, the export's own builder).

Geneva drives (one design at a time): ``p_max`` (MPa, peak Hertz pressure), ``wear_life`` (crank
revolutions until the allowed wear), ``thinnest_web``, ``part_envelope``.

A design that does not assemble (or cannot be built) gets NaN for every metric but ``assembled``.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..analyses.geneva.contact import contact
from ..analyses.parts.build import PartOptions, element_parts
from ..analyses.parts.check import thinnest_web
from ..errors import MechsketchError, RequestError
from ..model.geneva import Geneva, require_valid

UNITS = {"assembled": "", "full_cycle": "", "dead_point": "", "min_transmission_angle": "°", "path_error": "mm",
         "path_rms": "mm", "swing": "°", "peak_torque": "N·m", "rms_torque": "N·m", "peak_shaking_force": "N",
         "peak_shaking_moment": "N·m", "thinnest_web": "mm", "part_envelope": "mm", "p_max": "MPa",
         "wear_life": "rev"}
LINKAGE = ("assembled", "full_cycle", "dead_point", "min_transmission_angle", "path_error", "path_rms", "swing",
           "peak_torque", "rms_torque", "peak_shaking_force", "peak_shaking_moment", "thinnest_web", "part_envelope")
GENEVA = ("assembled", "p_max", "wear_life", "thinnest_web", "part_envelope")
FORCES = ("peak_torque", "rms_torque", "peak_shaking_force", "peak_shaking_moment")
PARTS = ("thinnest_web", "part_envelope")


def base(name: str) -> str:
    return name.split(":", 1)[0]


def unit(name: str) -> str:
    return UNITS.get(base(name), "")


def check_metrics(element, names, target=None) -> None:
    """RequestError naming a metric the element has no such thing as (or that needs a target)."""
    kind = getattr(element, "type", "")
    allowed = LINKAGE if kind == "linkage" else GENEVA if kind == "geneva" else ()
    for m in names:
        b = base(m)
        if b not in allowed:
            raise RequestError(f"metric {m!r}: not a metric of a {kind} (its metrics: {', '.join(allowed)})")
        if b in ("path_error", "path_rms", "swing"):
            arg = m.split(":", 1)[1] if ":" in m else ""
            ids = element.joint_ids if b != "swing" else element.moving_links
            if arg not in ids:
                raise RequestError(f"metric {m!r}: name a {'joint' if b != 'swing' else 'moving link'} after the "
                                   f"colon (one of {', '.join(ids)})")
            if b != "swing" and target is None:
                raise RequestError(f"metric {m!r} needs the study's \"target\" path")


def path_errors(curve: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per design the largest and RMS distance (mm) of the target points (M, 2) from the closed
    polyline of each design's curve (D, N, 2) (NaN where a design's curve has gaps)."""
    D = curve.shape[0]
    a = curve
    b = np.roll(curve, -1, axis=1)
    ab = b - a                                                        # (D, N, 2)
    L2 = np.maximum((ab * ab).sum(-1), 1e-300)
    worst, rms = np.full(D, np.nan), np.full(D, np.nan)
    ok = np.isfinite(curve).all(axis=(1, 2))
    for d0 in range(0, D, 64):
        sl = slice(d0, min(D, d0 + 64))
        ap = target[None, :, None, :] - a[sl, None, :, :]              # (d, M, N, 2)
        t = np.clip((ap * ab[sl, None]).sum(-1) / L2[sl, None], 0.0, 1.0)
        dist = np.hypot(*(ap - t[..., None] * ab[sl, None]).transpose(3, 0, 1, 2)).min(axis=2)   # (d, M)
        worst[sl] = dist.max(axis=1)
        rms[sl] = np.sqrt((dist * dist).mean(axis=1))
    return np.where(ok, worst, np.nan), np.where(ok, rms, np.nan)


def linkage_metrics(b, names: list[str], target: np.ndarray | None, designs=None) -> dict[str, np.ndarray]:
    """The metrics ``names`` of the designs of a solved :class:`~.variants.Variants` ``b``
    (``designs``: a callable d -> the design's linkage record, for the part metrics)."""
    out: dict[str, np.ndarray] = {}
    ok = b.assembled
    forces = None
    for m in names:
        kind = base(m)
        arg = m.split(":", 1)[1] if ":" in m else ""
        if kind == "assembled":
            v = ok.astype(float)
        elif kind in ("full_cycle", "dead_point"):
            v = getattr(b, kind).astype(float)
        elif kind == "min_transmission_angle":
            v = b.min_transmission_angle.copy()
        elif kind in ("path_error", "path_rms"):
            worst, rms = path_errors(b.position(arg), target)
            v = worst if kind == "path_error" else rms
        elif kind == "swing":
            a = np.degrees(b.angle(arg))
            with np.errstate(invalid="ignore"):
                v = np.nanmax(a, axis=1) - np.nanmin(a, axis=1)
        elif kind in FORCES:
            forces = forces if forces is not None else b.forces()
            v = {"peak_torque": forces.peak_effort, "rms_torque": forces.rms_effort,
                 "peak_shaking_force": forces.peak_shaking_force,
                 "peak_shaking_moment": forces.peak_shaking_moment}[kind]
        else:   # parts, one design at a time
            v = np.array([part_metric(designs(d), kind) if ok[d] else math.nan for d in range(b.n)])
        out[m] = np.where(ok | (kind == "assembled"), v, np.nan)
    return out


def part_metric(element, kind: str) -> float:
    """``thinnest_web`` (mm) or ``part_envelope`` (mm) of one element's cut-ready parts (NaN when
    they cannot be built)."""
    try:
        ps = element_parts(element, PartOptions())
    except (MechsketchError, ValueError):
        return math.nan
    if kind == "thinnest_web":
        webs = [thinnest_web(p)[0] for p in ps.parts if p.outer is not None]
        webs = [w for w in webs if math.isfinite(w)]
        return min(webs) if webs else math.nan
    sides = []
    for p in ps.parts:
        x0, y0, x1, y1 = p.bounds()
        sides.append(max(x1 - x0, y1 - y0))
    return max(sides) if sides else math.nan


# -- Geneva drives ------------------------------------------------------------------------------
def geneva_keys(g: Geneva) -> dict[str, float]:
    """The numeric fields a study may vary (dotted for the nested records): slots, center_distance,
    roller_radius, roller_length, speed_rpm, clearance.slot|bottom|lock, load.wheel_inertia|
    external_moment|journal_friction|journal_radius, wear.allowed_wear|specific_wear_rate."""
    out = {"slots": float(g.slots), "center_distance": g.center_distance, "roller_radius": g.roller_radius,
           "roller_length": g.roller_length, "speed_rpm": g.speed_rpm}
    for sub in ("clearance", "load", "wear"):
        rec = getattr(g, sub)
        for f in rec.__dataclass_fields__:
            out[f"{sub}.{f}"] = float(getattr(rec, f))
    return out


def geneva_design(g: Geneva, values: dict, d: int) -> Geneva:
    """Design ``d`` of a Geneva study: the drive with the values set (slots rounded)."""
    top, nested = {}, {}
    for k, v in values.items():
        x = float(v[d])
        if "." in k:
            sub, f = k.split(".", 1)
            nested.setdefault(sub, {})[f] = x
        else:
            top[k] = int(round(x)) if k == "slots" else x
    for sub, fields in nested.items():
        top[sub] = replace(getattr(g, sub), **fields)
    return replace(g, **top)


def geneva_metrics(g: Geneva, values: dict, n: int, names: list[str]) -> dict[str, np.ndarray]:
    """The metrics of n Geneva designs, one at a time (a design that is not a valid drive: NaN)."""
    out = {m: np.full(n, math.nan) for m in names}
    for d in range(n):
        try:
            el = geneva_design(g, values, d)
            require_valid(el)
        except (MechsketchError, ValueError, TypeError):
            if "assembled" in out:
                out["assembled"][d] = 0.0
            continue
        c = None
        for m in names:
            if m == "assembled":
                out[m][d] = 1.0
            elif m in ("p_max", "wear_life"):
                c = c if c is not None else contact(el, min(el.samples, 720), el.model)
                out[m][d] = c.pressure_max if m == "p_max" else c.life.cycles
            else:
                out[m][d] = part_metric(el, m)
    return out


__all__ = ["FORCES", "GENEVA", "LINKAGE", "PARTS", "UNITS", "base", "check_metrics", "geneva_design",
           "geneva_keys", "geneva_metrics", "linkage_metrics", "part_metric", "path_errors", "unit"]
