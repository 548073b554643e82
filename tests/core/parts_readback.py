"""Reading exported parts back, independently of the writers: DXF through ezdxf (audited; closed
LWPOLYLINEs with bulges decoded by ezdxf's ``bulge_to_arc``, CIRCLEs, and LINE/ARC chains joined
end to end) and SVG through a small parser of the path commands the writer may use (M, L, A, Z,
arcs converted to centres with the SVG specification's formulas). Each part layer (or ``<g
id="part-NAME">``) becomes a shapely polygon: the largest ring is the outline, the others holes.
"""
from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import ezdxf
import numpy as np
import shapely
from ezdxf.math import bulge_to_arc

FLAT = 1e-4  # mm, sagitta of the chords used to rebuild polygons from the files
JOIN = 1e-6  # mm, LINE/ARC ends closer than this are joined
NOTES = "NOTES_"  # layers (DXF) and group ids (SVG, "notes-") that are not cut


def _arc_points(c, r, a0, sweep) -> np.ndarray:
    """Points after the start of an arc (centre c, radius r, start angle a0, signed sweep), end included."""
    n = max(2, math.ceil(abs(sweep) / (2 * math.acos(max(-1.0, 1 - FLAT / r)))))
    ang = a0 + sweep * np.arange(1, n + 1) / n
    return np.c_[c[0] + r * np.cos(ang), c[1] + r * np.sin(ang)]


def _lwpolyline_ring(e) -> np.ndarray:
    v = e.get_points("xyb")
    out = []
    for k, (x, y, b) in enumerate(v):
        x1, y1, _ = v[(k + 1) % len(v)]
        out.append((x, y))
        if b == 0:
            continue
        c, a0, a1, r = bulge_to_arc((x, y), (x1, y1), b)
        sweep = (a1 - a0) % (2 * math.pi)
        pts = _arc_points((c.x, c.y), r, a0, sweep)[:-1]
        out.extend(map(tuple, pts if b > 0 else pts[::-1]))
    return np.array(out)


def _circle_ring(e) -> np.ndarray:
    c, r = e.dxf.center, e.dxf.radius
    return _arc_points((c.x, c.y), r, 0.0, 2 * math.pi)[:-1]


def _chains(pieces: list[np.ndarray]) -> list[np.ndarray]:
    """Join open polylines (each (M, 2), ordered) end to end into closed rings."""
    rings, todo = [], list(pieces)
    while todo:
        ring = [todo.pop(0)]
        while True:
            end = ring[-1][-1]
            if np.hypot(*(end - ring[0][0])) <= JOIN and len(ring) > 0 and sum(len(p) for p in ring) > 2:
                break
            for k, p in enumerate(todo):
                if np.hypot(*(p[0] - end)) <= JOIN:
                    ring.append(todo.pop(k))
                    break
                if np.hypot(*(p[-1] - end)) <= JOIN:
                    ring.append(todo.pop(k)[::-1])
                    break
            else:
                raise AssertionError(f"an open chain of LINE/ARC entities ends at {end}")
        rings.append(np.vstack([p[:-1] for p in ring]))
    return rings


def read_dxf(path) -> tuple[ezdxf.document.Drawing, dict[str, list[np.ndarray]]]:
    """The audited document and, per layer, its closed rings (inscribed, sagitta ≤ FLAT)."""
    doc = ezdxf.readfile(path)
    auditor = doc.audit()
    assert not auditor.has_errors, [str(e) for e in auditor.errors]
    rings: dict[str, list[np.ndarray]] = {}
    pieces: dict[str, list[np.ndarray]] = {}
    for e in doc.modelspace():
        layer = e.dxf.layer
        kind = e.dxftype()
        if kind == "LWPOLYLINE" and e.closed:
            rings.setdefault(layer, []).append(_lwpolyline_ring(e))
        elif kind == "CIRCLE":
            rings.setdefault(layer, []).append(_circle_ring(e))
        elif kind == "LINE":
            pieces.setdefault(layer, []).append(np.array([(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)], float))
        elif kind == "ARC":
            c, r = e.dxf.center, e.dxf.radius
            a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
            sweep = (a1 - a0) % (2 * math.pi) or 2 * math.pi
            start = np.array([[c.x + r * math.cos(a0), c.y + r * math.sin(a0)]])
            pieces.setdefault(layer, []).append(np.vstack([start, _arc_points((c.x, c.y), r, a0, sweep)]))
    for layer, ps in pieces.items():
        if not layer.startswith(NOTES):
            rings.setdefault(layer, []).extend(_chains(ps))
    return doc, rings


