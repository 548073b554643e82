"""Linkage plates read back from DXF and SVG: the four-bar's hole-centre distances equal its link
lengths, every slot holds its block over the whole cycle (checked by re-solving the linkage
independently at 20 000 crank angles), coupler curves within their tolerance of the solved path,
sizes that cannot make a plate refused naming the option, every linkage example exports."""
from __future__ import annotations

import math

import ezdxf
import numpy as np
import pytest
import shapely

from mechsketch import resources
from mechsketch.core import GeometryError, load_scene
from mechsketch.core.analyses.parts import check_part, disc_hull, lay_out
from mechsketch.core.analyses.parts.linkage import LinkageStyle, linkage_parts, travels
from mechsketch.core.io.export_parts import export_parts
from mechsketch.core.solver.plan import compile_plan

from parts_readback import FLAT, dxf_parts, svg_parts

LINKAGES = ["fourbar_crank_rocker", "fourbar_coupler_centrodes", "double_rocker", "slider_crank_offset",
            "inverted_slider_crank", "sixbar_moving_guide"]


def example(name):
    return load_scene(resources.example_path(name)).elements[0]


def circles(path):
    """Per layer, the CIRCLE centres and radii read back."""
    out = {}
    for e in ezdxf.readfile(path).modelspace().query("CIRCLE"):
        out.setdefault(e.dxf.layer, []).append((np.array([e.dxf.center.x, e.dxf.center.y]), e.dxf.radius))
    return out


@pytest.mark.parametrize("layout", ["assembled", "apart"])
def test_fourbar_plates_have_hole_centre_distances_equal_to_the_link_lengths(tmp_path, layout):
    lk = example("fourbar_crank_rocker")
    ps = linkage_parts(lk, compile_plan(lk))
    path = tmp_path / "fourbar.dxf"
    export_parts(ps, path, layout=layout)
    holes = circles(path)
    if layout == "assembled":
        # in place: every joint's bore centred exactly on its drawn position; stacked links share
        # one bore at a joint (drawn once), so each joint has exactly one circle
        pool = [c for v in holes.values() for c, _ in v]
        for j in lk.joints:
            assert sum(np.hypot(*(c - j.at)) <= 1e-13 * 200 for c in pool) == 1, j.id
        return
    for link in lk.links:
        got = holes[link.id]
        assert len(got) == len(link.joints)
        dists = [np.hypot(*(p - q)) for k, (p, _) in enumerate(got) for q, _ in got[k + 1:]]
        for i, a in enumerate(link.joints):
            for b in link.joints[i + 1:]:
                length = math.dist(lk.joint(a).at, lk.joint(b).at)
                assert min(abs(d - length) for d in dists) <= 1e-12 * length, (link.id, a, b)


def test_plate_outlines_are_stadiums_and_rounded_hulls_with_the_stated_areas(tmp_path):
    lk = example("fourbar_crank_rocker")
    ps = linkage_parts(lk, compile_plan(lk), LinkageStyle(boss_radius=10.0, bore_diameter=8.0))
    export_parts(ps, tmp_path / "p.dxf", layout="apart")
    _, parts = dxf_parts(tmp_path / "p.dxf")
    for link in lk.links:
        pts = [shapely.Point(*lk.joint(j).at) for j in link.joints]
        # independent: the union of the boss discs' convex hull, less the bores
        hull = shapely.union_all([p.buffer(10.0, quad_segs=4096) for p in pts]).convex_hull
        ref = hull.area - len(pts) * math.pi * 16.0
        poly = parts[link.id]
        assert poly.is_valid and len(poly.interiors) == len(pts)
        assert poly.area == pytest.approx(ref, abs=perimeter(poly) * 2 * FLAT + 1e-3)
        web = check_part(next(p for p in ps.parts if p.name == link.id)).web
        assert web == pytest.approx(6.0, abs=2e-4)  # boss 10 − bore 4


def perimeter(poly):
    return poly.exterior.length + sum(r.length for r in poly.interiors)


