"""A second, independent reader of the DXF files the exporter writes: the group-code/value pairs
of the ENTITIES section read line by line (no ezdxf), LINE, ARC, CIRCLE, LWPOLYLINE (with bulges)
and TEXT decoded from their group codes (DXF reference: 8 layer, 10/20 and 11/21 points, 40
radius, 50/51 start and end angles in degrees counter-clockwise, 42 bulge, 70 polyline flag 1 =
closed, 1 text). Each entity's exact length and, for closed contours, the area it encloses, from
the same formulas any reader uses (independent of the exporter's code)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class Entity:
    kind: str
    layer: str = ""
    codes: list[tuple[int, str]] = field(default_factory=list)

    def first(self, code: int) -> float:
        return float(next(v for c, v in self.codes if c == code))

    def all(self, code: int) -> list[float]:
        return [float(v) for c, v in self.codes if c == code]


def entities(path) -> list[Entity]:
    """The entities of the ENTITIES section, in file order."""
    lines = Path(path).read_text(encoding="utf-8", errors="strict").splitlines()
    pairs = [(int(lines[k].strip()), lines[k + 1].strip()) for k in range(0, len(lines) - 1, 2)]
    out, inside, cur = [], False, None
    for k, (code, value) in enumerate(pairs):
        if code == 2 and k > 0 and pairs[k - 1] == (0, "SECTION"):
            inside = value == "ENTITIES"
            continue
        if not inside:
            continue
        if code == 0:
            if cur is not None:
                out.append(cur)
            if value == "ENDSEC":
                inside, cur = False, None
                continue
            cur = Entity(value)
        elif cur is not None:
            if code == 8:
                cur.layer = value
            cur.codes.append((code, value))
    return out


def _bulge_arc(p, q, b) -> tuple[float, float]:
    """Length and the signed area between chord and arc of a bulge segment p -> q."""
    chord = math.dist(p, q)
    if b == 0:
        return chord, 0.0
    theta = 4 * math.atan(b)
    r = chord / (2 * abs(math.sin(theta / 2)))
    return abs(theta) * r, 0.5 * r * r * (theta - math.sin(theta))


def lwpolyline(e: Entity) -> tuple[list[tuple[float, float, float]], bool]:
    """Vertices (x, y, bulge) and the closed flag of an LWPOLYLINE."""
    xs, ys, verts, bul = [], [], [], {}
    for code, v in e.codes:
        if code == 10:
            xs.append(float(v))
        elif code == 20:
            ys.append(float(v))
        elif code == 42:
            bul[len(xs) - 1] = float(v)
    verts = [(x, y, bul.get(k, 0.0)) for k, (x, y) in enumerate(zip(xs, ys))]
    flags = int(e.first(70)) if any(c == 70 for c, _ in e.codes) else 0
    return verts, bool(flags & 1)


def measure(e: Entity) -> tuple[float, float]:
    """(length mm, enclosed area mm² — 0 for an open piece) of one entity."""
    if e.kind == "LINE":
        return math.dist((e.first(10), e.first(20)), (e.first(11), e.first(21))), 0.0
    if e.kind == "CIRCLE":
        r = e.first(40)
        return 2 * math.pi * r, math.pi * r * r
    if e.kind == "ARC":
        sweep = (e.first(51) - e.first(50)) % 360.0 or 360.0
        return math.radians(sweep) * e.first(40), 0.0
    if e.kind == "LWPOLYLINE":
        verts, closed = lwpolyline(e)
        n = len(verts) if closed else len(verts) - 1
        length = area = 0.0
        for k in range(n):
            (x0, y0, b), (x1, y1, _) = verts[k], verts[(k + 1) % len(verts)]
            seg, cap = _bulge_arc((x0, y0), (x1, y1), b)
            length += seg
            area += 0.5 * (x0 * y1 - x1 * y0) + cap
        return length, abs(area) if closed else 0.0
    raise ValueError(f"unexpected entity {e.kind}")


def arc_ends(e: Entity) -> tuple[tuple[float, float], tuple[float, float]]:
    """The start and end points of a LINE or ARC (an ARC runs counter-clockwise)."""
    if e.kind == "LINE":
        return (e.first(10), e.first(20)), (e.first(11), e.first(21))
    cx, cy, r = e.first(10), e.first(20), e.first(40)
    a0, a1 = math.radians(e.first(50)), math.radians(e.first(51))
    return (cx + r * math.cos(a0), cy + r * math.sin(a0)), (cx + r * math.cos(a1), cy + r * math.sin(a1))


def ring_area(pieces: list[Entity], join: float = 1e-6) -> float:
    """The area enclosed by LINE/ARC pieces that join end to end into one closed ring (shoelace
    over the ends plus each arc's cap, orientation from the chain)."""
    todo = list(pieces)
    first = todo.pop(0)
    chain = [(first, False)]
    end = arc_ends(first)[1]
    while todo:
        for k, e in enumerate(todo):
            a, b = arc_ends(e)
            if math.dist(a, end) <= join:
                chain.append((e, False))
                end = b
                todo.pop(k)
                break
            if math.dist(b, end) <= join:
                chain.append((e, True))
                end = a
                todo.pop(k)
                break
        else:
            raise AssertionError("LINE/ARC pieces do not join into one ring")
    area = 0.0
    for e, rev in chain:
        a, b = arc_ends(e)
        if rev:
            a, b = b, a
        area += 0.5 * (a[0] * b[1] - b[0] * a[1])
        if e.kind == "ARC":
            r = e.first(40)
            sweep = math.radians((e.first(51) - e.first(50)) % 360.0 or 360.0)
            cap = 0.5 * r * r * (sweep - math.sin(sweep))
            area += -cap if rev else cap
    return abs(area)


def rings_of_pieces(pieces: list[Entity], join: float = 1e-6) -> list[list[Entity]]:
    """LINE/ARC pieces grouped into closed rings (pieces sharing ends)."""
    todo, rings = list(pieces), []
    while todo:
        ring = [todo.pop(0)]
        start, end = arc_ends(ring[0])
        changed = True
        while changed and math.dist(start, end) > join:
            changed = False
            for k, e in enumerate(todo):
                a, b = arc_ends(e)
                if math.dist(a, end) <= join or math.dist(b, end) <= join:
                    end = b if math.dist(a, end) <= join else a
                    ring.append(todo.pop(k))
                    changed = True
                    break
        rings.append(ring)
    return rings
