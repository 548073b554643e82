"""The package as installed: wheel contents match the folders, core is Qt-free, entry point works."""
from __future__ import annotations

import os
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MAPPING = {"core": "mechsketch.core", "gui": "mechsketch.gui", "resources": "mechsketch.resources"}


def _folders() -> set[str]:
    out = set()
    for top, pkg in MAPPING.items():
        for init in (ROOT / top).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / top)
            out.add(".".join([pkg, *rel.parts]))
    return out


def test_pyproject_lists_every_package_folder():
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert set(conf["packages"]) == _folders()
    assert conf["package-dir"] == {v: k for k, v in MAPPING.items()}


def test_wheel_contains_every_package_and_resource(tmp_path):
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
                    "-w", str(tmp_path), str(ROOT)], check=True, capture_output=True)
    wheel = next(tmp_path.glob("mechsketch-*.whl"))
    names = zipfile.ZipFile(wheel).namelist()
    packages = {n.rsplit("/", 1)[0].replace("/", ".") for n in names if n.endswith("/__init__.py")}
    assert packages == _folders()
    for example in (ROOT / "resources" / "examples").glob("*.json"):
        assert f"mechsketch/resources/examples/{example.name}" in names
    for schema in (ROOT / "resources" / "schema").glob("*.json"):
        assert f"mechsketch/resources/schema/{schema.name}" in names
    assert not any(n.startswith(("core/", "gui/", "resources/", "tests/")) for n in names)
    # the offline manual (issue 24 item 8): the README, the getting-started page, every picture
    for name in ("README.md", "getting_started.md"):
        assert f"mechsketch/resources/manual/{name}" in names
    for picture in (ROOT / "docs" / "screenshots").glob("*.png"):
        assert f"mechsketch/resources/manual/pictures/{picture.name}" in names


def test_core_is_qt_free_and_works_without_qt():
    """Import every core module and run the CLI on every example with PySide6 made unimportable."""
    code = r"""
import importlib, pkgutil, sys, importlib.abc
class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in ('PySide6', 'pyqtgraph', 'shiboken6') or name.startswith('mechsketch.gui'):
            raise ModuleNotFoundError(name, name=name)
sys.meta_path.insert(0, Block())
import mechsketch.core as core
for m in pkgutil.walk_packages(core.__path__, 'mechsketch.core.'):
    importlib.import_module(m.name)
from mechsketch.core.cli import main
from mechsketch.resources import example_paths
for p in example_paths():
    assert main(['validate', str(p)]) == 0, p
bad = [m for m in sys.modules if m.split('.')[0] in ('PySide6', 'pyqtgraph')]
assert not bad, bad
print('ok')
"""
    env = dict(os.environ)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd="/")
    assert out.returncode == 0, out.stderr + out.stdout
    assert out.stdout.strip().endswith("ok")


def test_entry_point_runs_headless_commands():
    exe = Path(sys.executable).with_name("mechsketch")
    example = ROOT / "resources" / "examples" / "fourbar_crank_rocker.json"
    out = subprocess.run([str(exe), "validate", str(example)], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "ok" in out.stdout
