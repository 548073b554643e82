"""Independent references for the linkage solver tests (no solver formula is reused here).

* :class:`MpReference` — the whole linkage as raw rigid-body constraint equations, solved in
  mpmath at 50 digits by Newton's method from the float solution. Each moving link has a pose
  (x, y, θ): the point drawn at ``p0`` is at (x, y) + R(θ)(p0 − c), c the drawn position of the
  link's first joint. Constraints: an R joint shared by links a, b gives P_a(p0) = P_b(p0); a P
  joint gives θ_a = θ_b and cross(R(θ_a)u0, P_b(p0) − P_a(p0)) = 0. Velocities and accelerations
  solve the once and twice time-differentiated equations (linear in the rates), in mpmath.
  Nothing here knows about dyads, modes or Cramer's rule.
* :func:`closure_error` — loop closure checked from the public Solution API only (every link
  rigid, not mirrored, every R joint shared, every P joint a pure slide along its axis).
* :func:`continuation` — a generic float Newton continuation from the drawn pose, the same
  equations as the mpmath reference: an independent check of assembly-mode selection.
* builders of test linkages (four-bar, slider-crank, inverted slider-crank, PRP, Scotch yoke
  (RPP), six-bars, a class-III group) from drawn positions that close.
"""
from __future__ import annotations

import cmath
import math
from dataclasses import dataclass

import mpmath
import numpy as np

from mechsketch.core import Driver, Joint, JointKind, Link, Linkage

R, P = JointKind.R, JointKind.P
DPS = 50


# ---------------------------------------------------------------------------------------------
# building linkages
# ---------------------------------------------------------------------------------------------
def build(eid: str, joints, links, ground: str, driver: str, pivot: str, rpm: float = 60.0,
          samples: int = 360) -> Linkage:
    """joints: [(id, 'R'|'P', (x, y)[, axis_deg])], links: {id: [joint ids]}."""
    js = []
    for spec in joints:
        jid, kind, at = spec[0], JointKind(spec[1]), spec[2]
        axis = float(spec[3]) if len(spec) > 3 else (0.0 if kind is P else None)
        js.append(Joint(jid, kind, (float(at[0]), float(at[1])), axis))
    ls = tuple(Link(k, tuple(v)) for k, v in links.items())
    return Linkage(eid, tuple(js), ls, ground, Driver(driver, pivot, float(rpm)), int(samples))


def scene_dict(*linkages: Linkage) -> dict:
    return {"format": "mechsketch.scene", "schema_version": 1, "units": "mm",
            "elements": [lk.to_dict() for lk in linkages]}


def e(deg: float) -> complex:
    return cmath.exp(1j * math.radians(deg))


def xy(z: complex) -> tuple[float, float]:
    return (z.real, z.imag)


def cross2(a: complex, b: complex) -> float:
    return (a.conjugate() * b).imag


def circle_meet(p: complex, rp: float, q: complex, rq: float, side: int) -> complex:
    """Intersection of circles (p, rp), (q, rq) to the left (side +1) or right (−1) of p→q."""
    d = abs(q - p)
    a = (rp * rp - rq * rq + d * d) / (2 * d)
    h2 = rp * rp - a * a
    if h2 < 0:
        raise ValueError("circles do not meet")
    u = (q - p) / d
    return p + u * (a + 1j * side * math.sqrt(h2))


def line_circle(o: complex, u: complex, c: complex, r: float, sign: int) -> complex:
    """Point o + s·u (|u| = 1) at distance r from c, with the larger (+1) or smaller (−1) s."""
    w = o - c
    b = (w.conjugate() * u).real
    disc = b * b - (abs(w) ** 2 - r * r)
    if disc < 0:
        raise ValueError("line misses circle")
    return o + u * (-b + sign * math.sqrt(disc))


def fourbar(crank=40.0, coupler=140.0, rocker=120.0, ground=160.0, theta0=60.0, mode=1,
            origin=0j, rot=0.0, rpm=95.4929658551372, samples=360, eid="fourbar",
            coupler_point=None) -> Linkage:
    """Crank A–B, coupler B–C (+E), rocker D–C; C left (mode +1) or right of B→D."""
    r = e(rot)
    A, D = origin, origin + ground * r
    B = A + crank * e(theta0) * r
    C = circle_meet(B, coupler, D, rocker, mode)
    joints = [("A", "R", xy(A)), ("B", "R", xy(B)), ("C", "R", xy(C)), ("D", "R", xy(D))]
    cj = ["B", "C"]
    if coupler_point is not None:
        E = B + (C - B) / abs(C - B) * complex(*coupler_point)
        joints.append(("E", "R", xy(E)))
        cj.append("E")
    return build(eid, joints, {"ground": ["A", "D"], "crank": ["A", "B"], "coupler": cj,
                               "rocker": ["D", "C"]}, "ground", "crank", "A", rpm, samples)


def slider_crank(crank=40.0, rod=160.0, offset=20.0, xi=0.0, theta0=0.0, mode=1, pin=0j,
                 origin=0j, rpm=95.4929658551372, samples=360, eid="slider_crank") -> Linkage:
    """Crank A–B, rod B–C, slider (C, S) on a fixed guide at ``xi`` deg, signed offset ``offset``
    from A; the slider pin C sits at ``pin`` (guide frame: along, normal) from the slide point S.
    Mode +1: the rod's projection on the guide direction is positive."""
    u = e(xi)
    n = 1j * u
    A = origin
    B = A + crank * e(theta0)
    b = u * pin                       # C − S
    # C = A + offset·n + s·u + b, |C − B| = rod
    C = line_circle(A + offset * n + b, u, B, rod, mode)
    S = C - b
    return build(eid, [("A", "R", xy(A)), ("B", "R", xy(B)), ("C", "R", xy(C)), ("S", "P", xy(S), xi)],
                 {"ground": ["A", "S"], "crank": ["A", "B"], "rod": ["B", "C"], "slider": ["C", "S"]},
                 "ground", "crank", "A", rpm, samples)


