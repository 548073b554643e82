"""The authored Geneva drive (external, radial entry) and its closed-form wheel dimensions.

The element stores only what the user authored: slot count z, centre distance A, roller radius and
length, clearances, placement, speed, load, materials and wear data (mm, MPa, kg·m², N·m).
Everything else is derived: :func:`wheel_dimensions` gives the closed-form sizes of the
manufacturable wheel (seeds/NOTES.md, section B, "Geometry for drawing a manufacturable wheel"),
which ``parse`` uses to reject drives that cannot be built, naming the limit and by how much it is
violated. The analyses (kinematics, geometry, contact and wear) live in
``mechsketch.core.analyses.geneva_*`` and are reached through the element's methods.

Conventions: the crank angle φ is measured from the line of centres (crank centre → wheel
centre), counter-clockwise positive. Positive ``speed_rpm`` turns the crank counter-clockwise and the
wheel clockwise. The crank radius is r = A·sin(π/z) (radial entry, λ = r/A = sin(π/z), note B9).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

from ..errors import GeometryError, Problem
from .limits import SMALLEST, speed_problem
from .drawing import DEFAULT_MIN_WEB

SCHEMA = "geneva.schema.json"

XYTuple = tuple[float, float]

#: defaults of the optional keys (seeds/NOTES.md, "Suggested built-in example scenes", 4)
DEFAULT_ROLLER_LENGTH = 10.0  # mm
DEFAULT_CLEARANCE = {"slot": 0.05, "bottom": 0.5, "lock": 0.1}  # mm
DEFAULT_SPEED_RPM = 300.0 / math.pi  # ω1 = 10 rad/s
DEFAULT_LOAD = {"wheel_inertia": 0.05, "external_moment": 0.0, "journal_friction": 0.05,
                "journal_radius": 15.0}
STEEL = {"E": 210000.0, "poisson": 0.3}  # MPa, -
DEFAULT_WEAR = {"allowed_wear": 0.05, "specific_wear_rate": 1e-6}  # mm, mm³/(N·m)
DEFAULT_SAMPLES = 3600
#: default locking-arc radius R_arc = r − LOCK_ARC_FACTOR·w (notes: "a manufacturable default")
LOCK_ARC_FACTOR = 1.5
#: a horn land narrower than this (rad) is a knife edge (R_arc = r − w gives 0 up to rounding)
LAND_TOL = 1e-9

NORMAL_FORCE_MODELS = ("derived", "paper")
HALF_WIDTH_MODELS = ("paper_half", "hertz", "paper_full")
SLIP_RADIUS_MODELS = ("deformed", "undeformed")


@dataclass(frozen=True)
class Clearances:
    """Clearances (mm): ``slot`` per side of the roller, ``bottom`` below the deepest roller
    position, ``lock`` between the locking disc and the wheel's locking arcs."""

    slot: float = DEFAULT_CLEARANCE["slot"]
    bottom: float = DEFAULT_CLEARANCE["bottom"]
    lock: float = DEFAULT_CLEARANCE["lock"]

    def to_dict(self) -> dict:
        return {"slot": self.slot, "bottom": self.bottom, "lock": self.lock}


@dataclass(frozen=True)
class Load:
    """Load on the wheel: inertia J2 (kg·m²), constant external moment (N·m, opposing the indexing
    motion when positive), journal friction coefficient f02 (-) and journal radius r02 (mm)."""

    wheel_inertia: float = DEFAULT_LOAD["wheel_inertia"]
    external_moment: float = DEFAULT_LOAD["external_moment"]
    journal_friction: float = DEFAULT_LOAD["journal_friction"]
    journal_radius: float = DEFAULT_LOAD["journal_radius"]

    def to_dict(self) -> dict:
        return {"wheel_inertia": self.wheel_inertia, "external_moment": self.external_moment,
                "journal_friction": self.journal_friction, "journal_radius": self.journal_radius}


@dataclass(frozen=True)
class Material:
    """An isotropic material: Young's modulus ``E`` (MPa) and Poisson's ratio (the paper's μ)."""

    E: float = STEEL["E"]
    poisson: float = STEEL["poisson"]

    def to_dict(self) -> dict:
        return {"E": self.E, "poisson": self.poisson}


