"""Builders of linkages driven by any input: a V-engine crank with two pins, a crank carrying a
traced point, an excavator-style arm moved by a cylinder, a cylinder pushing a slider, a slider
driven along a fixed guide turning a crank. Drawn positions close (see :mod:`linkage_builders`)."""
from __future__ import annotations

import math
from dataclasses import replace

import linkage_builders as LB
from mechsketch.core import Driver, Linkage
from mechsketch.core.model.drivers import DriverKind, LawKind, MotionLaw


def law(kind: str = "constant", points=()) -> MotionLaw:
    return MotionLaw(LawKind(kind), tuple(points))


def vengine(theta0: float = 30.0, pin_angle: float = 90.0, r: float = 45.0, rod: float = 160.0,
            bank: float = 45.0, rpm: float = 3000.0, kind: str = "constant") -> Linkage:
    """A crank A with two pins B1, B2 (``pin_angle`` apart) driving pistons P1, P2 on guides through
    A at 90° ∓ ``bank`` (a V of 2·bank)."""
    B1, B2 = r * LB.e(theta0), r * LB.e(theta0 + pin_angle)
    u1, u2 = LB.e(90 - bank), LB.e(90 + bank)
    P1, P2 = LB.line_circle(0j, u1, B1, rod, 1), LB.line_circle(0j, u2, B2, rod, 1)
    lk = LB.build("vengine", [("A", "R", (0.0, 0.0)), ("B1", "R", LB.xy(B1)), ("B2", "R", LB.xy(B2)),
                              ("P1", "R", LB.xy(P1)), ("P2", "R", LB.xy(P2)),
                              ("G1", "P", LB.xy(P1), 90 - bank), ("G2", "P", LB.xy(P2), 90 + bank)],
                  {"ground": ["A", "G1", "G2"], "crank": ["A", "B1", "B2"], "rod1": ["B1", "P1"],
                   "piston1": ["P1", "G1"], "rod2": ["B2", "P2"], "piston2": ["P2", "G2"]},
                  "ground", "crank", "A", rpm=rpm)
    return replace(lk, driver=replace(lk.driver, law=law(kind)))


def crank_with_point(point=(5.0, 45.0), kind: str = "constant", **kw) -> Linkage:
    """The test four-bar whose crank also carries the traced point T."""
    lk = LB.fourbar(**kw)
    lk = lk.with_joint(lk.joint("B").__class__("T", lk.joint("B").kind, point))
    lk = lk.with_link(lk.link("crank").__class__("crank", ("A", "B", "T")))
    return replace(lk, driver=replace(lk.driver, law=law(kind)))


def excavator(kind: str = "cycloidal", stroke=(850.0, 1250.0), axis_off: float = 0.0, F=(-200.0, 450.0),
              G=(2450.0, 1250.0), E=(2600.0, 900.0), rpm: float = 6.0) -> Linkage:
    """Boom O–C2–E on the frame at O, lifted by the cylinder C1 (frame) – C2 (boom); the stick
    E–G–K is held by the tie F–G; K is the bucket tip. ``axis_off`` tilts the cylinder's slide
    axis off the line of its pivots (degrees)."""
    C1, C2 = (800.0, -550.0), (1200.0, 350.0)
    d = complex(C2[0] - C1[0], C2[1] - C1[1])
    ax = math.degrees(math.atan2(d.imag, d.real)) + axis_off
    mid = (C1[0] + 0.55 * d.real, C1[1] + 0.55 * d.imag)
    lk = LB.build("arm", [("O", "R", (0.0, 0.0)), ("C1", "R", C1), ("F", "R", F), ("C2", "R", C2),
                          ("E", "R", E), ("P", "P", mid, ax), ("G", "R", G), ("K", "R", (3100.0, 0.0))],
                  {"ground": ["O", "C1", "F"], "boom": ["O", "C2", "E"], "barrel": ["C1", "P"],
                   "rod": ["P", "C2"], "stick": ["E", "G", "K"], "tie": ["F", "G"]},
                  "ground", "barrel", "P", rpm=rpm)
    return replace(lk, driver=Driver("barrel", "P", rpm, DriverKind.CYLINDER, stroke, law(kind)))


def cylinder_slider(kind: str = "harmonic", stroke=(130.0, 190.0)) -> Linkage:
    """A cylinder from the frame pivot M to the pin L of a slider on a horizontal frame guide:
    the cylinder is the rod of an RRP group."""
    M, L = 0j, complex(150.0, 60.0)
    lk = LB.build("push", [("M", "R", (0.0, 0.0)), ("L", "R", LB.xy(L)), ("P", "P", LB.xy(0.5 * L),
                                                                         math.degrees(math.atan2(60, 150))),
                           ("S", "P", (150.0, 40.0), 0.0)],
                  {"ground": ["M", "S"], "barrel": ["M", "P"], "rod": ["P", "L"], "slider": ["L", "S"]},
                  "ground", "barrel", "P", rpm=20.0)
    return replace(lk, driver=Driver("barrel", "P", 20.0, DriverKind.CYLINDER, stroke, law(kind)))


def pushed_crank(kind: str = "harmonic", stroke=(-20.0, 15.0)) -> Linkage:
    """A slider C on a horizontal frame guide S, driven along it, turns the crank A–B (which also
    carries a point T) through the rod B–C."""
    C = 150 + 20j
    B = LB.circle_meet(0j, 50.0, C, 120.0, 1)
    lk = LB.build("pushed", [("A", "R", (0.0, 0.0)), ("B", "R", LB.xy(B)), ("C", "R", LB.xy(C)),
                             ("S", "P", (150.0, 20.0), 0.0), ("T", "R", (10.0, 30.0))],
                  {"ground": ["A", "S"], "crank": ["A", "B", "T"], "rod": ["B", "C"], "slider": ["C", "S"]},
                  "ground", "slider", "S", rpm=30.0)
    return replace(lk, driver=Driver("slider", "S", 30.0, DriverKind.SLIDER, stroke, law(kind)))
