"""The one-line Python API: an element of a workspace that solves itself.

``Workspace.open("scene.json")["sixbar"].solve(samples=3600)`` reads like a method of the model,
but the model records know nothing of solvers: :class:`ElementView` is a thin handle above the
layers that reads the record and asks the workspace (and so its caches) for every result.
Each method imports the analysis it calls: importing the workspace (as every CLI command does)
loads no analysis a command does not use (issue 14).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Iterable, Protocol

from ..errors import RequestError
from ..model.edits import Edit

if TYPE_CHECKING:  # pragma: no cover
    from ..analyses.forces.kinetostatics import ForceResult
    from ..studies.tolerance import LinearBand, ToleranceResult
    from ..studies.variants import Variants
    from ..analyses.geneva.contact import GenevaContact
    from ..analyses.geneva.geometry import GenevaGeometry
    from ..analyses.geneva.kinematics import GenevaKinematics
    from ..analyses.rolling.synthesis import RollingSynthesis
    from ..solver.dimensions import Dimension
    from ..solver.plan import Plan, Solution
    from .results import ElementResult


class Host(Protocol):
    """What a view asks of its workspace (:class:`~.workspace.Workspace` is one; the workspace
    imports this module, so the view names the methods it needs instead of the class)."""

    def element(self, element_id: str) -> Any: ...
    def apply(self, edit: Edit) -> Edit: ...
    def result(self, element_id: str) -> "ElementResult | None": ...
    def plan(self, element_id: str) -> "Plan": ...
    def solve(self, element_id: str, samples: int | None = None, order: int = 2,
              joints: Iterable[str] | None = None) -> "Solution": ...
    def forces(self, element_id: str, samples: int | None = None) -> "ForceResult": ...


class ElementView:
    """Element ``element_id`` of ``workspace``: its record's attributes plus the one-line API.

    Attribute reads (``view.joints``, ``view.slots``...) go to the element's current record.
    """

    def __init__(self, workspace: Host, element_id: str) -> None:
        workspace.element(element_id)  # UnknownIdError naming the scene's ids
        self._ws = workspace
        self._id = element_id

    @property
    def record(self) -> Any:
        """The element's immutable record as the scene holds it now."""
        return self._ws.element(self._id)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        return getattr(self.record, name)

    def __repr__(self) -> str:
        return f"ElementView({self._id!r}, {type(self.record).__name__})"

    def _need(self, *types: str) -> Any:
        rec = self.record
        if rec.type not in types:
            raise RequestError(f"element {self._id!r} is a {rec.type}; this applies to {' or '.join(types)}")
        return rec

    def result(self) -> "ElementResult | None":
        """The workspace's cached result of this element (see :mod:`mechsketch.core.workspace.results`)."""
        return self._ws.result(self._id)

    def summary(self) -> str:
        """The report text ``mechsketch analyze/synthesize --summary`` prints for this element."""
        res = self.result()
        return res.summary() if res is not None else f"{self._id}: nothing to report"

    # -- linkages -------------------------------------------------------------------------
    def compile(self) -> Plan:
        """The compiled structural plan (raises StructureError / GeometryError)."""
        self._need("linkage")
        return self._ws.plan(self._id)

    def solve(self, samples: int | None = None, order: int = 2, joints: Iterable[str] | None = None
              ) -> Solution:
        """One driver revolution: N = ``samples`` (default the element's), derivative ``order``
        0-2, only what ``joints`` depend on. Joint arrays (N, 2) mm; see :class:`Solution`."""
        self._need("linkage")
        return self._ws.solve(self._id, samples=samples, order=order, joints=joints)

    def forces(self, samples: int | None = None) -> ForceResult:
        """Driving torque, joint reactions, shaking force and moment over one revolution, with the
        power balance (SI units; arrays (N,) or (N, 2); see :class:`ForceResult`)."""
        self._need("linkage")
        return self._ws.forces(self._id, samples=samples)

    def dimensions(self) -> list[Dimension]:
        """Every length (mm) and angle (°) of the linkage, link by link: the dimension table
        (:mod:`mechsketch.core.solver.dimensions`)."""
        from ..solver.dimensions import dimensions

        return dimensions(self._need("linkage"))

    def set_dimension(self, key: str, value: float) -> Any:
        """Set one dimension (``"length:crank:A:B"``, …) and re-assemble the linkage at its drawn
        input, as one undoable edit of the workspace: returns the inverse edit. Raises EditError
        naming the group that cannot close and by how much (nothing changes)."""
        from ..solver.dimensions import SetDimension

        self._need("linkage")
        return self._ws.apply(SetDimension(self._id, key, value))

    # -- design studies (core/studies) ---------------------------------------------------
    def solve_variants(self, values: dict, samples: int | None = None, order: int = 2,
                       joints: Iterable[str] | None = None, links: Iterable[str] | None = None,
                       progress: Any = None) -> Variants:
        """D variants of this linkage at once: ``values`` {key: array (D,)} (dimension keys, pivots
        ``x:J``/``y:J``, coupler points, masses, loads: :mod:`mechsketch.core.studies.keys`).
        ``b.position("E")`` (D, N, 2) mm, ``b.velocity``, ``b.acceleration``, ``b.angle(link)``
        (D, N), ``b.valid`` (D, N), ``b.full_cycle`` (D,), ``b.min_transmission_angle`` (D,) °,
        ``b.forces()``; see :class:`~mechsketch.core.studies.variants.Variants`."""
        from ..studies.variants import solve_variants

        return solve_variants(self._need("linkage"), values, samples=samples, order=order, joints=joints,
                              links=links, progress=progress)

    def tolerance(self, spec: dict, builds: int = 10_000, samples: int | None = None, seed: int = 0,
                  client: Any = None, workers: int = 1, joints: Iterable[str] | None = None,
                  links: Iterable[str] | None = None, progress: Any = None, cancel: Any = None) -> ToleranceResult:
        """Tolerance and pin-clearance Monte Carlo of B = ``builds`` builds: ``spec`` {key:
        {"normal": σ} | {"uniform": half-width}, "clearance": {joint: "H7/g6"}}. ``t.deviation("E")``
        (B,) mm, ``t.envelope("E", q)`` (N, 2), ``t.angle_deviation(link)`` (B,) °,
        ``t.sensitivity()``; ``client`` a Dask client or scheduler address; see
        :mod:`mechsketch.core.studies.tolerance`."""
        from ..studies.tolerance import tolerance

        return tolerance(self._need("linkage"), spec, builds=builds, samples=samples, seed=seed, joints=joints,
                         links=links, client=client, workers=workers, progress=progress, cancel=cancel)

    def linearised_tolerance(self, spec: dict, samples: int | None = None, joints: Iterable[str] | None = None,
                             links: Iterable[str] | None = None) -> LinearBand:
        """The first-order band of ``spec`` from the exact derivatives (one solve): ``.sigma(j)``,
        ``.band(j, k=3)``, ``.envelope(j)``, ``.sensitivity(j)``, ``.agreement(t, j)`` against a
        Monte Carlo ``t``."""
        from ..studies.tolerance import linearised_tolerance

        return linearised_tolerance(self._need("linkage"), spec, samples=samples, joints=joints, links=links)

    # -- Geneva drives --------------------------------------------------------------------
    def kinematics(self, samples: int | None = None) -> GenevaKinematics:
        """Wheel angle, ω, α and jerk over one crank revolution (arrays (N,))."""
        from ..analyses.geneva.kinematics import kinematics

        rec = self._need("geneva")
        return kinematics(rec, samples or rec.samples)

    def contact(self, samples: int | None = None, model: Any = None) -> GenevaContact:
        """Roller/slot contact and wear over one crank revolution (arrays (N,))."""
        from ..analyses.geneva.contact import contact

        rec = self._need("geneva")
        return contact(rec, samples or rec.samples, model or rec.model)

    def geometry(self) -> GenevaGeometry:
        """The exact wheel, locking disc, crank arm and roller outlines (mm)."""
        from ..analyses.geneva.geometry import geometry

        return geometry(self._need("geneva"))

    # -- rolling levers -------------------------------------------------------------------
    def synthesize(self, method: str | None = None, points: int | None = None, measures: bool = True
                   ) -> RollingSynthesis:
        """The rolling profiles (centrodes) with their slip measures."""
        from ..analyses.rolling.synthesis import synthesize

        return synthesize(self._need("rolling_lever"), method=method, points=points, measures=measures)
