"""DXF export and CLI of the rolling lever: the file read back and audited, units and layers, the
exported plates' working edges measured against an independent exact curve (both directions),
bad requests."""
from __future__ import annotations

import csv
import io
import json
import math

import ezdxf
import numpy as np
import pytest
from scipy.spatial import cKDTree

import test_rolling_reference as ref
from mechsketch.core.analyses.biarc import Arc, arc_distance, biarc, fit_biarcs
from mechsketch.core.analyses.rolling.synthesis import COLUMNS, synthesize
from mechsketch.core.cli import main
from mechsketch.core.analyses.parts.rolling import RollingStyle, rolling_parts
from mechsketch.core.io.export_parts import export_parts


@pytest.fixture(scope="module")
def press_file(tmp_path_factory):
    p = tmp_path_factory.mktemp("rolling") / "press.json"
    p.write_text(json.dumps(ref.scene_of(ref.PRESS)))
    return p


def _exact_curves(n=20001):
    """Frame profile P and slider profile Q (ground / slider frame) densely, from DOP853."""
    th = np.linspace(0.0, -0.5926, n)
    a, s5 = ref.scipy_reference(ref.PRESS, th)
    geo = ref.Geo(ref.PRESS)
    _, P, _, _, P0, _ = geo.contact(a, th)
    return P, P0 - s5[:, None] * geo.ds