def inverted_slider_crank(crank=40.0, ground=100.0, offset=0.0, theta0=30.0, mode=1, q_along=0.0,
                          origin=0j, rot=0.0, rpm=95.4929658551372, samples=360,
                          eid="inverted") -> Linkage:
    """Crank A–B; a block pinned at B slides on the rocker C (ground pivot at distance ``ground``)
    along an axis at signed offset ``offset`` from C; mode: sign of the along-axis distance C→B."""
    r = e(rot)
    A, C = origin, origin + ground * r
    B = A + crank * e(theta0) * r
    d = B - C
    D = abs(d)
    sigma = mode * math.sqrt(D * D - offset * offset)
    u = d / complex(sigma, offset)    # cross(u, B − C) = offset, dot(u, B − C) = sigma
    Q = B + q_along * u
    T = C + 60.0 * u * 1j - 30.0 * u
    axis = math.degrees(cmath.phase(u))
    return build(eid, [("A", "R", xy(A)), ("B", "R", xy(B)), ("C", "R", xy(C)), ("Q", "P", xy(Q), axis),
                       ("T", "R", xy(T))],
                 {"ground": ["A", "C"], "crank": ["A", "B"], "block": ["B", "Q"], "rocker": ["C", "T", "Q"]},
                 "ground", "crank", "A", rpm, samples)


def prp_linkage(crank_dir=40.0, guide_offset=0.0, xi=100.0, g=(60.0, 10.0), q1_along=-15.0,
                q2_along=25.0, rpm=95.4929658551372, samples=360, eid="prp") -> Linkage:
    """Block i slides on a guide along the crank (offset ``guide_offset`` from A), pinned at L to
    block j sliding on a fixed guide through ``g`` at ``xi`` degrees (a PRP group)."""
    A = 0j
    u1 = e(crank_dir)
    o1 = A + guide_offset * 1j * u1
    G = complex(*g)
    u2 = e(xi)
    # L = o1 + t1 u1 = G + t2 u2
    t1 = cross2(G - o1, u2) / cross2(u1, u2)
    L = o1 + t1 * u1
    Q1 = L + q1_along * u1
    Q2 = L + q2_along * u2
    return build(eid, [("A", "R", (0.0, 0.0)), ("Q1", "P", xy(Q1), crank_dir), ("L", "R", xy(L)),
                       ("Q2", "P", xy(Q2), xi), ("G", "R", xy(G - 50))],
                 {"ground": ["A", "Q2", "G"], "crank": ["A", "Q1"], "block_i": ["Q1", "L"],
                  "block_j": ["L", "Q2"]}, "ground", "crank", "A", rpm, samples)


def scotch_yoke(crank=30.0, theta0=35.0, slot=90.0, guide=0.0, guide_at=(50.0, -30.0),
                slot_along=10.0, rpm=95.4929658551372, samples=360, eid="yoke") -> Linkage:
    """Crank A–B; block pinned at B slides in a slot (``slot`` deg) of the yoke, which slides on a
    fixed guide (``guide`` deg) through ``guide_at`` (an RPP group)."""
    B = crank * e(theta0)
    Qs = B + slot_along * e(slot)
    G = complex(*guide_at)
    u = e(guide)
    Qg = G + u * ((B - G).conjugate() * u).real
    return build(eid, [("A", "R", (0.0, 0.0)), ("B", "R", xy(B)), ("Qs", "P", xy(Qs), slot),
                       ("Qg", "P", xy(Qg), guide), ("Y", "R", xy(Qg + 40j))],
                 {"ground": ["A", "Qg"], "crank": ["A", "B"], "block": ["B", "Qs"],
                  "yoke": ["Qs", "Qg", "Y"]}, "ground", "crank", "A", rpm, samples)


def crank_guided(crank_dir=50.0, o2=(-60.0, 20.0), rod=70.0, pin=(0.0, 8.0), mode=1,
                 rpm=95.4929658551372, samples=360, eid="crank_guided") -> Linkage:
    """A rod from a ground pivot O2 carries a block E sliding on a guide of the driving crank
    (an RRP group whose guide rotates with the driver); ``pin``: E from the slide point
    (along, normal). Mode: sign of the rod's projection on the guide."""
    u = e(crank_dir)
    O2 = complex(*o2)
    b = u * complex(*pin)
    E = line_circle(b, u, O2, rod, mode)
    Q = E - b
    return build(eid, [("A", "R", (0.0, 0.0)), ("Q", "P", xy(Q), crank_dir), ("O2", "R", xy(O2)),
                       ("E", "R", xy(E))],
                 {"ground": ["A", "O2"], "crank": ["A", "Q"], "rod": ["O2", "E"], "block": ["E", "Q"]},
                 "ground", "crank", "A", rpm, samples)


def sixbar_stephenson(mode1=1, mode2=1, e_pt=(60.0, 40.0), f=(80.0, 180.0), rod=90.0, out=80.0,
                      on_rocker=False, theta0=60.0, eid="stephenson", **kw) -> Linkage:
    """Four-bar with a coupler point E; a second RRR dyad E–G–F with F on the ground (or, with
    ``on_rocker``, on the rocker: both outer joints on moving links)."""
    fb = fourbar(mode=mode1, theta0=theta0, coupler_point=e_pt, eid=eid, **kw)
    at = {j.id: complex(*j.at) for j in fb.joints}
    F = complex(*f)
    G = circle_meet(at["E"], rod, F, out, mode2)
    joints = [(j.id, j.kind.value, j.at) for j in fb.joints] + [("F", "R", xy(F)), ("G", "R", xy(G))]
    links = {k.id: list(k.joints) for k in fb.links}
    links["rod"] = ["E", "G"]
    links["out"] = ["F", "G"]
    if on_rocker:
        links["rocker"].append("F")
    else:
        links["ground"].append("F")
    return build(eid, joints, links, "ground", "crank", "A", fb.driver.speed_rpm, fb.samples)


def sixbar_compound(rod=110.0, offset=-10.0, mode=1, eid="compound") -> Linkage:
    """Four-bar plus a slider-crank whose rod starts at the coupler–rocker joint C (a joint on
    three links: the second dyad hangs on the first dyad's inner joint)."""
    fb = fourbar(eid=eid)
    C = complex(*fb.joint("C").at)
    u = 1 + 0j
    Ecoord = line_circle(complex(0.0, C.imag + offset), u, C, rod, mode)
    joints = [(j.id, j.kind.value, j.at) for j in fb.joints] + [("E", "R", xy(Ecoord)),
                                                                ("S", "P", xy(Ecoord), 0.0)]
    links = {k.id: list(k.joints) for k in fb.links}
    links["ground"].append("S")
    links["rod"] = ["C", "E"]
    links["slider"] = ["E", "S"]
    return build(eid, joints, links, "ground", "crank", "A", fb.driver.speed_rpm, fb.samples)


