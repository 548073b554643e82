"""Issue 13 item 12 for the app's own writers: a plot image or table keeps an overwritten file's
mode, a new one follows the umask, and a symlink is written through."""
from __future__ import annotations

import os
import stat
import sys

import pytest

from app_fakes import shell  # noqa: F401 - fixture

pytestmark = pytest.mark.skipif(sys.platform.startswith("win"), reason="POSIX modes")


def _mode(p) -> int:
    return stat.S_IMODE(os.stat(p).st_mode)


@pytest.mark.parametrize("kind", ["png", "csv"])
def test_plot_exports_keep_modes_and_follow_links(shell, tmp_path, kind):
    parts = shell()
    plots = parts.window.plots
    write = plots.export_png if kind == "png" else plots.export_csv
    old = os.umask(0o022)
    try:
        fresh = tmp_path / f"new.{kind}"
        write(fresh)
        assert _mode(fresh) == 0o644
        shared = tmp_path / f"shared.{kind}"
        shared.write_bytes(b"old")
        os.chmod(shared, 0o664)
        link = tmp_path / f"link.{kind}"
        link.symlink_to(shared.name)
        write(link)
        assert link.is_symlink() and _mode(shared) == 0o664 and shared.read_bytes() != b"old"
    finally:
        os.umask(old)
    assert not list(tmp_path.glob(".*"))
