"""Builders of the test linkages, from drawn positions that close: four-bar, slider-crank,
inverted slider-crank, PRP, Scotch yoke (RPP), a crank-guided RRP, six-bars, a class-III group,
an eight-bar; variants (the other assembly mode, translated); and the small complex-number
drawing helpers they use (:func:`e`, :func:`xy`, :func:`circle_meet`, :func:`line_circle`).

The references that check solutions of these linkages are in :mod:`reference` (the 50-digit
solver) and :mod:`solution_checks` (closure, finite differences, assembly-mode signs).
"""
from __future__ import annotations

import cmath
import math

from mechsketch.core import Driver, Joint, JointKind, Link, Linkage

P = JointKind.P

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
