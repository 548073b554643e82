"""Files: scene JSON, CSV tables, DXF export."""
