"""The ``mechsketch`` entry point: headless subcommands, or the desktop app.

Imports no Qt at module level, so headless commands work where no display (or no Qt) exists.
"""
from __future__ import annotations

import sys
from typing import Sequence

HEADLESS = {"analyze", "validate", "export", "synthesize", "centrodes"}


def prepare_process() -> None:
    """What the process sets before numpy is imported, for the app and the headless commands alike."""
    from mechsketch.core.cli import single_blas_thread
    from mechsketch.core.runtime import tune_allocator

    single_blas_thread()   # OpenBLAS threads only slow the start (core/cli: single_blas_thread)
    tune_allocator()   # glibc malloc keeps the sweeps' arrays (ctypes only)


def main(argv: Sequence[str] | None = None) -> int:
    """``mechsketch`` with no arguments opens the app on a built-in example; ``open SCENE`` a file."""
    prepare_process()
    args = list(sys.argv[1:] if argv is None else argv)
    if args and args[0] in HEADLESS | {"-h", "--help"}:
        from mechsketch.core.cli import main as cli_main

        if args[0] == "export" and any(a == "--pdf" or a.startswith("--pdf=") for a in args):
            from mechsketch.core.cli import export_cmds
            from mechsketch.gui.drawing_pdf import write_pdf

            export_cmds.PDF_WRITER = write_pdf   # Qt's PDF writer draws the sheets (core has no Qt)

        return cli_main(args)
    if args and args[0] not in ("open",):
        from mechsketch.core.cli import main as cli_main

        return cli_main(args)  # argparse explains the unknown command
    scene = args[1] if len(args) > 1 else None
    try:
        from mechsketch.gui.app import run_app
    except ImportError as exc:
        print(f"mechsketch: the desktop app is not available ({exc}); headless commands: "
              f"{', '.join(sorted(HEADLESS))}", file=sys.stderr)
        return 1
    return run_app(scene)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