def two_dyads(eid="two_dyads") -> Linkage:
    """One crank drives a four-bar dyad (coupler, rocker) and a slider dyad (rod, slider) from
    the same crank pin B: two independent groups."""
    fb = fourbar(eid=eid)
    B = complex(*fb.joint("B").at)
    S = line_circle(complex(0.0, -20.0), 1 + 0j, B, 150.0, -1)
    joints = [(j.id, j.kind.value, j.at) for j in fb.joints] + [("E", "R", xy(S)), ("S", "P", xy(S), 0.0)]
    links = {k.id: list(k.joints) for k in fb.links}
    links["ground"].append("S")
    links["rod"] = ["B", "E"]
    links["slider"] = ["E", "S"]
    return build(eid, joints, links, "ground", "crank", "A", fb.driver.speed_rpm, fb.samples)


def class3(eid="class3") -> Linkage:
    """A crank driving a class-III (triad) group: a ternary link X1 X2 X3 held by three binary
    links to the crank pin B and to ground pivots G2, G3. Mobility 1, but no dyad splits off."""
    A, B = 0j, 30 + 20j
    X1, X2, X3 = 80 + 60j, 140 + 70j, 110 + 20j
    G2, G3 = 170 + 150j, 160 - 40j
    pts = dict(A=A, B=B, X1=X1, X2=X2, X3=X3, G2=G2, G3=G3)
    return build(eid, [(k, "R", xy(v)) for k, v in pts.items()],
                 {"ground": ["A", "G2", "G3"], "crank": ["A", "B"], "b1": ["B", "X1"], "b2": ["G2", "X2"],
                  "b3": ["G3", "X3"], "tri": ["X1", "X2", "X3"]}, "ground", "crank", "A")


def sixbar_guide(mode=1, eid="sixbar") -> Linkage:
    """The six-bar example (a block E sliding on the rocker's guide line, rod B–E) in either
    assembly mode of its RRP group (mode: sign of the rod's projection on the guide)."""
    from mechsketch.core import load_scene
    from mechsketch.resources import example_path

    lk = load_scene(example_path("sixbar_moving_guide")).element("sixbar")
    B, Q = complex(*lk.joint("B").at), complex(*lk.joint("Q").at)
    E0 = complex(*lk.joint("E").at)
    u = e(lk.joint("Q").axis_deg)
    if mode == (1 if ((E0 - B).conjugate() * u).real >= 0 else -1):
        return lk
    E = line_circle(Q, u, B, abs(E0 - B), mode)
    return lk.with_joints_moved({"E": xy(E), "Q": xy(E)})


def _extend(lk, eid, joints, links):
    js = [(j.id, j.kind.value, j.at) + ((j.axis_deg,) if j.kind is P else ()) for j in lk.joints] + joints
    ls = {k.id: list(k.joints) for k in lk.links}
    for k, v in links.items():
        ls.setdefault(k, [])
        ls[k] += v
    return build(eid, js, ls, lk.ground, lk.driver.link, lk.driver.pivot, lk.driver.speed_rpm, lk.samples)


def rpr_on_moving_links(eid="rpr_moving") -> Linkage:
    """Four-bar + RPR group whose both outer joints are on moving links: a block pinned at the
    coupler point E slides along a rod pinned at a rocker point H."""
    fb = fourbar(coupler_point=(0.5, 0.6), eid=eid)
    at = {j.id: complex(*j.at) for j in fb.joints}
    H = at["D"] + 0.5 * (at["C"] - at["D"]) + 30j
    u = (at["E"] - H) / abs(at["E"] - H) * e(10)
    Q = at["E"] + 5 * u
    return _extend(fb, eid, [("H", "R", xy(H)), ("Q", "P", xy(Q), math.degrees(cmath.phase(u)))],
                   {"rocker": ["H"], "block": ["E", "Q"], "rod": ["H", "Q"]})


def rrp_guide_on_coupler(eid="rrp_coupler") -> Linkage:
    """Four-bar + RRP group whose guide is on the coupler (turning with angular acceleration);
    the block's pin P sits 6 mm off the slide axis."""
    fb = fourbar(coupler_point=(0.5, 0.6), eid=eid)
    G = complex(*fb.joint("E").at)
    xi, O2 = 25.0, -40 + 90j
    S = line_circle(G, e(xi), O2, 120.0, 1)
    Pp = S + 6j * e(xi)
    return _extend(fb, eid, [("O2", "R", xy(O2)), ("P", "R", xy(Pp)), ("S", "P", xy(S), xi)],
                   {"ground": ["O2"], "coupler": ["S"], "rod": ["O2", "P"], "block": ["P", "S"]})


def eight_bar(eid="eight_bar") -> Linkage:
    """Stephenson six-bar (second RRR on two moving links) + an RRP group sliding on a guide of
    the second dyad's output link: three groups in sequence."""
    st_ = sixbar_stephenson(on_rocker=True, f=(150.0, 60.0), eid=eid)
    G = complex(*st_.joint("G").at)
    xi = 70.0
    O3 = G + (60 + 80j)
    S = line_circle(G, e(xi), O3, 140.0, -1)
    return _extend(st_, eid, [("O3", "R", xy(O3)), ("S", "R", xy(S)), ("T", "P", xy(S), xi)],
                   {"ground": ["O3"], "out": ["T"], "rod3": ["O3", "S"], "blk": ["S", "T"]})


def mirrored(linkage: Linkage, joint: str, a: str, b: str, eid: str | None = None) -> Linkage:
    """The same linkage with ``joint`` reflected across the line through joints a and b (the
    other assembly mode of an RRR group)."""
    pa, pb = complex(*linkage.joint(a).at), complex(*linkage.joint(b).at)
    p = complex(*linkage.joint(joint).at)
    u = (pb - pa) / abs(pb - pa)
    w = (p - pa) / u
    q = pa + u * w.conjugate()
    lk = linkage.with_joint_moved(joint, xy(q))
    if eid:
        from dataclasses import replace
        lk = replace(lk, id=eid)
    return lk


def translated(linkage: Linkage, dx: float, dy: float) -> Linkage:
    from dataclasses import replace
    return replace(linkage, joints=tuple(j.moved((j.at[0] + dx, j.at[1] + dy)) for j in linkage.joints))


