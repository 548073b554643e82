"""Read a DXF, SVG or picture file as an underlay (core/model/underlay.py).

- DXF (ezdxf): lines, polylines with bulges, arcs, circles, ellipses, splines and block
  references, flattened to polylines within a tolerance relative to the drawing's size; the
  drawing's ``$INSUNITS`` gives millimetres per unit (unitless: mm).
- SVG (svgelements): every shape with its transforms, curves sampled; y is flipped (SVG's y points
  down); one user unit is a CSS pixel (1/96 in), as svgelements reports physical sizes.
- Pictures (Pillow): PNG and JPEG are kept as they are; any other format Pillow reads is stored as
  PNG; a picture over :data:`MAX_SIDE` pixels is scaled down so the scene stays small.

This module is imported when an underlay is read (it loads ezdxf, svgelements and Pillow), never
at start-up. Every reader refuses, with :class:`RequestError` naming the file and what is wrong, a file it
cannot read, one with nothing to draw, or a non-regular file (nothing is read from /proc or a FIFO).
"""
from __future__ import annotations

import base64
import io
import math
import os
import stat
from pathlib import Path

import ezdxf
import numpy as np
import svgelements as se
from ezdxf import recover
from ezdxf.path import make_path
from PIL import Image, UnidentifiedImageError

from ..errors import RequestError
from ..model.underlay import MAX_IMAGE_CHARS, MAX_POINTS, Placement, Underlay, UnderlayImage

DRAWINGS = (".dxf", ".svg")
PICTURES = (".png", ".jpg", ".jpeg", ".bmp", ".gif", ".tif", ".tiff", ".webp")
#: a picture's longest side after reading, pixels
MAX_SIDE = 4096
#: files larger than this are refused (bytes)
MAX_FILE_BYTES = 50 * 1024 * 1024
#: millimetres per drawing unit, by DXF $INSUNITS code (0: unitless, taken as mm)
INSUNITS_MM = {0: 1.0, 1: 25.4, 2: 304.8, 4: 1.0, 5: 10.0, 6: 1000.0, 8: 25.4e-6, 9: 25.4e-3, 10: 914.4,
               13: 1e-3, 14: 100.0}
#: mm per SVG user unit as svgelements reports them: 96 per inch with its inch of 1/0.0393701 mm
#: (so a size given in mm comes back exact; an exact 25.4/96 would be 5e-7 off for them)
SVG_MM_PER_UNIT = 1.0 / (96.0 * 0.0393701)


def underlay_kind(path: str | os.PathLike) -> str | None:
    """"drawing" or "picture" for a file an underlay can be read from (by its suffix), else None."""
    suffix = Path(path).suffix.lower()
    return "drawing" if suffix in DRAWINGS else "picture" if suffix in PICTURES else None


def _check_file(path: Path) -> None:
    try:
        st = os.stat(path)
    except OSError as exc:
        raise RequestError(f"cannot read {path}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise RequestError(f"{path} is not a regular file: an underlay is read from a DXF, SVG or picture file")
    if st.st_size > MAX_FILE_BYTES:
        raise RequestError(f"{path} is {st.st_size / 1e6:.0f} MB; underlay files are limited to "
                           f"{MAX_FILE_BYTES / 1e6:.0f} MB")


def read_underlay(path: str | os.PathLike, element_id: str) -> tuple[Underlay, float]:
    """The underlay in ``path`` (id ``element_id``, placed at the identity) and its millimetres
    per source unit (a DXF's or SVG's unit; 0 for a picture, whose size is set when it is placed)."""
    p = Path(path)
    kind = underlay_kind(p)
    if kind is None:
        raise RequestError(f"{p.name}: an underlay is a DXF or SVG drawing or a picture "
                           f"({', '.join(s[1:] for s in DRAWINGS + PICTURES)})")
    _check_file(p)
    if kind == "picture":
        return Underlay(element_id, p.name, image=read_picture(p)), 0.0
    paths, mm = read_dxf(p) if p.suffix.lower() == ".dxf" else read_svg(p)
    return Underlay(element_id, p.name, paths=paths), mm


def _simplified(polylines: list[np.ndarray]) -> tuple[tuple[tuple[float, float], ...], ...]:
    """Drop consecutive duplicates and degenerate paths; thin evenly if over MAX_POINTS."""
    out = []
    for pts in polylines:
        pts = np.asarray(pts, dtype=float).reshape(-1, 2)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) > 1:
            keep = np.ones(len(pts), dtype=bool)
            keep[1:] = np.any(np.abs(np.diff(pts, axis=0)) > 0, axis=1)
            pts = pts[keep]
        if len(pts) >= 2:
            out.append(pts)
    total = sum(len(p) for p in out)
    if total > MAX_POINTS:
        step = math.ceil(total / MAX_POINTS)
        out = [np.vstack([p[:-1:step], p[-1:]]) if len(p) > 2 else p for p in out]
    return tuple(tuple((float(x), float(y)) for x, y in p) for p in out)


