"""The import contract of core (DESIGN.md, "Dependency direction"), read from the source with ``ast``.

Layers, lowest first: ``errors.py`` (anyone may import it) < model < solver < analyses < studies <
design < io < workspace < cli, and ``core/__init__.py``, the public facade, on top. A module imports only from
its own layer or lower ones; nothing in core imports Qt, pyqtgraph or ``mechsketch.gui``; and model,
solver, analyses, studies, design and io import nothing of ours inside a function (a lazy import
there hides a cycle); and no two modules of core import each other, directly or through others
(TYPE_CHECKING imports included: a cycle of types is a cycle of meaning).
Every import counts, function-level ones included, except those under ``if TYPE_CHECKING:``; a
string constant that is a ``mechsketch.core...`` module name counts too (``importlib`` by name).
"""
from __future__ import annotations

import ast
import functools
import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest
from import_graph import import_cycles

import mechsketch.core

CORE = Path(mechsketch.core.__file__).resolve().parent
PACKAGE = "mechsketch.core"

#: rank of each layer; a module may import from layers of equal or lower rank
RANK = {"base": 0, "model": 1, "solver": 2, "analyses": 3, "studies": 4, "design": 5, "io": 6, "workspace": 7,
        "cli": 8, "facade": 9}
#: modules at the top of core, by file name
TOP_FILES = {"errors.py": "base", "runtime.py": "base", "__init__.py": "facade"}
#: layers whose modules may not import inside a function or class
NO_LAZY = ("base", "model", "solver", "analyses", "studies", "design", "io")
#: third-party packages that model/solver/analyses/io may import inside a function: heavy
#: (20-130 ms) and needed by few commands, so ``analyze --summary`` and the GUI's first frame do
#: not pay for them (issue 14). Our own modules never: a lazy import of one hides a cycle.
LAZY_THIRD_PARTY = ("jsonschema", "ezdxf", "shapely", "scipy", "dask", "distributed", "pymoo", "numba")
#: roots that no core module may import
FORBIDDEN = ("PySide6", "shiboken6", "pyqtgraph", "PyQt5", "PyQt6", "PySide2", "mechsketch.gui")
MODULE_NAME = re.compile(r"mechsketch(\.[A-Za-z_][A-Za-z0-9_]*)+")


@dataclass(frozen=True)
class Import:
    path: str      # relative to the repository root, e.g. core/model/linkage.py
    line: int
    text: str      # the statement as written
    target: str    # absolute module name
    nested: bool   # inside a function or class body

    def __str__(self) -> str:
        return f"{self.path}:{self.line}: {self.text}"


def layer_of_file(path: Path) -> str:
    rel = path.relative_to(CORE)
    if len(rel.parts) == 1:
        if rel.name not in TOP_FILES:
            raise AssertionError(f"core/{rel}: no layer for a new module at the top of core; "
                                 "put it in a layer folder or add it to TOP_FILES in this test")
        return TOP_FILES[rel.name]
    if rel.parts[0] not in RANK:
        raise AssertionError(f"core/{rel}: unknown layer folder {rel.parts[0]!r}; add it to RANK in this test")
    return rel.parts[0]


def layer_of_module(name: str) -> str | None:
    """The layer of an absolute module name inside core (None outside core)."""
    if name == PACKAGE:
        return "facade"
    if not name.startswith(PACKAGE + "."):
        return None
    first = name.split(".")[2]
    if first in ("errors", "runtime"):
        return "base"
    return first if first in RANK else "facade"


def module_name(path: Path) -> tuple[str, str]:
    """(module name, package name) of a core source file."""
    rel = path.relative_to(CORE).with_suffix("")
    parts = [PACKAGE, *rel.parts]
    if parts[-1] == "__init__":
        parts.pop()
        return ".".join(parts), ".".join(parts)
    return ".".join(parts), ".".join(parts[:-1])


def _is_submodule(name: str) -> bool:
    rel = name[len(PACKAGE):].lstrip(".").split(".") if name != PACKAGE else []
    base = CORE.joinpath(*rel) if rel else CORE
    return base.with_suffix(".py").is_file() or (base / "__init__.py").is_file()


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _docstring_nodes(tree: ast.AST) -> set[int]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                out.add(id(first.value))
    return out


def imports_of(path: Path, type_checking: bool = False) -> list[Import]:
    """Every import of a core file (TYPE_CHECKING blocks only if asked), with absolute targets."""
    return imports_in(path.read_text(encoding="utf-8"), module_name(path)[1], str(path.relative_to(CORE.parent)),
                      type_checking)


def imports_in(source: str, package: str, rel: str, type_checking: bool = False) -> list[Import]:
    """Every import of ``source``, a module of ``package`` shown as ``rel`` in messages."""
    tree = ast.parse(source, filename=rel)
    docstrings = _docstring_nodes(tree)
    found: list[Import] = []

    def record(node: ast.AST, target: str, nested: bool) -> None:
        text = ast.get_source_segment(source, node) or ast.unparse(node)
        found.append(Import(rel, node.lineno, " ".join(text.split()), target, nested))

    def visit(node: ast.AST, nested: bool) -> None:
        if isinstance(node, ast.If) and _is_type_checking(node.test) and not type_checking:
            for child in node.orelse:
                visit(child, nested)
            return
        if isinstance(node, ast.Import):
            for alias in node.names:
                record(node, alias.name, nested)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = package.split(".")
                base_parts = parts[:len(parts) - (node.level - 1)]
                base = ".".join(base_parts + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            for alias in node.names:
                full = f"{base}.{alias.name}"
                record(node, full if base.startswith(PACKAGE) and _is_submodule(full) else base, nested)
        elif (isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings
              and MODULE_NAME.fullmatch(node.value)):
            record(node, node.value, nested)
        inner = nested or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef))
        for child in ast.iter_child_nodes(node):
            visit(child, inner)

    for stmt in tree.body:
        visit(stmt, False)
    return found


