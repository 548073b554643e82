"""Synthesised designs as ordinary linkage elements, checked with the product's own solver.

:func:`build_linkage` turns a design of :mod:`.families` (parameters, assembly mode, crank angle
of the drawn pose) into a :class:`~mechsketch.core.model.linkage.Linkage` with fixed names: joints
``A`` (crank pivot), ``B`` (crank pin), ``C`` (the coupler's other pin), ``D`` (rocker pivot; the
inverted slider-crank's rocker pivot is ``C``), ``S``/``Q`` (prismatic joints), ``P`` (the
coupler point on link ``coupler``, when asked); links ``ground``, ``crank``, ``coupler`` and
``rocker``/``slider`` — or ``output`` for function synthesis.

:func:`drive_check` drives it with :func:`~mechsketch.core.solver.plan.compile_plan` over the
target span and refuses it unless the element reads back as a file would, every sample of the
span assembles, the solver's motion is the design's (no branch jump: the solver keeps each
group's mode continuous), the transmission angle stays above the threshold (no dead point in the
span) and the parts the export would cut pass their checks. A :class:`Candidate` is what passes.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..analyses.classify import fourbar_type
from ..analyses.parts import require_checked
from ..analyses.parts.build import PartOptions, linkage_style, min_web_of
from ..analyses.parts.linkage import BORE_FRACTION, BOSS_FRACTION, linkage_parts, scale_of
from ..errors import GeometryError, MechsketchError
from ..model.linkage import Driver, Joint, JointKind, Link, Linkage
from ..model.linkage_parse import parse
from ..solver.plan import Plan, compile_plan
from . import families as F

#: samples per turn of the dense drive check
CHECK_SAMPLES = 720
#: the solver and the closed form agree to this fraction of the size, or the design is refused
AGREE_REL = 1e-7
DEFAULT_RPM = 60.0


@dataclass
class Candidate:
    """One synthesised linkage, checked (see the module docstring).

    ``deviation``: the largest deviation from the target, in ``unit`` ("mm" for a path or the
    poses' points, "°" or "mm" for a function's output); ``angle_deviation``: the poses' largest
    angle error, °; ``min_transmission_deg`` over the target span; ``kind`` the type in words;
    ``inputs_rad`` the crank angle (world, rad) at each target point; ``seconds`` the time spent
    on this candidate (refinement and checks)."""

    linkage: Linkage
    topology: str
    params: np.ndarray
    sigma: float
    direction: float
    inputs_rad: np.ndarray
    deviation: float
    unit: str
    min_transmission_deg: float
    kind: str
    full_turn: bool
    seconds: float = 0.0
    angle_deviation: float | None = None
    rms: float | None = None
    notes: list[str] = field(default_factory=list)

    def line(self, rank: int | None = None) -> str:
        """The one-line report the CLI prints."""
        head = f"{rank}. " if rank is not None else ""
        dev = f"max deviation {self.deviation:.3g} {self.unit}"
        if self.angle_deviation is not None:
            dev += f", {self.angle_deviation:.3g}°"
        return (f"{head}{self.linkage.id}: {self.topology}, {dev}, min transmission angle "
                f"{self.min_transmission_deg:.1f}°, {self.kind}, {self.seconds:.3f} s")


def _pt(z: complex) -> tuple[float, float]:
    return (float(z.real), float(z.imag))


def _deg(z: complex) -> float:
    return math.degrees(math.atan2(z.imag, z.real))


def build_linkage(topology: str, x: np.ndarray, sigma: float, theta0: float, element_id: str,
                  direction: float = 1.0, output: bool = False, point: bool = True,
                  speed_rpm: float = DEFAULT_RPM, samples: int = 360) -> Linkage:
    """The linkage of design ``x`` (:mod:`.families` parameters) drawn at crank angle ``theta0``
    (rad, world), mode ``sigma``, its crank turning counter-clockwise for ``direction`` > 0.
    ``output``: name the output link ``output`` (function synthesis); ``point``: add the coupler
    point ``P``. Raises GeometryError where the design cannot be assembled at ``theta0``."""
    ev = F.evaluate(topology, np.asarray(x, float)[None], np.array([[theta0]]), sigma)
    if not ev.ok[0, 0]:
        raise GeometryError(f"the {topology} cannot be assembled at the drawn crank angle {math.degrees(theta0):.6g}°")
    j = {k: complex(v[0, 0]) for k, v in ev.joints.items()}
    P = complex(ev.P[0, 0])
    out_name = "output" if output else {F.SLIDER_CRANK: "slider", F.SIXBAR: "rocker2", F.WATT: "rocker2",
                                        F.SIXBAR_SLIDER: "slider", F.WATT_SLIDER: "slider", F.SIXBAR_GUIDE: "rocker2",
                                        F.WATT_GUIDE: "rocker2"}.get(topology, "rocker")
    R = JointKind.R
    if topology == F.FOURBAR:
        joints = [Joint("A", R, _pt(j["A"])), Joint("B", R, _pt(j["B"])), Joint("C", R, _pt(j["C"])),
                  Joint("D", R, _pt(j["D"]))]
        links = [Link("ground", ("A", "D")), Link("crank", ("A", "B")), Link("coupler", ("B", "C")),
                 Link(out_name, ("D", "C"))]
    elif topology == F.SLIDER_CRANK:
        joints = [Joint("A", R, _pt(j["A"])), Joint("B", R, _pt(j["B"])), Joint("C", R, _pt(j["C"])),
                  Joint("S", JointKind.P, _pt(j["C"]), _deg(j["e"]))]
        links = [Link("ground", ("A", "S")), Link("crank", ("A", "B")), Link("coupler", ("B", "C")),
                 Link(out_name, ("C", "S"))]
    elif topology == F.INVERTED:
        joints = [Joint("A", R, _pt(j["A"])), Joint("B", R, _pt(j["B"])), Joint("C", R, _pt(j["G"])),
                  Joint("Q", JointKind.P, _pt(j["B"]), _deg(j["u"]))]
        links = [Link("ground", ("A", "C")), Link("crank", ("A", "B")), Link("coupler", ("B", "Q")),
                 Link(out_name, ("C", "Q"))]
    else:
        joints, links = _sixbar_parts(topology, j, out_name)
    if point:
        joints.append(Joint("P", R, _pt(P)))
        links[2] = Link("coupler", links[2].joints + ("P",))
    rpm = abs(speed_rpm) if direction >= 0 else -abs(speed_rpm)
    return Linkage(element_id, tuple(joints), tuple(links), "ground", Driver("crank", "A", rpm), samples)


def _sixbar_parts(topology: str, j: dict[str, complex], out_name: str) -> tuple[list[Joint], list[Link]]:
    """A six-bar's joints and links: the path point's link ``coupler`` is the second dyad's
    link hung on the connector (Stephenson) or the rocker (Watt) at E: the rod E G to a rocker
    F G (RRR) or to a slider on the frame's guide S (RRP), or the block on the guide Q of a
    rocker pivoted at F (RPR)."""
    R = JointKind.R
    watt = topology in F.WATTS
    first = [Joint(k, R, _pt(j[k])) for k in ("A", "B", "C", "D", "E")]
    four = [Link("crank", ("A", "B")), Link("connector", ("B", "C") if watt else ("B", "C", "E")),
            Link("rocker", ("D", "C", "E") if watt else ("D", "C"))]
    if topology in F.SLIDER_SIXBARS:      # G a slider's pin on the guide through F: joint S
        joints = first + [Joint("G", R, _pt(j["G"])), Joint("S", JointKind.P, _pt(j["G"]), _deg(j["e"]))]
        return joints, [Link("ground", ("A", "D", "S")), four[0], Link("coupler", ("E", "G"))] + four[1:] + \
            [Link(out_name, ("G", "S"))]
    if topology in F.GUIDE_SIXBARS:       # the block E on the guide Q of the rocker F
        joints = first + [Joint("F", R, _pt(j["F"])), Joint("Q", JointKind.P, _pt(j["E"]), _deg(j["u"]))]
        return joints, [Link("ground", ("A", "D", "F")), four[0], Link("coupler", ("E", "Q"))] + four[1:] + \
            [Link(out_name, ("F", "Q"))]
    joints = first + [Joint("F", R, _pt(j["F"])), Joint("G", R, _pt(j["G"]))]
    return joints, [Link("ground", ("A", "D", "F")), four[0], Link("coupler", ("E", "G"))] + four[1:] + \
        [Link(out_name, ("F", "G"))]


def kind_text(topology: str, x: np.ndarray) -> str:
    """The design's type in words (Grashof class and four-bar type; slider-crank kind)."""
    x = np.asarray(x, float)
    if topology == F.FOURBAR:
        d = math.hypot(x[2] - x[0], x[3] - x[1])
        cls, kind = fourbar_type(d, x[4], x[5], x[6])
        return f"{kind.split(' (')[0]}, {cls.split(' (')[0]}"
    if topology in F.ALL_SIXBARS:
        d = math.hypot(x[2] - x[0], x[3] - x[1])
        name = "Watt II" if topology in F.WATTS else "Stephenson III"
        tail = (" and a slider" if topology in F.SLIDER_SIXBARS else
                " and a guided rocker" if topology in F.GUIDE_SIXBARS else "")
        return f"{name} six-bar on a " + fourbar_type(d, x[4], x[5], x[6])[1].split(" (")[0] + tail
    if topology == F.SLIDER_CRANK:
        off = abs(x[3])
        return ("centric" if off <= 1e-9 * max(x[4], x[5]) else f"offset {off:.4g} mm") + \
            (", crank turns fully" if x[4] + off <= x[5] else ", crank swings")
    dist = math.hypot(x[2] - x[0], x[3] - x[1])
    return "guide swings" if x[4] < dist else "guide turns fully (Whitworth)"


