"""CLI handlers for rolling-lever elements: ``synthesize`` (CSV table + summary) and ``export`` (DXF).

``synthesize`` columns: theta alpha F.x F.y P.x P.y u1 P0.x P0.y u2 k53 S5 Q.x Q.y (mm, rad, mm/rad
for k53; Q in the slider frame), one row per stroke sample k = 0…N of the element's method.
"""
from __future__ import annotations

import os

from ..analyses.rolling_report import summary
from ..analyses.rolling_synthesis import synthesize as _synthesize
from ..io.dxf_rolling import export_rolling
from ..model.rolling_lever import RollingLever
from . import Analysis


def synthesize(element: RollingLever) -> Analysis:
    """Synthesise the element's profiles with its method and N; table and summary (with slip measures)."""
    res = _synthesize(element, measures=True)
    return Analysis(res.table(), summary(res))


def export(element: RollingLever, path: str | os.PathLike, tolerance: float) -> str:
    """Write the DXF (frame profile, lever outline, slider profile; mm); returns the report text."""
    res = _synthesize(element, measures=False)
    return export_rolling(res, path, tolerance).report()
