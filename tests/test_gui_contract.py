"""The import contract of the GUI (DESIGN.md, "Dependency direction"), read from the source with ``ast``.

Folders and files of ``gui/``, lowest first:

- **base** — ``background.py``, ``frames.py``, ``qpath.py``, ``qtsafe.py``, ``selection.py``,
  ``units.py`` (and the package itself): helpers every part reads (heavy solves off the GUI
  thread, frames and samples, array-to-path code, safe Qt overrides, selection keys, display
  units); they import no other GUI module but each other;
- **controller** — ``controller.py``, the Qt adapter over the workspace: base only;
- **canvas** (``gui/canvas/``) and **panels** (``gui/panels/``): base, the controller and their own
  folder; they never import each other (the main window wires them with signals);
- **help** (``gui/help/``, the manual and context help): base, the controller and its own folder;
- **app** — every other module at the top of ``gui/`` (the main window, the app, files, autosave,
  dialogs, the player, the scrub bar, export workers, the launcher): anything above.

Every import counts (in functions, TYPE_CHECKING blocks and ``importlib`` names too), and no GUI
module reaches itself through imports. Runs without Qt: it only reads the files.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest
from import_graph import import_cycles

GUI = Path(__file__).resolve().parents[1] / "gui"
PACKAGE = "mechsketch.gui"
BASE_FILES = {"__init__.py", "background.py", "frames.py", "qpath.py", "qtsafe.py", "selection.py", "units.py"}
RANK = {"base": 0, "controller": 1, "canvas": 2, "panels": 2, "help": 2, "app": 3}
#: groups of equal rank that must not import each other
PEERS = {"canvas": "panels", "panels": "canvas"}


def group_of_file(path: Path) -> str:
    rel = path.relative_to(GUI)
    if len(rel.parts) > 1:
        if rel.parts[0] not in ("canvas", "panels", "help"):
            raise AssertionError(f"gui/{rel}: a new GUI folder needs a place in this contract")
        return rel.parts[0]
    if rel.name in BASE_FILES:
        return "base"
    return "controller" if rel.name == "controller.py" else "app"


def module_of_file(path: Path) -> tuple[str, str]:
    """(module name, package name) of a GUI source file."""
    parts = [PACKAGE, *path.relative_to(GUI).with_suffix("").parts]
    if parts[-1] == "__init__":
        parts.pop()
        return ".".join(parts), ".".join(parts)
    return ".".join(parts), ".".join(parts[:-1])


def _files() -> list[Path]:
    return sorted(p for p in GUI.rglob("*.py") if "__pycache__" not in p.parts)


MODULES = {module_of_file(p)[0]: p for p in _files()}


def _own(target: str) -> str | None:
    """The GUI module an import target names (a name imported from a module: that module)."""
    while target.startswith(PACKAGE):
        if target in MODULES:
            return target
        target = target.rsplit(".", 1)[0]
    return None


def imports_of(path: Path) -> list[tuple[int, str]]:
    """(line, GUI module) for every import of a GUI module in ``path``, of every kind."""
    name, package = module_of_file(path)
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out = []
    for node in ast.walk(tree):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([node.module] if node.module else []))
            targets = [f"{base}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.startswith(PACKAGE + "."):
            targets = [node.value]
        for t in targets:
            own = _own(t)
            if own is not None and own != name:
                out.append((node.lineno, own))
    return out


def test_the_reader_resolves_relative_imports_to_modules():
    got = dict((m, line) for line, m in imports_of(GUI / "canvas" / "overlays.py"))
    assert "mechsketch.gui.canvas.items" in got and "mechsketch.gui.frames" in got
    assert group_of_file(GUI / "canvas" / "view.py") == "canvas"
    assert group_of_file(GUI / "frames.py") == "base" and group_of_file(GUI / "main_window.py") == "app"


@pytest.mark.parametrize("group", list(RANK))
def test_a_gui_part_imports_only_lower_parts_or_its_own(group):
    bad = []
    for path in _files():
        if group_of_file(path) != group:
            continue
        for line, target in imports_of(path):
            dst = group_of_file(MODULES[target])
            if dst == group:
                continue
            if RANK[dst] >= RANK[group] or PEERS.get(group) == dst:
                bad.append(f"gui/{path.relative_to(GUI)}:{line} imports {target} ({group} must not import {dst})")
    assert not bad, f"GUI import contract broken ({len(bad)}):\n  " + "\n  ".join(bad)


def test_no_import_cycle_in_the_gui():
    graph = {module_of_file(p)[0]: {m for _, m in imports_of(p)} for p in _files()}
    cycles = import_cycles(graph)
    assert not cycles, "import cycles in the GUI:\n  " + "\n  ".join(" <-> ".join(c) for c in cycles)
