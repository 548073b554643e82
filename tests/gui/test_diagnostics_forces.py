"""Forces in view (issue 24 item 3): when a linkage has masses or loads, the Diagnostics dock shows
the forces summary, the same text as ``mechsketch analyze --forces --summary``; it follows edits
typed in Properties and their undo, and a linkage without masses or loads shows none."""
from __future__ import annotations

import contextlib
import io
import re

from mechsketch.core.cli import main as cli_main
from mechsketch.core.io.scene_file import save_scene
from mechsketch.resources import example_path

from app_fakes import shell, type_into  # noqa: F401 - fixture

EID = "loaded_fourbar"
#: lines whose numbers are times (they differ between two runs)
TIMED = re.compile(r"\d+(\.\d+)? (ms|µs)")


def cli_text(path) -> list[str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert cli_main(["analyze", str(path), "--forces", "--summary"]) == 0
    return out.getvalue().splitlines()


def untimed(lines: list[str]) -> list[str]:
    return [TIMED.sub("… ms", line.strip()) for line in lines]


def force_part(lines: list[str]) -> list[str]:
    start = next(k for k, line in enumerate(lines) if line.strip().startswith("forces of "))
    return lines[start:]


def panel_lines(parts) -> list[str]:
    return [line for line in parts.window.diagnostics.plain_text().splitlines() if line.strip()]


def test_the_forces_summary_is_the_clis_text(shell):
    parts = shell(example_path("fourbar_loaded"))
    shown = panel_lines(parts)
    expected = cli_text(example_path("fourbar_loaded"))
    assert untimed(force_part(shown)) == untimed(force_part(expected))
    assert any("driving torque (crank): peak 2.14729 N·m" in line for line in shown)
    assert any("with joint friction" in line for line in shown)
    assert any("power balance" in line for line in shown)
    # and every kinematic line of the CLI text is there too, in the same order
    kin = untimed(expected[:expected.index(force_part(expected)[0])])
    assert [line for line in untimed(shown) if line in kin] == kin


def test_it_follows_a_mass_typed_in_properties_and_its_undo(shell, qtbot, tmp_path):
    parts = shell(example_path("fourbar_loaded"))
    c = parts.controller
    before = force_part(panel_lines(parts))
    c.set_selection([(EID, "link", "rocker")])
    type_into(qtbot, parts.window.properties.fields["mass"], "3.5")
    after = force_part(panel_lines(parts))
    assert after != before
    save_scene(c.scene, tmp_path / "edited.json")
    assert untimed(after) == untimed(force_part(cli_text(tmp_path / "edited.json")))
    c.undo_stack.undo()
    assert untimed(force_part(panel_lines(parts))) == untimed(before)


def test_no_masses_and_no_loads_no_forces_summary(shell):
    parts = shell(example_path("fourbar_crank_rocker"))
    assert not any(line.strip().startswith("forces of ") for line in panel_lines(parts))
