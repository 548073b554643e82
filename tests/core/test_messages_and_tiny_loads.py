"""Issue 20, item 12: messages in the user's words, subnormal and vanishing loads, and the size cap
of scene text read from Python.

- A command that does not apply to an element says so with the command as typed
  (``mechsketch analyze --forces``), the element's kind in words and what does apply; no name of
  a Python function leaks.
- A load, mass, gravity, stiffness, damping or friction radius that is nonzero but below the
  physical floor (1e-12 in its unit; 1e-6 mm for a radius) is refused, naming the key, the value
  and the floor: a 5e-324 N·m torque made the power balance read 100 % and a 1e-300 N·m torque an
  RMS driving torque of 0 beside a peak of 3.5e-301 N·m. The floor and 0 are accepted, and the
  smallest accepted load gives a power balance at rounding and the RMS of the torque it causes.
- ``loads_scene`` refuses text of more than 10 MB (UTF-8 bytes, as files) before parsing it.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from mechsketch.core import ReplaceElement, Workspace, load_scene, loads_scene
from mechsketch.core.cli import main
from mechsketch.core.errors import EditError, SceneFormatError
from mechsketch.core.io.scene_file import MAX_FILE_BYTES
from mechsketch.resources import example_path


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


INTERNAL = ("analyze_forces", "_handler", "_pick", "centrodes(", "rolling_cmds", "geneva_cmds", "linkage_cmds")


@pytest.mark.parametrize("example, element, argv, says, instead", [
    ("rolling_lever_press", "press", ["analyze", "--forces"], "mechsketch analyze --forces", "mechsketch synthesize"),
    ("rolling_lever_press", "press", ["analyze"], "mechsketch analyze", "mechsketch synthesize"),
    ("rolling_lever_press", "press", ["centrodes", "--link", "x", "--csv", "-"], "mechsketch centrodes",
     "mechsketch synthesize"),
    ("geneva_z6", "indexer", ["synthesize"], "mechsketch synthesize", "mechsketch analyze"),
    ("geneva_z6", "indexer", ["centrodes", "--link", "x", "--csv", "-"], "mechsketch centrodes",
     "mechsketch analyze --forces"),
    ("fourbar_crank_rocker", "fourbar", ["synthesize"], "mechsketch synthesize", "mechsketch centrodes"),
])
def test_a_command_that_does_not_apply_says_so_in_the_users_words(capsys, example, element, argv, says, instead):
    cmd, *rest = argv
    code, out, err = run([cmd, example_path(example), "--element", element, *rest], capsys)
    assert code == 1 and out == ""
    assert f"{says} does not apply to" in err and repr(element) in err and instead in err, err
    kind = {"rolling_lever_press": "rolling lever", "geneva_z6": "Geneva drive", "fourbar_crank_rocker": "linkage"}
    assert kind[example] in err
    for name in INTERNAL:
        assert name not in err, err


def test_a_scene_without_an_element_for_the_command_says_which_command(capsys):
    code, _, err = run(["analyze", example_path("rolling_lever_press"), "--forces"], capsys)
    assert code == 1 and "no element that mechsketch analyze --forces applies to" in err, err
    assert "analyze_forces" not in err


# -- tiny loads ---------------------------------------------------------------------------------
def loaded_fourbar(**change) -> dict:
    doc = json.loads(example_path("fourbar_loaded").read_text())
    el = doc["elements"][0]
    for key, value in change.items():
        node = el
        *parents, leaf = key.split(".")
        for part in parents:
            node = node[int(part)] if isinstance(node, list) else node[part]
        node[int(leaf) if isinstance(node, list) else leaf] = value
    return doc


def _key_of(doc: dict, kind: str) -> str:
    """The JSON path below the element of the first load of ``kind`` and its value key."""
    loads = doc["elements"][0]["loads"]
    k = next(i for i, ld in enumerate(loads) if kind in ld)
    return f"loads.{k}.{kind}"


def _first_with(doc: dict, section: str, key: str) -> str:
    items = doc["elements"][0][section]
    k = next(i for i, it in enumerate(items) if key in it)
    return f"{section}.{k}.{key}"


def tiny_cases():
    doc = json.loads(example_path("fourbar_loaded").read_text())
    return [
        (_key_of(doc, "torque"), "1e-12 N·m"),
        (_key_of(doc, "stiffness"), "1e-12 N/mm"),
        (_key_of(doc, "damping"), "1e-12 N·s/mm"),
        (_first_with(doc, "links", "mass"), "1e-12 kg"),
        (_first_with(doc, "joints", "friction_radius"), "1e-06 mm"),
    ]


@pytest.mark.parametrize("key, floor", tiny_cases())
@pytest.mark.parametrize("value", [5e-324, -5e-324, 2.2e-308, 1e-300, 1e-13])
def test_a_vanishing_load_is_refused_naming_key_value_and_floor(key, floor, value):
    if value < 0 and "torque" not in key:
        value = -value   # only a torque may be negative; the schema words the others' sign
    doc = loaded_fourbar(**{key: value})
    with pytest.raises(SceneFormatError) as info:
        loads_scene(json.dumps(doc))
    text = str(info.value)
    where = "$.elements[0]." + "".join(f"[{p}]" if p.isdigit() else f".{p}" for p in key.split("."))[1:]
    assert where.replace(".[", "[") in text and f"0 or at least {floor}" in text and repr(value) in text, text
    # the floor itself and 0 are fine
    for ok in (0.0, float(floor.split()[0])):
        loads_scene(json.dumps(loaded_fourbar(**{key: ok})))


def test_inertia_and_gravity_and_force_have_floors_too():
    doc = loaded_fourbar()
    links = doc["elements"][0]["links"]
    k = next(i for i, ld in enumerate(links) if "mass" in ld)
    for key, value, floor in ((f"links.{k}.inertia", 1e-300, "1e-12 kg·m²"),
                              ("gravity", [0.0, -1e-200], "1e-12 m/s²"),
                              (_key_of(doc, "force"), [1e-300, 0.0], "1e-12 N")):
        with pytest.raises(SceneFormatError, match=f"0 or at least {floor}"):
            loads_scene(json.dumps(loaded_fourbar(**{key: value})))
    # a force whose one component is tiny beside the other is only rounding: accepted
    loads_scene(json.dumps(loaded_fourbar(**{_key_of(doc, "force"): [5.0, 1e-300]})))


def test_an_edit_to_a_subnormal_torque_is_refused_and_nothing_changes():
    """An element built in code (as the app's loads panel does) goes through the same parser."""
    import dataclasses

    ws = Workspace(loads_scene(json.dumps(loaded_fourbar())))
    el = ws.scene.elements[0]
    tq = next(ld for ld in el.loads if type(ld).__name__ == "Torque")
    bad = dataclasses.replace(el, loads=tuple(dataclasses.replace(ld, torque=5e-324) if ld is tq else ld
                                              for ld in el.loads))
    with pytest.raises(EditError, match="0 or at least 1e-12 N·m"):
        ws.apply(ReplaceElement(bad))
    assert ws.scene.elements[0] == el


def test_the_smallest_accepted_torque_balances_power_and_has_an_rms():
    """A 1e-12 N·m torque alone on the coupler of the crank-rocker (no masses): the driving torque
    is T·ω_coupler/ω_crank (virtual work), its RMS is that of the column, and the power balance is
    at rounding, where 5e-324 N·m read 100 % and 1e-300 N·m gave an RMS of 0."""
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    doc["elements"][0]["loads"] = [{"link": "coupler", "torque": 1e-12}]
    ws = Workspace(loads_scene(json.dumps(doc)))
    eid = ws.scene.elements[0].id
    forces = ws[eid].forces()
    sol = ws.result(eid).solution
    ref = -1e-12 * sol.omega("coupler") / sol.omega("crank")
    ok = np.isfinite(ref)
    assert np.allclose(forces.driver.values[ok], ref[ok], rtol=1e-12, atol=0)
    assert forces.power.worst <= 1e-12
    rms = float(np.sqrt(np.mean((ref[ok] * 1e12) ** 2))) * 1e-12
    assert rms > 0


# -- the size cap of loads_scene ----------------------------------------------------------------
def test_loads_scene_refuses_more_than_ten_megabytes_before_parsing():
    text = json.dumps(json.loads(example_path("fourbar_crank_rocker").read_text()))
    big = text[:-1] + " " * (2 * MAX_FILE_BYTES) + "}"
    with pytest.raises(SceneFormatError) as info:
        loads_scene(big)
    msg = str(info.value)
    assert f"{len(big) / 1e6:.1f} MB" in msg and "limited to 10 MB" in msg, msg
    # just under the limit: read (whitespace is valid JSON)
    loads_scene(text[:-1] + " " * (MAX_FILE_BYTES - len(text) - 10) + "}")


def test_the_cap_counts_utf8_bytes_as_for_files(tmp_path):
    """6 M two-byte characters are 12 MB in a file: refused by both readers alike."""
    text = json.dumps(json.loads(example_path("fourbar_crank_rocker").read_text()))
    big = text[:-1] + ', "note": "' + "é" * 6_000_000 + '"}'
    assert len(big) < MAX_FILE_BYTES < len(big.encode("utf-8"))
    with pytest.raises(SceneFormatError, match="limited to 10 MB"):
        loads_scene(big)
    path = tmp_path / "big.json"
    path.write_text(big, encoding="utf-8")
    with pytest.raises(SceneFormatError, match="limited to 10 MB"):
        load_scene(path)


def test_small_text_reads_as_the_file_does():
    text = example_path("fourbar_crank_rocker").read_text()
    assert loads_scene(text) == load_scene(example_path("fourbar_crank_rocker"))
