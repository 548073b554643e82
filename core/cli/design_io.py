"""Shared pieces of the requirement-driven ``mechsketch design`` kinds (geneva, rolling, gears):
read the REQ file, write the designed element as a scene, print the report.

The REQ file is read like a scene file (a regular file of at most 10 MB, UTF-8 JSON); the result
is a scene of one element written atomically, which ``mechsketch validate`` accepts and the app
opens.
"""
from __future__ import annotations

import argparse
import sys
from typing import Any

from ..errors import RequestError


def add_common(p: argparse.ArgumentParser, default_id: str) -> None:
    """REQ, ``--out`` and ``--id``: the arguments every requirement-driven kind takes."""
    p.add_argument("requirements", metavar="REQ.json", help="the requirements (a JSON object; see the README)")
    p.add_argument("--out", required=True, metavar="OUT.json",
                   help="write the designed element as a scene file ('-': to standard output)")
    p.add_argument("--id", default=default_id, help=f"the element's id (default {default_id!r})")


def read_requirements(path: str) -> Any:
    """The REQ document; :class:`RequestError` naming the file's problem."""
    from ..io.scene_file import read_scene_text

    doc, problems = read_scene_text(path)
    if problems:
        raise RequestError(f"requirements {path}: " + "; ".join(p.message for p in problems))
    return doc


def write_result(elements: tuple, out: str, report_text: str) -> int:
    """Write the scene of ``elements`` to ``out`` (or stdout) and print the report; exit 0."""
    from ..io.scene_file import dumps_scene, save_scene
    from ..model.scene import Scene

    scene = Scene(tuple(elements))
    if out == "-":
        sys.stdout.write(dumps_scene(scene))
        print(report_text, file=sys.stderr)
    else:
        save_scene(scene, out)
        print(report_text)
        print(f"written: {out}")
    return 0
