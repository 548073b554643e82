"""What the Design dock runs on its worker thread (Qt-free): linkage synthesis from a path, poses or
an input–output function (issue 22), and Geneva drives, rolling levers and gear pairs from
requirements (issue 25).

:func:`linkage_target` reads the target table's rows into the core's checked target (in the GUI
thread, before anything runs: a bad target is refused at once, naming what to add or change);
:func:`linkage_work` and :func:`requirement_work` run on the worker thread with the
:class:`~.jobs.Ticket`'s callbacks. The core's design modules are imported when a design runs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

#: the linkage syntheses, and the requirement designs (kind -> words)
LINKAGE_MODES = {"path": "Path (a coupler point traces it)", "motion": "Motion (rigid-body poses)",
                 "function": "Function (input → output)"}
REQUIREMENT_MODES = {"geneva": "Geneva drive from requirements", "rolling": "Rolling lever with a slider law",
                     "gears": "Non-circular gears from a function"}
#: --topology of ``mechsketch design path``
PATH_TOPOLOGIES = ("fourbar", "slider_crank", "inverted_slider_crank", "sixbar", "any")
FUNCTION_TOPOLOGIES = ("fourbar", "slider_crank")


@dataclass(frozen=True)
class LinkageRequest:
    """A linkage synthesis as the dock asks it: ``mode`` ("path", "motion", "function"), the target
    table's ``rows`` (M, columns) in model units (mm, °), ``closed`` (a path), ``timed`` (a path
    with its third column the crank angle), ``unit`` of a function's output ("deg" or "mm"),
    ``topology``, and the core's ``options`` (a :class:`~mechsketch.core.design.options.LinkageOptions`)."""

    mode: str
    rows: np.ndarray
    options: Any
    topology: str = "fourbar"
    closed: bool = True
    timed: bool = False
    unit: str = "deg"


def linkage_target(req: LinkageRequest):
    """The core's checked target of ``req``; DesignError naming what is wrong."""
    from mechsketch.core.design.targets import function_target, path_target, pose_target

    rows = np.asarray(req.rows, dtype=float)
    if req.mode == "path":
        return path_target(rows[:, :2], closed=req.closed, inputs_deg=rows[:, 2] if req.timed else None)
    if req.mode == "motion":
        return pose_target(rows[:, :3])
    return function_target(rows[:, :2], req.unit)


def linkage_work(req: LinkageRequest, target, ticket):
    """The synthesis of ``req`` (a :class:`~mechsketch.core.design.options.DesignResult`)."""
    progress = ticket.synthesis_progress
    ticket.report(0.0, f"{req.mode} synthesis: starting")
    if req.mode == "path":
        from mechsketch.core.design.linkage_path import synthesize_path

        return synthesize_path(target, req.options, req.topology, progress=progress)
    if req.mode == "motion":
        from mechsketch.core.design.motion import synthesize_motion

        return synthesize_motion(target, req.options, progress=progress)
    from mechsketch.core.design.function import synthesize_function

    return synthesize_function(target, req.options, req.topology, progress=progress)


def requirement_work(kind: str, requirements: dict, element_id: str, ticket):
    """The design of ``kind`` ("geneva", "rolling", "gears") meeting ``requirements`` (a REQ dict
    as ``mechsketch design KIND`` reads it): the core's result, with ``element`` and ``report``."""
    progress = ticket.requirement_progress
    ticket.report(0.0, f"{kind}: reading the requirements")
    if kind == "geneva":
        if requirements.get("smooth") is not None:
            from mechsketch.core.design.smooth_geneva import design_smooth_geneva

            return design_smooth_geneva(requirements, element_id, progress=progress)
        from mechsketch.core.design.geneva import design_geneva

        return design_geneva(requirements, element_id, progress=progress)
    if kind == "rolling":
        from mechsketch.core.design.rolling import design_rolling

        return design_rolling(requirements, element_id, progress=progress)
    from mechsketch.core.design.gears import design_gears

    return design_gears(requirements, element_id, progress=progress)


def candidate_lines(c, rank: int) -> tuple[str, str]:
    """A candidate's title and numbers for the list: rank, topology and type; its largest
    deviation (and the poses' angle error), least transmission angle and time."""
    dev = f"max deviation {c.deviation:.3g} {c.unit}"
    if c.angle_deviation is not None:
        dev += f", {c.angle_deviation:.3g}°"
    return (f"{rank}. {c.topology.replace('_', ' ')}: {c.kind}",
            f"{dev} · μmin {c.min_transmission_deg:.1f}° · {c.seconds:.3f} s")


def report_rows(report) -> list[tuple[str, str, str, str, str, bool]]:
    """(requirement, what, value, limit, margin, binding) of each row of a
    :class:`~mechsketch.core.design.design_report.DesignReport`, as text."""
    out = []
    binding = report.binding
    for r in report.requirements:
        unit = f" {r.unit}" if r.unit else ""
        out.append((r.name, r.what, f"{_num(r.value)}{unit}", f"{r.sense} {_num(r.limit)}{unit}",
                    f"{100 * r.margin:+.3g} %", r is binding))
    return out


def _num(x: float) -> str:
    if isinstance(x, int) or (math.isfinite(x) and x == int(x) and abs(x) < 1e15):
        return f"{int(x)}"
    return f"{x:.6g}"


__all__ = ["FUNCTION_TOPOLOGIES", "LINKAGE_MODES", "LinkageRequest", "PATH_TOPOLOGIES", "REQUIREMENT_MODES",
           "candidate_lines", "linkage_target", "linkage_work", "report_rows", "requirement_work"]
