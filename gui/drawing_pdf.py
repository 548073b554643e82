"""Drawing sheets as PDF with Qt's own PDF writer (QPdfWriter): renders the pages that
:func:`mechsketch.core.io.drawing_sheet.drawing_page` lays out (paper mm, y up) for
``mechsketch export --pdf`` (the launcher hands :func:`write_pdf` to the headless command) and
File › Export Drawing. Parts are drawn as outlines (arcs as chords of at most 0.005 mm sagitta on
paper), dimensions with extension lines, arrows and their value in mm, then the title block and
the analysis summary. Written to a temporary file and renamed: a failed write leaves nothing.
"""
from __future__ import annotations

import math
import os
import sys
import tempfile
from pathlib import Path
from typing import Sequence

from PySide6.QtCore import QMarginsF, QPointF, QRectF, Qt
from PySide6.QtGui import QFont, QGuiApplication, QImage, QPageLayout, QPageSize, QPainter, QPainterPath, QPdfWriter, QPen, QPolygonF

from mechsketch.core.errors import ExportError
from mechsketch.core.io.drawing_sheet import MARGIN, STRIP, SUMMARY_TEXT, TEXT, TITLE_WIDTH, Dimension, Page

DPI = 600
SAGITTA = 0.005   # mm on paper
_SIZES = {"A4": QPageSize.PageSizeId.A4, "A3": QPageSize.PageSizeId.A3}


def ensure_gui_application() -> QGuiApplication:
    """The running Qt application, or an offscreen one for a headless command (fonts need it): a
    QApplication, so that the app or a test's widgets can run in the same process afterwards."""
    app = QGuiApplication.instance()
    if app is None:
        from PySide6.QtWidgets import QApplication

        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
        app = QApplication(sys.argv[:1] or ["mechsketch"])
    return app


class _Paper:
    """Paper mm (y up) to device pixels (y down) for one page."""

    def __init__(self, painter: QPainter, height_mm: float, dpi: float = DPI) -> None:
        self.painter, self.h, self.f = painter, height_mm, dpi / 25.4

    def pt(self, x: float, y: float) -> QPointF:
        return QPointF(x * self.f, (self.h - y) * self.f)

    def pen(self, width_mm: float, style=Qt.PenStyle.SolidLine) -> None:
        p = QPen(Qt.GlobalColor.black, width_mm * self.f)
        p.setStyle(style)
        self.painter.setPen(p)

    def text(self, x: float, y: float, s: str, size_mm: float, angle_deg: float = 0.0) -> None:
        font = QFont("DejaVu Sans")
        font.setPixelSize(max(1, round(size_mm * self.f)))
        for tag in ("liga", "clig"):     # "ff", "fi" stay letters: text copied from the sheet reads as typed
            font.setFeature(QFont.Tag(tag), 0)
        self.painter.setFont(font)
        self.painter.save()
        self.painter.translate(self.pt(x, y))
        self.painter.rotate(-angle_deg)
        self.painter.drawText(QPointF(0, 0), s)
        self.painter.restore()

    def line(self, a, b) -> None:
        self.painter.drawLine(self.pt(*a), self.pt(*b))


def _draw_contour(paper: _Paper, c) -> None:
    pts = c.polyline(SAGITTA)
    poly = QPolygonF([paper.pt(float(x), float(y)) for x, y in pts])
    path = QPainterPath()
    path.addPolygon(poly)
    path.closeSubpath()
    paper.painter.drawPath(path)


def _arrow(paper: _Paper, tip, towards) -> None:
    d = math.dist(tip, towards) or 1.0
    ux, uy = (towards[0] - tip[0]) / d, (towards[1] - tip[1]) / d
    size, half = 2.5, 0.8
    a = (tip[0] + size * ux - half * uy, tip[1] + size * uy + half * ux)
    b = (tip[0] + size * ux + half * uy, tip[1] + size * uy - half * ux)
    paper.painter.drawPolygon(QPolygonF([paper.pt(*tip), paper.pt(*a), paper.pt(*b)]))


