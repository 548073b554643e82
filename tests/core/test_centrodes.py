"""Centrodes of linkage links: the four-bar's known instant centres (Aronhold–Kennedy), both frames,
the rolling of the moving centrode on the fixed one, translations flagged, bad requests."""
from __future__ import annotations

import math

import numpy as np
import pytest

from mechsketch.core import load_scene
from mechsketch.core.analyses.centrodes import linkage_centrodes
from mechsketch.core.cli import main
from mechsketch.core.errors import GeometryError
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


@pytest.fixture(scope="module")
def fourbar():
    lk = load_scene(example_path("fourbar_coupler_centrodes")).element("fourbar")
    return lk, compile_plan(lk).sweep(samples=720, order=1)


def _line_distance(p, a, b):
    d = (b - a) / np.linalg.norm(b - a, axis=1)[:, None]
    r = p - a
    return np.abs(d[:, 0] * r[:, 1] - d[:, 1] * r[:, 0])


def _meet(a, b, c, d):
    """Intersection of lines ab and cd, (N, 2)."""
    u, v, w = b - a, d - c, c - a
    den = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    t = (w[:, 0] * v[:, 1] - w[:, 1] * v[:, 0]) / den
    return a + t[:, None] * u


def test_coupler_instant_centre_is_where_crank_and_rocker_lines_meet(fourbar):
    lk, sol = fourbar
    c = linkage_centrodes(sol, lk, "coupler")
    A, B, C, D = (sol.position(j) for j in "ABCD")
    ok = c.valid
    assert ok.sum() > 700
    expect = _meet(A, B, D, C)
    scale = 1.0 + np.linalg.norm(expect, axis=1)
    assert np.all(np.linalg.norm(c.P - expect, axis=1)[ok] <= 1e-9 * scale[ok] ** 2 / 100)
    assert np.all(_line_distance(c.P, A, B)[ok] <= 1e-9 * scale[ok])
    assert np.all(_line_distance(c.P, D, C)[ok] <= 1e-9 * scale[ok])
    # the moving centrode is the same point carried in the coupler's frame
    back = np.array([sol.point("coupler", tuple(p))[k] for k, p in enumerate(c.p) if ok[k]][:50])
    assert np.abs(back - c.P[ok][:50]).max() < 1e-9 * scale[ok][:50].max()
    # in the drawn pose the coupler frame is the ground frame
    assert np.allclose(c.p[0], c.P[0], rtol=1e-12, atol=1e-9)


def test_crank_and_coupler_relative_to_rocker(fourbar):
    lk, sol = fourbar
    crank = linkage_centrodes(sol, lk, "crank")
    assert np.allclose(crank.P, 0.0, atol=1e-9) and np.allclose(crank.p, 0.0, atol=1e-9)  # pivot A
    rel = linkage_centrodes(sol, lk, "coupler", relative_to="rocker")
    C0 = np.array(lk.joint("C").at)
    ok = rel.valid
    assert np.abs(rel.P - C0)[ok].max() < 1e-9 and np.abs(rel.p - C0)[ok].max() < 1e-9  # joint C in both frames
    # ω_coupler = ω_rocker exactly when the crank lies along the frame line (inputs 0 and π are sampled):
    # the relative motion is at rest there, its centre undefined, and those samples alone are flagged
    flagged = np.flatnonzero(~ok)
    assert np.allclose(np.sin(sol.input[flagged]), 0.0, atol=1e-12) and len(flagged) == 2
    # the rocker relative to the crank: I24 on line A–D and on line B–C, expressed in the crank frame
    r24 = linkage_centrodes(sol, lk, "rocker", relative_to="crank")
    A, B, C, D = (sol.position(j) for j in "ABCD")
    ground = _meet(A, D, B, C)
    rho = sol.input - sol.input[0]
    c_, s_ = np.cos(rho), np.sin(rho)
    in_crank = np.stack([c_ * ground[:, 0] + s_ * ground[:, 1], -s_ * ground[:, 0] + c_ * ground[:, 1]], -1)
    ok = r24.valid & (np.linalg.norm(ground, axis=1) < 1e4)
    assert ok.sum() > 600
    assert np.abs(r24.P - in_crank)[ok].max() < 1e-7


