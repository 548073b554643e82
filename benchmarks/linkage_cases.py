"""The linkages of the linkage benchmark: the drawn examples, the near-change-point four-bar
built to a given toggle gap, the mechanism's size, and a pylinkage model of the example four-bar.
"""
from __future__ import annotations

import math
from pathlib import Path

import mpmath

from mechsketch.core.io.scene_file import load_scene
from mechsketch.core.model.linkage import Driver, Joint, JointKind, Link, Linkage
from mechsketch.core.solver.plan import compile_plan

EXAMPLES = Path(__file__).resolve().parent.parent / "resources" / "examples"


def example(name: str) -> Linkage:
    return load_scene(EXAMPLES / f"{name}.json").elements[0]


def near_change_point(delta_rel: float) -> tuple[Linkage, float]:
    """Grashof crank-rocker with s + l = p + q − δ, δ = delta_rel·(s + l).

    Frame A(0,0)–D(120,0), crank 40 drawn at 60°, coupler 100, rocker 60 + δ. At crank angle 180°
    (sample N/3 of every sweep) coupler and rocker are within a gap δ of collinear. Returns the
    linkage and δ as realised by the rounded drawn coordinates (computed in mpmath).
    """
    s, l, p = 40.0, 120.0, 100.0
    with mpmath.workdps(60):
        d = mpmath.mpf(delta_rel) * (s + l)
        q = mpmath.mpf(s) + l - p + d
        B = (s * math.cos(math.radians(60)), s * math.sin(math.radians(60)))
        Bm = mpmath.matrix([mpmath.mpf(B[0]), mpmath.mpf(B[1])])
        Dm = mpmath.matrix([mpmath.mpf(l), mpmath.mpf(0)])
        v = Dm - Bm
        dist = mpmath.norm(v)
        a = (p * p - q * q + dist * dist) / (2 * dist)
        h = mpmath.sqrt(p * p - a * a)
        e = v / dist
        C = Bm + a * e + h * mpmath.matrix([-e[1], e[0]])   # left of B→D: the upper assembly
        C = (float(C[0]), float(C[1]))
        real = (mpmath.hypot(mpmath.mpf(C[0]) - B[0], mpmath.mpf(C[1]) - B[1])
                + mpmath.hypot(mpmath.mpf(C[0]) - l, mpmath.mpf(C[1]))
                - mpmath.hypot(mpmath.mpf(B[0]), mpmath.mpf(B[1])) - l)
    R = JointKind.R
    lk = Linkage(
        id="near_change_point",
        joints=(Joint("A", R, (0.0, 0.0)), Joint("B", R, B), Joint("C", R, C), Joint("D", R, (l, 0.0))),
        links=(Link("ground", ("A", "D")), Link("crank", ("A", "B")), Link("coupler", ("B", "C")),
               Link("rocker", ("D", "C"))),
        ground="ground", driver=Driver("crank", "A", 60.0 * 10.0 / (2 * math.pi)), samples=360)
    return lk, float(real)


def size_of(lk: Linkage) -> float:
    pts = [j.at for j in lk.joints]
    return max(math.dist(a, b) for a in pts for b in pts)


def pylinkage_fourbar(lk: Linkage, N: int):
    """A pylinkage model of the example four-bar (A, D frame; B crank; C RRR; E coupler point)."""
    import pylinkage as pl

    at = {j.id: j.at for j in lk.joints}
    plan = compile_plan(lk)
    sgn = 1.0 if lk.driver.omega >= 0 else -1.0
    d = sgn * 2 * math.pi / N
    O1 = pl.Ground(*at["A"], name="A")
    O2 = pl.Ground(*at["D"], name="D")
    cr = pl.Crank(O1, radius=math.dist(at["A"], at["B"]), angular_velocity=d,
                  initial_angle=plan.theta0 - d, name="B")  # its first output is sample 0
    rr = pl.RRRDyad(cr.output, O2, distance1=math.dist(at["B"], at["C"]),
                    distance2=math.dist(at["D"], at["C"]), x=at["C"][0], y=at["C"][1], name="C")
    ang = (math.atan2(at["E"][1] - at["B"][1], at["E"][0] - at["B"][0])
           - math.atan2(at["C"][1] - at["B"][1], at["C"][0] - at["B"][0]))
    fx = pl.FixedDyad(cr.output, rr, distance=math.dist(at["B"], at["E"]), angle=ang, name="E")
    L = pl.Linkage([O1, O2, cr, rr, fx])
    L.set_input_velocity(cr, omega=lk.driver.omega)
    return L, L.get_coords(), ["A", "D", "B", "C", "E"]


