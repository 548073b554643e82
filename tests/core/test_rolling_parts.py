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


def _centres(part, kind="fastener"):
    from mechsketch.core.analyses.parts import is_circle

    return sorted((round(c[0][0], 9), round(c[0][1], 9)) for h in part.holes if h.kinds and h.kinds[0] == kind
                  for c in [is_circle(h)])


@pytest.mark.parametrize("base", [False, True])
def test_fastener_holes_match_on_the_part_the_frame_plate_mounts_on(tmp_path, base):
    """Issue 23 item 5: two Ø5 mm fastener holes in the frame and slider plates, one diameter in
    from the back edge (measured with shapely: the centre's distance to the plate's back line),
    the frame's pair at the same places in the drilling pattern or the base plate, which then
    carries every pivot and encloses the frame plate; the plates keep ≥ 1.1 × the minimum web;
    OGR reads the frame plate's area as the outline's less the two holes (within 1e-6)."""
    from ogr_readback import ogr_layers

    from mechsketch.core.analyses.parts import check_part

    res = synth("rolling_lever_press")
    plain = rolling_parts(res)
    ps = rolling_parts(res, RollingStyle(fasteners=5.0, base_plate=base))
    by = {p.name: p for p in ps.parts}
    mount = by["base_plate" if base else "frame_pivots"]
    assert ("frame_pivots" in by) == (not base)
    assert len(_centres(by["frame"])) == len(_centres(by["slider"])) == 2
    assert _centres(mount) == _centres(by["frame"])
    pivots = {p.name: p for p in plain.parts}["frame_pivots"]
    assert _centres(mount, "bore") == _centres(pivots, "bore")
    for name in ("frame", "slider"):
        poly = by[name].polygon(1e-6)
        for x, y in _centres(by[name]):     # the nearest edge is the back, one diameter away
            assert shapely.Point(x, y).distance(poly.exterior) == pytest.approx(5.0, abs=1e-6)
        assert check_part(by[name], 1.0).web >= 1.1
    if base:
        plate = mount.polygon(1e-6)
        assert shapely.Polygon(plate.exterior).contains(by["frame"].polygon(1e-6))
        assert check_part(mount, 1.0).ok
    path = tmp_path / "rl.dxf"
    exp = export_parts(ps, path, layout="assembled")
    assert "fasteners: 2 × Ø5 mm" in exp.report
    area = abs(by["frame"].outer.area()) - 2 * math.pi * 2.5 ** 2
    assert ogr_layers(path)["frame"][0] == pytest.approx(area, rel=1e-6)


def test_fastener_and_base_plate_options_are_refused_where_they_do_not_apply(tmp_path, capsys):
    from mechsketch.core.cli import main

    rl, gv = (str(resources.example_path(n)) for n in ("rolling_lever_press", "geneva_z6"))
    assert main(["export", rl, "--dxf", str(tmp_path / "a.dxf"), "--fasteners", "5", "--base-plate"]) == 0
    assert "base_plate:" in capsys.readouterr().out
    assert main(["export", gv, "--dxf", str(tmp_path / "g.dxf"), "--fasteners", "5"]) == 1
    assert "--fasteners does not apply" in capsys.readouterr().err
    assert main(["export", gv, "--dxf", str(tmp_path / "g.dxf"), "--base-plate"]) == 1
    assert "--base-plate does not apply" in capsys.readouterr().err
    assert main(["export", rl, "--dxf", str(tmp_path / "b.dxf"), "--fasteners", "0"]) == 1
    assert "--fasteners must be a positive number" in capsys.readouterr().err
    assert main(["export", rl, "--dxf", str(tmp_path / "b.dxf"), "--fasteners", "30"]) == 1
    assert "below half the plate depth" in capsys.readouterr().err
    assert not (tmp_path / "g.dxf").exists() and not (tmp_path / "b.dxf").exists()