def test_the_moving_centrode_rolls_on_the_fixed_one(fourbar):
    """Equal arc lengths of both centrodes between the same samples (the defining property)."""
    lk, sol = fourbar
    c = linkage_centrodes(sol, lk, "coupler")
    far = np.linalg.norm(c.P, axis=1) > 2000
    # the longest run of samples with a bounded centre
    runs = np.split(np.arange(len(far)), np.flatnonzero(np.diff(far.astype(int))) + 1)
    run = max((r for r in runs if not far[r[0]]), key=len)
    P, p = c.P[run], c.p[run]
    lf = np.hypot(*np.diff(P, axis=0).T).sum()
    lm = np.hypot(*np.diff(p, axis=0).T).sum()
    assert lf > 100
    assert lm == pytest.approx(lf, rel=2e-4)  # chords of both polygons, 720 samples per turn


def test_pure_translation_is_flagged_not_an_error():
    lk = load_scene(example_path("slider_crank_offset")).elements[0]
    sol = compile_plan(lk).sweep(samples=36, order=1)
    c = linkage_centrodes(sol, lk, "slider")
    assert not c.valid.any() and c.translation.all()
    assert np.isnan(c.P).all() and np.isnan(c.p).all()
    table = c.table()
    assert table.columns == ["input", "P.x", "P.y", "p.x", "p.y", "valid"]
    assert "\n" + repr(float(sol.input[1])) + ",,,,,0\n" in table.to_csv()
    # the rod is not translating; relative to the slider it turns about C
    rod = linkage_centrodes(sol, lk, "rod", relative_to="slider")
    assert np.abs(rod.P - np.array(lk.joint("C").at))[rod.valid].max() < 1e-9
    # the rod stops turning where the crank is perpendicular to the guide (90°, 270° are sampled)
    assert np.allclose(np.cos(sol.input[~rod.valid]), 0.0, atol=1e-12) and (~rod.valid).sum() == 2


class _Fake:
    """A tiny solution: a link spinning about (5, 0) whose ω passes through zero at one sample."""

    def __init__(self):
        self.input = np.linspace(-1.0, 1.0, 5)
        self.omega_ = self.input ** 3  # 0 at the middle sample
        self.angle_ = self.input ** 4 / 4
        self.valid = np.array([True, True, True, True, False])

    def point(self, link, xy):
        x = np.array(xy, float) - (5.0, 0.0)
        c, s = np.cos(self.angle_), np.sin(self.angle_)
        return np.stack([5 + c * x[0] - s * x[1], s * x[0] + c * x[1]], -1)

    def point_velocity(self, link, xy):
        r = self.point(link, xy) - (5.0, 0.0)
        return self.omega_[:, None] * np.stack([-r[:, 1], r[:, 0]], -1)

    def omega(self, link):
        return self.omega_


class _Link:
    def __init__(self, joints):
        self.joints = joints


class _Joint:
    def __init__(self, at):
        self.at = at


class _Linkage:
    id = "fake"
    ground = "ground"
    link_ids = ("ground", "arm")

    class driver:
        link = "arm"

    def link(self, lid):
        return _Link(("J",))

    def joint(self, jid):
        return _Joint((8.0, 1.0))


def test_translation_instant_and_invalid_samples_on_a_minimal_solution():
    c = linkage_centrodes(_Fake(), _Linkage(), "arm")
    assert c.valid.tolist() == [True, True, False, True, False]
    assert c.translation.tolist() == [False, False, True, False, False]
    assert np.allclose(c.P[c.valid], (5.0, 0.0)) and np.allclose(c.p[c.valid], (5.0, 0.0))


@pytest.mark.parametrize("link,rel,fragment", [
    ("ground", None, "is the ground"),
    ("nope", None, "has no link 'nope'"),
    ("coupler", "coupler", "relative to itself"),
    ("coupler", "nope", "has no link 'nope'"),
])
def test_bad_requests(fourbar, link, rel, fragment):
    lk, sol = fourbar
    with pytest.raises(GeometryError, match=fragment):
        linkage_centrodes(sol, lk, link, rel)


def test_cli_centrodes(tmp_path, capsys):
    out = tmp_path / "c.csv"
    path = str(example_path("fourbar_coupler_centrodes"))
    assert main(["centrodes", path, "--link", "coupler", "--samples", "12", "--csv", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert lines[0] == "input,P.x,P.y,p.x,p.y,valid" and len(lines) == 13
    first = [float(v) for v in lines[1].split(",")]
    assert first[0] == pytest.approx(math.pi / 3)
    # drawn pose: crank at 60°, the crank line y = √3 x meets the rocker line D–C
    assert first[2] == pytest.approx(math.sqrt(3) * first[1], rel=1e-12)
    assert main(["centrodes", path, "--link", "ground", "--csv", "-"]) == 1
    assert "is the ground" in capsys.readouterr().err
