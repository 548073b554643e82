"""Drawing defaults shared by the model's validation and the cut-ready parts.

A part keeps at least :data:`DEFAULT_MIN_WEB` mm of material between its holes and its edges
unless the element (``drawing.min_web`` of a Geneva drive) or the export (``--min-web``) says
otherwise; validation checks the same number, so a drive that validates can be cut.
"""
from __future__ import annotations

#: thinnest web (mm) a part keeps by default
DEFAULT_MIN_WEB = 1.0
