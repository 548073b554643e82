"""Cut-ready parts: closed outlines of exact lines and arcs with their holes, checked, laid out.

Parts are derived data like solutions: the builders (:mod:`.linkage`, :mod:`.geneva`,
:mod:`.rolling`) make them from the model, :func:`check_part` checks each one (closed,
finite, a valid polygon without self-intersection, holes inside and apart, the thinnest web at
least a minimum) and :func:`lay_out` places them on a sheet (``assembled`` in the mechanism's
frame, or ``apart``: side by side without overlap, each named). Writers (``core/io/dxf_parts.py``,
``core/io/svg_parts.py``) only serialise a :class:`Sheet`.

Geometry is in millimetres. A :class:`~..contour.Contour` is a closed chain of lines and
arcs (vertices and DXF bulges); outer contours are counter-clockwise.

This package's ``__init__`` is the one place callers import records and checks from; the code lives in
- :mod:`.outline`: contours made (circle, stadium, rectangle, the exact hull of discs) and
  queried (orientation, exact bounds, is it a circle);
- :mod:`.records`: :class:`Part`, :class:`Curve`, :class:`PartSet`;
- :mod:`.check`: the checks, the thinnest web (how it is measured is said there) and the
  report lines; :mod:`.distance` (exact distances between contours through a spatial index) and
  :mod:`.thickness` (the outline's thickness along its normals) measure it;
- :mod:`.layout`: :class:`Sheet` and :func:`lay_out`;
- :mod:`.keys`: what the user can change, named as the front end in use names it.
"""
from __future__ import annotations

from .check import (DEFAULT_MIN_WEB, PartCheck, check_part, check_parts, check_tolerance, failures, report_lines,
                    require_checked, thinnest_web)
from .thickness import HEAD_ON_DEG, NECK_SAMPLES, necks
from .keys import API, Vocabulary, name_of, names_of
from .layout import LAYOUTS, Label, Sheet, lay_out
from .outline import ccw, circle, contour_bounds, disc_hull, is_circle, rectangle, reversed_contour, stadium
from .records import CHECK_TOL, Curve, Part, PartSet

__all__ = ["API", "CHECK_TOL", "DEFAULT_MIN_WEB", "HEAD_ON_DEG", "LAYOUTS", "NECK_SAMPLES", "Curve", "Label", "Part",
           "PartCheck", "PartSet", "Sheet", "ccw", "check_part", "check_parts", "check_tolerance", "circle", "contour_bounds",
           "Vocabulary", "disc_hull", "failures", "is_circle", "name_of", "names_of", "lay_out", "necks", "rectangle", "report_lines", "require_checked",
           "reversed_contour", "stadium", "thinnest_web"]
