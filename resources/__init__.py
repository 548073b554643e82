"""Packaged resources: example scenes, JSON schemas, icons."""
from __future__ import annotations

import json
from pathlib import Path


def _root():
    """The package folder (read as plain files: importlib.resources costs 5-8 ms of every command's
    start-up, issue 14); through importlib.resources only when the package is not on a file system."""
    here = globals().get("__file__")
    if here:
        return Path(here).parent
    from importlib import resources

    return resources.files(__name__)


def example_paths() -> list[Path]:
    """Every built-in example scene, sorted by file name."""
    folder = _root() / "examples"
    return sorted((Path(str(p)) for p in folder.iterdir() if p.name.endswith(".json")), key=lambda p: p.name)


def example_path(name: str) -> Path:
    """The example scene ``name`` (with or without ``.json``)."""
    stem = name[:-5] if name.endswith(".json") else name
    path = Path(str(_root() / "examples" / f"{stem}.json"))
    if not path.is_file():
        known = ", ".join(p.stem for p in example_paths())
        raise FileNotFoundError(f"no example scene {name!r}; examples: {known}")
    return path


def schema(name: str) -> dict:
    """A JSON schema shipped in ``schema/`` (e.g. ``"linkage.schema.json"``)."""
    return json.loads((_root() / "schema" / name).read_text(encoding="utf-8"))


DEFAULT_EXAMPLE = "fourbar_crank_rocker"
