"""GDAL/OGR as a reader of the exported DXF files (issue 23): ``ogrinfo`` (Debian's gdal-bin, which
``.ci/install`` installs) reads every entity, arcs stroked every 0.02° (so a stroked area or length
is within 2e-8 of the exact one), and its SQLite dialect (SpatiaLite) measures, per layer, the
length of every entity and the area of the region they bound (ST_BuildArea: an outline less its
holes; a drilling pattern's holes added)."""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest

STEP_DEG = 0.02
SQL = ("SELECT Layer, ST_Area(ST_BuildArea(ST_Union(ST_SnapToGrid(geometry, 0.000001)))) AS area, "
       "SUM(ST_Length(geometry)) AS length, COUNT(*) AS n, "
       "SUM(CASE WHEN SubClasses LIKE '%AcDbText%' THEN 1 ELSE 0 END) AS texts FROM entities GROUP BY Layer")


def ogrinfo() -> str:
    """The ogrinfo executable; the tests fail (they do not skip) where GDAL is missing."""
    exe = shutil.which("ogrinfo")
    if exe is None:
        pytest.fail("GDAL's ogrinfo is not installed: install the Debian package gdal-bin (.ci/install does)")
    return exe


def ogr_layers(path) -> dict[str, tuple[float, float, int, int]]:
    """Per layer of a DXF read by OGR: (area bounded mm², length mm, entities, TEXT entities)."""
    out = subprocess.run([ogrinfo(), "-q", "--config", "OGR_ARC_STEPSIZE", str(STEP_DEG), "-dialect", "SQLite",
                          "-sql", SQL, str(path)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    layers: dict[str, tuple[float, float, int]] = {}
    for block in out.stdout.split("OGRFeature")[1:]:
        layer = re.search(r"Layer \(String\) = (.*)", block)[1].strip()
        area = re.search(r"area \((?:Real|String)\) = (\S+)", block)
        length = re.search(r"length \((?:Real|String)\) = (\S+)", block)
        n = re.search(r"n \(Integer\) = (\d+)", block)
        texts = re.search(r"texts \(Integer\) = (\d+)", block)
        layers[layer] = (float(area[1]) if area and area[1] != "(null)" else 0.0,
                         float(length[1]) if length and length[1] != "(null)" else 0.0, int(n[1]), int(texts[1]))
    return layers