@dataclass(frozen=True)
class Wear:
    """Allowed wear depth [h] (mm) and Archard specific wear rate k (mm³/(N·m))."""

    allowed_wear: float = DEFAULT_WEAR["allowed_wear"]
    specific_wear_rate: float = DEFAULT_WEAR["specific_wear_rate"]

    def to_dict(self) -> dict:
        return {"allowed_wear": self.allowed_wear, "specific_wear_rate": self.specific_wear_rate}


class NormalForce(StrEnum):
    """How the roller/slot normal force is found (a ``str``: equal to and printed as its value)."""

    DERIVED = "derived"   # moment balance with the friction sign by phase, note B3
    PAPER = "paper"       # eq. 3 as printed


class HalfWidth(StrEnum):
    """The contact half-width b entering the slip model."""

    PAPER_HALF = "paper_half"  # a_paper / 2, note B2
    HERTZ = "hertz"            # general Hertz b
    PAPER_FULL = "paper_full"  # the literal a_paper


class SlipRadius(StrEnum):
    """The roller radius entering the slip model."""

    DEFORMED = "deformed"      # ρ_eff = r_p − Δ, eq. 4
    UNDEFORMED = "undeformed"  # ρ_eff = r_p


@dataclass(frozen=True)
class ContactModel:
    """Choices of the contact model (each is stated in the analysis output).

    ``normal_force``: ``"derived"`` (moment balance with the friction sign by phase, note B3) or
    ``"paper"`` (eq. 3 as printed); it feeds every downstream quantity.
    ``half_width``: the half-width b entering the slip model, ``"paper_half"`` (a_paper/2, B2),
    ``"hertz"`` (general Hertz b) or ``"paper_full"`` (the literal a_paper).
    ``slip_radius``: ``"deformed"`` (ρ_eff = r_p − Δ, eq. 4) or ``"undeformed"`` (ρ_eff = r_p).
    Each is a string enum (:class:`NormalForce`, :class:`HalfWidth`, :class:`SlipRadius`); a
    plain string given here is converted (ValueError naming the choices if it is none of them).
    """

    normal_force: NormalForce = NormalForce.DERIVED
    half_width: HalfWidth = HalfWidth.PAPER_HALF
    slip_radius: SlipRadius = SlipRadius.DEFORMED

    def __post_init__(self) -> None:
        for name, enum in (("normal_force", NormalForce), ("half_width", HalfWidth),
                           ("slip_radius", SlipRadius)):
            value = getattr(self, name)
            if isinstance(value, enum):
                continue
            try:
                object.__setattr__(self, name, enum(value))
            except ValueError:
                choices = ", ".join(repr(m.value) for m in enum)
                raise ValueError(f"{name} must be one of {choices}; got {value!r}") from None

    def to_dict(self) -> dict:
        return {"normal_force": self.normal_force.value, "half_width": self.half_width.value,
                "slip_radius": self.slip_radius.value}


@dataclass(frozen=True)
class Drawing:
    """Optional drawing sizes (mm); ``None`` means the default stated on each field.

    ``locking_arc_radius``: R_arc, default r − 1.5·w. ``wheel_bore_radius``: the hub bore, default
    the journal radius r02. ``crank_bore_radius``: the crank shaft bore of the locking disc and the
    crank arm, default R_L/4 but at most the disc's thinnest section A − R_relief less the
    minimum web. ``pin_radius``: the roller pin, default r_p/2 but at most r_p less the minimum
    web. ``min_web``: the thinnest web every part keeps (mm, default
    :data:`~mechsketch.core.model.drawing.DEFAULT_MIN_WEB`); validation checks it.
    """

    locking_arc_radius: float | None = None
    wheel_bore_radius: float | None = None
    crank_bore_radius: float | None = None
    pin_radius: float | None = None
    min_web: float | None = None

    @property
    def web(self) -> float:
        """The minimum web in force (mm)."""
        return DEFAULT_MIN_WEB if self.min_web is None else self.min_web

    def to_dict(self) -> dict:
        return {k: v for k, v in (("locking_arc_radius", self.locking_arc_radius),
                                  ("wheel_bore_radius", self.wheel_bore_radius),
                                  ("crank_bore_radius", self.crank_bore_radius),
                                  ("pin_radius", self.pin_radius),
                                  ("min_web", self.min_web)) if v is not None}