@dataclass
class DriveCheck:
    """What :func:`drive_check` found: ``ok`` or the ``reason`` why not; the solver's ``plan``;
    the minimum transmission angle (°) over the span; ``full_turn``: the crank turns fully."""

    ok: bool
    reason: str = ""
    plan: Plan | None = None
    min_transmission_deg: float = 0.0
    full_turn: bool = False


def span_inputs(inputs: np.ndarray, direction: float, closed: bool, samples: int = CHECK_SAMPLES
                ) -> np.ndarray | None:
    """Dense crank angles (rad, world) from the first target input through the last in the
    driving direction (a whole turn when ``closed``), including the targets' own; None when the
    targets are not met in order within one turn (an order defect)."""
    th0 = float(inputs[0])
    off = np.remainder(direction * (np.asarray(inputs, float) - th0), 2 * math.pi)
    off[0] = 0.0
    if np.any(np.diff(off) <= 0.0):
        return None
    end = 2 * math.pi if closed else float(off[-1])
    n = max(int(samples * end / (2 * math.pi)), 8)
    grid = np.concatenate([np.linspace(0.0, end, n, endpoint=not closed), off])
    return th0 + direction * np.sort(grid)


def drive_check(linkage: Linkage, topology: str, x: np.ndarray, sigma: float, theta: np.ndarray,
                min_mu_deg: float, size: float, parts: bool = True) -> DriveCheck:
    """Drive ``linkage`` (built by :func:`build_linkage` from ``x``, ``sigma``) with the product's
    solver at crank angles ``theta`` (rad, world; from :func:`span_inputs`) and check it (see the
    module docstring). ``size`` (mm) scales the agreement tolerance."""
    _, problems = parse(linkage.to_dict(), "$")
    if problems:
        return DriveCheck(False, "; ".join(p.message for p in problems))
    try:
        plan = compile_plan(linkage)
    except MechsketchError as exc:
        return DriveCheck(False, str(exc))
    sol = plan.evaluate(theta, order=0)
    if not sol.valid.all():
        k = int(np.flatnonzero(~sol.valid)[0])
        return DriveCheck(False, f"cannot be assembled at crank angle {math.degrees(theta[k]):.4g}° inside the span",
                          plan)
    ev = F.evaluate(topology, x[None], theta[None], sigma)
    name, ref = ("P", ev.P[0]) if "P" in linkage.joint_ids else ("C", ev.joints["C"][0])
    if topology in F.ALL_SIXBARS and name == "C":     # the second dyad's moving joint
        name = "G" if "G" in ev.joints else "E"
        ref = ev.joints[name][0]
    got = sol.position(name)
    gap = np.max(np.abs(got[:, 0] + 1j * got[:, 1] - ref))
    if not gap <= AGREE_REL * max(size, 1.0):
        return DriveCheck(False, f"the solver's motion leaves the design's branch (by {gap:.3g} mm)", plan)
    mu = math.degrees(math.asin(min(float(np.min(ev.sin_mu)), 1.0)))
    if not mu >= min_mu_deg:
        return DriveCheck(False, f"transmission angle {mu:.1f}° < {min_mu_deg:g}° inside the span", plan, mu)
    full = bool(plan.evaluate(theta[0] + np.linspace(0.0, 2 * math.pi, 361), order=0).valid.all())
    short = _too_close(linkage)
    if short:
        return DriveCheck(False, f"cannot be cut: {short}", plan, mu, full)
    if parts:
        why = cut_check(linkage, plan)
        if why:
            return DriveCheck(False, why, plan, mu, full)
    return DriveCheck(True, "", plan, mu, full)


