"""Cut-ready blanks of a non-circular gear pair: each pitch curve as a closed outline of biarcs
within the tolerance (the largest deviation from the exact curve measured and stated), with its
bore; placed at the pivots in the pose of the first sample (input rotation 0), so the assembled
layout shows them touching at the pitch point.

The blanks carry the pitch curve, not teeth: a gear cutter (or a friction drive) takes them from
there; the report says so. Used for a ``gear_pair`` and for the gears of a ``geared_geneva``.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import GeometryError
from ..gears.function import FunctionEval
from ...model.gear_function import GearFunction
from ...model.gear_pair import GearPair
from ...model.geared_geneva import GearedGeneva
from ..biarc import fit_biarcs
from ..contour import Contour
from ..gears.pitch import pitch_radii
from ..geneva.geometry import geometry
from .geneva import geneva_parts
from .outline import ccw, circle
from .records import Part, PartSet

KEYS = ("center_distance", "function", "tolerance", "bore_radius")


def _blank(name: str, curve, t1: float, tol: float, bore: float) -> Part:
    """A closed pitch-curve outline of biarcs over t ∈ [0, t1] with a bore at the origin."""
    try:
        fit = fit_biarcs(curve, 0.0, t1, tol, initial_spans=16)
    except (ValueError, GeometryError) as exc:
        raise GeometryError(f"cannot fit the {name} pitch curve within {tol:g} mm: {exc}") from None
    pts = np.array([a.start for a in fit.arcs], dtype=float)
    bul = np.array([a.bulge for a in fit.arcs])
    outline = ccw(Contour(pts, bul, (name,) * len(bul)))
    return Part(name, outline, (circle((0.0, 0.0), bore),), group=name, deviation=fit.max_deviation, keys=KEYS)


def gear_blanks(fn: GearFunction, a: float, sense: float, tol: float, bore: float,
                input_center: tuple[float, float], direction: float, names=("input_gear", "output_gear")) -> tuple[Part, Part]:
    """The input and output blanks placed in the world (mm; ``direction`` rad input → output)."""
    ev = FunctionEval(fn)
    m = fn.lobes

    def c1(t):
        r1, _ = pitch_radii(a, ev.derivatives(t)[1])
        return r1[:, None] * np.stack([np.cos(-sense * t), np.sin(-sense * t)], axis=-1)

    def c2(t):
        psi, d1, _, _ = ev.derivatives(t)
        _, r2 = pitch_radii(a, d1)
        ang = math.pi + sense * psi
        return r2[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=-1)

    span2 = 2 * math.pi / round(fn.ratio) if fn.ratio > 1 else 2 * math.pi * m   # one output turn
    inp = _blank(names[0], c1, 2 * math.pi, tol, bore)
    out = _blank(names[1], c2, span2, tol, bore)
    oc = (input_center[0] + a * math.cos(direction), input_center[1] + a * math.sin(direction))
    return inp.moved(direction, input_center), out.moved(direction, oc)


def gear_parts(element) -> PartSet:
    """The parts of a ``gear_pair`` (its two blanks) or a ``geared_geneva`` (the drive's four parts
    at crank angle 0 and the blanks, the output blank on the crank shaft): a :class:`PartSet`."""
    if isinstance(element, GearedGeneva):
        g = element.geneva
        pair = element.gear_pair
        geo = geometry(g)
        drive = geneva_parts(g, geo=geo)
        sense = 1.0 if pair.speed_rpm > 0 else -1.0
        bore = pair.bore_radius if pair.bore_radius is not None else geo.crank_bore   # both on the crank's shaft size
        pair = replace(pair, bore_radius=bore)
        blanks = gear_blanks(pair.function, pair.center_distance, sense, pair.tolerance, bore,
                             pair.input_center, math.radians(pair.direction_deg))
        notes = drive.notes + (_note(pair, blanks),)
        return PartSet(element.id, drive.parts + blanks, drive.curves, notes)
    sense = 1.0 if element.speed_rpm > 0 else -1.0
    blanks = gear_blanks(element.function, element.center_distance, sense, element.tolerance, element.bore,
                         element.input_center, math.radians(element.direction_deg))
    return PartSet(element.id, blanks, (), (_note(element, blanks),))


def _note(pair: GearPair, blanks: tuple[Part, Part]) -> str:
    dev = max(b.deviation for b in blanks)
    return (f"gears: pitch-curve blanks (the exact centrodes, biarcs within {pair.tolerance:g} mm: largest deviation "
            f"{dev:.3e} mm), bores {pair.bore:g} mm, centre distance {pair.center_distance:g} mm; the teeth are not "
            "cut (generate them on these pitch curves)")
