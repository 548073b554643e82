"""Underlay elements (issue 22 item 6; scene schema_version 3): the placement's similarity and its
inverse, placing by two points of known distance, the record's round trip through a scene file,
and the readers checked against geometry written by an independent writer (ezdxf, an SVG text,
Pillow): every point where the file put it, in millimetres."""
from __future__ import annotations

import base64
import io
import json
import math
import os

import ezdxf
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from mechsketch.core import RequestError, SceneFormatError, dumps_scene, load_scene, loads_scene, save_scene
from mechsketch.core.cli import main as cli_main
from mechsketch.core.io.underlay_files import MAX_SIDE, placed, read_underlay, underlay_kind
from mechsketch.core.model.scene import Scene
from mechsketch.core.model.transform import extent, translated
from mechsketch.core.model.underlay import Placement, Underlay
from mechsketch.resources import example_path

finite = st.floats(-1e4, 1e4, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(scale=st.floats(1e-3, 1e3), angle=st.floats(-720, 720), ox=finite, oy=finite,
       pts=st.lists(st.tuples(finite, finite), min_size=1, max_size=20))
def test_placement_is_a_similarity_and_to_source_inverts_it(scale, angle, ox, oy, pts):
    pl = Placement(scale, angle, (ox, oy))
    src = np.array(pts)
    world = np.array(pl.to_world(src))
    t = math.radians(angle)
    ref = np.array([[ox + scale * (x * math.cos(t) - y * math.sin(t)),
                     oy + scale * (x * math.sin(t) + y * math.cos(t))] for x, y in pts])
    assert np.allclose(world, ref, rtol=1e-12, atol=1e-9 * (1 + scale * 1e4))
    assert np.allclose(np.array(pl.to_source(world)), src, rtol=1e-9, atol=1e-7)
    if len(pts) >= 2:   # distances scale by ``scale``
        d_src = np.hypot(*(src[1] - src[0]))
        assert np.hypot(*(world[1] - world[0])) == pytest.approx(scale * d_src, rel=1e-9, abs=1e-7)


def test_placing_by_two_points_keeps_the_first_and_sets_the_distance():
    pl = Placement(0.5, 30.0, (10.0, -4.0))
    a_src, b_src = np.array([[3.0, 4.0]]), np.array([[40.0, -11.0]])
    a, b = np.array(pl.to_world(a_src)[0]), np.array(pl.to_world(b_src)[0])
    new = pl.scaled_about(tuple(a), 120.0 / np.hypot(*(b - a)))
    a2, b2 = np.array(new.to_world(a_src)[0]), np.array(new.to_world(b_src)[0])
    assert np.allclose(a2, a, atol=1e-12) and np.hypot(*(b2 - a2)) == pytest.approx(120.0, rel=1e-14)
    assert new.angle_deg == 30.0
    with pytest.raises(ValueError, match="positive"):
        pl.scaled_about((0, 0), 0.0)


def _drawing(**kw) -> Underlay:
    return Underlay("outline", "frame.dxf", paths=(((0.0, 0.0), (100.0, 0.0), (100.0, 50.0)), ((5.0, 5.0), (9.0, 9.0))),
                    placement=Placement(2.0, 90.0, (10.0, 20.0)), **kw)


def _png(w: int = 8, h: int = 4) -> bytes:
    buf = io.BytesIO()
    Image.new("RGB", (w, h), (200, 10, 10)).save(buf, "PNG")
    return buf.getvalue()


def test_an_underlay_round_trips_through_a_version_3_scene_file(tmp_path):
    from mechsketch.core.model.underlay import UnderlayImage

    pic = Underlay("photo", "part.png", image=UnderlayImage("png", base64.b64encode(_png()).decode(), 8, 4),
                   placement=Placement(0.25, -12.5, (-3.0, 4.0)), visible=False, opacity=0.3)
    scene = load_scene(example_path("fourbar_crank_rocker"))
    scene = Scene(scene.elements + (_drawing(), pic))
    save_scene(scene, tmp_path / "s.json")
    doc = json.loads((tmp_path / "s.json").read_text())
    assert doc["schema_version"] == 3 and [e["type"] for e in doc["elements"]] == ["linkage", "underlay", "underlay"]
    assert load_scene(tmp_path / "s.json") == scene
    assert loads_scene(dumps_scene(scene)) == scene
    assert cli_main(["validate", str(tmp_path / "s.json")]) == 0        # a reference, no parts checked
    assert cli_main(["analyze", str(tmp_path / "s.json"), "--summary"]) == 0


@pytest.mark.parametrize("change, where, says", [
    (lambda d: d.update(image={"format": "png", "data": "iVBORw0KGgo=", "width": 1, "height": 1}), "$.elements[0]",
     "either 'paths'"),
    (lambda d: d.pop("paths"), "$.elements[0]", "either 'paths'"),
    (lambda d: d["placement"].update(scale=0), "$.elements[0].placement.scale", "less than the minimum"),
    (lambda d: d["paths"].append([[1, 2]]), "$.elements[0].paths[2]", "is too short"),
    (lambda d: d.update(opacity=2), "$.elements[0].opacity", "greater than the maximum"),
])
def test_a_bad_underlay_is_refused_with_its_path(change, where, says):
    d = _drawing().to_dict()
    change(d)
    doc = {"format": "mechsketch.scene", "schema_version": 3, "units": "mm", "elements": [d]}
    with pytest.raises(SceneFormatError) as err:
        loads_scene(json.dumps(doc))
    assert any(p.path == where and says in p.message for p in err.value.problems), err.value.problems


def test_a_picture_that_is_not_what_it_says_is_refused():
    d = {"type": "underlay", "id": "p", "name": "x.png", "placement": {"scale": 1, "offset": [0, 0]},
         "image": {"format": "jpeg", "data": base64.b64encode(_png()).decode(), "width": 8, "height": 4}}
    doc = {"format": "mechsketch.scene", "schema_version": 3, "units": "mm", "elements": [d]}
    with pytest.raises(SceneFormatError, match="does not hold a JPEG picture"):
        loads_scene(json.dumps(doc))
    d["image"]["data"] = "not base64!"
    with pytest.raises(SceneFormatError, match="not base64"):
        loads_scene(json.dumps(doc))


def test_translated_and_extent_move_and_bound_an_underlay():
    u = _drawing()
    x0, y0, x1, y1 = extent(u)
    world = np.array(u.world_points())
    assert (x0, y0, x1, y1) == pytest.approx((world[:, 0].min(), world[:, 1].min(), world[:, 0].max(),
                                              world[:, 1].max()))
    moved = translated(u, 5.0, -2.0)
    assert np.allclose(np.array(moved.world_points()), world + [5.0, -2.0])


def test_dxf_geometry_in_inches_arrives_in_millimetres(tmp_path):
    doc = ezdxf.new(units=1)                                     # inches
    msp = doc.modelspace()
    msp.add_line((0, 0), (4, 0))
    msp.add_circle((2, 3), 1.0)
    msp.add_lwpolyline([(0, 0, 0), (1, 0, 1), (1, 1, 0)], format="xyb")   # a half circle by its bulge
    block = doc.blocks.new("PIN")
    block.add_line((0, 0), (0.5, 0))
    msp.add_blockref("PIN", (10, 10), dxfattribs={"rotation": 90})
    doc.saveas(tmp_path / "a.dxf")
    u, mm = read_underlay(tmp_path / "a.dxf", "u")
    assert mm == 25.4 and u.kind == "drawing"
    world = placed(u, mm)
    paths = [np.array(p) for p in world.world_paths()]
    line = next(p for p in paths if len(p) == 2 and abs(p[0][1]) < 1e-9 and abs(p[1][1]) < 1e-9)
    assert np.hypot(*(line[1] - line[0])) == pytest.approx(101.6, rel=1e-12)
    circle = max(paths, key=len)
    r = np.hypot(circle[:, 0] - 2 * 25.4, circle[:, 1] - 3 * 25.4)
    assert r == pytest.approx(25.4, abs=25.4 * 2e-3)             # flattened within 1e-4 of the diagonal
    pin = next(p for p in paths if len(p) == 2 and abs(p[0][0] - 254.0) < 1e-6)
    assert pin[1] == pytest.approx([254.0, 254.0 + 12.7], abs=1e-9)   # the block turned by 90°
    bulge = next(p for p in paths if len(p) > 3 and np.allclose(p[0], [0.0, 0.0], atol=1e-9))
    arc = bulge[1:]                                              # after the straight first segment
    r = np.hypot(arc[:, 0] - 25.4, arc[:, 1] - 12.7)
    assert r == pytest.approx(12.7, rel=2e-3) and arc[:, 0].max() == pytest.approx(38.1, rel=1e-3)


def test_svg_shapes_with_transforms_and_units(tmp_path):
    (tmp_path / "a.svg").write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="100mm" viewBox="0 0 200 100">'
        '<g transform="translate(10 20)"><rect x="0" y="0" width="50" height="30"/></g>'
        '<path d="M 100 50 L 150 50"/><circle cx="30" cy="70" r="10"/><text x="1" y="1">ignored</text></svg>')
    u, mm = read_underlay(tmp_path / "a.svg", "s")
    w = [np.array(p) for p in placed(u, mm).world_paths()]
    rect = next(p for p in w if len(p) <= 6 and np.ptp(p[:, 0]) == pytest.approx(50.0, rel=1e-9))
    assert rect[:, 0].min() == pytest.approx(10.0, rel=1e-9) and rect[:, 1].max() == pytest.approx(-20.0, rel=1e-9)
    assert np.ptp(rect[:, 1]) == pytest.approx(30.0, rel=1e-9)   # y flipped: SVG's y points down
    line = next(p for p in w if len(p) == 2)
    assert np.allclose(line, [[100.0, -50.0], [150.0, -50.0]], rtol=1e-9, atol=0)
    circle = max(w, key=len)
    assert np.hypot(circle[:, 0] - 30, circle[:, 1] + 70) == pytest.approx(10.0, rel=1e-6)


