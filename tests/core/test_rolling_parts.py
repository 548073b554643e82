"""Rolling-lever plates read back from DXF and SVG: closed outlines whose working edges are the
synthesised profiles (within the tolerance of the exact curves, measured on the file) and the
lever's two working arcs (true arcs on the outline), the frame's pivots as a drilling pattern."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from mechsketch import resources
from mechsketch.core import GeometryError, load_scene
from mechsketch.core.analyses.parts.rolling import RollingStyle, rolling_parts
from mechsketch.core.analyses.rolling.synthesis import synthesize
from mechsketch.core.io.export_parts import export_parts

from parts_readback import FLAT, dxf_parts, read_dxf, svg_parts

EXAMPLES = ["rolling_lever_press", "rolling_lever_inclined"]


def synth(name, **kw):
    el = load_scene(resources.example_path(name)).elements[0]
    return synthesize(el, measures=False, **kw)


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_rolling_example_exports_closed_valid_plates(tmp_path, name):
    res = synth(name)
    ps = rolling_parts(res)
    assert ps.names == ("frame", "frame_pivots", "lever", "slider")
    for fmt, arcs in (("dxf", "bulge"), ("dxf", "entities"), ("svg", "bulge")):
        path = tmp_path / f"{arcs}.{fmt}"
        exp = export_parts(ps, path, fmt=fmt, arcs=arcs)
        parts = (svg_parts if fmt == "svg" else dxf_parts)(path)[1]
        for part, check in zip(ps.parts, exp.checks):
            poly = parts[part.name]
            assert poly.is_valid
            if part.outer is not None:
                assert len(poly.interiors) == len(part.holes)
                assert poly.area == pytest.approx(check.area, abs=1e-3 * poly.length)


@pytest.mark.parametrize("name", EXAMPLES)
def test_working_edges_are_the_profiles_and_the_lever_arcs(tmp_path, name):
    res = synth(name)
    tol = 0.002
    ps = rolling_parts(res, RollingStyle(tolerance=tol))
    export_parts(ps, tmp_path / "a.dxf", layout="assembled")
    _, rings = read_dxf(tmp_path / "a.dxf")
    frame = shapely.LinearRing(rings["frame"][0])
    curve, t0, t1 = res.frame_profile()
    exact = curve(np.linspace(t0, t1, 4001))
    assert shapely.distance(frame, shapely.points(exact)).max() <= tol + 2 * FLAT
    slider = shapely.LinearRing(rings["slider"][0])
    curve, t0, t1 = res.slider_profile()
    exact = curve(np.linspace(t0, t1, 4001))
    assert shapely.distance(slider, shapely.points(exact)).max() <= tol + 2 * FLAT
    # the lever's outline holds both working arcs whole (as read from the file)
    lever = max(rings["lever"], key=lambda r: shapely.Polygon(r).area)
    el = res.element
    for circ, u in ((el.lever_circle, res.u1), (el.slider_circle, res.u2)):
        ang = np.linspace(u.min(), u.max(), 500)
        pts = np.c_[circ.center[0] + circ.radius * np.cos(ang), circ.center[1] + circ.radius * np.sin(ang)]
        assert shapely.distance(shapely.LinearRing(lever), shapely.points(pts)).max() <= 2 * FLAT
    # pins: bores of the pin diameter at the pin and the coupler point
    holes = [shapely.Polygon(r) for r in rings["lever"] if shapely.Polygon(r).area < 1000]
    centres = sorted(tuple(np.round([h.centroid.x, h.centroid.y], 4)) for h in holes)
    assert centres == sorted([tuple(np.round(el.pin, 4)), tuple(np.round(el.drive.coupler_point, 4))])
    assert all(h.area == pytest.approx(math.pi * 25.0, rel=1e-4) for h in holes)  # inscribed chords
    # the frame's pivots: a drilling pattern at G and A
    pivots = sorted(tuple(np.round(shapely.Polygon(r).centroid.coords[0], 4)) for r in rings["frame_pivots"])
    assert pivots == sorted([tuple(np.round(el.rocker_pivot, 4)), tuple(np.round(el.drive.crank_pivot, 4))])


def test_the_report_states_deviations_and_a_construction_its_distance_from_the_exact_centrode(tmp_path):
    res = synth("rolling_lever_press", method="corrected", points=50)
    exp = export_parts(rolling_parts(res), tmp_path / "p.dxf")
    assert "construction itself deviates" in exp.report and "within" in exp.report
    assert "frame profile:" in exp.report and "(tolerance 0.001 mm)" in exp.report


def test_the_papers_construction_gives_a_slider_profile_that_folds_back_and_is_refused(tmp_path):
    """The literal construction's slider profile turns back on itself near its start (its last
    point lies 4 mm from its first instead of 29 mm): no plate can carry it."""
    res = synth("rolling_lever_press", method="paper", points=200)
    assert np.hypot(*(res.Q[-1] - res.Q[0])) < 5.0
    with pytest.raises(GeometryError, match="part 'slider': the outline intersects itself"):
        export_parts(rolling_parts(res), tmp_path / "p.dxf")
    assert not (tmp_path / "p.dxf").exists()


@pytest.mark.parametrize("style, message", [
    (RollingStyle(tolerance=1e-9), "below what is exported faithfully"),
    (RollingStyle(tolerance=float("nan")), "positive number"),
    (RollingStyle(depth=-3.0), "the plate depth must be a positive"),
    (RollingStyle(depth=-3.0, depth_name="--depth"), "--depth must be a positive"),
])
def test_bad_styles_are_refused(style, message):
    with pytest.raises(GeometryError, match=message):
        rolling_parts(synth("rolling_lever_press"), style)
