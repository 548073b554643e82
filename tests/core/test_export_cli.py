"""``mechsketch export`` for every element type and every example (DXF with bulges or LINE/ARC
entities, SVG), read back; its options; ``mechsketch validate`` runs the export's check."""
from __future__ import annotations

import json

import pytest

from mechsketch import resources
from mechsketch.core.cli import main

from parts_readback import dxf_parts, svg_parts

EXAMPLES = sorted(p.stem for p in resources.example_path("geneva_z6").parent.glob("*.json"))


def run(args, capsys):
    code = main([str(a) for a in args])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_validates_and_exports_closed_valid_parts(tmp_path, capsys, name):
    scene = resources.example_path(name)
    code, out, _ = run(["validate", scene], capsys)
    assert code == 0, out
    for flag, suffix, extra in (("--dxf", "dxf", []), ("--dxf", "dxf", ["--arcs", "entities"]),
                                ("--svg", "svg", ["--layout", "assembled"])):
        path = tmp_path / f"{name}.{suffix}"
        code, out, err = run(["export", scene, flag, path, *extra], capsys)
        assert code == 0, err
        assert "checked before writing" in out and "thinnest web" in out
        parts = (svg_parts if suffix == "svg" else dxf_parts)(path)[1]
        assert parts and all(p.is_valid for p in parts.values())


def test_parts_split_and_min_web_options(tmp_path, capsys):
    scene = resources.example_path("fourbar_crank_rocker")
    code, out, _ = run(["export", scene, "--dxf", tmp_path / "f.dxf", "--parts", "crank,coupler", "--split"], capsys)
    assert code == 0 and (tmp_path / "f_crank.dxf").exists() and (tmp_path / "f_coupler.dxf").exists()
    assert set(dxf_parts(tmp_path / "f_crank.dxf")[1]) == {"crank"}
    code, _, err = run(["export", scene, "--dxf", tmp_path / "g.dxf", "--parts", "crank,gear"], capsys)
    assert code == 1 and "no part 'gear'" in err and "ground, crank, coupler, rocker" in err
    code, _, err = run(["export", scene, "--dxf", tmp_path / "g.dxf", "--min-web", "8"], capsys)
    assert code == 1 and "below the minimum web 8 mm" in err and "--boss-radius" in err
    assert not (tmp_path / "g.dxf").exists()
    code, out, _ = run(["export", scene, "--dxf", tmp_path / "g.dxf", "--boss-radius", "15",
                        "--bore-diameter", "6", "--frame", "drill"], capsys)
    assert code == 0 and "boss radius 15.000 mm, bores Ø6.000 mm" in out and "drilling pattern" in out


def test_export_needs_one_target(tmp_path, capsys):
    scene = resources.example_path("geneva_z6")
    with pytest.raises(SystemExit):
        main(["export", str(scene)])
    with pytest.raises(SystemExit):
        main(["export", str(scene), "--dxf", str(tmp_path / "a.dxf"), "--svg", str(tmp_path / "a.svg")])
    capsys.readouterr()


@pytest.mark.parametrize("z, a, rp, text, analysable", [
    (6, 100.0, 26.0, "roller_radius", False),  # neighbouring slots overlap: refused when loading
    (16, 100.0, 8.0, "slots", True),            # no room for a crank bore: analysable, not cuttable
])
def test_validate_reports_a_drive_that_cannot_be_drawn_naming_the_key(tmp_path, capsys, z, a, rp, text, analysable):
    """A drive that loads and can be analysed validates (exit 0) with a manufacturability warning
    naming the key; ``--strict`` makes it an error; the export refuses it either way."""
    doc = {"format": "mechsketch.scene", "schema_version": 1, "units": "mm",
           "elements": [{"type": "geneva", "id": "g", "slots": z, "center_distance": a, "roller_radius": rp}]}
    p = tmp_path / "g.json"
    p.write_text(json.dumps(doc))
    code, out, _ = run(["validate", p], capsys)
    assert code == (0 if analysable else 1) and text in out
    assert ("manufacturability warnings" in out) == analysable
    code, _, _ = run(["analyze", p, "--summary"], capsys)
    assert code == (0 if analysable else 1)
    code, out, _ = run(["validate", "--strict", p], capsys)
    assert code == 1 and text in out
    code, _, err = run(["export", p, "--dxf", tmp_path / "g.dxf"], capsys)
    assert code == 1 and text in err and not (tmp_path / "g.dxf").exists()