def test_pictures_are_kept_or_converted_and_scaled_down(tmp_path):
    (tmp_path / "a.png").write_bytes(_png(8, 4))
    u, mm = read_underlay(tmp_path / "a.png", "p")
    assert (u.image.format, u.image.width, u.image.height, mm) == ("png", 8, 4, 0.0)
    assert u.image.raw() == _png(8, 4)                             # PNG kept byte for byte
    Image.new("RGB", (MAX_SIDE * 2, 10), (0, 0, 0)).save(tmp_path / "wide.bmp")
    w, _ = read_underlay(tmp_path / "wide.bmp", "w")
    assert w.image.format == "png" and (w.image.width, w.image.height) == (MAX_SIDE, 5)
    p = placed(u, 0.0, centre=(100.0, 50.0), width_mm=80.0)
    assert p.world_bounds() == pytest.approx((60.0, 30.0, 140.0, 70.0))


@pytest.mark.parametrize("name, content, says", [
    ("x.txt", b"hello", "a DXF or SVG drawing or a picture"),
    ("empty.dxf", None, "no lines, arcs"),
    ("bad.svg", b"<svg", "cannot read bad.svg as an SVG drawing"),
    ("blank.svg", b'<svg xmlns="http://www.w3.org/2000/svg"></svg>', "no paths, lines or shapes"),
    ("bad.png", b"\x89PNG\r\n\x1a\nbroken", "cannot read bad.png as a picture"),
    ("gone.dxf", "missing", "cannot read"),
])
def test_a_file_that_cannot_be_an_underlay_says_why(tmp_path, name, content, says):
    path = tmp_path / name
    if content is None:
        ezdxf.new().saveas(path)
    elif content != "missing":
        path.write_bytes(content)
    with pytest.raises(RequestError, match=says):
        read_underlay(path, "u")


def test_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "pipe.svg"
    os.mkfifo(fifo)
    with pytest.raises(RequestError, match="not a regular file"):
        read_underlay(fifo, "u")
    assert underlay_kind("a.DXF") == "drawing" and underlay_kind("b.JPG") == "picture" and underlay_kind("c.json") is None


def test_the_scene_reader_loads_no_numpy_for_underlays():
    """The model stays pure Python: the CLI's start-up (and its one-BLAS-thread request) needs it."""
    import subprocess
    import sys

    code = "import sys, mechsketch.core.model.underlay, mechsketch.core.io.scene_file; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "False", out.stderr