def polygon_of(rings: list[np.ndarray]) -> shapely.Geometry:
    """The largest ring as the outline, the others as holes; rings that do not lie inside each
    other (a drilling pattern) give a MultiPolygon of them."""
    rings = sorted(rings, key=lambda r: -abs(shapely.Polygon(r).area))
    outer = shapely.Polygon(rings[0])
    if all(outer.contains(shapely.Polygon(r)) for r in rings[1:]):
        return shapely.Polygon(rings[0], rings[1:])
    return shapely.MultiPolygon([shapely.Polygon(r) for r in rings])


def dxf_parts(path) -> tuple[ezdxf.document.Drawing, dict[str, shapely.Polygon]]:
    """Each part layer of a DXF as a polygon (the NOTES_ layers left out)."""
    doc, rings = read_dxf(path)
    return doc, {k: polygon_of(v) for k, v in rings.items() if not k.startswith(NOTES)}


_TOKEN = re.compile(r"[MLAZ]|-?[0-9.]+(?:e[-+]?[0-9]+)?", re.I)


def _svg_arc_centre(p0, p1, r, large, sweep):
    """SVG arc endpoint -> centre (specification F.6.5, rx = ry, no rotation)."""
    mid = (p0 - p1) / 2
    d2 = mid @ mid
    coef = math.sqrt(max(r * r / d2 - 1.0, 0.0))
    if large == sweep:
        coef = -coef
    cp = coef * np.array([mid[1], -mid[0]])
    c = cp + (p0 + p1) / 2
    a0 = math.atan2(p0[1] - c[1], p0[0] - c[0])
    a1 = math.atan2(p1[1] - c[1], p1[0] - c[0])
    dth = a1 - a0
    if sweep and dth < 0:
        dth += 2 * math.pi
    elif not sweep and dth > 0:
        dth -= 2 * math.pi
    return c, a0, dth


def svg_rings(d: str) -> list[np.ndarray]:
    """Closed rings of an SVG path (M/L/A/Z only)."""
    toks = _TOKEN.findall(d)
    rings, cur, k = [], [], 0
    while k < len(toks):
        t = toks[k]
        if t == "M":
            cur = [np.array([float(toks[k + 1]), float(toks[k + 2])])]
            k += 3
        elif t == "L":
            cur.append(np.array([float(toks[k + 1]), float(toks[k + 2])]))
            k += 3
        elif t == "A":
            r = float(toks[k + 1])
            large, sweep = int(toks[k + 4]), int(toks[k + 5])
            p1 = np.array([float(toks[k + 6]), float(toks[k + 7])])
            c, a0, dth = _svg_arc_centre(cur[-1], p1, r, large, sweep)
            cur.extend(_arc_points(c, r, a0, dth))
            k += 8
        elif t.upper() == "Z":
            rings.append(np.array(cur[:-1] if np.hypot(*(cur[-1] - cur[0])) < JOIN else cur))
            k += 1
        else:
            raise AssertionError(f"unexpected SVG path token {t!r}")
    return rings


