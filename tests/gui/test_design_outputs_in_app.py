"""Issue 25, "done when": what each ``mechsketch design geneva|rolling|gears`` command writes opens
in the app (File › Open as a user would, through the dialog service), is solved there without an
error, is drawn on the canvas, and File › Export DXF writes cut-ready parts from it that ezdxf
reads back without audit errors, on the layers of the designed element's parts."""
from __future__ import annotations

import json

import ezdxf
import pytest

from mechsketch.core import load_scene
from mechsketch.core.cli import main
from mechsketch.core.design.rolling import requirements_of
from mechsketch.resources import example_path

from app_fakes import shell  # noqa: F401 - fixture

GENEVA = {"slots": 6, "speed_rpm": 300, "roller_length": 12,
          "load": {"wheel_inertia": 0.5, "external_moment": 2, "journal_friction": 0.05, "journal_radius": 12},
          "material": {"roller": {"E": 210000, "poisson": 0.3}, "wheel": {"E": 210000, "poisson": 0.3}},
          "wear": {"allowed_wear": 0.05, "specific_wear_rate": 1e-6},
          "allowable_contact_stress": 900, "life_cycles": 1e7, "max_center_distance": 400, "min_web": 1}
SMOOTH = {"slots": 5, "speed_rpm": 120, "load": {"wheel_inertia": 0.05, "journal_radius": 8},
          "allowable_contact_stress": 700, "smooth": {}}
GEARS = {"function": {"elliptic": {"eccentricity": 0.3}}, "center_distance": 100, "bore_radius": 4,
         "max_pressure_deg": 30}


def _rolling() -> dict:
    req = requirements_of(load_scene(example_path("rolling_lever_press")).elements[0])
    req["slider_law"] = {"law": "constant", "travel": 50.43}
    return req


CASES = [("geneva", GENEVA, "geneva", {"wheel", "locking_disc", "crank_arm", "roller"}),
         ("geneva", SMOOTH, "geared_geneva", {"wheel", "locking_disc", "crank_arm", "roller"}),
         ("rolling", None, "rolling_lever", {"frame", "lever", "slider"}),
         ("gears", GEARS, "gear_pair", set())]


@pytest.mark.parametrize("kind, req, typ, layers", CASES, ids=["geneva", "smooth_geneva", "rolling", "gears"])
def test_a_designed_scene_opens_solves_draws_and_exports_in_the_app(shell, qtbot, tmp_path, capsys,
                                                                    kind, req, typ, layers):
    path = tmp_path / "req.json"
    path.write_text(json.dumps(_rolling() if req is None else req))
    out = tmp_path / "designed.json"
    assert main(["design", kind, str(path), "--out", str(out), "--id", "made"]) == 0
    capsys.readouterr()
    parts = shell()
    parts.dialogs.open_names.append(str(out))
    parts.window.actions["open"].trigger()
    c = parts.controller
    assert c.scene.ids == ("made",) and c.scene.element("made").type == typ
    res = c.element_result("made")
    assert res is not None and getattr(res, "error", None) in (None, "")
    view = parts.window.canvas
    assert "made" in view.element_items
    assert view.extent().width() > 0 and view.extent().height() > 0
    dxf = tmp_path / "made.dxf"
    parts.dialogs.save_names.append(str(dxf))
    parts.window.actions["export_dxf"].trigger()
    qtbot.waitUntil(lambda: not parts.window.exporter.busy, timeout=60000)
    assert not parts.dialogs.errors, parts.dialogs.errors
    doc = ezdxf.readfile(dxf)
    assert not doc.audit().has_errors
    got = {e.dxf.layer for e in doc.modelspace()}
    assert layers <= got and len(list(doc.modelspace())) > 0
    assert c.scene.element("made") == load_scene(out).elements[0]      # nothing the user made changed


def test_every_element_kind_with_cut_parts_is_offered_by_file_export():
    """The app's export offers every element of every example whose parts the core builds (gear
    pairs and smooth Geneva drives were missing: File › Export DXF said nothing and wrote nothing)."""
    from mechsketch.core.analyses.parts.build import element_parts
    from mechsketch.gui.export_worker import exportable
    from mechsketch.resources import example_paths

    kinds = set()
    for path in example_paths():
        for el in load_scene(path).elements:
            if el.type == "underlay":
                continue
            assert element_parts(el).parts, el.id
            assert exportable(el), f"{path.name}: {el.type} {el.id} has parts but File › Export skips it"
            kinds.add(el.type)
    assert {"linkage", "geneva", "rolling_lever", "gear_pair", "geared_geneva"} <= kinds
