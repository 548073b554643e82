"""A compiled solving step, and the surface of a plan that the branch search, the drives and a
solution read.

:class:`~.plan.Plan` runs the branch-point search (:mod:`.branches`, :mod:`.drive`) and makes
:class:`~.solution.Solution` objects, which in turn read the plan's steps and run them again:
they name what they use of it here, as :class:`StepPlan`, so that the plan imports them and they
do not import the plan.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Iterable, Protocol

import numpy as np

from ..model.linkage import Linkage
from . import kernels as K
from .structure import Group


@dataclass
class Step:
    """A compiled group: its record, the links it needs known, and its kernel call."""

    group: Group
    needs: tuple[str, str]
    run: Callable[[dict, int, "np.ndarray | None"], K.DyadOut]
    scale: float = 1.0   # length scale of the group (mm), for branch-point tolerances
    coord: float = 0.0   # largest drawn coordinate magnitude of the group and its known links, mm


class StepPlan(Protocol):
    """What the branch search, the drives and a solution read of a :class:`~.plan.Plan`."""

    linkage: Linkage
    steps: list[Step]
    theta0: float
    angle0: dict[str, float]
    coord_scale: float
    joint_at: dict[str, tuple[str, complex]]
    #: the plan's drive (:mod:`.drive`): a crank, slider or cylinder
    drive: Any

    @property
    def direction(self) -> float: ...
    @property
    def input_unit(self) -> str: ...
    def local(self) -> "StepPlan": ...
    def needed(self, links: Iterable[str]) -> set[int]: ...
    def closure(self, k: int) -> list[int]: ...
    def run_steps(self, inputs: np.ndarray, order: int, idx: Iterable[int], branches: dict[str, np.ndarray],
                  omega: float | None = None, alpha: float = 0.0, states: dict | None = None
                  ) -> dict[str, K.DyadOut]: ...