def svg_parts(path) -> tuple[ET.Element, dict[str, shapely.Polygon]]:
    """Each ``<g id="part-NAME">`` of an SVG as a polygon (y as written, i.e. flipped)."""
    root = ET.parse(path).getroot()
    ns = {"s": "http://www.w3.org/2000/svg"}
    out = {}
    for g in root.findall("s:g", ns):
        gid = g.get("id", "")
        if gid.startswith("part-"):
            rings = [r for p in g.findall("s:path", ns) for r in svg_rings(p.get("d"))]
            out[gid[5:]] = polygon_of(rings)
    return root, out


def _svg_ring_measures(d: str) -> list[tuple[float, float]]:
    """Exact (length, signed area) of each closed ring of an SVG path, the arcs' centres found
    from their end points by the specification's formulas (y as written)."""
    toks = _TOKEN.findall(d)
    out, k, cur, length, area, start = [], 0, None, 0.0, 0.0, None
    while k < len(toks):
        t = toks[k]
        if t == "M":
            cur = start = np.array([float(toks[k + 1]), float(toks[k + 2])])
            length = area = 0.0
            k += 3
        elif t == "L":
            p1 = np.array([float(toks[k + 1]), float(toks[k + 2])])
            length += float(np.hypot(*(p1 - cur)))
            area += 0.5 * (cur[0] * p1[1] - p1[0] * cur[1])
            cur = p1
            k += 3
        elif t == "A":
            r = float(toks[k + 1])
            large, sweep = int(toks[k + 4]), int(toks[k + 5])
            p1 = np.array([float(toks[k + 6]), float(toks[k + 7])])
            _, _, dth = _svg_arc_centre(cur, p1, r, large, sweep)
            length += abs(dth) * r
            area += 0.5 * (cur[0] * p1[1] - p1[0] * cur[1]) + 0.5 * r * r * (dth - math.sin(dth))
            cur = p1
            k += 8
        elif t.upper() == "Z":
            length += float(np.hypot(*(start - cur)))
            area += 0.5 * (cur[0] * start[1] - start[0] * cur[1])
            out.append((length, area))
            k += 1
        else:
            raise AssertionError(f"unexpected SVG path token {t!r}")
    return out


def svg_measures(path) -> dict[str, tuple[float, float]]:
    """Per ``<g id="part-NAME">``: the exact length of its rings and the area they enclose
    (the largest ring less the others; a drilling pattern: the sum)."""
    root = ET.parse(path).getroot()
    ns = {"s": "http://www.w3.org/2000/svg"}
    out = {}
    for g in root.findall("s:g", ns):
        gid = g.get("id", "")
        if gid.startswith("part-"):
            rings = [m for p in g.findall("s:path", ns) for m in _svg_ring_measures(p.get("d"))]
            areas = sorted((abs(a) for _, a in rings), reverse=True)
            polys = [shapely.Polygon(r) for p in g.findall("s:path", ns) for r in svg_rings(p.get("d"))]
            biggest = max(polys, key=lambda q: q.area)
            nested = all(biggest.contains(q.representative_point()) for q in polys if q is not biggest)
            enclosed = areas[0] - sum(areas[1:]) if nested and len(polys) > 1 else sum(areas)
            if len(polys) == 1:
                enclosed = areas[0]
            out[gid[5:]] = (sum(length for length, _ in rings), enclosed)
    return out


def svg_max_sweep(path) -> float:
    """The widest arc (rad) of any path of an SVG, its centre found from its end points."""
    root = ET.parse(path).getroot()
    widest = 0.0
    for p in root.iter("{http://www.w3.org/2000/svg}path"):
        toks = _TOKEN.findall(p.get("d"))
        cur, k = None, 0
        while k < len(toks):
            t = toks[k]
            if t in ("M", "L"):
                cur = np.array([float(toks[k + 1]), float(toks[k + 2])])
                k += 3
            elif t == "A":
                p1 = np.array([float(toks[k + 6]), float(toks[k + 7])])
                _, _, dth = _svg_arc_centre(cur, p1, float(toks[k + 1]), int(toks[k + 4]), int(toks[k + 5]))
                widest, cur = max(widest, abs(dth)), p1
                k += 8
            else:
                k += 1
    return widest