def cut_check(linkage: Linkage, plan: Plan | None = None) -> str:
    """Why the parts ``validate`` builds for ``linkage`` (default options) cannot be cut, or "":
    the export's own part check (closed, valid outlines, the minimum web) on the plates
    :func:`~mechsketch.core.analyses.parts.build.element_parts` builds, without the traced
    coupler curves (never cut nor checked; their biarc fit was three quarters of the time)."""
    try:
        opts = PartOptions()
        plates = linkage_parts(linkage, plan if plan is not None else compile_plan(linkage),
                               linkage_style(linkage, opts), min_web_of(linkage, opts), traces=False)
        require_checked(plates, min_web_of(linkage, opts))
    except (GeometryError, ValueError) as exc:
        return f"cannot be cut: {exc}"
    return ""


def _too_close(linkage: Linkage) -> str:
    """Why two bores of one link would leave less than the minimum web between them with the
    export's default sizes (a quick test before the full part check), or ""."""
    bore = BORE_FRACTION * BOSS_FRACTION * scale_of(linkage)
    need = 2.0 * bore + 1.1 * min_web_of(linkage, PartOptions())
    for lk in linkage.links:
        pts = [(j, linkage.joint(j)) for j in lk.joints if linkage.joint(j).kind is JointKind.R]
        for i, (a, ja) in enumerate(pts):
            for b, jb in pts[i + 1:]:
                if math.dist(ja.at, jb.at) < need:
                    return f"joints {a} and {b} of link {lk.id} are {math.dist(ja.at, jb.at):.3g} mm apart, " \
                           f"less than two bores and the minimum web ({need:.3g} mm)"
    return ""


class Stopwatch:
    """Seconds since it was made (``elapsed``)."""

    def __init__(self) -> None:
        self.start = time.perf_counter()

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self.start


__all__ = ["Candidate", "DriveCheck", "Stopwatch", "build_linkage", "cut_check", "drive_check", "kind_text",
           "span_inputs"]
