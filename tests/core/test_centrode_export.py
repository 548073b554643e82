"""Centrodes for drawing and export: world instant centres, body frames, breaks at translations,
CSV and arc-fitted DXF read back and measured against an independent Kennedy construction."""
from __future__ import annotations

import cmath
import math
import re

import ezdxf
import numpy as np
import pytest
from scipy.spatial import cKDTree

from mechsketch.core import load_scene
from mechsketch.core.analyses.centrodes import linkage_centrodes, runs
from mechsketch.core.errors import GeometryError
from mechsketch.core.io.dxf_centrodes import default_limit, export_centrodes
from mechsketch.core.io.table import write_csv
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path

A, B0, C0, D = 0j, complex(20.0, 34.64101615137755), complex(133.22973437035895, 116.97586451109673), 160 + 0j


@pytest.fixture(scope="module")
def fourbar():
    return load_scene(example_path("fourbar_coupler_centrodes")).elements[0]


def kennedy(theta: np.ndarray):
    """Coupler centre (world) and the coupler's rotation, by circle intersection and line
    intersection of A-B and D-C, from scratch."""
    r, lc, lr = abs(B0 - A), abs(C0 - B0), abs(C0 - D)
    side = np.sign(((D - B0).conjugate() * (C0 - B0)).imag)
    b = A + r * np.exp(1j * theta)
    d = np.abs(D - b)
    a = (lc ** 2 - lr ** 2 + d ** 2) / (2 * d)
    h = np.sqrt(np.maximum(lc ** 2 - a ** 2, 0))
    u = (D - b) / d
    c = b + a * u + side * h * u * 1j
    # intersection of the lines A + s (b - A) and D + t (c - D)
    e1, e2 = b - A, c - D
    cross = (e1.conjugate() * e2).imag
    s = ((D - A).conjugate() * e2).imag / cross
    ic = A + s * e1
    rot = np.angle((c - b) / (C0 - B0))
    return ic, b, rot


def test_world_centres_and_body_frames_match_kennedy(fourbar):
    sol = compile_plan(fourbar).sweep(360, order=1)
    c = linkage_centrodes(sol, fourbar, "coupler")
    ic, b, rot = kennedy(sol.input)
    ok = c.valid
    assert ok.sum() > 300
    assert np.max(np.abs(c.world[ok, 0] + 1j * c.world[ok, 1] - ic[ok]) / np.maximum(1, np.abs(ic[ok]))) < 1e-9
    np.testing.assert_allclose(c.at[:, 0] + 1j * c.at[:, 1], b, atol=1e-9)
    assert np.max(np.abs(np.angle(np.exp(1j * (c.rotation - rot))))) < 1e-9
    # the moving centrode carried by the link's frame lands on the fixed one at every sample
    k = np.flatnonzero(ok)[::37]
    moved = c.at[k] + np.stack([np.cos(c.rotation[k]) * (c.p[k, 0] - c.origin[0]) - np.sin(c.rotation[k]) * (c.p[k, 1] - c.origin[1]),
                                np.sin(c.rotation[k]) * (c.p[k, 0] - c.origin[0]) + np.cos(c.rotation[k]) * (c.p[k, 1] - c.origin[1])], axis=-1)
    np.testing.assert_allclose(moved, c.P[k], atol=1e-7)


def test_runs_split_at_gaps_and_join_across_the_end_of_the_turn():
    m = np.array([1, 1, 0, 0, 1, 1, 1, 0, 1], dtype=bool)
    got = [list(r) for r in runs(m)]
    assert got == [[8, 0, 1], [4, 5, 6]]
    assert [list(r) for r in runs(m, cyclic=False)] == [[0, 1], [4, 5, 6], [8]]
    assert runs(np.zeros(4, bool)) == [] and [list(r) for r in runs(np.ones(3, bool))] == [[0, 1, 2]]


def test_the_crank_rocker_coupler_translates_twice_a_turn_so_its_centrodes_break(fourbar):
    sol = compile_plan(fourbar).sweep(720, order=1)
    c = linkage_centrodes(sol, fourbar, "coupler")
    w = sol.omega("coupler")
    assert np.sum(np.sign(w) != np.roll(np.sign(w), 1)) == 2          # ω of the coupler changes sign twice
    pieces = runs(c.drawable(default_limit(fourbar)))
    assert len(pieces) == 2


