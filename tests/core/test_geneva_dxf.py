"""Geneva DXF: read back with ezdxf, audited, units and layers, arcs as bulges (never chords),
outlines rebuilt as shapely polygons (through ezdxf's own path code) checked against closed forms."""
from __future__ import annotations

import math

import ezdxf
import numpy as np
import pytest
import shapely
from ezdxf.math import bulge_to_arc

from mechsketch.core import ExportError
from mechsketch.core.analyses.geneva_geometry import geometry
from mechsketch.core.io.dxf_geneva import LAYERS, export_geneva
from mechsketch.core.model.geneva import Drawing, Geneva

FLAT = 1e-4  # mm, flattening distance when rebuilding polygons from the file


def lens(r1: float, r2: float, d: float) -> float:
    a1 = r1 * r1 * math.acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1))
    a2 = r2 * r2 * math.acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2))
    return a1 + a2 - 0.5 * math.sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2))


def notes_wheel_area(z, a, rp, cs, cb, bore, r_arc=None):
    """seeds/NOTES.md, "Area check", written out here from the inputs."""
    r = a * math.sin(math.pi / z)
    w = rp + cs
    xc = a * math.cos(math.pi / z)
    xb = a - r - cb
    ro = math.hypot(xc, w)
    ra = r - 1.5 * w if r_arc is None else r_arc
    slot = 2 * w * (xc - xb) + math.pi * w * w / 2 + (ro * ro * math.acos(xc / ro) - xc * w)
    return math.pi * ro * ro - z * slot - z * lens(ro, ra, a) - math.pi * bore * bore


def ring_of(e) -> np.ndarray:
    """The closed LWPOLYLINE as a ring inscribed in its arcs (sagitta ≤ FLAT), arcs decoded by
    ezdxf's own ``bulge_to_arc`` (ezdxf.path would turn them into Béziers, off by 2.7e-4·R)."""
    v = e.get_points("xyb")
    out = []
    for k, (x, y, b) in enumerate(v):
        x1, y1, _ = v[(k + 1) % len(v)]
        out.append((x, y))
        if b == 0:
            continue
        c, a0, a1, r = bulge_to_arc((x, y), (x1, y1), b)
        sweep = (a1 - a0) % (2 * math.pi)
        n = max(2, math.ceil(sweep / (2 * math.acos(1 - FLAT / r))))
        ang = a0 + sweep * np.arange(1, n) / n
        arc = np.c_[c.x + r * np.cos(ang), c.y + r * np.sin(ang)]
        out.extend(map(tuple, arc if b > 0 else arc[::-1]))
    return np.array(out)


def read_parts(path):
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    parts = {}
    for layer in LAYERS:
        if layer == "centre_marks":
            continue
        rings = []
        for e in doc.modelspace().query(f'LWPOLYLINE[layer=="{layer}"]'):
            assert e.closed
            rings.append(ring_of(e))
        rings.sort(key=lambda r: -abs(shapely.Polygon(r).area))
        parts[layer] = (shapely.Polygon(rings[0], rings[1:]), rings)
    return doc, parts


@pytest.fixture(scope="module")
def z6(tmp_path_factory):
    el = Geneva("indexer", 6, 100.0, 8.0, crank_center=(20.0, -10.0), wheel_direction_deg=30.0)
    path = tmp_path_factory.mktemp("dxf") / "z6.dxf"
    report = export_geneva(el, path)
    return el, path, report


def test_file_is_r2010_mm_audited_and_has_one_layer_per_part(z6):
    el, path, report = z6
    doc, parts = read_parts(path)
    assert doc.dxfversion >= "AC1024"  # R2010 or newer
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    for layer in LAYERS:
        assert layer in doc.layers
    kinds = {e.dxftype() for e in doc.modelspace()}
    assert kinds == {"LWPOLYLINE", "LINE"}  # no splines, no short segments of an approximation
    assert {e.dxf.layer for e in doc.modelspace().query("LINE")} == {"centre_marks"}
    counts = {k: len(rings) for k, (_, rings) in parts.items()}
    assert counts == {"wheel": 2, "locking_disc": 2, "crank_arm": 3, "roller": 2}  # outline + holes
    for poly, _ in parts.values():
        assert poly.is_valid
    assert "millimetres" in report and str(path) in report