@dataclass(frozen=True)
class WheelDimensions:
    """Closed-form sizes of the drawable wheel (mm, rad), seeds/NOTES.md section B.

    ``w`` slot half-width r_p + c_s; ``x_c`` slot-corner abscissa on the slot axis (= a_w, the
    entry radius of the roller centre, A·cos(π/z)); ``x_b`` centre of the slot-bottom semicircle
    A − r − c_b; ``outer_radius`` R_o = √(x_c² + w²); ``lock_arc_radius`` R_arc (centred on the
    bisector at A); ``lock_disc_radius`` R_L = R_arc − c_l; ``hub_max`` = x_b − w (largest hub
    radius); ``slot_depth`` = x_c − (x_b − w); ``beta_c`` = atan2(w, x_c) (corner half-angle);
    ``gamma`` half-angle, seen from the wheel centre, of the locking arc's meeting points with the
    outer circle; ``land_angle`` = π/z − β_c − γ, the horn land on each side of a slot;
    ``lock_half_angle`` β_L, half-angle of the locking arc seen from its centre (the crank centre
    during the dwell), measured from the line of centres.
    """

    slots: int
    center_distance: float
    crank_radius: float
    lam: float
    phi0: float
    w: float
    x_c: float
    x_b: float
    outer_radius: float
    lock_arc_radius: float
    lock_disc_radius: float
    hub_max: float
    slot_depth: float
    beta_c: float
    gamma: float
    land_angle: float
    lock_half_angle: float

    @property
    def lock_arc_range(self) -> tuple[float, float]:
        """Admissible R_arc: (A − R_o, r − w]; at r − w the horns are knife edges (mm)."""
        return self.center_distance - self.outer_radius, self.crank_radius - self.w


def wheel_dimensions(slots: int, center_distance: float, roller_radius: float, clearance: Clearances,
                     lock_arc_radius: float | None = None) -> WheelDimensions:
    """Closed-form wheel sizes for z slots, centre distance A (mm) and roller radius r_p (mm).

    Pure arithmetic; impossible values come out as NaN or out of range and are judged by the
    caller (``parse`` turns them into messages). ``lock_arc_radius`` None: r − 1.5·w.
    """
    z = int(slots)
    a = float(center_distance)
    lam = math.sin(math.pi / z)
    r = a * lam
    w = roller_radius + clearance.slot
    x_c = a * math.cos(math.pi / z)
    x_b = a - r - clearance.bottom
    r_o = math.hypot(x_c, w)
    r_arc = r - LOCK_ARC_FACTOR * w if lock_arc_radius is None else float(lock_arc_radius)
    cos_g = (a * a + r_o * r_o - r_arc * r_arc) / (2.0 * a * r_o)
    gamma = math.acos(cos_g) if -1.0 <= cos_g <= 1.0 else math.nan
    cos_l = (a * a + r_arc * r_arc - r_o * r_o) / (2.0 * a * r_arc) if r_arc > 0 else math.nan
    beta_l = math.acos(cos_l) if -1.0 <= cos_l <= 1.0 else math.nan
    beta_c = math.atan2(w, x_c)
    return WheelDimensions(
        slots=z, center_distance=a, crank_radius=r, lam=lam, phi0=math.pi / 2 - math.pi / z, w=w,
        x_c=x_c, x_b=x_b, outer_radius=r_o, lock_arc_radius=r_arc,
        lock_disc_radius=r_arc - clearance.lock, hub_max=x_b - w, slot_depth=x_c - (x_b - w),
        beta_c=beta_c, gamma=gamma, land_angle=math.pi / z - beta_c - gamma, lock_half_angle=beta_l)


