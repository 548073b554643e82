"""Keyways and flats on shaft bores (issue 23, item 5): the bore contours against closed forms
and shapely, DIN 6885-1 sizes, the keyed examples exported and read back by GDAL (each part's
area less exactly what the key removes), with a kerf, and the option refused where it does not
apply."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mechsketch.core.errors import GeometryError
import shapely

from mechsketch import resources
from mechsketch.core import GeometryError, load_scene
from mechsketch.core.analyses.parts import is_circle
from mechsketch.core.analyses.parts.bore_keys import FLAT_AT, key_size, keyed_bore
from mechsketch.core.analyses.parts.build import PartOptions, element_parts
from mechsketch.core.analyses.parts.kerf import kerf_part
from mechsketch.core.io.export_parts import export_parts

from ogr_readback import ogr_layers


@pytest.mark.parametrize("r", [3.5, 6.0, 10.0, 24.0])
@pytest.mark.parametrize("angle", [0.0, 1.0, -2.5])
def test_keyed_bores_against_closed_forms(r, angle):
    c = (12.0, -7.0)
    flat = keyed_bore(c, r, "flat", angle)
    h = FLAT_AT * r
    exact = math.pi * r * r - (r * r * math.acos(h / r) - h * math.sqrt(r * r - h * h))
    assert flat.area() == pytest.approx(exact, rel=1e-12)
    b, t2 = key_size(2 * r)
    key = keyed_bore(c, r, "keyway", angle)
    u = np.array([math.cos(angle), math.sin(angle)])
    v = np.array([-u[1], u[0]])
    box = shapely.Polygon([np.array(c) + s * u + w * v for s, w in ((0, -b / 2), (r + t2, -b / 2), (r + t2, b / 2),
                                                                     (0, b / 2))])
    ref = shapely.Point(c).buffer(r, quad_segs=4096).union(box).area
    assert key.area() == pytest.approx(ref, rel=1e-6)
    far = max(np.hypot(*(np.asarray(key.points) - c).T))      # the keyway's corners at the hub depth
    assert far == pytest.approx(math.hypot(r + t2, b / 2), rel=1e-12)


def test_din_6885_sizes_and_their_limits():
    assert key_size(20.0) == (6.0, 2.8) and key_size(30.0) == (8.0, 3.3) and key_size(30.1) == (10.0, 3.3)
    with pytest.raises(GeometryError, match="use a flat instead"):
        key_size(5.0)


KEYED = {"geneva": {"crank_arm", "locking_disc", "wheel"}, "gear_pair": {"input_gear", "output_gear"},
         "geared_geneva": {"crank_arm", "locking_disc", "wheel", "input_gear", "output_gear"}}


@pytest.mark.parametrize("name", ["fourbar_crank_rocker", "geneva_z6", "slider_crank_offset", "gears_elliptic",
                                  "smooth_geneva_z5"])
@pytest.mark.parametrize("key", ["keyway", "flat"])
def test_keyed_examples_read_back_with_what_the_key_removes(tmp_path, name, key):
    el = load_scene(resources.example_path(name)).elements[0]
    plain = {p.name: p for p in element_parts(el, PartOptions()).parts}
    ps = element_parts(el, PartOptions(bore_key=key))
    keyed = [p for p in ps.parts if any(h.kinds and h.kinds[0] in ("keyway", "flat") for h in p.holes)]
    assert {p.name for p in keyed} == KEYED.get(el.type, {el.driver.link} if el.type == "linkage" else set())
    if (name, key) == ("smooth_geneva_z5", "keyway"):   # its wheel's hub is too thin for a keyway
        with pytest.raises(GeometryError, match="part 'wheel'.*bore_key"):
            export_parts(ps, tmp_path / "refused.dxf")
        assert not (tmp_path / "refused.dxf").exists()
        return
    for arcs in ("bulge", "entities"):
        path = tmp_path / f"{name}_{key}_{arcs}.dxf"
        export_parts(ps, path, arcs=arcs, kerf=0.0)
        ogr = ogr_layers(path)
        for p in keyed:
            removed = sum(abs(h.area()) - math.pi * is_circle(g)[1] ** 2
                          for h, g in zip(p.holes, plain[p.name].holes) if is_circle(h) is None)
            assert (removed > 0) == (key == "keyway")     # a keyway widens the hole, a flat fills part of it
            assert ogr[p.name][0] == pytest.approx(plain[p.name].area - removed, rel=1e-6)
    for p in keyed:                               # a kerf keeps the keyed bore a valid tool path
        assert kerf_part(p, 0.2).polygon(1e-6).is_valid


def test_the_bore_key_is_refused_where_there_is_no_shaft(tmp_path, capsys):
    from mechsketch.core.cli import main

    rl = str(resources.example_path("rolling_lever_press"))
    assert main(["export", rl, "--dxf", str(tmp_path / "r.dxf"), "--bore-key", "flat"]) == 1
    assert "--bore-key does not apply" in capsys.readouterr().err
    g8 = str(resources.example_path("geneva_z8"))        # the crank arm's hub is too thin for a keyway
    assert main(["export", g8, "--dxf", str(tmp_path / "g.dxf"), "--bore-key", "keyway"]) == 1
    err = capsys.readouterr().err
    assert "crank_arm" in err and "--bore-key" in err and not list(tmp_path.glob("*.dxf"))