@pytest.mark.parametrize("name", ["slider_crank_offset", "inverted_slider_crank", "sixbar_moving_guide"])
def test_every_slot_holds_its_block_over_the_whole_cycle(name):
    """Re-solve at 20 000 angles: the block, moved by the slide, stays inside its slot."""
    lk = example(name)
    plan = compile_plan(lk)
    style = LinkageStyle()
    ps = linkage_parts(lk, plan, style)
    sol = plan.sweep(20000, order=0)
    for t in travels(plan):
        g = next(g for g in sol.groups if t.joint in g.joints)
        dy = sol.group_output(g.name)
        idx = 1 if (g.kind == "PRP" and t.joint == g.outer_j) or (g.kind == "RPP" and t.joint == g.outer_j) else 0
        s = dy.slides[idx].s[dy.ok]
        assert t.s_min <= s.min() + 1e-9 and t.s_max >= s.max() - 1e-9
        assert t.s_min == pytest.approx(s.min(), abs=1e-6) and t.s_max == pytest.approx(s.max(), abs=1e-6)
        # the slot (its own plate or a hole of the guide link) contains the block at both ends
        holder = [p for p in ps.parts if p.name in (t.guide, f"{t.guide}_guide_{t.joint}")]
        slot = next(shapely.Polygon(h.polyline(1e-4)) for p in holder for h in p.holes if h.kinds[0] == "slot")
        block = next(p for p in ps.parts if p.name == t.slider).outer
        u = np.array(t.axis)
        for s_end in (s.min(), s.max()):
            moved = shapely.Polygon(block.polyline(1e-4) + s_end * u)
            assert slot.contains(moved)


def test_slider_crank_stroke_against_its_closed_form():
    lk = example("slider_crank_offset")
    (t,) = travels(compile_plan(lk))
    r, e = 40.0, 20.0
    rod = math.dist(lk.joint("B").at, lk.joint("C").at)
    x0 = lk.joint("S").at[0]
    assert t.s_max == pytest.approx(math.sqrt((rod + r) ** 2 - e * e) - x0, abs=1e-9)
    assert t.s_min == pytest.approx(math.sqrt((rod - r) ** 2 - e * e) - x0, abs=1e-9)


def test_coupler_curve_is_within_its_tolerance_of_the_solved_path(tmp_path):
    lk = example("fourbar_crank_rocker")
    plan = compile_plan(lk)
    ps = linkage_parts(lk, plan, LinkageStyle(tolerance=0.005))
    (curve,) = ps.curves
    assert curve.name == "E" and curve.closed and curve.deviation <= 0.005
    export_parts(ps, tmp_path / "c.dxf", layout="assembled", annotate=True)
    doc = ezdxf.readfile(tmp_path / "c.dxf")
    (pl,) = doc.modelspace().query('LWPOLYLINE[layer=="NOTES_TRACE_E"]')
    assert pl.closed
    from parts_readback import _lwpolyline_ring  # the same decoding as the parts
    ring = shapely.LinearRing(_lwpolyline_ring(pl))
    path = plan.sweep(5000, order=0).position("E")
    d = shapely.distance(ring, shapely.points(path))
    assert d.max() <= 0.005 + 2 * FLAT


def test_frame_as_a_drilling_pattern_and_dog_bone_links(tmp_path):
    lk = example("fourbar_crank_rocker")
    ps = linkage_parts(lk, compile_plan(lk), LinkageStyle(frame="drill", boss_radius=12.0, width=12.0))
    ground = next(p for p in ps.parts if p.name == "ground")
    assert ground.outer is None and len(ground.holes) == 2
    for fmt in ("dxf", "svg"):
        path = tmp_path / f"d.{fmt}"
        export_parts(ps, path, fmt=fmt, layout="apart", arcs="entities")
    crank = next(p for p in ps.parts if p.name == "crank")
    # dog-bone: bar 12 wide between bosses of radius 12: bar length L − 2·e, e = √(12² − 6²)
    L = math.dist(lk.joint("A").at, lk.joint("B").at)
    sg = crank.outer.segments()
    assert sg.length[0] == pytest.approx(L - 2 * math.sqrt(144 - 36), rel=1e-12)
    assert check_part(crank).web == pytest.approx(min(12.0, 12.0 - 0.4 * 12.0), abs=2e-4)


@pytest.mark.parametrize("style, message", [
    (LinkageStyle(boss_radius=5.0, bore_diameter=12.0), "change drawing.bore_diameter or drawing.boss_radius"),
    (LinkageStyle(boss_radius=5.0, width=14.0), r"\(drawing.link_width\) is wider"),
    (LinkageStyle(boss_radius=-1.0), "drawing.boss_radius must be a positive"),
    (LinkageStyle(block_width=0.0), "drawing.block_width must be a positive"),
    (LinkageStyle(frame="glued"), "frame must be one of plate, drill"),
])
def test_sizes_that_cannot_make_a_plate_are_refused_naming_the_key(style, message):
    lk = example("fourbar_crank_rocker")
    with pytest.raises(GeometryError, match=message):
        linkage_parts(lk, compile_plan(lk), style)


