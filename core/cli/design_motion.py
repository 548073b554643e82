"""``mechsketch design motion POSES.csv --out OUT.json``: four-bars whose coupler carries the
poses (columns ``x,y,angle_deg``: mm, mm, °), exact for 3 and 4 poses (Burmester), least squares
for more. Each candidate's joint ``P`` on link ``coupler`` passes through the poses."""
from __future__ import annotations

import argparse

HELP = "four-bars whose coupler passes through 3 or more poses (x, y, angle_deg)"


def add_arguments(p: argparse.ArgumentParser) -> None:
    from .design_args import add_common

    p.add_argument("poses", metavar="POSES.csv", help="columns x,y,angle_deg (mm, mm, degrees)")
    add_common(p)


def run(args: argparse.Namespace) -> int:
    from ..design.motion import synthesize_motion
    from ..design.targets import pose_target
    from .design_linkage import check_writable, options_from, read_columns, stderr_progress, write_result

    options = options_from(args)
    check_writable(args.out)
    cols = read_columns(args.poses, ("x", "y", "angle_deg"))
    target = pose_target(list(zip(cols["x"], cols["y"], cols["angle_deg"])))
    return write_result(synthesize_motion(target, options, stderr_progress()), args.out)
