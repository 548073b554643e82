"""The GUI monkey, bounded (issues 13 and 20): a fixed budget of seeded random user events on the
whole app (see tests/gui/monkey.py) raises nothing. ``python tools/gui_monkey.py`` runs the
big version (10,000 events and more) and counts tracebacks, hangs and crashes."""
from __future__ import annotations

import os

import pytest

from app_fakes import shell  # noqa: F401 - fixture
from monkey import run

#: the fixed budget CI runs (MECHSKETCH_MONKEY_EVENTS runs more by hand)
EVENTS = int(os.environ.get("MECHSKETCH_MONKEY_EVENTS", "600"))


@pytest.mark.slow
def test_random_user_events_raise_nothing(shell, qtbot, tmp_path):
    parts = shell(state_dir=tmp_path / "state")
    monkey, errors = run(parts, qtbot, EVENTS)
    assert not errors, errors[0]
    unexpected = [e for e in parts.dialogs.errors if "nexpected" in e[0] or "Traceback" in e[2]]
    assert not unexpected, unexpected[:3]
    assert len(monkey.log) >= EVENTS * 0.9
