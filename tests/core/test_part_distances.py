"""The part checks' distances are exact and scale with the part (issue 20, item 7): the distance
between two contours of lines and arcs against closed forms and against shapely on polygons a
thousand times finer than any check uses; a plate with hundreds of bores measured through the
spatial index (the pairs evaluated grow like n, not n²; no timing); a congruent part takes the
check of the first one, equal to checking it afresh."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mechsketch.core.analyses.contour import Contour
from mechsketch.core.analyses.parts import Part, check_part, check_parts, circle, disc_hull, rectangle, stadium
from mechsketch.core.analyses.parts import distance as dist_mod
from mechsketch.core.analyses.parts.distance import nearest_between_contours
from mechsketch.core.analyses.parts.outline import is_convex, reversed_contour

FINE = 1e-6  # mm, sagitta of the reference polygons


def reference(a: Contour, b: Contour) -> float:
    return float(shapely.distance(shapely.LinearRing(a.polyline(FINE)), shapely.LinearRing(b.polyline(FINE))))


def sector(r0, r1, a0, a1) -> Contour:
    """An annular sector about the origin: radii r0 < r1, angles a0 < a1 (rad), CCW."""
    e = lambda r, a: (r * math.cos(a), r * math.sin(a))  # noqa: E731
    q = math.tan((a1 - a0) / 4)
    return Contour(np.array([e(r1, a0), e(r1, a1), e(r0, a1), e(r0, a0)]), np.array([q, 0.0, -q, 0.0]))


def arc_piece(c, r, a0, a1) -> Contour:
    """A closed contour: the arc of radius r about c from a0 to a1 (CCW) closed by its chord."""
    p = np.array([[c[0] + r * math.cos(a0), c[1] + r * math.sin(a0)], [c[0] + r * math.cos(a1), c[1] + r * math.sin(a1)]])
    return Contour(p, np.array([math.tan((a1 - a0) / 4), 0.0]))


@pytest.mark.parametrize("a, b, expected", [
    (circle((0, 0), 3), circle((10, 0), 2), 5.0),                      # apart
    (circle((0, 0), 10), circle((2, 1), 3), 10 - 3 - math.hypot(2, 1)),  # nested
    (circle((0, 0), 3), circle((4, 0), 2), 0.0),                       # crossing
    (circle((0, 0), 2), rectangle((10, 0), 4, 4, 0.0), 6.0),           # circle to a side
    (circle((0, 0), 2), rectangle((10, 10), 4, 4, 0.0), math.hypot(8, 8) - 2),  # to a corner
    (stadium((0, 0), (50, 0), 5), circle((25, 0), 3), 2.0),            # a bore in a bar
    (sector(9, 10, 0.2, 1.0), sector(14, 15, 0.5, 1.4), 4.0),   # concentric arcs facing each other
    (sector(9, 10, 0.2, 0.4), sector(14, 15, 0.9, 1.4),          # concentric, no overlap: corner to corner
     math.dist((10 * math.cos(0.4), 10 * math.sin(0.4)), (14 * math.cos(0.9), 14 * math.sin(0.9)))),
])
def test_distances_against_closed_forms(a, b, expected):
    d, at, pair = nearest_between_contours([a, b])
    assert d == pytest.approx(expected, abs=1e-12 * 50)
    assert sorted(pair) == [0, 1]
    assert reference(a, b) == pytest.approx(expected, abs=2 * FINE)


def contour(kind: int, c, size: float, s2: float, ang: float) -> Contour:
    if kind == 0:
        return circle(c, size)
    if kind == 1:
        return stadium(c, (c[0] + 3 * size * math.cos(ang), c[1] + 3 * size * math.sin(ang)), s2)
    if kind == 2:
        return rectangle(c, 2 * size, s2 + 0.5, ang)
    if kind == 3:
        pts = np.array([c, (c[0] + 2 * size, c[1] + s2), (c[0] - s2, c[1] + 2 * size)])
        return disc_hull(pts, np.array([size / 3, 0.0, s2 / 2]))
    return reversed_contour(arc_piece(c, size + 1, ang, ang + 1.0 + s2))


coords = st.floats(-30, 30, allow_nan=False)
shapes = st.tuples(st.integers(0, 4), st.tuples(coords, coords), st.floats(0.5, 8), st.floats(0.3, 4),
                   st.floats(0, 2 * math.pi))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(a=shapes, b=shapes, c=shapes)
def test_distances_against_fine_polygons(a, b, c):
    """Lines and arcs, apart, touching, crossing, nested, either way round: the least distance
    between any two of three contours equals shapely's on polygons of sagitta 1e-6 mm (whose own
    error is below 2e-6 mm: they are inscribed)."""
    cs = [contour(*a), contour(*b), contour(*c)]
    d, at, pair = nearest_between_contours(cs, guess=0.1)
    ref = min(reference(cs[i], cs[j]) for i in range(3) for j in range(i + 1, 3))
    assert d == pytest.approx(ref, abs=2.5 * FINE)
    i, j = pair
    assert reference(cs[i], cs[j]) == pytest.approx(d, abs=2.5 * FINE)
    if d > 1e-9:   # the midpoint of the nearest points lies halfway between the two contours
        p = shapely.Point(at)
        for k in (i, j):
            assert float(shapely.distance(p, shapely.LinearRing(cs[k].polyline(FINE)))) == pytest.approx(d / 2, abs=3 * FINE)


def grid_plate(n_side: int, pitch: float = 20.0, bore: float = 3.0, boss: float = 8.0) -> Part:
    """A frame plate: the rounded hull of n_side² bosses on a square grid, a bore on each."""
    xy = np.array([(i * pitch, j * pitch) for i in range(n_side) for j in range(n_side)], float)
    outer = disc_hull(xy, np.full(len(xy), boss))
    return Part("frame", outer, tuple(circle(p, bore) for p in xy))


def test_a_plate_with_hundreds_of_bores_is_measured_through_the_index(monkeypatch):
    """400 bores: the web (bore to bore, pitch − 2·bore = 14 mm; bore to edge, boss − bore = 5 mm)
    is exact, and the contour pairs measured grow like the bores, not their square."""
    counted = []
    real = dist_mod._least

    def counting(pc, discs, i, j, reach):
        counted.append(len(i))
        return real(pc, discs, i, j, reach)

    monkeypatch.setattr(dist_mod, "_least", counting)
    sizes = {}
    for n_side in (10, 20):
        counted.clear()
        plate = grid_plate(n_side)
        chk = check_part(plate, min_web=1.0)
        assert chk.ok and chk.web == pytest.approx(5.0, abs=1e-12)
        assert chk.area == pytest.approx(plate.outer.area() - n_side ** 2 * math.pi * 9.0, rel=1e-13)
        sizes[n_side] = sum(counted)
    # 4x the bores: at most ~4x the pairs (all pairs would be 16x)
    assert sizes[20] <= 5 * sizes[10], sizes
    assert sizes[20] < 0.01 * (2 * 400 + 4) ** 2 / 2


def test_a_bore_too_close_to_its_neighbour_is_found_among_hundreds():
    plate = grid_plate(15)
    holes = list(plate.holes)
    c = np.asarray(holes[117].points).mean(axis=0)
    holes[117] = circle((c[0] + 13.5, c[1]), 3.0)      # 0.5 mm from the next bore
    chk = check_part(Part("frame", plate.outer, tuple(holes)), min_web=1.0)
    assert not chk.ok
    assert chk.web == pytest.approx(0.5, abs=1e-12)
    assert "thinnest web 0.5 mm" in chk.problems[0] and f"({c[0] + 13.5 + 3.25:.3f}, {c[1]:.3f})" in chk.problems[0]


def test_congruent_parts_take_the_first_ones_check_moved_with_them():
    rng = np.random.default_rng(4)
    base = Part("link", disc_hull(np.array([[0, 0], [40, 0], [15, 25]], float), np.array([6.0, 6.0, 5.0])),
                (circle((0, 0), 2.0), circle((40, 0), 2.5), circle((15, 25), 1.0)))
    parts = [base] + [base.moved(rng.uniform(-3, 3), rng.uniform(-500, 500, 2)) for _ in range(6)]
    parts = [Part(f"p{k}", p.outer, p.holes) for k, p in enumerate(parts)]
    together = check_parts(parts, 1.0)
    alone = [check_part(p, 1.0) for p in parts]
    for t, a, part in zip(together, alone, parts):
        assert t.name == a.name and t.ok and a.ok
        assert t.web == pytest.approx(a.web, abs=1e-9) and t.area == pytest.approx(a.area, rel=1e-12)
        # the place, moved with the part, is halfway across a web of that width in this part
        # (the 3.5 mm ligament runs all along the boss arc: any place on it is right)
        rings = [shapely.LinearRing(c.polyline(FINE)) for c in part.contours]
        gaps = sorted(float(shapely.distance(shapely.Point(t.web_at), r)) for r in rings)
        assert gaps[0] == pytest.approx(t.web / 2, abs=3 * FINE) and gaps[1] == pytest.approx(t.web / 2, abs=3 * FINE)
    # a mirror image is not congruent by a rigid motion: checked on its own, same web
    mirror = Part("m", reversed_contour(base.outer.moved(0.0)), base.holes)
    assert check_parts([base, mirror], 1.0)[1].web == pytest.approx(check_part(base).web, abs=1e-9)


def test_convexity_of_the_plate_shapes():
    rng = np.random.default_rng(5)
    for _ in range(50):
        c = disc_hull(rng.uniform(-50, 50, (4, 2)), rng.uniform(0, 10, 4))
        assert is_convex(c) and is_convex(reversed_contour(c))
    assert is_convex(stadium((0, 0), (10, 3), 2)) and is_convex(rectangle((0, 0), 3, 2, 0.3))
    assert is_convex(circle((1, 1), 2))
    # a figure of eight is not convex, nor an L
    l_shape = Contour(np.array([[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]], float), np.zeros(6))
    eight = Contour(np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float), np.zeros(4))
    assert not is_convex(l_shape) and not is_convex(eight)
    assert check_part(Part("eight", eight)).problems == ("the outline intersects itself",)


def test_a_convex_outline_without_corners_is_at_least_twice_its_smallest_radius_thick():
    """Why the checks skip the necks of stadiums and hulls of bosses when 2R is not below the web:
    the rays cast along every normal never find a chord shorter than 2R (R: the least arc radius)."""
    from mechsketch.core.analyses.parts.thickness import necks
    from mechsketch.core.analyses.parts.outline import rolling_radius

    rng = np.random.default_rng(9)
    for _ in range(25):
        k = int(rng.integers(2, 6))
        c = disc_hull(rng.uniform(-40, 40, (k, 2)), rng.uniform(1, 12, k))
        radius = rolling_radius(c)
        assert radius > 0
        d, _ = necks(c, samples=400)
        assert d >= 2 * radius - 1e-9
    assert rolling_radius(stadium((0, 0), (30, 5), 4.0)) == pytest.approx(4.0, rel=1e-15)
    assert rolling_radius(rectangle((0, 0), 10, 4, 0.0)) == 0.0          # corners: no bound
    assert necks(rectangle((0, 0), 10, 4, 0.0))[0] == pytest.approx(4.0, abs=1e-12)