@pytest.mark.parametrize("options, drawing, message", [
    (dict(boss_radius=5.0, bore_diameter=12.0), {}, "change --bore-diameter or --boss-radius"),
    (dict(boss_radius=5.0), {"bore_diameter": 12.0}, "change drawing.bore_diameter or --boss-radius"),
    ({}, {"boss_radius": 5.0, "bore_diameter": 12.0}, "change drawing.bore_diameter or drawing.boss_radius"),
    (dict(bore_diameter=40.0), {}, "change --bore-diameter or --boss-radius or drawing.boss_radius"),
    (dict(link_width=30.0), {"boss_radius": 5.0}, r"\(--link-width\) is wider .* raise drawing.boss_radius"),
])
def test_a_size_is_named_where_it_came_from(options, drawing, message):
    """An export option overrides the drawing block; a message names the flag the user typed, the
    key of the scene that set it, or (a default) both ways the user can change it."""
    from dataclasses import replace

    from mechsketch.core.analyses.parts.build import PartOptions, element_parts
    from mechsketch.core.cli.export_cmds import export_vocabulary
    from mechsketch.core.model.drawing import LinkageDrawing

    lk = replace(example("fourbar_crank_rocker"), drawing=LinkageDrawing(**drawing))
    with pytest.raises(GeometryError, match=message):
        element_parts(lk, PartOptions(**options, vocabulary=export_vocabulary()))


def test_a_web_below_the_minimum_is_refused_before_anything_is_written(tmp_path):
    lk = example("fourbar_crank_rocker")
    ps = linkage_parts(lk, compile_plan(lk), LinkageStyle(boss_radius=5.0, bore_diameter=9.6))
    with pytest.raises(GeometryError, match=r"part 'ground': thinnest web 0.2 mm.*drawing.boss_radius"):
        export_parts(ps, tmp_path / "x.dxf", min_web=1.0)
    assert not (tmp_path / "x.dxf").exists()
    export_parts(ps, tmp_path / "x.dxf", min_web=0.1)


@pytest.mark.parametrize("name", LINKAGES)
def test_every_linkage_example_exports_closed_valid_parts(tmp_path, name):
    lk = example(name)
    ps = linkage_parts(lk, compile_plan(lk))
    for fmt, arcs in (("dxf", "bulge"), ("dxf", "entities"), ("svg", "bulge")):
        path = tmp_path / f"{name}_{arcs}.{fmt}"
        exp = export_parts(ps, path, fmt=fmt, arcs=arcs)
        parts = (svg_parts if fmt == "svg" else dxf_parts)(path)[1]
        assert set(parts) == set(ps.names)
        for p, part in zip(exp.checks, ps.parts):
            poly = parts[part.name]
            assert poly.is_valid and len(poly.interiors) == len(part.holes)
            assert poly.area == pytest.approx(p.area, abs=perimeter(poly) * FLAT)
        polys = list(parts.values())
        assert all(polys[i].distance(polys[j]) > 1.0 for i in range(len(polys)) for j in range(i + 1, len(polys)))


def test_disc_hull_against_shapely():
    rng = np.random.default_rng(7)
    for _ in range(20):
        c = rng.uniform(-50, 50, (5, 2))
        r = rng.uniform(0, 15, 5)
        r[0] = 0.0
        hull = disc_hull(c, r)
        ref = shapely.union_all([shapely.Point(*p).buffer(max(q, 1e-9), quad_segs=4096) for p, q in zip(c, r)]).convex_hull
        poly = shapely.Polygon(hull.polyline(1e-5))
        assert poly.is_valid and hull.area() > 0
        assert poly.area == pytest.approx(ref.area, rel=1e-5)
        assert poly.symmetric_difference(ref).area < 1e-3 * ref.length
    lay_out  # noqa: B018 - imported for the apart layout used above


def test_a_separate_guide_plate_is_fastened_to_its_link_through_matching_holes(tmp_path):
    """Issue 23 item 5: ``fasteners`` drills two holes beyond the ends of a separate guide
    plate's slot, the same centres in the link it is stacked on; both parts keep their webs
    (shapely: the fastener's distance to every other boundary of the guide plate), the assembled
    export read back by GDAL has the guide plate's area less the two holes; a linkage without a
    separate guide plate refuses the option; a fastener wider than the rim is refused."""
    from mechsketch.core.analyses.parts import check_part, is_circle
    from mechsketch.core.analyses.parts.build import PartOptions, element_parts
    from ogr_readback import ogr_layers

    el = example("sixbar_moving_guide")
    plain = {p.name: p for p in element_parts(el, PartOptions()).parts}
    ps = element_parts(el, PartOptions(fasteners=4.0))
    by = {p.name: p for p in ps.parts}

    def fasteners(p):
        return sorted(tuple(np.round(is_circle(h)[0], 9)) for h in p.holes if h.kinds and h.kinds[0] == "fastener")

    assert len(fasteners(by["rocker_guide_Q"])) == 2 and fasteners(by["rocker_guide_Q"]) == fasteners(by["rocker"])
    for name in ("rocker_guide_Q", "rocker"):
        assert check_part(by[name], 1.0).web >= 1.1
        poly = by[name].polygon(1e-6)
        for x, y in fasteners(by[name]):
            rings = [poly.exterior] + [r for r in poly.interiors if r.distance(shapely.Point(x, y)) > 2.0 + 1e-6]
            assert min(r.distance(shapely.Point(x, y)) for r in rings) - 2.0 >= 1.1 - 1e-6
    path = tmp_path / "six.dxf"
    export_parts(ps, path, layout="assembled")
    area = plain["rocker_guide_Q"].area - 2 * math.pi * 2.0 ** 2
    assert ogr_layers(path)["rocker_guide_Q"][0] == pytest.approx(area, rel=1e-6)
    with pytest.raises(GeometryError, match="has none"):
        element_parts(example("fourbar_crank_rocker"), PartOptions(fasteners=4.0))
    with pytest.raises(GeometryError, match="must fit its rim"):
        element_parts(el, PartOptions(fasteners=9.0))