def core_files() -> list[Path]:
    return sorted(p for p in CORE.rglob("*.py") if "__pycache__" not in p.parts)


@functools.cache
def all_imports() -> tuple[tuple[str, Import], ...]:
    """(layer of the importing file, import) for every import in core (read once per session)."""
    return tuple((layer_of_file(p), imp) for p in core_files() for imp in imports_of(p))


def _report(title: str, bad: list[str]) -> str:
    return f"{title} ({len(bad)}):\n  " + "\n  ".join(bad)


# -- the reader itself ---------------------------------------------------------------------------
SAMPLE = """\"""mechsketch.core.solver is named here, in a docstring: not an import.\"""
from typing import TYPE_CHECKING
import numpy as np
from ..errors import GeometryError
from . import edits
from .linkage import Linkage
from mechsketch import resources

if TYPE_CHECKING:
    from ..analyses.centrodes import Centrodes
else:
    from ..io import table

NAMES = {"x": "mechsketch.core.solver.plan"}


def lazy():
    from ..solver.plan import compile_plan


class Holder:
    import json
"""


def test_the_reader_resolves_imports_and_skips_type_checking_and_docstrings():
    got = [(i.line, i.target, i.nested) for i in imports_in(SAMPLE, "mechsketch.core.model", "core/model/x.py")]
    assert got == [(2, "typing", False), (3, "numpy", False), (4, "mechsketch.core.errors", False),
                   (5, "mechsketch.core.model.edits", False), (6, "mechsketch.core.model.linkage", False),
                   (7, "mechsketch", False), (12, "mechsketch.core.io.table", False),
                   (14, "mechsketch.core.solver.plan", False), (18, "mechsketch.core.solver.plan", True),
                   (22, "json", True)]
    assert str(imports_in(SAMPLE, "mechsketch.core.model", "core/model/x.py")[-2]) == (
        "core/model/x.py:18: from ..solver.plan import compile_plan")
    assert layer_of_module("mechsketch.core") == "facade"
    assert layer_of_module("mechsketch.core.errors") == "base"
    assert layer_of_module("mechsketch.core.io.table") == "io"
    assert layer_of_module("mechsketch.resources") is None
    assert layer_of_file(CORE / "errors.py") == "base" and layer_of_file(CORE / "io" / "table.py") == "io"
    assert layer_of_file(CORE / "__init__.py") == "facade"


def test_every_core_module_has_a_layer():
    for path in core_files():
        assert layer_of_file(path) in RANK


# -- the contract --------------------------------------------------------------------------------
@pytest.mark.parametrize("layer", ["base", "model", "solver", "analyses", "studies", "design", "io", "workspace",
                                   "cli"])
def test_a_layer_imports_only_its_own_or_lower_layers(layer):
    bad = []
    for src, imp in all_imports():
        if src != layer:
            continue
        dst = layer_of_module(imp.target)
        if dst is not None and RANK[dst] > RANK[src]:
            bad.append(f"{imp}   ({src} must not import {dst}: {imp.target})")
    assert not bad, _report(f"upward imports from {layer}", bad)


def test_nothing_in_core_imports_qt_pyqtgraph_or_the_gui():
    bad = [f"{imp}   ({imp.target})" for _, imp in all_imports()
           if any(imp.target == f or imp.target.startswith(f + ".") for f in FORBIDDEN)]
    assert not bad, _report("core imports Qt, pyqtgraph or the GUI", bad)


@pytest.mark.parametrize("layer", NO_LAZY)
def test_no_function_level_import(layer):
    bad = [str(imp) for src, imp in all_imports() if src == layer and imp.nested
           and imp.target.split(".")[0] not in LAZY_THIRD_PARTY]
    assert not bad, _report(f"imports inside a function or class in {layer} (move them to the top; "
                            "if that makes a cycle, the code is in the wrong module)", bad)


def test_importing_core_and_its_cli_loads_no_qt():
    code = ("import sys, mechsketch.core, mechsketch.core.cli\n"
            f"bad = sorted(m for m in sys.modules if m.split('.')[0] in {FORBIDDEN[:-1]!r} "
            "or m.startswith('mechsketch.gui'))\n"
            "print(bad)\n")
    env = {k: v for k, v in os.environ.items() if k != "MECHSKETCH_BLOCK_QT"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd="/")
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]", f"importing mechsketch.core and its CLI loaded {out.stdout.strip()}"


def test_the_cycle_finder_finds_cycles():
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert import_cycles({"a": {"b"}, "b": set(), "c": {"b"}}) == []
    assert import_cycles({"a": {"b"}, "b": {"a"}, "c": {"d"}, "d": {"c"}}) == [["a", "b"], ["c", "d"]]


def test_no_import_cycle_in_core():
    """No module of core reaches itself through imports of any kind (TYPE_CHECKING, in functions)."""
    graph: dict[str, set[str]] = {}
    for path in core_files():
        name = module_name(path)[0]
        graph[name] = {_module_of(imp.target) for imp in imports_of(path, type_checking=True)} - {None, name}
    cycles = import_cycles(graph)
    assert not cycles, "import cycles in core:\n  " + "\n  ".join(" <-> ".join(c) for c in cycles)


def _module_of(target: str) -> str | None:
    """The core module that an import target names (a name imported from a module: that module)."""
    while target.startswith(PACKAGE):
        if _is_submodule(target):
            return target
        target = target.rsplit(".", 1)[0]
    return None