def _arc_points(path: str):
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    assert not auditor.has_errors
    assert doc.header["$INSUNITS"] == 4
    out = {}
    for e in doc.modelspace().query("LWPOLYLINE"):
        pts = []
        for seg in e.virtual_entities():
            if seg.dxftype() == "ARC":
                a0, a1 = math.radians(seg.dxf.start_angle), math.radians(seg.dxf.end_angle)
                if a1 < a0:
                    a1 += 2 * math.pi
                t = np.linspace(a0, a1, 40)
                c = seg.dxf.center
                pts.append(np.stack([c.x + seg.dxf.radius * np.cos(t), c.y + seg.dxf.radius * np.sin(t)], -1))
            else:
                s, t = seg.dxf.start, seg.dxf.end
                u = np.linspace(0, 1, 40)[:, None]
                pts.append(np.array([s.x, s.y]) * (1 - u) + np.array([t.x, t.y]) * u)
        out.setdefault(e.dxf.layer, []).append(np.concatenate(pts))
    return out, doc


def _deviation(points: np.ndarray, reference: np.ndarray) -> float:
    """Largest distance of points (M, 2) from the polyline through reference (K, 2)."""
    tree = cKDTree(reference)
    _, j = tree.query(points)
    best = np.full(len(points), np.inf)
    for off in (-1, 0):
        a = np.clip(j + off, 0, len(reference) - 2)
        p0, p1 = reference[a], reference[a + 1]
        d = p1 - p0
        s = np.clip(np.einsum("ij,ij->i", points - p0, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
        best = np.minimum(best, np.linalg.norm(points - (p0 + s[:, None] * d), axis=1))
    return float(best.max())


def test_dxf_export_reads_back_within_the_tolerance_of_the_exact_centrodes(fourbar, tmp_path):
    plan = compile_plan(fourbar)
    path = tmp_path / "coupler.dxf"
    rep = export_centrodes(plan, "coupler", None, path, tolerance=0.01)
    assert rep.max_deviation <= 0.01 and rep.breaks == 2 and len(rep.fixed) == len(rep.moving) == 2
    assert "max deviation" in rep.report() and "break" in rep.report()
    layers, doc = _arc_points(str(path))
    assert set(layers) == {"FIXED_CENTRODE", "MOVING_CENTRODE"}
    # independent dense reference (Kennedy), cut where the centre is farther than the exporter's limit
    th = plan.theta0 + np.linspace(0, 2 * math.pi, 400001)
    ic, b, rot = kennedy(th)
    limit = default_limit(fourbar)
    near = np.abs(ic - B0 - (b - B0)) < limit
    fixed = np.stack([ic.real, ic.imag], -1)
    mov = B0 + (ic - b) * np.exp(-1j * rot)
    moving = np.stack([mov.real, mov.imag], -1)
    for name, ref in (("FIXED_CENTRODE", fixed), ("MOVING_CENTRODE", moving)):
        ref = np.where(near[:, None], ref, np.nan)
        ref = ref[np.isfinite(ref).all(axis=1)]
        for pts in layers[name]:
            assert _deviation(pts, ref) < 0.01 + 2e-4
    # the joints of both bodies are marked
    circles = [(round(e.dxf.center.x, 6), round(e.dxf.center.y, 6), e.dxf.layer) for e in doc.modelspace().query("CIRCLE")]
    assert (160.0, 0.0, "FIXED_CENTRODE") in circles and (20.0, round(B0.imag, 6), "MOVING_CENTRODE") in circles


def test_csv_of_the_centrodes_reads_back(fourbar, tmp_path):
    sol = compile_plan(fourbar).sweep(90, order=1)
    c = linkage_centrodes(sol, fourbar, "coupler", relative_to="crank")
    path = tmp_path / "c.csv"
    write_csv(c.table(), path)
    rows = path.read_text().splitlines()
    assert rows[0] == "input,P.x,P.y,p.x,p.y,valid" and len(rows) == 91
    k = 7
    vals = rows[k + 1].split(",")
    assert float(vals[1]) == pytest.approx(c.P[k, 0], rel=1e-9) and vals[5] == "1"
    # relative to the crank, the coupler's centre is the joint B itself (they share it)
    np.testing.assert_allclose(c.P[c.valid], np.tile([B0.real, B0.imag], (int(c.valid.sum()), 1)), atol=1e-8)


def test_bad_requests_are_refused_with_the_reason(fourbar, tmp_path):
    plan = compile_plan(fourbar)
    with pytest.raises(GeometryError, match="tolerance"):
        export_centrodes(plan, "coupler", None, tmp_path / "x.dxf", tolerance=0.0)
    with pytest.raises(GeometryError, match="no link 'nope'"):
        export_centrodes(plan, "nope", None, tmp_path / "x.dxf")


def test_the_centrodes_command_writes_the_dxf_read_back_by_ezdxf_and_gdal(fourbar, tmp_path, capsys):
    """``mechsketch centrodes SCENE --link coupler --dxf PATH``: the same curves as the API (the
    fitted arcs' total length equals what GDAL measures per layer), audited by ezdxf."""
    from ogr_readback import ogr_layers

    from mechsketch.core.cli import main

    scene = str(example_path("fourbar_coupler_centrodes"))
    path = tmp_path / "c.dxf"
    assert main(["centrodes", scene, "--link", "coupler", "--dxf", str(path), "--tolerance", "0.02"]) == 0
    out = capsys.readouterr().out
    assert "FIXED_CENTRODE" in out and "tolerance 0.02 mm" in out
    doc = ezdxf.readfile(path)
    assert not doc.audit().has_errors
    ref = export_centrodes(compile_plan(fourbar), "coupler", None, tmp_path / "api.dxf", tolerance=0.02)
    assert ref.max_deviation <= 0.02
    ogr = ogr_layers(path)
    marks = {layer: 2 * math.pi * 1.0 * len([e for e in doc.modelspace().query("CIRCLE") if e.dxf.layer == layer])
             for layer in ("FIXED_CENTRODE", "MOVING_CENTRODE")}
    for layer, fits in (("FIXED_CENTRODE", ref.fixed), ("MOVING_CENTRODE", ref.moving)):
        exact = sum(abs(a.sweep) * a.radius if a.center is not None else math.dist(a.start, a.end)
                    for f in fits for a in f.arcs)
        assert ogr[layer][1] - marks[layer] == pytest.approx(exact, rel=1e-6)


@pytest.mark.parametrize("link, rel, at", [("crank", None, (0.0, 0.0)),
                                           ("coupler", "crank", (B0.real, B0.imag)),
                                           ("coupler", "rocker", (C0.real, C0.imag))])
def test_a_point_like_centrode_is_named_as_a_point(tmp_path, capsys, link, rel, at):
    """A link turning about a pivot it shares with the reference body: "the centrode is a point
    at (x, y)", not a failed fit (it was "more than 20000 biarcs"); nothing is written. The CSV is
    written with the same note."""
    from mechsketch.core.cli import main

    scene = str(example_path("fourbar_coupler_centrodes"))
    extra = ["--relative-to", rel] if rel else []
    assert main(["centrodes", scene, "--link", link, *extra, "--dxf", str(tmp_path / "p.dxf")]) == 1
    err = capsys.readouterr().err
    m = re.search(r"the centrode is a point at \((\S+), (\S+)\) mm", err)
    assert m and "biarc" not in err and not (tmp_path / "p.dxf").exists()
    assert (float(m[1]), float(m[2])) == pytest.approx(at, abs=1e-6)
    assert main(["centrodes", scene, "--link", link, *extra, "--csv", str(tmp_path / "p.csv")]) == 0
    assert "the centrode is a point at" in capsys.readouterr().err and (tmp_path / "p.csv").exists()


def test_the_centrodes_command_refuses_what_does_not_fit(tmp_path, capsys):
    from mechsketch.core.cli import main

    scene = str(example_path("fourbar_coupler_centrodes"))
    with pytest.raises(SystemExit) as e:   # one output, not both, not none
        main(["centrodes", scene, "--link", "coupler", "--csv", "-", "--dxf", str(tmp_path / "x.dxf")])
    assert e.value.code == 2
    with pytest.raises(SystemExit):
        main(["centrodes", scene, "--link", "coupler"])
    assert main(["centrodes", scene, "--link", "coupler", "--csv", "-", "--tolerance", "0.1"]) == 1
    assert "--tolerance applies to --dxf only" in capsys.readouterr().err
    assert main(["centrodes", scene, "--link", "coupler", "--dxf", str(tmp_path / "x.dxf"), "--tolerance", "0"]) == 1
    assert "tolerance" in capsys.readouterr().err and not (tmp_path / "x.dxf").exists()
