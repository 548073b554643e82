"""Issue 13 item 9: ids with a comma, a quote or a line break never misalign a CSV; ids with line
breaks or other control characters (and ids starting or ending with a space) are refused."""
from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

from mechsketch.core.analyses.table import Table
from mechsketch.core.cli import main
from mechsketch.core.io.scene_file import loads_scene
from mechsketch.core.errors import SceneFormatError
from mechsketch.resources import example_path


def _read(text: str) -> list[list[str]]:
    return list(csv.reader(io.StringIO(text)))


def test_a_table_quotes_its_header_as_the_csv_module_does():
    names = ["t", "B,1.x", 'say "hi".y', "semi;colon", "plain"]
    t = Table.from_columns({n: np.arange(3.0) + k for k, n in enumerate(names)}, integer={"plain"})
    rows = _read(t.to_csv())
    assert rows[0] == names
    assert all(len(r) == len(names) for r in rows)
    assert rows[1] == ["0.0", "1.0", "2.0", "3.0", "4"]
    plain = Table.from_columns({"t": np.zeros(1), "B.x": np.ones(1)})
    assert plain.to_csv() == "t,B.x\n0.0,1.0\n"             # nothing to quote: unchanged bytes


def _fourbar_with_joint_id(new: str) -> dict:
    doc = json.loads(example_path("fourbar_crank_rocker").read_text())
    text = json.dumps(doc).replace('"B"', json.dumps(new))
    return json.loads(text)


def test_the_analysis_csv_of_a_joint_named_with_a_comma_reads_back_aligned(tmp_path, capsys):
    p = tmp_path / "s.json"
    p.write_text(json.dumps(_fourbar_with_joint_id('B,"1"')))
    target = tmp_path / "out.csv"
    assert main(["analyze", str(p), "--csv", str(target)]) == 0
    rows = _read(target.read_text())
    assert 'B,"1".x' in rows[0] and 'B,"1".ay' in rows[0]
    assert {len(r) for r in rows} == {len(rows[0])} and len(rows) == 361
    col = rows[0].index('B,"1".x')
    ref = rows[0].index("C.x")
    assert float(rows[1][col]) == pytest.approx(20.0) and rows[1][ref] != ""


@pytest.mark.parametrize("bad", ["B\n2", "B\r", "tab\there", "nul\x00", " lead", "trail ", "del\x7f"])
def test_ids_with_control_characters_or_outer_spaces_are_refused(bad):
    with pytest.raises(SceneFormatError) as info:
        loads_scene(json.dumps(_fourbar_with_joint_id(bad)))
    msg = str(info.value)
    assert "control characters" in msg and "joints[1].id" in msg, msg


@pytest.mark.parametrize("good", ["B,1", 'B"q', "Kurbel-2", "ведущий", "pin 3", "a.b+c"])
def test_other_ids_still_load(good):
    scene = loads_scene(json.dumps(_fourbar_with_joint_id(good)))
    assert good in scene.elements[0].joint_ids
