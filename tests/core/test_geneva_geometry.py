"""Drawable Geneva geometry: exact areas against the notes' closed form and shapely, the relief that
truly clears (checked by an independent shapely sweep, tight, and the classical R_o failing), the
limits, and random valid drives (hypothesis)."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from mechsketch.core.analyses.geneva.clearance import check_clearances
from mechsketch.core.analyses.contour import Contour
from mechsketch.core.analyses.geneva.geometry import geometry
from mechsketch.core.analyses.geneva.geometry import relief_values, wheel_outline
from mechsketch.core.model.geneva import Clearances, Drawing, Geneva, parse


def drive(z: int, a: float = 100.0, rp: float = 8.0, **kw) -> Geneva:
    kw.setdefault("drawing", Drawing(wheel_bore_radius=min(15.0, 0.5 * (a - a * math.sin(math.pi / z) - 0.5 - rp))))
    return Geneva("g", z, a, rp, **kw)


def lens(r1: float, r2: float, d: float) -> float:
    """Area of the intersection of two circles (independent of the module)."""
    a1 = r1 * r1 * math.acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1))
    a2 = r2 * r2 * math.acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2))
    return a1 + a2 - 0.5 * math.sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2))


def test_contour_primitives_exact_area_offset_and_polyline():
    c = Contour.circle((3.0, -2.0), 5.0)
    assert c.area() == pytest.approx(math.pi * 25, rel=1e-15) and c.length == pytest.approx(10 * math.pi)
    square = Contour(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]), np.zeros(4))
    grown = square.offset(0.5)  # 4 sides + 4 quarter-circle corners
    assert len(grown) == 8 and grown.kinds.count("corner") == 4
    assert grown.area() == pytest.approx(4 + 4 * 2 * 0.5 + math.pi * 0.25, rel=1e-14)
    poly = shapely.Polygon(c.polyline(1e-4))
    assert poly.is_valid and c.area() - poly.area < c.length * 1e-4
    ell = Contour(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]), np.zeros(6))
    assert ell.area() == pytest.approx(3.0, rel=1e-15)
    with pytest.raises(ValueError, match="concave corner at vertex 3"):
        ell.offset(0.1)


@pytest.mark.parametrize("z", range(3, 13))
def test_wheel_area_exact_equals_the_notes_closed_form_and_shapely(z):
    el = drive(z)
    geo = geometry(el)
    d = geo.dims
    ro, w, xc, xb, ra, a = d.outer_radius, d.w, d.x_c, d.x_b, d.lock_arc_radius, d.center_distance
    closed = (math.pi * ro ** 2 - z * (2 * w * (xc - xb) + math.pi * w * w / 2 + (ro ** 2 * math.acos(xc / ro) - xc * w))
              - z * lens(ro, ra, a) - math.pi * geo.wheel_bore ** 2)
    assert geo.wheel_area == pytest.approx(closed, rel=1e-12)
    assert geo.wheel_area_closed_form == pytest.approx(closed, rel=1e-13)
    tol = 1e-5
    poly = geo.wheel.polygon(tol)
    assert poly.is_valid and len(poly.interiors) == 1
    per = geo.wheel.outer.length + 2 * math.pi * geo.wheel_bore
    assert abs(closed - poly.area) <= per * tol  # inscribed chords move the outline by ≤ the sagitta
    assert len(geo.wheel.outer) == 6 * z  # 2 walls, 1 bottom, 2 lands, 1 locking arc per slot
    sg = geo.wheel.outer.segments()
    lines = ~sg.is_arc
    assert lines.sum() == 2 * z and np.allclose(sg.length[lines], xc - xb, rtol=1e-12)


def test_limits_reported_for_the_default_scene():
    geo = geometry(drive(6, drawing=None))  # bore = journal radius 15 mm
    d = geo.dims
    assert round(d.hub_max, 2) == 41.45 and round(d.slot_depth, 2) == 45.15
    assert math.degrees(d.land_angle) == pytest.approx(2.6716, abs=1e-4)
    assert geo.wheel_bore == 15.0 and geo.pin_radius == 4.0
    # default crank bore: a quarter of the disc, capped so the disc keeps the minimum web
    assert geo.crank_bore == pytest.approx(min(0.25 * d.lock_disc_radius, 100 - geo.relief.drawn - 1.0))
    assert 0 < geo.locking_margin < d.phi0 + d.lock_half_angle
    assert geo.relief_half_angle == pytest.approx(d.phi0, abs=math.radians(1))  # "≈ φ0" (notes)


def test_relief_values_of_the_notes_and_beyond():
    r6 = geometry(drive(6)).relief
    assert round(r6.classical, 3) == 86.976
    assert round(r6.touch, 2) == 87.50  # "relief radius ≥ 87.50 mm (R_o = 86.976)"
    assert r6.exact == pytest.approx(r6.touch + 0.1, abs=1e-6)  # the horn land binds: offset by c_l
    assert r6.drawn >= r6.exact and r6.drawn - r6.exact < 1e-3
    for z in range(3, 13):
        r = geometry(drive(z)).relief
        excess = (r.touch - r.classical) / 100.0
        assert 0.002 < excess < 0.012, (z, excess)  # R_o + (0.2 … 1.2) % A
        assert r.exact >= r.limit_end - 1e-12 and r.exact >= r.touch


def test_relief_value_function_is_the_farthest_covered_disc_point():
    """V(φ) from closed-form candidates against brute force over the densely sampled offset outline."""
    el = drive(6)
    d = el.dimensions()
    off = wheel_outline(d).offset(el.clearance.lock)
    phis = np.linspace(-d.phi0 * 0.98, d.phi0 * 0.98, 19)
    v = relief_values(phis, off, d)
    sg = off.segments()  # dense points every ≤ 1 µm along every line and arc
    chunks = []
    for k in range(len(off)):
        n = max(2, int(math.ceil(sg.length[k] / 1e-3)))
        t = np.linspace(0.0, 1.0, n)
        if sg.is_arc[k]:
            ang = sg.a0[k] + sg.theta[k] * t
            chunks.append(sg.centre[k] + sg.radius[k] * np.c_[np.cos(ang), np.sin(ang)])
        else:
            chunks.append(sg.p0[k] + np.outer(t, sg.p1[k] - sg.p0[k]))
    pts = np.vstack(chunks)
    reach = d.lock_disc_radius + 2 * d.center_distance * math.sin(math.pi / (2 * d.slots)) + 1.0
    pts = pts[np.hypot(pts[:, 0] + d.center_distance, pts[:, 1]) < reach]  # what the disc can reach
    th = np.arctan2(d.lam * np.sin(phis), 1 - d.lam * np.cos(phis))
    for k, phi in enumerate(phis):
        rot = -phi - th[k]
        q = pts @ np.array([[math.cos(rot), math.sin(rot)], [-math.sin(rot), math.cos(rot)]])
        q = q + [d.center_distance * math.cos(phi), -d.center_distance * math.sin(phi)]
        inside = np.hypot(q[:, 0], q[:, 1]) <= d.lock_disc_radius
        brute = np.hypot(q[inside, 0] - d.center_distance, q[inside, 1]).max() if inside.any() else -np.inf
        if np.isfinite(v[k]) or np.isfinite(brute):
            assert v[k] == pytest.approx(brute, abs=1e-3), phi  # the sampling step of the crossings
            assert v[k] >= brute - 1e-6


@pytest.mark.parametrize("z", [3, 4, 6, 8, 12])
def test_shapely_sweep_no_overlap_roller_clearance_equals_slot_clearance(z):
    geo = geometry(drive(z))
    rep = check_clearances(geo, 360)
    tol = 2 * rep.tol
    assert not rep.overlap_roller and not rep.overlap_disc
    assert rep.roller == pytest.approx(0.05, abs=tol)  # the minimum roller clearance is c_s
    assert rep.disc >= 0.1 - tol and rep.disc == pytest.approx(0.1, abs=tol)  # c_l, met in the dwell
    # in the slot the gap is c_s over the whole engagement (both walls are parallel to the roller path)
    eng = np.abs(rep.phi) <= geo.dims.phi0
    assert np.all(np.abs(rep.roller_gap[eng] - 0.05) <= tol)
    classical = check_clearances(geo, 90, relief_radius=geo.relief.classical)
    assert classical.overlap_disc  # the classical relief R_o is too small: the horns hit the disc


@pytest.mark.parametrize("z", [5, 9])
def test_relief_is_tight(z):
    geo = geometry(drive(z))
    smaller = check_clearances(geo, 360, relief_radius=geo.relief.exact - 0.01)
    assert smaller.disc < 0.1 - 0.005 and abs(smaller.phi_disc) < geo.dims.phi0


def test_world_placement_keeps_the_roller_on_the_slot_axis():
    el = drive(5, crank_center=(40.0, -25.0), wheel_direction_deg=137.0)
    geo = geometry(el)
    o2 = np.array(el.wheel_center)
    for phi in np.linspace(-geo.dims.phi0, geo.dims.phi0, 9):
        parts = geo.placed(phi)
        roller = parts["roller"].outer.segments()
        centre = roller.centre[0]
        # slot 0's wall midpoints, placed: the roller centre is on the line through O2 between them
        walls = parts["wheel"].outer.segments()
        mid = 0.5 * (walls.p0[0] + walls.p1[2])  # lower and upper wall of slot 0 at x_c
        axis = (mid - o2) / np.linalg.norm(mid - o2)
        off = centre - o2
        assert abs(axis[0] * off[1] - axis[1] * off[0]) < 1e-9
        crank = math.radians(137.0) + phi
        expected = np.array(el.crank_center) + el.crank_radius * np.array([math.cos(crank), math.sin(crank)])
        assert np.allclose(centre, expected, atol=1e-12)  # and it is the crank's roller position


@st.composite
def valid_drives(draw):
    z = draw(st.integers(3, 12))
    a = draw(st.floats(40.0, 400.0))
    r = a * math.sin(math.pi / z)
    rp = draw(st.floats(0.02, 0.3)) * r
    # polygons cannot judge an exact fit, so every clearance is at least 5 times the chord tolerance
    cl = Clearances(draw(st.floats(0.01, 0.2)), draw(st.floats(0.0, 1.0)), draw(st.floats(0.01, 0.3)))
    data = {"type": "geneva", "id": "h", "slots": z, "center_distance": a, "roller_radius": rp,
            "clearance": cl.to_dict(), "drawing": {"wheel_bore_radius": 0.0}}
    el, problems = parse(data, "$")
    assume(el is not None)
    return el


@settings(max_examples=8, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(valid_drives())
def test_random_valid_drives_build_clear_and_never_overlap(el):
    geo = geometry(el)
    assert geo.wheel.polygon(1e-4).is_valid and geo.locking_disc.polygon(1e-4).is_valid
    assert geo.wheel_area == pytest.approx(geo.wheel_area_closed_form, rel=1e-10)
    assert geo.locking_margin > 0 and geo.relief.drawn > geo.relief.classical
    rep = check_clearances(geo, 120, tol=1e-3)
    assert not rep.overlap_roller and not rep.overlap_disc
    assert rep.roller == pytest.approx(el.clearance.slot, abs=2e-3)
    assert rep.disc >= el.clearance.lock - 2e-3
