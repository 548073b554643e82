"""Shared DXF plumbing: a new document in millimetres, layers, and an atomic save.

Part-specific writers (Geneva wheel, rolling-lever profiles) build on these helpers. ezdxf
(about 0.1 s to import) is imported when a document is made, not with this module.
"""
from __future__ import annotations

import os

from .atomic import atomic_write

DXF_VERSION = "R2010"


def new_document(layers: dict[str, int] | None = None):
    """A new R2010 DXF document whose drawing units are millimetres ($INSUNITS = 4).

    ``layers`` maps layer name -> ACI colour; each is created.
    """
    import ezdxf
    from ezdxf import units

    doc = ezdxf.new(DXF_VERSION, setup=False, units=units.MM)
    doc.header["$INSUNITS"] = units.MM
    doc.header["$MEASUREMENT"] = 1  # metric
    doc.header["$LUNITS"] = 2  # decimal
    for name, colour in (layers or {}).items():
        if name not in doc.layers:
            doc.layers.add(name, color=colour)
    return doc


def save_document(doc, path: str | os.PathLike) -> None:
    """Save atomically (temporary file, then rename); :class:`ExportError` names the path."""
    atomic_write(path, doc.saveas)