def size_of(linkage: Linkage) -> float:
    """The mechanism's extent (mm): the largest distance between two drawn joints."""
    pts = [complex(*j.at) for j in linkage.joints]
    return max(abs(p - q) for p in pts for q in pts)


# ---------------------------------------------------------------------------------------------
# loop closure from the public Solution API
# ---------------------------------------------------------------------------------------------
def _frames(linkage: Linkage, sol, scale: float):
    """Per link: origin point, x-probe and y-probe positions (complex (N,)), from sol.point."""
    out = {}
    for lk in linkage.links:
        c = linkage.joint(lk.joints[0]).at
        p = sol.point(lk.id, c)
        px = sol.point(lk.id, (c[0] + scale, c[1]))
        py = sol.point(lk.id, (c[0], c[1] + scale))
        z = lambda a: a[:, 0] + 1j * a[:, 1]  # noqa: E731
        out[lk.id] = (z(p), z(px), z(py), c)
    return out


def closure_error(linkage: Linkage, sol, mask=None) -> float:
    """Largest violation (mm) of the linkage's constraints over the samples in ``mask`` (default:
    ``sol.valid``), computed only from ``sol.point``/``sol.position``."""
    scale = size_of(linkage)
    mask = sol.valid if mask is None else mask
    fr = _frames(linkage, sol, scale)
    worst = 0.0

    def upd(v):
        nonlocal worst
        v = np.abs(v)[mask]
        if v.size:
            m = float(np.max(v))
            worst = max(worst, m if np.isfinite(m) else math.inf)

    rot = {}
    for k, (p, px, py, c) in fr.items():
        upd(np.abs(px - p) - scale)                 # rigid
        upd(np.abs(py - p) - scale)
        upd((py - p) - 1j * (px - p))               # not mirrored, not sheared
        rot[k] = (px - p) / scale
        pts = {j: sol.point(k, linkage.joint(j).at) for j in linkage.link(k).joints}
        for a in pts:
            for b in pts:
                da = complex(*linkage.joint(a).at) - complex(*linkage.joint(b).at)
                dd = (pts[a][:, 0] - pts[b][:, 0]) + 1j * (pts[a][:, 1] - pts[b][:, 1])
                upd(dd - rot[k] * da)
    for j in linkage.joints:
        carriers = linkage.links_of(j.id)
        pts = [sol.point(k, j.at) for k in carriers]
        pts = [a[:, 0] + 1j * a[:, 1] for a in pts]
        if j.kind is R:
            for q in pts[1:]:
                upd(q - pts[0])
        else:
            a, b = carriers
            upd(scale * (rot[a] - rot[b]))
            u = rot[a] * e(j.axis_deg)
            upd(cross2_arr(u, pts[1] - pts[0]))
    # the ground does not move; the driver turns about its pivot by the input
    g = fr[linkage.ground]
    upd(g[0] - complex(*g[3]))
    upd(rot[linkage.ground] - 1)
    drv = linkage.driver
    pv = complex(*linkage.joint(drv.pivot).at)
    tip = next(x for x in linkage.link(drv.link).joints if x != drv.pivot)
    t0 = complex(*linkage.joint(tip).at) - pv
    tp = sol.point(drv.link, linkage.joint(tip).at)
    tp = tp[:, 0] + 1j * tp[:, 1]
    upd(scale * (np.angle((tp - pv) / t0 * np.exp(-1j * (sol.input - math.atan2(t0.imag, t0.real))))))
    pp = sol.point(drv.link, linkage.joint(drv.pivot).at)
    upd(pp[:, 0] + 1j * pp[:, 1] - pv)
    return worst


def cross2_arr(a, b):
    return (np.conj(a) * b).imag


# ---------------------------------------------------------------------------------------------
# the 50-digit reference
# ---------------------------------------------------------------------------------------------
@dataclass
class RefState:
    """Poses and rates of every link at one driver angle, mpmath numbers."""

    pose: dict      # link -> (x, y, th)
    rate: dict      # link -> (xd, yd, thd)
    acc: dict       # link -> (xdd, ydd, thdd)
    c: dict         # link -> (cx, cy) drawn reference point
    iterations: int

    def point(self, link: str, p0):
        """(P, V, A) of the point of ``link`` drawn at p0, each an (x, y) pair of mpf."""
        x, y, th = self.pose[link]
        xd, yd, thd = self.rate[link]
        xdd, ydd, thdd = self.acc[link]
        cx, cy = self.c[link]
        dx, dy = mpmath.mpf(p0[0]) - cx, mpmath.mpf(p0[1]) - cy
        co, si = mpmath.cos(th), mpmath.sin(th)
        rx, ry = co * dx - si * dy, si * dx + co * dy
        P = (x + rx, y + ry)
        V = (xd - thd * ry, yd + thd * rx)
        A = (xdd - thdd * ry - thd * thd * rx, ydd + thdd * rx - thd * thd * ry)
        return P, V, A


class _Num:
    """Arithmetic backend of the constraint system: mpmath (reference) or float (continuation)."""

    def __init__(self, kind: str):
        self.kind = kind
        if kind == "mp":
            self.cos, self.sin, self.num = mpmath.cos, mpmath.sin, mpmath.mpf
            self.zero, self.one = mpmath.mpf(0), mpmath.mpf(1)
        else:
            self.cos, self.sin, self.num = math.cos, math.sin, float
            self.zero, self.one = 0.0, 1.0

    def zeros(self, n):
        return mpmath.mp.zeros(n, n) if self.kind == "mp" else np.zeros((n, n))