def _polyline_distance(x, poly):
    """Distance of points x (M, 2) from the polyline (K, 2) (nearest vertex, then its two segments)."""
    _, j = cKDTree(poly).query(x)
    best = np.full(len(x), np.inf)
    for k0 in (j - 1, j):
        k0 = np.clip(k0, 0, len(poly) - 2)
        a, b = poly[k0], poly[k0 + 1]
        ab = b - a
        s = np.clip(np.einsum("ij,ij->i", x - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
        best = np.minimum(best, np.linalg.norm(x - a - s[:, None] * ab, axis=1))
    return best


def _arcs_of(entity):
    out = []
    for v in entity.virtual_entities():
        if v.dxftype() == "ARC":
            c, r = np.array(v.dxf.center)[:2], v.dxf.radius
            a0, a1 = math.radians(v.dxf.start_angle), math.radians(v.dxf.end_angle)
            sweep = (a1 - a0) % (2 * math.pi)
            ang = a0 + np.linspace(0, sweep, 200)
            out.append(("arc", c + r * np.stack([np.cos(ang), np.sin(ang)], -1), (c, r, a0, sweep)))
        else:
            s, e = np.array(v.dxf.start)[:2], np.array(v.dxf.end)[:2]
            out.append(("line", s + np.linspace(0, 1, 200)[:, None] * (e - s), (s, e)))
    return out


def test_export_reads_back_audited_in_millimetres(press_file, tmp_path, capsys):
    out = tmp_path / "press.dxf"
    assert main(["export", str(press_file), "--dxf", str(out), "--layout", "assembled", "--arcs", "entities"]) == 0
    report = capsys.readouterr().out
    doc = ezdxf.readfile(out)
    auditor = doc.audit()
    assert not auditor.has_errors
    assert doc.header["$INSUNITS"] == 4  # millimetres
    assert {"frame", "frame_pivots", "lever", "slider"} <= {layer.dxf.name for layer in doc.layers}
    msp = doc.modelspace()
    kinds = {}
    for e in msp:
        kinds.setdefault(e.dxf.layer, []).append(e.dxftype())
    assert sorted(kinds["frame_pivots"]) == ["CIRCLE", "CIRCLE"]  # pivots G and A
    assert kinds["lever"].count("CIRCLE") == 2  # pin f, coupler pin C
    arcs = {round(e.dxf.radius, 6): e for e in msp.query('ARC[layer=="lever"]')}
    lever = arcs[50.0]
    assert tuple(lever.dxf.center)[:2] == pytest.approx((0.0, 0.0), abs=1e-12)

    def deg(a):
        return (a + 180.0) % 360.0 - 180.0

    assert deg(lever.dxf.start_angle) == pytest.approx(-143.7646, abs=1e-3)
    assert deg(lever.dxf.end_angle) == pytest.approx(-93.8533, abs=1e-3)
    assert tuple(arcs[80.0].dxf.center)[:2] == pytest.approx((20.0, 0.0), abs=1e-12)
    assert "max deviation" in report and "frame profile" in report


@pytest.mark.parametrize("tol", [1e-3, 1e-5])
def test_exported_profiles_are_within_the_tolerance_of_the_exact_curves(tmp_path, tol):
    res = synthesize(ref.element(), measures=False)
    out = tmp_path / "p.dxf"
    ps = rolling_parts(res, RollingStyle(tolerance=tol))
    export_parts(ps, out, layout="assembled")
    dev = {p.name: p.deviation for p in ps.parts}
    assert dev["frame"] <= tol and dev["slider"] <= tol
    P, Q = _exact_curves()
    msp = ezdxf.readfile(out).modelspace()
    for layer, exact in (("frame", P), ("slider", Q)):
        poly = msp.query(f'LWPOLYLINE[layer=="{layer}"]')[0]
        assert poly.closed
        # the working edge: the pieces of the closed outline that lie on the profile (the plate's
        # three back edges lie a plate depth away)
        pieces = [p for p in _arcs_of(poly) if _polyline_distance(p[1], exact).max() < 0.1]
        assert len(pieces) == len(poly) - 3
        pts = np.concatenate([p for _, p, _ in pieces])
        d_arc = _polyline_distance(pts, exact).max()
        d_curve = np.full(len(exact), np.inf)
        for kind, _, g in pieces:
            if kind == "arc":
                c, r, a0, sweep = g
                a = Arc(tuple(c + r * np.array([math.cos(a0), math.sin(a0)])),
                        tuple(c + r * np.array([math.cos(a0 + sweep), math.sin(a0 + sweep)])), sweep, tuple(c))
            else:
                a = Arc(tuple(g[0]), tuple(g[1]), 0.0, None)
            d_curve = np.minimum(d_curve, arc_distance(exact, a))
        assert d_arc <= tol and d_curve.max() <= tol
        assert d_curve.max() == pytest.approx(dev[layer], rel=0.05)  # the reported value is the true one


def test_biarc_of_a_circle_is_exact():
    c, r = np.array([3.0, -2.0]), 7.0

    def circle(t):
        return c + r * np.stack([np.cos(t), np.sin(t)], -1)

    fit = fit_biarcs(circle, 0.2, 2.9, 1e-9)
    assert fit.spans == 4 and fit.max_deviation < 1e-12
    assert all(a.radius == pytest.approx(r, rel=1e-9) for a in fit.arcs)
    # a straight segment is a line
    line = biarc(np.zeros(2), np.array([1.0, 0.0]), np.array([2.0, 0.0]), np.array([1.0, 0.0]))
    assert all(a.center is None and a.bulge == 0.0 for a in line)


def test_corrected_method_export_reports_its_distance_from_the_exact_centrode(tmp_path):
    res = synthesize(ref.element(method="corrected", points=64), measures=False)
    text = export_parts(rolling_parts(res), tmp_path / "corrected.dxf").report
    assert "constructed profile" in text
    assert "construction itself deviates" in text


def test_cli_synthesize_table_and_summary(press_file, tmp_path, capsys):
    out = tmp_path / "press.csv"
    assert main(["synthesize", str(press_file), "--csv", str(out), "--summary"]) == 0
    summary = capsys.readouterr().out
    rows = list(csv.reader(io.StringIO(out.read_text())))
    assert tuple(rows[0]) == COLUMNS
    assert len(rows) == 202
    res = synthesize(ref.element(), measures=False)
    table = res.table()
    got = np.array([[float(v) for v in r] for r in rows[1:]])
    assert np.array_equal(got, table.data)
    assert got[-1, COLUMNS.index("S5")] == pytest.approx(50.4371, abs=1e-4)
    for text in ("crank 29.0783 mm", "coupler 149.494 mm", "S5 0 … 50.4371 mm", "time:", "worst:",
                 "dead centres", "working range"):
        assert text in summary
    # CSV on stdout, summary on stderr
    assert main(["synthesize", str(press_file), "--csv", "-", "--summary"]) == 0
    cap = capsys.readouterr()
    assert cap.out.splitlines()[0] == ",".join(COLUMNS) and "crank" in cap.err


@pytest.mark.parametrize("args,message", [
    (["--dxf", "/nonexistent-folder/x.dxf"], "cannot write /nonexistent-folder/x.dxf"),
    (["--dxf", "{tmp}/x.dxf", "--tolerance", "1e-9"], "below what is exported faithfully"),
    (["--dxf", "{tmp}/x.dxf", "--tolerance", "0"], "must be a positive number of millimetres"),
    (["--dxf", "{tmp}/x.dxf", "--tolerance", "nan"], "must be a positive number of millimetres"),
])
def test_bad_export_requests(press_file, tmp_path, capsys, args, message):
    args = [a.replace("{tmp}", str(tmp_path)) for a in args]
    assert main(["export", str(press_file), *args]) == 1
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.dxf").exists()


def test_stroke_beyond_the_range_via_the_cli(tmp_path, capsys):
    p = tmp_path / "far.json"
    p.write_text(json.dumps(ref.scene_of(ref.PRESS | {"stroke": {"from": 0.0, "to": -1.0}})))
    assert main(["synthesize", str(p)]) == 1
    err = capsys.readouterr().err
    assert "goes beyond the working range" in err and "Reachable range" in err