def test_every_arc_is_a_bulge_and_the_slots_are_true_stadiums(z6):
    el, path, _ = z6
    doc = ezdxf.readfile(path)
    (wheel, bore) = sorted(doc.modelspace().query('LWPOLYLINE[layer=="wheel"]'), key=lambda e: -len(e))
    pts = np.array(wheel.get_points("xyb"))
    z = el.slots
    assert len(pts) == 6 * z  # per slot: 2 walls, 1 semicircle, 2 horn lands, 1 locking arc
    bulge = pts[:, 2]
    assert np.sum(bulge == 0) == 2 * z and np.sum(np.isclose(bulge, -1.0)) == z  # walls, bottoms
    assert len(bore) == 2 and np.allclose([v[4] for v in bore.get_points()], 1.0)  # a circle: 2 half arcs
    # each slot: two parallel walls 2w = 2(r_p + c_s) apart, of length x_c − x_b
    w = el.roller_radius + el.clearance.slot
    r = el.crank_radius
    xc, xb = el.center_distance * math.cos(math.pi / z), el.center_distance - r - el.clearance.bottom
    for k in range(z):
        p = pts[6 * k: 6 * k + 4, :2]
        d1, d2 = p[1] - p[0], p[3] - p[2]
        assert np.linalg.norm(d1) == pytest.approx(xc - xb, rel=1e-12)
        assert abs(d1[0] * d2[1] - d1[1] * d2[0]) < 1e-9 * np.dot(d1, d1)  # parallel
        n = np.array([-d1[1], d1[0]]) / np.linalg.norm(d1)
        assert abs(np.dot(p[2] - p[0], n)) == pytest.approx(2 * w, rel=1e-12)  # slot width


def test_areas_against_closed_forms(z6):
    el, path, _ = z6
    _, parts = read_parts(path)
    geo = geometry(el)
    wheel, wring = parts["wheel"]
    closed = notes_wheel_area(6, 100.0, 8.0, 0.05, 0.5, 15.0)
    perim = sum(shapely.LinearRing(r).length for r in wring)
    assert abs(wheel.area - closed) <= perim * FLAT
    disc, drings = parts["locking_disc"]
    rl = (50.0 - 1.5 * 8.05) - 0.1
    disc_closed = math.pi * rl * rl - lens(rl, geo.relief.drawn, 100.0) - math.pi * geo.crank_bore ** 2
    assert abs(disc.area - disc_closed) <= sum(shapely.LinearRing(r).length for r in drings) * FLAT
    roller, _ = parts["roller"]
    assert abs(roller.area - math.pi * (8.0 ** 2 - 4.0 ** 2)) <= 2 * math.pi * (8.0 + 4.0) * FLAT
    arm, _ = parts["crank_arm"]
    hull = shapely.union(shapely.Point(0, 0).buffer(geo.crank_bore + 4.0, quad_segs=2048),
                         shapely.Point(50.0, 0).buffer(8.0, quad_segs=2048)).convex_hull
    holes = math.pi * (geo.crank_bore ** 2 + 4.0 ** 2)
    assert arm.area == pytest.approx(hull.area - holes, rel=2e-5)


def test_parts_are_placed_in_the_scene_frame(z6):
    el, path, _ = z6
    doc, parts = read_parts(path)
    o1, o2 = np.array(el.crank_center), np.array(el.wheel_center)
    assert np.allclose(o2 - o1, 100.0 * np.array([math.cos(math.radians(30)), math.sin(math.radians(30))]))
    lines = doc.modelspace().query("LINE")
    mids = {tuple(np.round((np.array(e.dxf.start)[:2] + np.array(e.dxf.end)[:2]) / 2, 9)) for e in lines}
    roller_c = o1 + 50.0 * np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])  # φ = 0
    for c in (o1, o2, roller_c):
        assert tuple(np.round(c, 9)) in mids
    assert shapely.Point(*o2).within(parts["wheel"][0].buffer(0).envelope)
    assert parts["wheel"][0].centroid.distance(shapely.Point(*o2)) < 1e-6  # z-fold symmetric about O2
    assert parts["roller"][0].centroid.distance(shapely.Point(*roller_c)) < 1e-9
    # mid-engagement: the roller sits in a slot with the slot clearance on both sides
    assert parts["wheel"][0].distance(parts["roller"][0]) == pytest.approx(0.05, abs=2 * FLAT)


@pytest.mark.parametrize("z", [3, 8])
def test_other_slot_counts(tmp_path, z):
    el = Geneva("g", z, 100.0, 8.0, drawing=Drawing(wheel_bore_radius=4.0))
    export_geneva(el, tmp_path / "w.dxf")
    _, parts = read_parts(tmp_path / "w.dxf")
    wheel, rings = parts["wheel"]
    closed = notes_wheel_area(z, 100.0, 8.0, 0.05, 0.5, 4.0)
    assert wheel.is_valid and abs(wheel.area - closed) <= sum(shapely.LinearRing(r).length for r in rings) * FLAT


def test_unwritable_path_raises_export_error_naming_it(tmp_path):
    el = Geneva("g", 6, 100.0, 8.0)
    with pytest.raises(ExportError, match="no_such_folder"):
        export_geneva(el, tmp_path / "no_such_folder" / "w.dxf")