@dataclass(frozen=True)
class Geneva:
    """A Geneva-drive element of a scene (type ``"geneva"``): external, radial entry, z ≥ 3.

    Lengths mm; ``wheel_direction_deg`` is the direction from ``crank_center`` to the wheel centre;
    positive ``speed_rpm`` turns the crank counter-clockwise. ``samples`` is the default number of
    samples N over one crank revolution (φ_k = −π + 2πk/N for a CCW crank).
    """

    id: str
    slots: int
    center_distance: float
    roller_radius: float
    roller_length: float = DEFAULT_ROLLER_LENGTH
    clearance: Clearances = Clearances()
    crank_center: XYTuple = (0.0, 0.0)
    wheel_direction_deg: float = 0.0
    speed_rpm: float = DEFAULT_SPEED_RPM
    load: Load = Load()
    roller_material: Material = Material()
    wheel_material: Material = Material()
    wear: Wear = Wear()
    samples: int = DEFAULT_SAMPLES
    contact_model: ContactModel | None = None
    drawing: Drawing | None = None
    type: str = field(default="geneva", init=False)

    # -- derived constants ----------------------------------------------------------------
    @property
    def lam(self) -> float:
        """λ = r/A = sin(π/z), the invariant of geometric similarity (radial entry only, B9)."""
        return math.sin(math.pi / self.slots)

    @property
    def crank_radius(self) -> float:
        """r = A·sin(π/z) (mm)."""
        return self.center_distance * self.lam

    @property
    def phi0(self) -> float:
        """Half the engagement angle, φ0 = π/2 − π/z (rad)."""
        return math.pi / 2 - math.pi / self.slots

    @property
    def omega1(self) -> float:
        """Crank angular speed ω1 (rad/s, signed, CCW positive)."""
        return self.speed_rpm * math.pi / 30.0

    @property
    def wheel_center(self) -> XYTuple:
        """World position of the wheel centre O2 (mm)."""
        d = math.radians(self.wheel_direction_deg)
        return (self.crank_center[0] + self.center_distance * math.cos(d),
                self.crank_center[1] + self.center_distance * math.sin(d))

    @property
    def min_web(self) -> float:
        """The thinnest web its parts keep (mm): ``drawing.min_web`` or the default."""
        return self.drawing.web if self.drawing else DEFAULT_MIN_WEB

    @property
    def model(self) -> ContactModel:
        """The contact-model choices in force (defaults when the scene gives none)."""
        return self.contact_model or ContactModel()

    def dimensions(self) -> WheelDimensions:
        """Closed-form wheel sizes (see :func:`wheel_dimensions`)."""
        lock = self.drawing.locking_arc_radius if self.drawing else None
        return wheel_dimensions(self.slots, self.center_distance, self.roller_radius, self.clearance, lock)

    def to_dict(self) -> dict:
        d: dict[str, Any] = {
            "type": "geneva", "id": self.id, "slots": self.slots,
            "center_distance": self.center_distance, "roller_radius": self.roller_radius,
            "roller_length": self.roller_length, "clearance": self.clearance.to_dict(),
            "crank_center": [self.crank_center[0], self.crank_center[1]],
            "wheel_direction_deg": self.wheel_direction_deg, "speed_rpm": self.speed_rpm,
            "load": self.load.to_dict(),
            "material": {"roller": self.roller_material.to_dict(), "wheel": self.wheel_material.to_dict()},
            "wear": self.wear.to_dict(), "samples": self.samples,
        }
        if self.contact_model is not None:
            d["contact_model"] = self.contact_model.to_dict()
        if self.drawing is not None:
            d["drawing"] = self.drawing.to_dict()
        return d


# -- parsing ------------------------------------------------------------------------------
def _num(x: float) -> str:
    return f"{x:.6g}"


class _Checker:
    """Collects problems for one element; messages name the limit and the amount of violation."""

    def __init__(self, path: str, eid: str) -> None:
        self.path, self.eid, self.problems = path, eid, []

    def bad(self, where: str, msg: str) -> None:
        self.problems.append(Problem(f"{self.path}.{where}", msg, self.eid))

    def at_least_or_zero(self, where: str, value: float, unit: str) -> None:
        """A value too small to be physical where 0 is allowed (a denormal load underflows)."""
        self.bad(where, f"must be 0 or at least {SMALLEST[unit]:g} {unit} in size; got {value:g} {unit}")

    def positive(self, where: str, value: float, unit: str) -> bool:
        least = SMALLEST.get(unit, 0.0)
        if value > 0 and value >= least:
            return True
        u = f" {unit}" if unit else ""
        if value > 0:
            self.bad(where, f"must be at least {least:g}{u} (the smallest value accepted); got {value:g}{u}")
            return False
        by = "at the limit" if value == 0 else f"{_num(-value)}{u} below the limit"
        self.bad(where, f"must be > 0{u}; got {_num(value)}{u} ({by})")
        return False

    def non_negative(self, where: str, value: float, unit: str) -> bool:
        if value == 0 or value >= SMALLEST.get(unit, 0.0):
            return True
        if value > 0:
            self.at_least_or_zero(where, value, unit)
            return False
        u = f" {unit}" if unit else ""
        self.bad(where, f"must be >= 0{u}; got {_num(value)}{u} ({_num(-value)}{u} below the limit)")
        return False


