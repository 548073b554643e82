"""A small atlas for the synthesis tests: built once per session into a temporary cache folder
(``MECHSKETCH_CACHE_DIR``), so that no test reads or writes the user's cache."""
from __future__ import annotations

import os

import pytest

from mechsketch.core.design.atlas import forget_loaded, load_atlas

#: designs per topology of the test atlas (about a second to build each)
TEST_DESIGNS = 4000


@pytest.fixture(scope="session")
def atlas_cache(tmp_path_factory):
    """The temporary cache folder with the test atlases of the nine topologies."""
    folder = tmp_path_factory.mktemp("mechsketch-cache")
    old = {k: os.environ.get(k) for k in ("MECHSKETCH_CACHE_DIR", "MECHSKETCH_ATLAS_DESIGNS")}
    os.environ["MECHSKETCH_CACHE_DIR"] = str(folder)
    os.environ["MECHSKETCH_ATLAS_DESIGNS"] = str(TEST_DESIGNS)
    forget_loaded()
    for top in ("fourbar", "slider_crank", "inverted_slider_crank", "sixbar", "watt_sixbar", "sixbar_slider",
                "watt_sixbar_slider", "sixbar_guide", "watt_sixbar_guide"):
        load_atlas(top)
    yield folder
    forget_loaded()
    for k, v in old.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v
