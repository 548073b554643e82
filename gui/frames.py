"""Frames of the animation and the samples of a solution: which sample a frame shows, the input
as a person reads it, and walking through valid samples only, so that neither the animation nor
a crank drag nor the scrub bar ever jumps across an infeasible gap.

Qt-free, and below the controller, the canvas, the panels and the player, which all read it.
"""
from __future__ import annotations

import math
from typing import Iterable

import numpy as np

from mechsketch.core.model.drivers import input_text
from mechsketch.core.solver.solution import Solution


def map_frame(frame: int, n_frames: int, n: int) -> int:
    """The sample of a solution with ``n`` samples shown at global frame ``frame`` of ``n_frames``."""
    if n_frames <= 0 or n == n_frames:
        return frame % max(n, 1)
    return int(round(frame * n / n_frames)) % n


def input_value_text(sol: Solution, k: int, digits: int = 1) -> str:
    """The input at sample ``k`` as read by a person: a crank angle in degrees within ±180°, an
    actuator's length or displacement in mm."""
    unit = sol.plan.input_unit
    v = float(sol.input[k])
    return input_text(v if unit == "mm" else math.remainder(v, 2 * math.pi), unit, digits)


def dead_samples(sol: Solution, valid: np.ndarray, inputs: Iterable[float]) -> list[int]:
    """For each driver input (rad, the sweep's unwrapped convention; mm for an actuator), the
    nearest valid sample. A constant-speed crank's samples are equally spaced; any other law's
    are searched (the first sample nearest the input; angles compared modulo a turn)."""
    n = len(sol)
    inp = np.asarray(sol.input, dtype=float)
    drv = sol.plan.linkage.driver
    uniform = not drv.linear and drv.law.is_constant
    step = float(inp[1] - inp[0]) if n > 1 else 1.0
    out = []
    for x in inputs:
        if uniform:
            k = int(round((x - float(inp[0])) / step)) % n
        else:
            d = inp - x if drv.linear else np.remainder(inp - x + np.pi, 2 * np.pi) - np.pi
            k = int(np.argmin(np.abs(d)))
        near = nearest_valid(valid, k)
        out.append(k if near is None else near)
    return out


# -- walking frames through valid samples only -----------------------------------------------

def nearest_valid(valid: np.ndarray, k: int) -> int | None:
    """The valid sample nearest to ``k`` (cyclic), or None if none is valid."""
    n = len(valid)
    if n == 0:
        return None
    k %= n
    if valid[k]:
        return k
    idx = np.flatnonzero(valid)
    if not idx.size:
        return None
    d = np.minimum((idx - k) % n, (k - idx) % n)
    return int(idx[int(np.argmin(d))])


def _walk(valid: np.ndarray, start: int, steps: int, direction: int) -> tuple[int, bool]:
    """Go ``steps`` samples from ``start`` in ``direction``; stop before an invalid one."""
    n = len(valid)
    path = (start + direction * np.arange(1, steps + 1)) % n
    bad = np.flatnonzero(~valid[path])
    if not bad.size:
        return (int(path[-1]) if steps else start), False
    first = int(bad[0])
    return (int(path[first - 1]) if first else start), True


def walk_to(valid: np.ndarray, start: int, target: int, cyclic: bool = True) -> tuple[int, bool]:
    """Move from ``start`` towards ``target`` through valid samples only.

    ``cyclic``: the shorter way round the cycle (a crank follows the mouse); otherwise straight
    along the sample index (a scrub bar). Returns ``(index reached, blocked)``; when blocked the
    index is the last valid sample before the gap (a reachable limit), never one beyond it.
    """
    n = len(valid)
    if n == 0:
        return 0, False
    start, target = start % n, target % n
    if target == start:
        return start, False
    if cyclic:
        fwd = (target - start) % n
        steps, direction = (fwd, 1) if fwd <= n - fwd else (n - fwd, -1)
    else:
        steps, direction = abs(target - start), (1 if target > start else -1)
    return _walk(valid, start, steps, direction)