def test_a_drilling_pattern_frame_can_sit_on_a_base_plate(tmp_path):
    """Issue 23 item 5: with ``frame`` "drill" and ``base_plate`` the frame's pivots are carried
    by a rectangular plate one boss radius around them (GDAL: its area is the rectangle's less the
    bores); without "drill" the option is refused with what to choose."""
    from mechsketch.core.analyses.parts import is_circle
    from mechsketch.core.analyses.parts.build import PartOptions, element_parts
    from ogr_readback import ogr_layers

    el = example("sixbar_moving_guide")
    drill = {p.name: p for p in element_parts(el, PartOptions(frame="drill")).parts}["ground"]
    ps = element_parts(el, PartOptions(frame="drill", base_plate=True))
    base = {p.name: p for p in ps.parts}["ground"]
    centres = np.array([is_circle(h)[0] for h in base.holes])
    assert drill.outer is None and np.array_equal(centres, [is_circle(h)[0] for h in drill.holes])
    r = max(is_circle(h)[1] for h in base.holes)
    x0, y0, x1, y1 = base.outer.points[:, 0].min(), base.outer.points[:, 1].min(), \
        base.outer.points[:, 0].max(), base.outer.points[:, 1].max()
    boss = (x1 - x0 - np.ptp(centres[:, 0]) - 2 * r) / 2
    assert boss == pytest.approx((y1 - y0 - np.ptp(centres[:, 1]) - 2 * r) / 2, abs=1e-9) and boss > 0
    path = tmp_path / "base.dxf"
    export_parts(ps, path, layout="assembled")
    holes = sum(math.pi * is_circle(h)[1] ** 2 for h in base.holes)
    assert ogr_layers(path)["ground"][0] == pytest.approx((x1 - x0) * (y1 - y0) - holes, rel=1e-6)
    with pytest.raises(GeometryError, match="choose PartOptions.frame drill"):
        element_parts(el, PartOptions(base_plate=True))


@pytest.mark.parametrize("name", LINKAGES)
def test_plates_without_traces_are_the_plates_with_them(name):
    """A cut check (design/candidates.cut_check) builds the plates only: the same parts, no curves."""
    lk = example(name)
    plan = compile_plan(lk)
    full, plates = linkage_parts(lk, plan), linkage_parts(lk, plan, traces=False)
    assert plates.curves == () and len(full.curves) == sum(len(lk.links_of(j.id)) == 1 for j in lk.joints
                                                         if lk.links_of(j.id)[0] != lk.ground)

    def key(ps):
        return [(p.name, p.group, p.keys, [np.asarray(c.points).tobytes() + np.asarray(c.bulges).tobytes()
                                            for c in p.contours]) for p in ps.parts]

    assert key(plates) == key(full)


def test_the_design_cut_check_is_the_export_check():
    from dataclasses import replace

    from mechsketch.core.analyses.parts import require_checked
    from mechsketch.core.analyses.parts.build import PartOptions, element_parts, min_web_of
    from mechsketch.core.design.candidates import build_linkage, cut_check
    from mechsketch.core.model.linkage import LinkageDrawing

    lk = build_linkage("fourbar", np.array([0, 0, 100, 0, 35, 110, 90, 60, 35.0]), 1.0, 0.3, "c")
    assert element_parts(lk).curves   # its coupler point P is traced
    assert cut_check(lk) == ""
    bad = replace(lk, drawing=LinkageDrawing(min_web=1e3))
    with pytest.raises(GeometryError) as exc:
        require_checked(element_parts(bad), min_web_of(bad, PartOptions()))
    assert cut_check(bad) == f"cannot be cut: {exc.value}"
