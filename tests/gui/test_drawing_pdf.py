"""The drawing sheet (issue 23, item 9): ``mechsketch export --pdf`` through the launcher (Qt's
QPdfWriter), read back with pypdf: one landscape A4/A3 page per part set, the title block's
fields, the analysis summary, and the dimensions the model says (hole-to-hole distances are the
linkage's joint distances; the overall sizes are the parts' exact bounding boxes, measured here
on shapely polygons of the parts)."""
from __future__ import annotations

import math
import re

import numpy as np
import pypdf
import pytest
from PySide6.QtCore import Qt

from mechsketch import resources
from mechsketch.core import load_scene
from mechsketch.core.analyses.parts import is_circle
from mechsketch.core.analyses.parts.build import PartOptions, element_parts
from mechsketch.core.cli import export_cmds
from mechsketch.core.cli import main as core_main
from mechsketch.core.errors import GeometryError
from mechsketch.core.io.drawing_sheet import drawing_page
from mechsketch.gui.drawing_export import export_drawing
from mechsketch.gui.drawing_pdf import page_image
from mechsketch.gui.launcher import main

from app_fakes import shell  # noqa: F401 - fixture

EXAMPLES = sorted(p.stem for p in resources.example_path("geneva_z6").parent.glob("*.json"))
PAPER_PT = {"A4": (842, 595), "A3": (1191, 842)}


def part_sets(name):
    out = []
    for el in load_scene(resources.example_path(name)).elements:
        try:
            out.append((el, element_parts(el, PartOptions())))
        except GeometryError:
            pass
    return out


def words(text: str) -> str:
    return re.sub(r"\s+", " ", text)


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_draws_a_sheet_that_opens_with_its_dimensions(tmp_path, capsys, name):
    path = tmp_path / f"{name}.pdf"
    assert main(["export", str(resources.example_path(name)), "--pdf", str(path), "--material", "S235",
                 "--thickness", "4"]) == 0
    sets = part_sets(name)
    report = capsys.readouterr().out
    reader = pypdf.PdfReader(path)
    assert len(reader.pages) == len(sets) >= 1
    for page, (el, ps) in zip(reader.pages, sets):
        text = words(page.extract_text())
        paper = re.search(rf"{re.escape(el.id)}: (A[34]) at (\S+),", report)
        w, h = PAPER_PT[paper[1]]
        assert (round(float(page.mediabox.width)), round(float(page.mediabox.height))) == (w, h)
        for field in (f"{name}.json", el.id, "units: mm", "material: S235", "thickness: 4 mm", paper[2],
                      "Analysis summary"):
            assert field in text, field
        nums = {float(x) for x in re.findall(r"\d+\.\d\d(?!\d)", text)}
        for p in ps.parts:        # overall sizes: the exact bounds, measured on a fine polygon
            x0, y0, x1, y1 = p.polygon(1e-5).bounds
            dims = sorted([x1 - x0, y1 - y0])
            flat = [min(nums, key=lambda v: abs(v - d)) for d in dims]
            # laid out flat (turned): the width and height of the turned part; at least its
            # smaller side or its diagonal-free width is shown within the 0.005 mm of rounding
            assert any(abs(f - d) <= 0.0051 for f, d in zip(flat, dims)) or p.group, (p.name, dims, flat)
        if el.type == "linkage":  # hole-to-hole: the joint distances of every binary link bored twice
            bored = {p.name for p in ps.parts if sum(is_circle(c) is not None for c in p.holes) == 2}
            checked = 0
            for link in el.links:
                if len(link.joints) == 2 and link.id in bored:
                    a, b = (np.asarray(el.joint(j).at) for j in link.joints)
                    d = float(np.hypot(*(a - b)))
                    assert f"{d:.2f}" in text, (link.id, d)
                    checked += 1
            assert checked >= 1
        if name.startswith("fourbar"):
            assert "Grashof" in text


def test_a_sheet_is_drawn_to_scale_with_its_title_block(tmp_path):
    """The page's geometry as data: parts inside the border and clear of the title strip, scaled
    by the stated scale (a part's paper size over its real size), and the rendering not blank."""
    el, ps = part_sets("fourbar_crank_rocker")[0]
    page = drawing_page(ps, "fb.json", ["Grashof crank-rocker"], "S235", "4")
    w, h = page.size
    real = {p.name: p for p in ps.parts}
    assert sorted(q.name for q in page.parts) == sorted(real)
    for q in page.parts:
        x0, y0, x1, y1 = q.bounds()
        assert 10 < x0 and x1 < w - 10 and 10 + 62 < y0 and y1 < h - 10
        assert math.isclose(q.area, real[q.name].area * page.scale ** 2, rel_tol=1e-9)
        assert math.isclose(q.polygon(1e-6).length, real[q.name].polygon(1e-6 / page.scale).length * page.scale,
                            rel_tol=1e-6)
    assert dict(page.title)["thickness"] == "4 mm" and page.scale_text == "1:2"
    img = page_image(page, 50)
    dark = sum(1 for x in range(0, img.width(), 3) for y in range(0, img.height(), 3)
               if img.pixelColor(x, y).lightness() < 128)
    assert dark > 200