def _draw_dimension(paper: _Paper, d: Dimension) -> None:
    (x0, y0), (x1, y1) = d.p0, d.p1
    length = math.hypot(x1 - x0, y1 - y0)
    if length == 0:
        return
    nx, ny = -(y1 - y0) / length, (x1 - x0) / length        # left of p0 -> p1
    a = (x0 + d.offset * nx, y0 + d.offset * ny)
    b = (x1 + d.offset * nx, y1 + d.offset * ny)
    paper.pen(0.13)
    if d.offset:
        extra = math.copysign(1.5, d.offset)
        paper.line((x0, y0), (a[0] + extra * nx, a[1] + extra * ny))
        paper.line((x1, y1), (b[0] + extra * nx, b[1] + extra * ny))
    paper.line(a, b)
    paper.painter.setBrush(Qt.GlobalColor.black)
    _arrow(paper, a, b)
    _arrow(paper, b, a)
    paper.painter.setBrush(Qt.BrushStyle.NoBrush)
    angle = math.degrees(math.atan2(y1 - y0, x1 - x0))
    if angle > 90.0 or angle <= -90.0:                     # text reads left to right or upwards
        angle -= math.copysign(180.0, angle)
        a, b = b, a
        nx, ny = -nx, -ny
    ux, uy = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    w = 0.55 * TEXT * len(d.text)
    mid = (0.5 * (a[0] + b[0]) - 0.5 * w * ux + 0.8 * (-uy), 0.5 * (a[1] + b[1]) - 0.5 * w * uy + 0.8 * ux)
    paper.text(mid[0], mid[1], d.text, TEXT, angle)


def _draw_blocks(paper: _Paper, page: Page) -> None:
    w, h = page.size
    paper.pen(0.5)
    paper.painter.drawRect(QRectF(paper.pt(MARGIN, h - MARGIN), paper.pt(w - MARGIN, MARGIN)))
    paper.pen(0.35)
    paper.line((MARGIN, MARGIN + STRIP), (w - MARGIN, MARGIN + STRIP))
    tx = w - MARGIN - TITLE_WIDTH
    paper.line((tx, MARGIN), (tx, MARGIN + STRIP))
    row = STRIP / len(page.title)
    for k, (field, value) in enumerate(page.title):
        y = MARGIN + STRIP - (k + 1) * row
        paper.pen(0.13)
        if k:
            paper.line((tx, y + row), (w - MARGIN, y + row))
        paper.text(tx + 2.0, y + 0.3 * row, f"{field}:", TEXT)
        paper.text(tx + 28.0, y + 0.3 * row, value or "", TEXT)
    paper.text(MARGIN + 2.0, MARGIN + STRIP - 4.0, "Analysis summary", TEXT)
    for k, line in enumerate(page.summary):
        paper.text(MARGIN + 2.0, MARGIN + STRIP - 7.5 - k * 1.3 * SUMMARY_TEXT * 0.95, line, SUMMARY_TEXT)


def _draw_page(painter: QPainter, page: Page, dpi: float = DPI) -> None:
    paper = _Paper(painter, page.size[1], dpi)
    painter.setBrush(Qt.BrushStyle.NoBrush)
    paper.pen(0.35)
    for p in page.parts:
        for c in p.contours:
            _draw_contour(paper, c)
    for d in page.dimensions:
        _draw_dimension(paper, d)
    for text, (x, y) in page.labels:
        paper.text(x, y, text, TEXT)
    _draw_blocks(paper, page)


def page_image(page: Page, dpi: float = 100.0) -> QImage:
    """``page`` drawn on a white image at ``dpi`` (what the PDF shows; a preview)."""
    ensure_gui_application()
    w, h = page.size
    img = QImage(round(w * dpi / 25.4), round(h * dpi / 25.4), QImage.Format.Format_RGB32)
    img.fill(Qt.GlobalColor.white)
    painter = QPainter(img)
    painter.setRenderHint(QPainter.RenderHint.Antialiasing)
    _draw_page(painter, page, dpi)
    painter.end()
    return img


def write_pdf(pages: Sequence[Page], path: str | os.PathLike, title: str = "mechsketch drawing") -> None:
    """Write ``pages`` as one PDF (a page each, landscape, their paper size) to ``path``,
    atomically; :class:`ExportError` names the path when it cannot be written."""
    if not pages:
        raise ExportError("no page to write")
    ensure_gui_application()
    target = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(suffix=".pdf", prefix=f".{target.name}.", dir=target.parent or ".")
        os.close(fd)
    except OSError as exc:
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from None
    writer = QPdfWriter(tmp)
    writer.setResolution(DPI)
    writer.setTitle(title)
    writer.setCreator("mechsketch")

    def layout(page: Page) -> QPageLayout:
        return QPageLayout(QPageSize(_SIZES[page.paper]), QPageLayout.Orientation.Landscape, QMarginsF(0, 0, 0, 0))

    writer.setPageLayout(layout(pages[0]))
    painter = QPainter()
    try:
        if not painter.begin(writer):
            raise ExportError(f"cannot write {target}: Qt's PDF writer could not open it")
        for k, page in enumerate(pages):
            if k:
                writer.setPageLayout(layout(page))
                writer.newPage()
            _draw_page(painter, page)
        painter.end()
        os.replace(tmp, target)
    except OSError as exc:
        raise ExportError(f"cannot write {target}: {exc.strerror or exc}") from None
    finally:
        if painter.isActive():
            painter.end()
        if os.path.exists(tmp):
            os.unlink(tmp)