def _pylinkage_crank(lk: Linkage, N: int):
    """The ground pivot A and the crank B of a pylinkage model sampled like ``plan.sweep``."""
    import pylinkage as pl

    at = {j.id: j.at for j in lk.joints}
    d = (1.0 if lk.driver.omega >= 0 else -1.0) * 2 * math.pi / N
    O1 = pl.Ground(*at["A"], name="A")
    cr = pl.Crank(O1, radius=math.dist(at["A"], at["B"]), angular_velocity=d,
                  initial_angle=compile_plan(lk).theta0 - d, name="B")  # its first output is sample 0
    return at, O1, cr


def pylinkage_slider_crank(lk: Linkage, N: int):
    """A pylinkage model of the offset slider-crank (A frame; B crank; C on the fixed guide through
    S, an RRPDyad on a line through two frame points); the slider S is reported at C."""
    import pylinkage as pl

    at, O1, cr = _pylinkage_crank(lk, N)
    a = math.radians(lk.joint("S").axis_deg or 0.0)
    S1 = pl.Ground(*at["S"], name="S1")
    S2 = pl.Ground(at["S"][0] + 100.0 * math.cos(a), at["S"][1] + 100.0 * math.sin(a), name="S2")
    sl = pl.RRPDyad(cr.output, S1, S2, distance=math.dist(at["B"], at["C"]), x=at["C"][0], y=at["C"][1],
                    name="C")
    L = pl.Linkage([O1, S1, S2, cr, sl])
    L.set_input_velocity(cr, omega=lk.driver.omega)
    return L, L.get_coords(), ["A", "S1", "S2", "B", "C"], {"S": "C"}


def pylinkage_sixbar(lk: Linkage, N: int):
    """A pylinkage model of the six-bar with a moving guide (the four-bar A–B–C–D; the block E on
    the rocker's guide through Q: an RRPDyad on a line through two points fixed to the rocker);
    the slider Q is reported at E."""
    import pylinkage as pl

    at, O1, cr = _pylinkage_crank(lk, N)
    O2 = pl.Ground(*at["D"], name="D")
    rr = pl.RRRDyad(cr.output, O2, distance1=math.dist(at["B"], at["C"]),
                    distance2=math.dist(at["D"], at["C"]), x=at["C"][0], y=at["C"][1], name="C")
    D, C0, Q0 = (complex(*at[k]) for k in ("D", "C", "Q"))
    a = math.radians(lk.joint("Q").axis_deg or 0.0)

    def on_rocker(p: complex, name: str):
        v = p - D
        ang = math.atan2(v.imag, v.real) - math.atan2((C0 - D).imag, (C0 - D).real)
        return pl.FixedDyad(O2, rr, distance=abs(v), angle=ang, name=name)

    g1, g2 = on_rocker(Q0, "G1"), on_rocker(Q0 + 100.0 * complex(math.cos(a), math.sin(a)), "G2")
    bl = pl.RRPDyad(cr.output, g1, g2, distance=math.dist(at["B"], at["E"]), x=at["E"][0], y=at["E"][1],
                    name="E")
    L = pl.Linkage([O1, O2, cr, rr, g1, g2, bl])
    L.set_input_velocity(cr, omega=lk.driver.omega)
    return L, L.get_coords(), ["A", "D", "B", "C", "G1", "G2", "E"], {"Q": "E"}