def _sub(data: dict, key: str, defaults: dict) -> dict:
    out = dict(defaults)
    out.update({k: float(v) for k, v in data.get(key, {}).items()})
    return out


def parse(data: dict[str, Any], path: str) -> tuple[Geneva | None, list[Problem]]:
    """Check a schema-valid geneva dict for meaning; return the element (or None) and problems.

    Checks: z ≥ 3; positive sizes, moduli, speed and wear data; clearances ≥ 0; Poisson's ratio in
    (−1, 0.5); then, when the sizes it needs are sound, the wheel geometry: a locking arc between
    A − R_o and r − w, a locking disc of positive radius, a land between slots (horn land angle
    > 0), a hub around the bore (slot bottoms outside it), a non-self-locking journal
    (f02·r02 < A − r), a roller pin inside the roller, a crank bore inside the locking disc.
    """
    eid = data["id"]
    ck = _Checker(path, eid)
    z = data["slots"]
    if z < 3:
        ck.bad("slots", f"a Geneva drive needs at least 3 slots; got {z} ({3 - z} short)")
    a = float(data["center_distance"])
    rp = float(data["roller_radius"])
    length = float(data.get("roller_length", DEFAULT_ROLLER_LENGTH))
    sizes_ok = all([ck.positive("center_distance", a, "mm"), ck.positive("roller_radius", rp, "mm"),
                    ck.positive("roller_length", length, "mm")])
    cl = _sub(data, "clearance", DEFAULT_CLEARANCE)
    for k in ("slot", "bottom", "lock"):
        sizes_ok &= ck.non_negative(f"clearance.{k}", cl[k], "mm")
    speed = float(data.get("speed_rpm", DEFAULT_SPEED_RPM))
    if speed == 0.0:
        ck.bad("speed_rpm", "must not be zero (the sign gives the direction: positive turns the crank CCW)")
    elif speed_problem(speed) is not None:
        ck.bad("speed_rpm", speed_problem(speed))
    ld = _sub(data, "load", DEFAULT_LOAD)
    ck.non_negative("load.wheel_inertia", ld["wheel_inertia"], "kg·m²")
    if 0 < abs(ld["external_moment"]) < SMALLEST["N·m"]:
        ck.at_least_or_zero("load.external_moment", ld["external_moment"], "N·m")
    sizes_ok &= ck.non_negative("load.journal_friction", ld["journal_friction"], "")
    sizes_ok &= ck.non_negative("load.journal_radius", ld["journal_radius"], "mm")
    mats = {}
    for part in ("roller", "wheel"):
        md = dict(STEEL)
        md.update({k: float(v) for k, v in data.get("material", {}).get(part, {}).items()})
        ck.positive(f"material.{part}.E", md["E"], "MPa")
        nu = md["poisson"]
        if not -1.0 < nu < 0.5:
            lim, by = (0.5, nu - 0.5) if nu >= 0.5 else (-1.0, -1.0 - nu)
            ck.bad(f"material.{part}.poisson", f"Poisson's ratio must lie in (−1, 0.5); got {_num(nu)} "
                                               f"({_num(by)} beyond the limit {lim})")
        mats[part] = Material(md["E"], md["poisson"])
    wd = _sub(data, "wear", DEFAULT_WEAR)
    ck.positive("wear.allowed_wear", wd["allowed_wear"], "mm")
    ck.positive("wear.specific_wear_rate", wd["specific_wear_rate"], "mm³/(N·m)")
    samples = int(data.get("samples", DEFAULT_SAMPLES))
    if samples < 2:
        ck.bad("samples", f"must be at least 2; got {samples} ({2 - samples} short)")
    cm = None
    if "contact_model" in data:
        cm = ContactModel(**{**ContactModel().to_dict(), **data["contact_model"]})
    dr = None
    if "drawing" in data:
        dr = Drawing(**{k: float(v) for k, v in data["drawing"].items()})
        for k, v in dr.to_dict().items():
            if k in ("locking_arc_radius", "min_web"):
                sizes_ok &= ck.positive(f"drawing.{k}", v, "mm")
            else:
                sizes_ok &= ck.non_negative(f"drawing.{k}", v, "mm")
    clearance = Clearances(cl["slot"], cl["bottom"], cl["lock"])
    if z >= 3 and sizes_ok:
        _check_geometry(ck, z, a, rp, clearance, ld, dr)
    if ck.problems:
        return None, ck.problems
    cc = data.get("crank_center", [0.0, 0.0])
    el = Geneva(eid, int(z), a, rp, length, clearance, (float(cc[0]), float(cc[1])),
                float(data.get("wheel_direction_deg", 0.0)), speed, Load(**ld), mats["roller"],
                mats["wheel"], Wear(**wd), samples, cm, dr)
    return el, []