class MpReference:
    """The linkage's constraint equations, in mpmath at ``dps`` digits (see the module docstring).

    ``backend="float"`` evaluates the same equations in float64 (for :func:`continuation`).
    """

    def __init__(self, linkage: Linkage, dps: int = DPS, backend: str = "mp"):
        self.lk = linkage
        self.dps = dps
        self.N = N = _Num(backend)
        self._cos, self._sin = N.cos, N.sin
        with mpmath.workdps(dps):
            self.ground = linkage.ground
            self.driver = linkage.driver.link
            self.unknown = [k.id for k in linkage.links if k.id not in (self.ground, self.driver)]
            self.col = {k: 3 * i for i, k in enumerate(self.unknown)}
            at = {j.id: (N.num(j.at[0]), N.num(j.at[1])) for j in linkage.joints}
            self.at = at
            self.c = {k.id: at[k.joints[0]] for k in linkage.links}
            drv = linkage.driver
            self.c[self.driver] = at[drv.pivot]
            tip = next(x for x in linkage.link(drv.link).joints if x != drv.pivot)
            pv, tp = linkage.joint(drv.pivot).at, linkage.joint(tip).at
            self.theta0 = mpmath.atan2(mpmath.mpf(tp[1]) - pv[1], mpmath.mpf(tp[0]) - pv[0])
            known = (self.ground, self.driver)
            self.rc = []    # (joint, link a, link b)
            self.pc = []    # (joint, link a, link b, u0)
            for j in linkage.joints:
                carriers = sorted(linkage.links_of(j.id), key=lambda k: (k not in known,))
                if j.kind is R:
                    for b in carriers[1:]:
                        if {carriers[0], b} == set(known):
                            continue
                        self.rc.append((j.id, carriers[0], b))
                else:
                    a, b = carriers
                    ang = mpmath.radians(mpmath.mpf(j.axis_deg))
                    self.pc.append((j.id, a, b, (N.num(mpmath.cos(ang)), N.num(mpmath.sin(ang)))))
            self.n = 3 * len(self.unknown)
            m = 2 * len(self.rc) + 2 * len(self.pc)
            if m != self.n:
                raise ValueError(f"reference needs a square system: {m} equations, {self.n} unknowns")

    # -- kinematics of one link's points ----------------------------------------------------
    def _r(self, link, pose, p0):
        x, y, th = pose[link]
        cx, cy = self.c[link]
        dx, dy = p0[0] - cx, p0[1] - cy
        co, si = self._cos(th), self._sin(th)
        return co * dx - si * dy, si * dx + co * dy

    def _u(self, th, u0):
        co, si = self._cos(th), self._sin(th)
        return co * u0[0] - si * u0[1], si * u0[0] + co * u0[1]

    def _poses(self, q, rho):
        N = self.N
        pose = {self.ground: (self.c[self.ground][0], self.c[self.ground][1], N.zero),
                self.driver: (self.c[self.driver][0], self.c[self.driver][1], rho)}
        for k in self.unknown:
            i = self.col[k]
            pose[k] = (q[i], q[i + 1], q[i + 2])
        return pose

    def _rates(self, qd, w):
        N = self.N
        rate = {self.ground: (N.zero, N.zero, N.zero), self.driver: (N.zero, N.zero, w)}
        for k in self.unknown:
            i = self.col[k]
            rate[k] = (qd[i], qd[i + 1], qd[i + 2])
        return rate

    def _pva(self, link, p0, pose, rate=None, acc=None):
        rx, ry = self._r(link, pose, p0)
        P = (pose[link][0] + rx, pose[link][1] + ry)
        if rate is None:
            return P, None, None
        xd, yd, thd = rate[link]
        V = (xd - thd * ry, yd + thd * rx)
        if acc is None:
            return P, V, None
        xdd, ydd, thdd = acc[link]
        return P, V, (xdd - thdd * ry - thd * thd * rx, ydd + thdd * rx - thd * thd * ry)

    # -- the equations ----------------------------------------------------------------------
    def residual(self, q, rho):
        """F(q; ρ): R joints P_a − P_b (2 rows); P joints sin(θa − θb), cross(u_a, P_b − P_a)."""
        pose = self._poses(q, rho)
        out = []
        for jid, a, b in self.rc:
            (pa, _, _), (pb, _, _) = self._pva(a, self.at[jid], pose), self._pva(b, self.at[jid], pose)
            out += [pa[0] - pb[0], pa[1] - pb[1]]
        for jid, a, b, u0 in self.pc:
            ux, uy = self._u(pose[a][2], u0)
            (pa, _, _), (pb, _, _) = self._pva(a, self.at[jid], pose), self._pva(b, self.at[jid], pose)
            out += [self._sin(pose[a][2] - pose[b][2]), ux * (pb[1] - pa[1]) - uy * (pb[0] - pa[0])]
        return out

    def jacobian(self, q, rho):
        """∂F/∂q, written out by hand."""
        pose = self._poses(q, rho)
        J = self.N.zeros(self.n)
        row = 0

        def put(r, link, ddx, ddy, dth):
            if link in self.col:
                i = self.col[link]
                J[r, i] += ddx
                J[r, i + 1] += ddy
                J[r, i + 2] += dth

        for jid, a, b in self.rc:
            ra, rb = self._r(a, pose, self.at[jid]), self._r(b, pose, self.at[jid])
            put(row, a, 1, 0, -ra[1])
            put(row + 1, a, 0, 1, ra[0])
            put(row, b, -1, 0, rb[1])
            put(row + 1, b, 0, -1, -rb[0])
            row += 2
        for jid, a, b, u0 in self.pc:
            ux, uy = self._u(pose[a][2], u0)
            ra, rb = self._r(a, pose, self.at[jid]), self._r(b, pose, self.at[jid])
            dx = pose[b][0] + rb[0] - pose[a][0] - ra[0]
            dy = pose[b][1] + rb[1] - pose[a][1] - ra[1]
            cd = self._cos(pose[a][2] - pose[b][2])
            put(row, a, 0, 0, cd)
            put(row, b, 0, 0, -cd)
            # g = ux·dy − uy·dx; ∂u/∂θa = (−uy, ux); ∂d/∂(xb, yb, θb) = (1, 0), (0, 1), J rb;
            # ∂d/∂(xa, ya, θa) = −(1, 0), −(0, 1), −J ra
            put(row + 1, b, -uy, ux, ux * rb[0] + uy * rb[1])
            put(row + 1, a, uy, -ux, -(ux * ra[0] + uy * ra[1]) - uy * dy - ux * dx)
            row += 2
        return J

    def vel_residual(self, q, qd, rho, w):
        """dF/dt for unknown rates qd and driver speed w (linear in qd; P rows at cos(θa−θb) = 1)."""
        pose, rate = self._poses(q, rho), self._rates(qd, w)
        out = []
        for jid, a, b in self.rc:
            (_, va, _), (_, vb, _) = self._pva(a, self.at[jid], pose, rate), self._pva(b, self.at[jid], pose, rate)
            out += [va[0] - vb[0], va[1] - vb[1]]
        for jid, a, b, u0 in self.pc:
            thd = rate[a][2]
            ux, uy = self._u(pose[a][2], u0)
            (pa, va, _), (pb, vb, _) = self._pva(a, self.at[jid], pose, rate), self._pva(b, self.at[jid], pose, rate)
            dx, dy = pb[0] - pa[0], pb[1] - pa[1]
            dvx, dvy = vb[0] - va[0], vb[1] - va[1]
            udx, udy = -thd * uy, thd * ux
            out += [rate[a][2] - rate[b][2], (udx * dy - udy * dx) + (ux * dvy - uy * dvx)]
        return out

    def acc_residual(self, q, qd, qdd, rho, w, al):
        """d²F/dt² (linear in the unknown accelerations qdd)."""
        N = self.N
        pose, rate = self._poses(q, rho), self._rates(qd, w)
        acc = {self.ground: (N.zero, N.zero, N.zero), self.driver: (N.zero, N.zero, al)}
        for k in self.unknown:
            i = self.col[k]
            acc[k] = (qdd[i], qdd[i + 1], qdd[i + 2])

        def cr(p, r):
            return p[0] * r[1] - p[1] * r[0]

        out = []
        for jid, a, b in self.rc:
            (_, _, aa), (_, _, ab) = (self._pva(a, self.at[jid], pose, rate, acc),
                                      self._pva(b, self.at[jid], pose, rate, acc))
            out += [aa[0] - ab[0], aa[1] - ab[1]]
        for jid, a, b, u0 in self.pc:
            thd, thdd = rate[a][2], acc[a][2]
            ux, uy = self._u(pose[a][2], u0)
            (pa, va, aa), (pb, vb, ab) = (self._pva(a, self.at[jid], pose, rate, acc),
                                          self._pva(b, self.at[jid], pose, rate, acc))
            d = (pb[0] - pa[0], pb[1] - pa[1])
            dv = (vb[0] - va[0], vb[1] - va[1])
            da = (ab[0] - aa[0], ab[1] - aa[1])
            ud = (-thd * uy, thd * ux)
            udd = (-thdd * uy - thd * thd * ux, thdd * ux - thd * thd * uy)
            out += [acc[a][2] - acc[b][2], cr(udd, d) + 2 * cr(ud, dv) + cr((ux, uy), da)]
        return out

    # -- solving (mpmath backend) -----------------------------------------------------------
    @staticmethod
    def _lu(J):
        """LU factors with partial pivoting of a square mp.matrix, on plain lists (fast)."""
        n = J.rows
        a = [[J[i, k] for k in range(n)] for i in range(n)]
        perm = list(range(n))
        for c in range(n):
            piv = max(range(c, n), key=lambda r: abs(a[r][c]))
            if a[piv][c] == 0:
                raise ZeroDivisionError("singular Jacobian")
            a[c], a[piv] = a[piv], a[c]
            perm[c], perm[piv] = perm[piv], perm[c]
            inv = 1 / a[c][c]
            rowc = a[c]
            for r in range(c + 1, n):
                f = a[r][c] * inv
                if f:
                    rowr = a[r]
                    rowr[c] = f
                    for k in range(c + 1, n):
                        rowr[k] -= f * rowc[k]
                else:
                    a[r][c] = f
        return a, perm

    @staticmethod
    def _lu_solve(lu, b):
        a, perm = lu
        n = len(a)
        y = [b[p] for p in perm]
        for i in range(n):
            row = a[i]
            y[i] = y[i] - sum((row[k] * y[k] for k in range(i)), mpmath.mpf(0))
        for i in range(n - 1, -1, -1):
            row = a[i]
            y[i] = (y[i] - sum((row[k] * y[k] for k in range(i + 1, n)), mpmath.mpf(0))) / row[i]
        return mpmath.mp.matrix(y)

    def solve_positions(self, rho, guess):
        """Chord-Newton from ``guess`` (3 floats per unknown link; the Jacobian factored at the
        guess), then one full Newton step; returns (q, iterations, LU of the final Jacobian)."""
        mp = mpmath.mp
        if not self.n:
            return [], 0, None
        q = mp.matrix([mp.mpf(v) for v in guess])
        scale = max([abs(mp.mpf(c)) for p in self.at.values() for c in p] + [mp.one])
        tol = mp.mpf(10) ** (-(mp.dps - 6)) * scale
        lu = self._lu(self.jacobian(q, rho))
        for it in range(1, 80):
            dq = self._lu_solve(lu, [-v for v in self.residual(q, rho)])
            q = q + dq
            if max(abs(v) for v in dq) <= tol:
                break
            if it % 10 == 0:  # slow chord convergence: refresh the Jacobian
                lu = self._lu(self.jacobian(q, rho))
        else:
            raise RuntimeError("reference Newton did not converge")
        lu = self._lu(self.jacobian(q, rho))
        q = q + self._lu_solve(lu, [-v for v in self.residual(q, rho)])
        return q, it, lu

    def solve(self, inp: float, w: float, guess, al: float = 0.0) -> RefState:
        """Positions, rates and accelerations at driver angle ``inp`` (rad), speed ``w`` (rad/s)
        and driver angular acceleration ``al``, from a float ``guess`` (see :meth:`guess_from`)."""
        mp = mpmath.mp
        with mpmath.workdps(self.dps):
            rho = mp.mpf(inp) - self.theta0
            q, its, lu = self.solve_positions(rho, guess)
            w, al = mp.mpf(w), mp.mpf(al)
            zero = [mp.zero] * self.n
            if self.n:
                qd = self._lu_solve(lu, [-v for v in self.vel_residual(q, zero, rho, w)])
                qdd = self._lu_solve(lu, [-v for v in self.acc_residual(q, qd, zero, rho, w, al)])
            else:
                qd = qdd = []
            pose = self._poses(q, rho)
            rate = self._rates(qd, w)
            acc = {self.ground: (mp.zero,) * 3, self.driver: (mp.zero, mp.zero, al)}
            for k in self.unknown:
                i = self.col[k]
                acc[k] = (qdd[i], qdd[i + 1], qdd[i + 2])
            return RefState(pose, rate, acc, self.c, its)

    def guess_from(self, sol, k: int, arr=None) -> list[float]:
        """Float initial guess at sample ``k`` of a Solution, from sol.point only."""
        out = []
        pt = (lambda link, p0: arr("point", link, p0)) if arr else sol.point
        for link in self.unknown:
            c = (float(self.c[link][0]), float(self.c[link][1]))
            p = pt(link, c)[k]
            px = pt(link, (c[0] + 1.0, c[1]))[k]
            out += [p[0], p[1], math.atan2(px[1] - p[1], px[0] - p[0])]
        return out