def test_pdf_requests_that_cannot_be_met_are_refused(tmp_path, capsys, monkeypatch):
    scene = str(resources.example_path("geneva_z6"))
    monkeypatch.setattr(export_cmds, "PDF_WRITER", None)      # the core CLI alone has no Qt
    assert core_main(["export", scene, "--pdf", str(tmp_path / "a.pdf")]) == 1
    assert "run it with the 'mechsketch' command" in capsys.readouterr().err
    assert main(["export", scene, "--pdf", str(tmp_path / "a.pdf"), "--kerf", "0.2"]) == 1
    assert "--kerf do not apply to --pdf" in capsys.readouterr().err
    assert main(["export", scene, "--dxf", str(tmp_path / "a.dxf"), "--material", "S235"]) == 1
    assert "--material applies to --pdf only" in capsys.readouterr().err
    assert main(["export", scene, "--pdf", str(tmp_path / "no" / "a.pdf")]) == 1
    assert "cannot write" in capsys.readouterr().err
    assert not list(tmp_path.rglob("*.pdf")) and not list(tmp_path.rglob("*.dxf"))


def test_file_export_drawing_writes_the_sheet_the_command_writes(shell, qtbot, tmp_path):
    """File › Export Drawing (PDF)…: the window's scene (the four-bar with its coupler point) as
    one A4 sheet, read back; an unwritable folder is an error message and nothing is written.
    The sheets are built and written off the GUI thread (issue 20): the action returns at once
    with the export running, the status bar shows it, and the result arrives as a signal."""
    parts = shell()
    w = parts.window
    action = w.actions["export_drawing"]
    assert action in w.menuBar().actions()[0].menu().actions()
    parts.dialogs.save_names.append(str(tmp_path / "sheet"))
    with qtbot.waitSignal(w.exporter.finished, timeout=60000):
        action.trigger()
        assert w.exporter.busy and w.export_status.isVisibleTo(w) and not (tmp_path / "sheet.pdf").exists()
    reader = pypdf.PdfReader(tmp_path / "sheet.pdf")
    el = next(e for e in w.controller.scene.elements if e.type == "linkage")
    assert len(reader.pages) == 1
    text = words(reader.pages[0].extract_text())
    assert el.id in text and "units: mm" in text and "Grashof" in text
    for link in el.links:
        if len(link.joints) == 2:
            a, b = (np.asarray(el.joint(j).at) for j in link.joints)
            assert f"{float(np.hypot(*(a - b))):.2f}" in text
    title, report = parts.dialogs.infos[-1]
    assert title == "Drawing exported" and "A4" in report
    parts.dialogs.save_names.append(str(tmp_path / "missing" / "sheet.pdf"))
    scene = w.controller.scene
    with qtbot.waitSignal(w.exporter.failed, timeout=60000):
        action.trigger()
    title, text, _ = parts.dialogs.errors[-1]
    assert title == "Export Drawing" and "cannot write" in text and not (tmp_path / "missing").exists()
    assert str(tmp_path / "missing" / "sheet.pdf") in text and "The scene is not affected" in text
    assert w.controller.scene is scene and not w.exporter.busy


def test_cancel_in_the_status_bar_stops_the_drawing_before_it_is_written(shell, qtbot, tmp_path):
    """Cancel pressed while the sheets are built: nothing is written, the status bar says so, the
    exporter is free again and a second Export Drawing writes the file."""
    parts = shell()
    w = parts.window
    parts.dialogs.save_names.append(str(tmp_path / "sheet.pdf"))

    def press_cancel(_element_id: str) -> None:   # the moment the export starts, as a user would
        qtbot.mouseClick(w.export_status.cancel_button, Qt.MouseButton.LeftButton)
    w.exporter.started.connect(press_cancel)
    with qtbot.waitSignal(w.exporter.cancelled, timeout=60000) as blocker:
        w.actions["export_drawing"].trigger()
    w.exporter.started.disconnect(press_cancel)
    assert "not written" in blocker.args[0] and "not written" in w.statusBar().currentMessage()
    qtbot.waitUntil(lambda: not w.exporter.busy)
    assert not list(tmp_path.glob("*.pdf")) and not list(tmp_path.glob(".sheet*")) and not parts.dialogs.errors
    parts.dialogs.save_names.append(str(tmp_path / "sheet.pdf"))
    with qtbot.waitSignal(w.exporter.finished, timeout=60000):
        w.actions["export_drawing"].trigger()
    assert len(pypdf.PdfReader(tmp_path / "sheet.pdf").pages) == 1 and [p.name for p in tmp_path.glob("*sheet*")] == ["sheet.pdf"]


def test_export_drawing_refuses_to_start_while_an_export_runs(shell, qtbot, tmp_path):
    parts = shell()
    w = parts.window
    parts.dialogs.save_names.extend([str(tmp_path / "a.pdf"), str(tmp_path / "b.pdf")])
    with qtbot.waitSignal(w.exporter.finished, timeout=60000):
        assert w.actions["export_drawing"].trigger() is None and w.exporter.busy
        assert export_drawing(w) is False and "an export is running" in w.statusBar().currentMessage()
    assert (tmp_path / "a.pdf").exists() and not (tmp_path / "b.pdf").exists()