def _check_geometry(ck: _Checker, z: int, a: float, rp: float, cl: Clearances, ld: dict,
                    dr: Drawing | None) -> None:
    """Wheel-geometry limits (mm, degrees in messages)."""
    dims = wheel_dimensions(z, a, rp, cl, dr.locking_arc_radius if dr else None)
    lo, hi = dims.lock_arc_range
    arc_key = "drawing.locking_arc_radius" if dr and dr.locking_arc_radius is not None else "roller_radius"
    what = "locking_arc_radius" if arc_key.startswith("drawing") else "the default locking arc radius r − 1.5·w"
    if hi <= lo:
        ck.bad("roller_radius", f"roller too large for the crank: no locking arc and no land fit between "
                                f"the slots; r − w = {_num(hi)} mm must exceed A − R_o = {_num(lo)} mm (short "
                                f"by {_num(lo - hi)} mm); reduce roller_radius or clearance.slot, or use "
                                "fewer slots or a larger center_distance")
        return
    r_arc = dims.lock_arc_radius
    if not r_arc > lo:
        ck.bad(arc_key, f"{what} = {_num(r_arc)} mm must exceed A − R_o = {_num(lo)} mm (short by "
                        f"{_num(lo - r_arc)} mm): the locking arc would not meet the outer circle; reduce "
                        "roller_radius or clearance.slot")
        return
    if r_arc > hi:
        ck.bad(arc_key, f"{what} = {_num(r_arc)} mm exceeds r − w = {_num(hi)} mm by {_num(r_arc - hi)} "
                        "mm: the locking arc would cut into the slot walls")
        return
    if not dims.lock_disc_radius > 0:
        ck.bad("clearance.lock", f"the locking disc radius R_arc − c_l = {_num(dims.lock_disc_radius)} mm "
                                 f"must be > 0 (clearance.lock is {_num(-dims.lock_disc_radius)} mm too large)")
    m = dr.web if dr is not None else DEFAULT_MIN_WEB
    web_note = f"the minimum web {_num(m)} mm (drawing.min_web)"
    if not dims.land_angle > LAND_TOL:
        ck.bad("roller_radius", f"no land between slots: the horn land angle π/z − β_c − γ is "
                                f"{math.degrees(dims.land_angle):.4g}°, must be > 0° (short by "
                                f"{-math.degrees(dims.land_angle):.4g}°); reduce roller_radius or clearance.slot")
    else:
        horn = dims.crank_radius - dims.w - r_arc
        if not horn >= m:
            ck.bad(arc_key, f"the horns are too thin: between slot wall and locking arc r − w − R_arc = "
                            f"{_num(horn)} mm, below {web_note} by {_num(m - horn)} mm; use a smaller "
                            "locking_arc_radius, a smaller roller_radius or clearance.slot, or a lower min_web")
    slot_web = 2.0 * (dims.x_b * math.sin(math.pi / z) - dims.w)
    if not slot_web >= m:
        what = "overlap" if slot_web < 0 else "leave too thin a web between them"
        ck.bad("roller_radius", f"neighbouring slots {what}: their bottoms are 2·(x_b·sin(π/z) − w) = "
                                f"{_num(slot_web)} mm apart, below {web_note} by {_num(m - slot_web)} mm; "
                                "reduce roller_radius or clearance.bottom, or use fewer slots or a larger "
                                "center_distance")
    bore = ld["journal_radius"] if dr is None or dr.wheel_bore_radius is None else dr.wheel_bore_radius
    bore_key = "load.journal_radius" if dr is None or dr.wheel_bore_radius is None else "drawing.wheel_bore_radius"
    if not dims.hub_max > bore:
        ck.bad(bore_key, f"no hub: the slot bottoms reach radius x_b − w = {_num(dims.hub_max)} mm, which "
                         f"must exceed the wheel bore radius {_num(bore)} mm (short by "
                         f"{_num(bore - dims.hub_max)} mm); reduce roller_radius, clearance.bottom or the "
                         "bore, or increase center_distance")
    elif not dims.hub_max - bore >= m:
        ck.bad(bore_key, f"the hub is too thin: the slot bottoms at radius x_b − w = {_num(dims.hub_max)} mm "
                         f"leave {_num(dims.hub_max - bore)} mm around the wheel bore ({_num(bore)} mm), "
                         f"below {web_note} by {_num(m - (dims.hub_max - bore))} mm; reduce the bore, "
                         "roller_radius or clearance.bottom, or increase center_distance")
    lever = a - dims.crank_radius
    fr = ld["journal_friction"] * ld["journal_radius"]
    if not fr < lever:
        ck.bad("load.journal_friction", f"self-locking journal: f02·r02 = {_num(fr)} mm must be below the "
                                        f"shortest roller lever A − r = {_num(lever)} mm (over by {_num(fr - lever)} mm)")
    if dr is not None and dr.pin_radius is not None and not dr.pin_radius < rp:
        ck.bad("drawing.pin_radius", f"the roller pin radius {_num(dr.pin_radius)} mm must be below the roller "
                                     f"radius {_num(rp)} mm (over by {_num(dr.pin_radius - rp)} mm)")
    elif dr is not None and dr.pin_radius is not None and not rp - dr.pin_radius >= m:
        ck.bad("drawing.pin_radius", f"the roller around its pin (radius {_num(dr.pin_radius)} mm) is "
                                     f"{_num(rp - dr.pin_radius)} mm thick, below {web_note}")
    elif not rp > m:
        ck.bad("roller_radius", f"the roller (radius {_num(rp)} mm) leaves no room for a pin with {web_note}")
    # necessary bound: the relief is at least R_o + c_l, so the disc's thinnest section is below
    # A − R_o − c_l; the exact relief is checked when the drive is drawn (mechsketch validate)
    room = a - dims.outer_radius - cl.lock
    if dr is not None and dr.crank_bore_radius is not None:
        if not dr.crank_bore_radius < room - m:
            ck.bad("drawing.crank_bore_radius", f"the crank bore radius {_num(dr.crank_bore_radius)} mm must be "
                                                f"below A − R_o − c_l − min_web = {_num(room - m)} mm, the locking "
                                                f"disc's thinnest section at most less {web_note} (over by "
                                                f"{_num(dr.crank_bore_radius - room + m)} mm)")
    elif dims.lock_disc_radius > 0 and not room > m:
        ck.bad("slots", f"no room for a crank bore: the locking disc's relief comes within A − R_o − c_l = "
                        f"{_num(room)} mm of the crank centre, not more than {web_note}; use fewer slots, a "
                        "larger center_distance, a smaller roller_radius or clearance.lock")


def require_valid(element: Geneva) -> WheelDimensions:
    """The element's wheel dimensions; :class:`GeometryError` if an element built in code (not
    parsed) violates a limit that ``parse`` checks."""
    _, problems = parse(element.to_dict(), "$")
    if problems:
        raise GeometryError(f"geneva {element.id!r}: " + "; ".join(p.message for p in problems))
    return element.dimensions()