def read_dxf(path: Path) -> tuple[tuple[tuple[tuple[float, float], ...], ...], float]:
    """Polylines of every drawable entity of a DXF's modelspace, and mm per drawing unit."""
    try:
        doc, _auditor = recover.readfile(str(path))
    except (OSError, ezdxf.DXFStructureError) as exc:
        raise RequestError(f"cannot read {path.name} as a DXF drawing: {exc}") from None
    mm = INSUNITS_MM.get(int(doc.header.get("$INSUNITS", 0)), 1.0)
    entities = []

    def collect(entity, depth: int = 0) -> None:
        if entity.dxftype() == "INSERT" and depth < 8:
            for sub in entity.virtual_entities():
                collect(sub, depth + 1)
        elif entity.dxftype() in ("LINE", "LWPOLYLINE", "POLYLINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE"):
            entities.append(entity)

    for e in doc.modelspace():
        collect(e)
    built = []
    for e in entities:
        try:
            built.append(make_path(e))
        except (TypeError, ValueError, ezdxf.DXFError):
            continue
    vertices = [np.array([(v.x, v.y) for v in p.control_vertices()]).reshape(-1, 2) for p in built]
    vertices = [v for v in vertices if len(v)]
    if not vertices:
        raise RequestError(f"{path.name}: no lines, arcs, circles, polylines or splines to draw")
    ext = np.vstack(vertices)
    size = float(np.hypot(*(ext.max(axis=0) - ext.min(axis=0)))) or 1.0
    tol = size * 1e-4     # flattening: a ten-thousandth of the drawing's diagonal
    lines = [np.array([(v.x, v.y) for v in p.flattening(tol)]) for p in built]
    return _simplified(lines), mm


def read_svg(path: Path) -> tuple[tuple[tuple[tuple[float, float], ...], ...], float]:
    """Polylines of every shape of an SVG (transforms applied, y flipped), and mm per user unit."""
    try:
        svg = se.SVG.parse(str(path), reify=True)
    except (OSError, ValueError, SyntaxError) as exc:   # the XML parser's ParseError is a SyntaxError
        raise RequestError(f"cannot read {path.name} as an SVG drawing: {exc}") from None
    lines: list[np.ndarray] = []
    for element in svg.elements():
        if not isinstance(element, se.Shape) or isinstance(element, se.Text):
            continue
        shape = se.Path(element)
        for sub in shape.as_subpaths():
            pts = _sample_subpath(sub)
            if len(pts) >= 2:
                lines.append(pts * np.array([1.0, -1.0]))
    if not lines:
        raise RequestError(f"{path.name}: no paths, lines or shapes to draw")
    return _simplified(lines), SVG_MM_PER_UNIT


def _sample_subpath(sub) -> np.ndarray:
    pts: list[tuple[float, float]] = []
    for seg in sub:
        if isinstance(seg, se.Move):
            if seg.end is not None:
                pts.append((seg.end.x, seg.end.y))
            continue
        if isinstance(seg, (se.Line, se.Close)):
            if seg.end is not None:
                pts.append((seg.end.x, seg.end.y))
            continue
        n = max(8, min(64, int(seg.length(error=1e-3) / 0.5) + 1)) if hasattr(seg, "length") else 16
        for p in seg.npoint(np.linspace(0.0, 1.0, n)[1:]):
            pts.append((float(p[0]), float(p[1])))
    return np.array(pts, dtype=float).reshape(-1, 2)


def read_picture(path: Path) -> UnderlayImage:
    """A picture as stored in a scene: PNG or JPEG bytes (others converted to PNG), at most
    :data:`MAX_SIDE` pixels a side."""
    raw = path.read_bytes()
    try:
        with Image.open(io.BytesIO(raw)) as im:
            im.load()
            fmt = (im.format or "").upper()
            if max(im.size) > MAX_SIDE or fmt not in ("PNG", "JPEG"):
                im = im.copy()
                im.thumbnail((MAX_SIDE, MAX_SIDE))
                if im.mode not in ("RGB", "RGBA", "L", "LA"):
                    im = im.convert("RGBA")
                buf = io.BytesIO()
                im.save(buf, "PNG", optimize=True)
                raw, fmt = buf.getvalue(), "PNG"
            width, height = im.size
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise RequestError(f"cannot read {path.name} as a picture: {exc}") from None
    data = base64.b64encode(raw).decode("ascii")
    if len(data) > MAX_IMAGE_CHARS:
        raise RequestError(f"{path.name} is {len(raw) / 1e6:.1f} MB as {fmt}; a picture under the canvas is "
                           f"limited to {MAX_IMAGE_CHARS * 3 / 4 / 1e6:.1f} MB (save it smaller or as JPEG)")
    return UnderlayImage("png" if fmt == "PNG" else "jpeg", data, int(width), int(height))


def placed(underlay: Underlay, mm_per_unit: float, centre: tuple[float, float] | None = None,
           width_mm: float | None = None) -> Underlay:
    """``underlay`` placed at its units' scale (a drawing: ``mm_per_unit``; a picture:
    ``width_mm`` wide), its middle at ``centre`` when given (a drawing keeps its own coordinates
    otherwise)."""
    if underlay.image is not None:
        scale = (width_mm or underlay.image.width) / underlay.image.width
    else:
        scale = mm_per_unit or 1.0
    pl = Placement(scale, 0.0, (0.0, 0.0))
    if centre is not None:
        corners = pl.to_world(underlay.source_corners())
        cx, cy = sum(x for x, _ in corners) / 4, sum(y for _, y in corners) / 4
        pl = pl.moved(centre[0] - cx, centre[1] - cy)
    return underlay.with_placement(pl)