def compare(linkage: Linkage, sol, samples, ref: MpReference | None = None) -> dict:
    """Errors of ``sol`` (order 2) against the 50-digit reference at sample indices ``samples``.

    Every link's joints (via sol.point/point_velocity/point_acceleration), every joint via
    sol.position/velocity/acceleration (P joints: the later link in the file), and every moving
    link's angle (mod 2π), omega, alpha. Returns absolute maxima and the reference scales.
    """
    ref = ref or MpReference(linkage)
    mp = mpmath.mp
    err = dict(pos=0.0, vel=0.0, acc=0.0, ang=0.0, omega=0.0, alpha=0.0)
    scale = dict(vel=0.0, acc=0.0, omega=0.0, alpha=0.0)
    order = linkage.link_ids
    arrays = {}

    def arr(kind, link, p0):
        key = (kind, link, p0)
        if key not in arrays:
            fn = getattr(sol, kind)
            arrays[key] = fn(link) if p0 is None else fn(link, p0)
        return arrays[key]

    for k in samples:
        st = ref.solve(float(sol.input[k]), sol.omega_driver, ref.guess_from(sol, k, arr))
        with mpmath.workdps(ref.dps):
            for lk in linkage.links:
                for p0 in [linkage.joint(j).at for j in lk.joints]:
                    Pr, Vr, Ar = st.point(lk.id, p0)
                    fp = arr("point", lk.id, p0)[k]
                    fv = arr("point_velocity", lk.id, p0)[k]
                    fa = arr("point_acceleration", lk.id, p0)[k]
                    for name, f, r in (("pos", fp, Pr), ("vel", fv, Vr), ("acc", fa, Ar)):
                        d = float(mp.hypot(mp.mpf(f[0]) - r[0], mp.mpf(f[1]) - r[1]))
                        err[name] = max(err[name], d)
                        if name != "pos":
                            scale[name] = max(scale[name], float(mp.hypot(*r)))
                if lk.id == linkage.ground:
                    continue
                th = st.pose[lk.id][2]
                if lk.id == linkage.driver.link:
                    th = mp.mpf(sol.input[k]) - ref.theta0
                pv = [complex(*linkage.joint(j).at) for j in lk.joints[:2]]
                a0 = (mp.atan2(mp.mpf(pv[1].imag) - pv[0].imag, mp.mpf(pv[1].real) - pv[0].real)
                      if len(pv) == 2 and pv[1] != pv[0] else 0)
                dang = mp.mpf(arr("angle", lk.id, None)[k]) - (th + a0)
                dang = dang - 2 * mp.pi * mp.nint(dang / (2 * mp.pi))
                err["ang"] = max(err["ang"], float(abs(dang)))
                for name, f, r in (("omega", arr("omega", lk.id, None)[k], st.rate[lk.id][2]),
                                   ("alpha", arr("alpha", lk.id, None)[k], st.acc[lk.id][2])):
                    err[name] = max(err[name], float(abs(mp.mpf(f) - r)))
                    scale[name] = max(scale[name], float(abs(r)))
            for j in linkage.joints:
                carriers = linkage.links_of(j.id)
                rep = max(carriers, key=order.index) if j.kind is P else carriers[0]
                Pr, Vr, Ar = st.point(rep, j.at)
                for name, f, r in (("pos", arr("position", j.id, None)[k], Pr),
                                   ("vel", arr("velocity", j.id, None)[k], Vr),
                                   ("acc", arr("acceleration", j.id, None)[k], Ar)):
                    d = float(mp.hypot(mp.mpf(f[0]) - r[0], mp.mpf(f[1]) - r[1]))
                    err[name] = max(err[name], d)
    err["scale"] = scale
    err["size"] = size_of(linkage)
    err["w"] = abs(sol.omega_driver)
    return err


