"""Fixtures and import path for the core tests (the solver references live in reference.py)."""
from __future__ import annotations

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:
    sys.path.insert(0, HERE)

# the synthesis tests' small atlas, built once per session for every module that asks for it (a
# session fixture imported into each module would be one fixture per module, each building it)
from design_atlas_fixture import atlas_cache  # noqa: E402,F401  (fixture)
