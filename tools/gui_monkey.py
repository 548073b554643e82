"""The big GUI monkey run (issue 20, done-when): many thousand seeded random user events on the
whole app (the monkey: tests/gui/monkey.py), counting tracebacks, hangs and crashes. Not a test
(tests/gui/test_monkey.py runs a bounded version in CI). From the repository root::

    .venv/bin/python tools/gui_monkey.py --events 10000 [--seed N] [--runs K] [--hang S]

Each run is a child process (offscreen Qt) so that a crash is counted, not suffered: its exit
status says how it ended (a signal is a crash), a single event blocking for ``--hang`` seconds
dumps every thread's stack and ends the child (a hang), and every exception that reaches
``sys.excepthook`` is a traceback (the run stops at the first and prints it with the events
before it). The parent prints one line per run and the totals.
"""
from __future__ import annotations

import argparse
import faulthandler
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1] / "tests" / "gui"   # the monkey and the app's test fakes
HANG_EXIT = 3


class _Bot:
    """The few pytest-qt ``qtbot`` calls the monkey makes, on QTest."""

    def __getattr__(self, name):
        from PySide6.QtTest import QTest

        return getattr(QTest, name)

    @staticmethod
    def keyClick(widget, key, modifier=None):  # noqa: N802 - QTest's name
        from PySide6.QtCore import Qt
        from PySide6.QtTest import QTest

        QTest.keyClick(widget, key, modifier if modifier is not None else Qt.KeyboardModifier.NoModifier)


def child(events: int, seed: int, hang: float, trace: str = "") -> int:
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    sys.path.insert(0, str(HERE))
    from app_fakes import FakeDialogs   # noqa: E402 - the test helpers, by path
    from monkey import run

    from mechsketch.gui.app import build

    state = Path(tempfile.mkdtemp(prefix="monkey-"))
    parts = build(dialogs=FakeDialogs(), settings_path=state / "settings.ini", state_dir=state / "state",
                  offer_recovery=False)
    parts.window.show()
    started = time.perf_counter()

    slowest = [0.0, 0]
    last = [time.perf_counter()]

    def watchdog(k: int) -> None:   # re-armed after every event: one event may take `hang` s
        faulthandler.dump_traceback_later(hang, exit=True)
        if trace:   # what a hang's stack does not say: the events before it and the scene's size
            sizes = [(e.id, e.type, len(getattr(e, "joints", ())), getattr(e, "samples", getattr(e, "points", None)))
                     for e in parts.controller.scene.elements]
            Path(trace).write_text("\n".join(monkey_ref[0].log[-20:]) + f"\nscene: {sizes}\n", encoding="utf-8")
        now = time.perf_counter()
        if now - last[0] > slowest[0]:
            slowest[:] = [now - last[0], k]
        last[0] = now

    faulthandler.dump_traceback_later(hang, exit=True)
    monkey_ref: list = []
    monkey, errors = run(parts, _Bot(), events, seed=seed, on_event=watchdog, on_start=monkey_ref.append)
    faulthandler.cancel_dump_traceback_later()
    seconds = time.perf_counter() - started
    if errors:
        print(errors[0], file=sys.stderr)
    print(json.dumps({"steps": monkey.steps, "events": len(monkey.log), "tracebacks": len(errors),
                      "seconds": round(seconds, 1), "slowest_step_s": round(slowest[0], 2),
                      "slowest_step": slowest[1], "load": os.getloadavg()[0]}))
    parts.autosave.stop()
    sys.stdout.flush()
    os._exit(0)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--events", type=int, default=10000, help="events per run (default 10000)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the first run (default 1)")
    ap.add_argument("--runs", type=int, default=1, help="runs, seeds seed, seed+1, ... (default 1)")
    ap.add_argument("--hang", type=float, default=30.0,
                    help="seconds one step (an event or a burst) may take before it counts as a hang (default 30)")
    ap.add_argument("--trace", default="", help="file the child rewrites after each step with the last events "
                    "and the scene's elements (read it after a hang)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return child(args.events, args.seed, args.hang, args.trace)
    totals = {"steps": 0, "events": 0, "tracebacks": 0, "hangs": 0, "crashes": 0}
    for seed in range(args.seed, args.seed + args.runs):
        cmd = [sys.executable, __file__, "--child", "--events", str(args.events), "--seed", str(seed),
               "--hang", str(args.hang), "--trace", args.trace]
        out = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, QT_QPA_PLATFORM="offscreen"))
        last = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else ""
        got = json.loads(last) if last.startswith("{") else {}
        hang = out.returncode == HANG_EXIT or (out.returncode == 1 and "Timeout" in out.stderr)
        crash = out.returncode < 0
        totals["steps"] += got.get("steps", 0)
        totals["events"] += got.get("events", 0)
        totals["tracebacks"] += got.get("tracebacks", 0)
        totals["hangs"] += int(hang)
        totals["crashes"] += int(crash)
        print(f"seed {seed}: exit {out.returncode}, {got or 'no summary'}", flush=True)
        if got.get("tracebacks") or hang or crash or not got:
            print(out.stderr[-4000:], file=sys.stderr)
    print("total:", json.dumps(totals))
    return 0 if totals["tracebacks"] == totals["hangs"] == totals["crashes"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