def relative(err: dict) -> dict:
    """Relative errors: positions to the mechanism's size, angles in rad, rates to the largest
    reference value of their kind (ω floored at |ω_driver|, α at ω_driver²)."""
    s = err["scale"]
    size = err["size"]
    w = err["w"]
    return dict(pos=err["pos"] / size, ang=err["ang"],
                vel=err["vel"] / max(s["vel"], 1e-300), acc=err["acc"] / max(s["acc"], 1e-300),
                omega=err["omega"] / max(s["omega"], w), alpha=err["alpha"] / max(s["alpha"], w * w))


# ---------------------------------------------------------------------------------------------
# a generic float Newton continuation (independent branch following)
# ---------------------------------------------------------------------------------------------
def continuation(linkage: Linkage, inputs, substeps: int = 4):
    """Follow the constraint equations from the drawn pose through ``inputs`` (rad; inputs[0]
    must be the drawn input) by Newton steps with a tangent predictor, in float64.

    Returns ({link: (N, 3) poses (x, y, θ)}, reference); rows are NaN from the first sample
    where Newton fails (e.g. past an assembly limit)."""
    ref = MpReference(linkage, backend="float")
    n = ref.n
    q = np.zeros(n)
    for link in ref.unknown:
        i = ref.col[link]
        q[i], q[i + 1] = ref.c[link]
    th0 = float(ref.theta0)
    out = np.full((len(inputs), n), np.nan)
    out[0] = q
    scale = size_of(linkage)
    zero = np.zeros(n)
    for k in range(1, len(inputs)):
        a, b = inputs[k - 1] - th0, inputs[k] - th0
        ok = True
        for s in range(1, substeps + 1):
            rho0 = a + (b - a) * (s - 1) / substeps
            rho = a + (b - a) * s / substeps
            try:
                tangent = np.linalg.solve(ref.jacobian(q, rho0), -np.array(ref.vel_residual(q, zero, rho0, 1.0)))
                qn = q + tangent * (rho - rho0)
                for _ in range(20):
                    dq = np.linalg.solve(ref.jacobian(qn, rho), -np.array(ref.residual(qn, rho)))
                    qn = qn + dq
                    if np.max(np.abs(dq)) < 1e-12 * scale:
                        break
            except np.linalg.LinAlgError:
                ok = False
            if not ok or not np.all(np.isfinite(qn)) or np.max(np.abs(ref.residual(qn, rho))) > 1e-9 * scale:
                ok = False
                break
            q = qn
        if not ok:
            break
        out[k] = q
    return {link: out[:, ref.col[link]:ref.col[link] + 3] for link in ref.unknown}, ref


# ---------------------------------------------------------------------------------------------
# finite differences of the solver itself
# ---------------------------------------------------------------------------------------------
def fd_check(plan, inputs, h: float = 1e-4):
    """Central 5-point differences along the driver angle, for every link point of every joint.

    Returns (v_solver, v_fd, v_fd_half, a_solver, a_fd, a_fd_half) as complex arrays (M, N):
    FD of positions for velocities and of velocities for accelerations, at steps h and h/2 (their
    difference estimates the FD error)."""
    lk = plan.linkage
    w = plan.omega
    inputs = np.asarray(inputs, float)
    pts = [(k.id, lk.joint(j).at) for k in lk.links for j in k.joints]

    def z(a):
        return a[:, 0] + 1j * a[:, 1]

    def at(offsets, order):
        x = np.concatenate([inputs + o for o in offsets])
        s = plan.evaluate(x, order=order)
        n = len(inputs)
        res = []
        for link, p0 in pts:
            if order == 0:
                v = z(s.point(link, p0))
            else:
                v = z(s.point_velocity(link, p0))
            res.append(v.reshape(len(offsets), n))
        return np.array(res)  # (M, len(offsets), N)

    def d5(arr, hh):
        return (arr[:, 0] - 8 * arr[:, 1] + 8 * arr[:, 2] - arr[:, 3]) / (12 * hh)

    base = plan.evaluate(inputs, order=2)
    vs = np.array([z(base.point_velocity(k, p)) for k, p in pts])
    as_ = np.array([z(base.point_acceleration(k, p)) for k, p in pts])
    out = []
    for order in (0, 1):
        r = []
        for hh in (h, h / 2):
            arr = at([-2 * hh, -hh, hh, 2 * hh], order)
            r.append(d5(arr, hh) * w)
        out.append(r)
    return vs, out[0][0], out[0][1], as_, out[1][0], out[1][1]


def continuation_point(ref: MpReference, poses: dict, link: str, p0) -> np.ndarray:
    """(N,) complex positions of the point of ``link`` drawn at p0, from :func:`continuation`."""
    pz = poses[link]
    c = complex(*ref.c[link])
    return pz[:, 0] + 1j * pz[:, 1] + np.exp(1j * pz[:, 2]) * (complex(*p0) - c)


# ---------------------------------------------------------------------------------------------
# assembly-mode invariants and check helpers used by several test files
# ---------------------------------------------------------------------------------------------
def _z(a: np.ndarray) -> np.ndarray:
    return a[:, 0] + 1j * a[:, 1]


def link_rotation(sol, linkage: Linkage, link: str) -> np.ndarray:
    """exp(i·rotation from the drawn pose) of ``link``, from two sol.point probes."""
    c = linkage.joint(linkage.link(link).joints[0]).at
    return _z(sol.point(link, (c[0] + 1.0, c[1]))) - _z(sol.point(link, c))


def mode_signs(linkage: Linkage, sol, group) -> np.ndarray:
    """(N,) sign of the group's assembly-mode invariant, from positions only (0 where undefined):
    RRR cross(H − M, L − M); RRP dot(u, L − M), u the guide direction; RPR dot(u, M − H).
    PRP and RPP have a single assembly: ones."""
    k = group.kind
    if k == "RRR":
        M, Lp = _z(sol.point(group.link_i, linkage.joint(group.outer_i).at)), _z(sol.position(group.inner))
        H = _z(sol.point(group.link_j, linkage.joint(group.outer_j).at))
        return np.sign(cross2_arr(H - M, Lp - M))
    if k == "RRP":
        M = _z(sol.point(group.link_i, linkage.joint(group.outer_i).at))
        Lp = _z(sol.point(group.link_i, linkage.joint(group.inner).at))
        u = link_rotation(sol, linkage, group.link_j) * e(linkage.joint(group.outer_j).axis_deg)
        return np.sign(((np.conj(u)) * (Lp - M)).real)
    if k == "RPR":
        M = _z(sol.point(group.link_i, linkage.joint(group.outer_i).at))
        H = _z(sol.point(group.link_j, linkage.joint(group.outer_j).at))
        u = link_rotation(sol, linkage, group.link_j) * e(linkage.joint(group.inner).axis_deg)
        return np.sign(((np.conj(u)) * (M - H)).real)
    return np.ones(len(sol))


def fd_errors(plan, inputs, h: float = 1e-4, cond_min: float = 1e-3):
    """Compare the solver's velocities/accelerations with 5-point differences of its positions /
    velocities at the given inputs. Returns (bad_v, bad_a, checked, sharp) where bad_* count
    samples whose error exceeds 1e-9 of the scale plus twice the FD error estimate, ``checked``
    the samples used (all stencil points valid, every group's conditioning > cond_min) and
    ``sharp`` those whose FD error estimate is below 1e-7 of the scale."""
    vs, v1, v2, as_, a1, a2 = fd_check(plan, inputs, h)
    sol = plan.evaluate(np.asarray(inputs, float), order=0)
    ok = np.isfinite(vs).all(axis=0) & np.isfinite(v1).all(axis=0) & np.isfinite(v2).all(axis=0)
    ok &= np.isfinite(a1).all(axis=0) & np.isfinite(a2).all(axis=0)
    for g in sol.groups:
        ok &= np.nan_to_num(sol.conditioning(g.name), nan=0.0) > cond_min
    if not ok.any():
        return 0, 0, 0, 0, {}
    vsc = np.max(np.abs(vs[:, ok]))
    asc = np.max(np.abs(as_[:, ok]))
    vsc = vsc if vsc > 0 else 1.0
    asc = asc if asc > 0 else 1.0
    ev, estv = np.abs(vs - v2)[:, ok], np.abs(v1 - v2)[:, ok]
    ea, esta = np.abs(as_ - a2)[:, ok], np.abs(a1 - a2)[:, ok]
    bad_v = int(np.sum(np.any(ev > 1e-9 * vsc + 2 * estv, axis=0)))
    bad_a = int(np.sum(np.any(ea > 1e-9 * asc + 2 * esta, axis=0)))
    sharp = int(np.sum(np.all(estv < 1e-7 * vsc, axis=0) & np.all(esta < 1e-7 * asc, axis=0)))
    info = dict(v=float(np.max(ev) / vsc), a=float(np.max(ea) / asc))
    return bad_v, bad_a, int(ok.sum()), sharp, info
