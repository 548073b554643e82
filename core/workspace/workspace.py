"""The workspace: the scene being edited, its edits, and each element's results computed once.

Qt-free; the CLI and the desktop app both go through it. ``apply(edit)`` changes the scene and
returns the inverse edit (the GUI's undo stack keeps it); listeners then receive one
:class:`Change` naming the elements that changed and whether it is a drag preview. Results are
lazy and cached:

- per element *value* (elements are immutable records), so an undo, a redo or a pre-check of an
  edit finds the result it had before, and an edit of one element leaves every other element's
  result where it is;
- a linkage whose joints moved but whose topology did not (a drag) is re-swept from its previous
  solution: only the groups that use a moved joint, and those downstream of them, run again
  (:mod:`mechsketch.core.solver.incremental`);
- a solve request (order, samples, joints) is cached beside the default result.

``stats`` counts the solves actually run (``solve:<kind>`` per element kind, ``solve:request``;
``incremental`` says how many of the linkage solves were re-sweeps), so tests and benchmarks can
check that an edit re-solves only what it touches.
"""
from __future__ import annotations

from collections import Counter, OrderedDict
from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING, Any, Callable, Hashable, Iterable

from pathlib import Path

from ..errors import EditError, MechsketchError, RequestError, UnknownIdError
from ..io.scene_file import dump_element, element_problems_since, load_scene
from ..model.edits import Edit
from ..model.linkage import Linkage
from ..model.scene import Scene
from ..solver.incremental import moved_joints, resweep, topology_key
from ..solver.plan import Plan, Solution, compile_plan
from .budget import check_request
from .facade import ElementView
from .results import ElementResult, LinkageResult, RollingResult, solve_element, solve_linkage

if TYPE_CHECKING:  # pragma: no cover  (the forces are imported by forces(): issue 14)
    from ..analyses.forces.kinetostatics import ForceResult

#: results kept by value beyond the current ones (undo/redo, pre-checks of edits, requests)
CACHE_SIZE = 32


class ElementChange(str, Enum):
    """How one element changed in a :class:`Change`."""

    ADDED = "added"
    REMOVED = "removed"
    MODIFIED = "modified"

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class Change:
    """What one edit, preview, undo or reset changed.

    ``elements`` maps element id -> :class:`ElementChange`; ``preview`` is True for a drag preview
    (no history entry; a final change follows on release); ``replaced`` is True when the whole
    document was replaced (New, Open) — then ``elements`` lists every element of the new scene.
    """

    elements: tuple[tuple[str, ElementChange], ...] = ()
    preview: bool = False
    replaced: bool = False
    order_changed: bool = field(default=False)

    @property
    def ids(self) -> frozenset[str]:
        return frozenset(eid for eid, _ in self.elements)

    def kind(self, element_id: str) -> ElementChange | None:
        return dict(self.elements).get(element_id)

    def __contains__(self, element_id: object) -> bool:
        return any(eid == element_id for eid, _ in self.elements)

    def __bool__(self) -> bool:
        return bool(self.elements) or self.replaced or self.order_changed


def diff_scenes(old: Scene, new: Scene) -> tuple[tuple[tuple[str, ElementChange], ...], bool]:
    """The per-element changes from ``old`` to ``new`` (records compared by identity first, then
    value), and whether the order of the common elements changed."""
    before = {e.id: e for e in old.elements}
    after = {e.id: e for e in new.elements}
    out: list[tuple[str, ElementChange]] = []
    for eid, el in after.items():
        if eid not in before:
            out.append((eid, ElementChange.ADDED))
        elif before[eid] is not el and before[eid] != el:
            out.append((eid, ElementChange.MODIFIED))
    out.extend((eid, ElementChange.REMOVED) for eid in before if eid not in after)
    common_old = [e for e in before if e in after]
    common_new = [e for e in after if e in before]
    return tuple(out), common_old != common_new


Listener = Callable[[Change], None]


class Workspace:
    """The scene being edited, with its results computed lazily and cached.

    ``samples``: when set, overrides every linkage's and Geneva drive's own sample count (the
    desktop app's resolution setting); None uses each element's.
    """

    def __init__(self, scene: Scene | None = None, samples: int | None = None) -> None:
        self._scene = scene if scene is not None else Scene()
        self._samples = samples
        self._listeners: list[Listener] = []
        self._current: dict[str, tuple[Any, ElementResult | None]] = {}   # id -> (element, result)
        self._by_value: OrderedDict[Hashable, ElementResult | None] = OrderedDict()
        self._requests: OrderedDict[Hashable, Solution] = OrderedDict()
        self._forces: OrderedDict[Hashable, ForceResult] = OrderedDict()
        self._plans: OrderedDict[Linkage, Plan] = OrderedDict()
        self._valid: OrderedDict[Any, Any] = OrderedDict()   # records the scene reader accepts: their JSON object, or True
        self._remember(self._scene)
        self._structures: OrderedDict[tuple, list] = OrderedDict()   # topology -> Assur groups
        self._preview_base: Scene | None = None
        self._pending: dict[str, ElementChange] = {}
        self._unkept: set[str] = set()   # ids whose current result is a preview's (not kept by value)
        self.stats: Counter[str] = Counter()

    @classmethod
    def open(cls, path: str | Path, samples: int | None = None) -> "Workspace":
        """A workspace on the scene file at ``path`` (raises SceneFormatError listing its problems)."""
        return cls(load_scene(path), samples)

    def __getitem__(self, element_id: str) -> ElementView:
        """The one-line API on one element: ``ws["sixbar"].solve(samples=3600)``."""
        return ElementView(self, element_id)

    # -- the document ---------------------------------------------------------------------
    @property
    def scene(self) -> Scene:
        return self._scene

    @property
    def samples(self) -> int | None:
        return self._samples

    @samples.setter
    def samples(self, value: int | None) -> None:
        """Change the sample override; every linkage and Geneva drive is re-solved on demand."""
        if value == self._samples:
            return
        self._samples = value
        self._current.clear()
        ids = tuple((e.id, ElementChange.MODIFIED) for e in self._scene.elements)
        self._notify(Change(ids))

    def element(self, element_id: str) -> Any:
        """The record of ``element_id`` (raises UnknownIdError naming the scene's ids)."""
        try:
            return self._scene.element(element_id)
        except KeyError as exc:
            raise UnknownIdError(str(exc.args[0]) if exc.args else element_id) from None

    def subscribe(self, listener: Listener) -> Callable[[], None]:
        """Call ``listener(change)`` after every change; returns a function that unsubscribes."""
        self._listeners.append(listener)
        return lambda: self._listeners.remove(listener) if listener in self._listeners else None

    def check(self, edit: Edit) -> Scene:
        """The scene ``edit`` would give (the document is not changed); raises MechsketchError
        (or the edit's own error) when the edit is refused, :class:`EditError` with the scene
        reader's messages when an element it adds or changes could not be read from a file."""
        new = edit.apply_to(self._scene)[0]
        self._validate(new)
        return new

    def apply(self, edit: Edit) -> Edit:
        """Apply ``edit`` for good; return its inverse. The scene is unchanged if it raises
        (refused as in :meth:`check`)."""
        new, inverse = edit.apply_to(self._scene)
        self._validate(new)
        self._set(new, preview=False)
        return inverse

    def _validate(self, new: Scene) -> None:
        """Check the elements of ``new`` that differ from the current scene's with the scene
        reader (schema, parser): one validation for files and edits alike. Elements found valid
        are remembered by value, so undo, redo and a pushed pre-check do not check again."""
        old = {e.id: e for e in self._scene.elements}
        for el in new.elements:
            if old.get(el.id) is el:
                continue
            try:
                if el in self._valid:
                    self._valid.move_to_end(el)
                    continue
            except TypeError:   # an unhashable record (not one of ours): check it every time
                pass
            problems, data = element_problems_since(el, self._valid_data(old.get(el.id)))
            if problems:
                def text(p) -> str:
                    tail = p.path.removeprefix("$.elements[0]").lstrip(".") or "element"
                    who = f" [{p.id}]" if p.id and p.id != el.id else ""
                    return f"{tail}{who}: {p.message}"
                raise EditError(f"{getattr(el, 'type', 'element')} {el.id!r}: "
                                + "; ".join(text(p) for p in problems))
            try:
                self._store(self._valid, el, data if data is not None else True)
            except TypeError:
                pass

    def _valid_data(self, el: Any) -> dict | None:
        """The JSON object of ``el`` if it is a record known valid (kept with it), else None."""
        try:
            data = self._valid.get(el) if el is not None else None
        except TypeError:
            return None
        if data is True:
            try:
                data = self._valid[el] = dump_element(el)
            except (OverflowError, ValueError, TypeError, AttributeError):
                return None
        return data

    def reset(self, scene: Scene) -> None:
        """Replace the whole document (New, Open): not an undoable edit."""
        self._preview_base = None
        self._pending.clear()
        self._scene = scene
        self._current.clear()
        self._remember(scene)
        self._notify(Change(tuple((e.id, ElementChange.ADDED) for e in scene.elements), replaced=True))

    def _remember(self, scene: Scene) -> None:
        """Take the elements of a whole new document as checked: an undo that brings one of them
        back is never refused (they were read by the scene reader, or given by the API caller)."""
        for el in scene.elements:
            try:
                self._store(self._valid, el, True)
            except TypeError:
                pass

    # -- drag previews --------------------------------------------------------------------
    @property
    def previewing(self) -> bool:
        return self._preview_base is not None

    def begin_preview(self) -> None:
        """Start a live drag: later :meth:`preview` calls show edits of the scene as it is now,
        without history."""
        if self._preview_base is None:
            self._preview_base = self._scene

    def preview(self, edit: Edit) -> Change:
        """Show ``edit`` applied to the scene at :meth:`begin_preview`; returns the change
        (raises, leaving the shown scene as it was, if the edit is refused)."""
        base = self._preview_base if self._preview_base is not None else self._scene
        new, _ = edit.apply_to(base)
        return self._set(new, preview=True)

    def end_preview(self, notify: bool = True) -> None:
        """End a drag and show the scene of :meth:`begin_preview` again. With ``notify`` False the
        elements the preview touched are reported with the next change instead (the final edit
        that usually follows), so listeners see one change on release."""
        base, self._preview_base = self._preview_base, None
        if base is None:
            return
        changes, _ = diff_scenes(self._scene, base)
        self._scene = base
        for eid, how in changes:
            self._pending.setdefault(eid, how)
        if notify:
            self.flush()

    def flush(self) -> None:
        """Report the elements a preview touched that no change has reported yet."""
        if self._pending:
            pending, self._pending = tuple(self._pending.items()), {}
            self._notify(Change(pending))

    def _set(self, new: Scene, preview: bool) -> Change:
        changes, reordered = diff_scenes(self._scene, new)
        self._scene = new
        merged = dict(self._pending) if not preview else {}
        if not preview:
            self._pending.clear()
        for eid, how in changes:
            merged[eid] = how
        for eid, how in changes:
            if how is ElementChange.REMOVED:
                self._current.pop(eid, None)
        change = Change(tuple(merged.items()), preview=preview, order_changed=reordered)
        if change:   # an edit that changes nothing (a drag back onto the same point) tells no one
            self._notify(change)
        return change

    def _notify(self, change: Change) -> None:
        for listener in list(self._listeners):
            listener(change)

    # -- results --------------------------------------------------------------------------
    def _samples_for(self, element: Any) -> int | None:
        return self._samples if element.type in ("linkage", "geneva") else None

    def result(self, element_id: str) -> ElementResult | None:
        """The result of the element ``element_id`` as the scene holds it now (computed on first
        request, then cached); None for an element type this version does not solve."""
        el = self.element(element_id)
        hit = self._current.get(element_id)
        if hit is not None and hit[0] is el:
            if element_id in self._unkept and not self.previewing:   # a preview that became final
                self._unkept.discard(element_id)
                res = hit[1]
                if isinstance(res, RollingResult) and res.synthesis is not None and res.synthesis.slip is None:
                    res = self.result_of(el)   # the preview skipped the slip report: solve in full
                    self._current[element_id] = (el, res)
                    return res
                self._store(self._by_value, (el, self._samples_for(el)), res)
            return hit[1]
        # drag previews are not kept by value: a long drag would push out what undo needs
        keep = not self.previewing
        res = self.result_of(el, previous=hit, keep=keep)
        self._current[element_id] = (el, res)
        if keep:
            self._unkept.discard(element_id)
        else:
            self._unkept.add(element_id)
        return res

    def results(self) -> dict[str, ElementResult]:
        """Results of every element the workspace solves, in scene order."""
        out = {}
        for el in self._scene.elements:
            res = self.result(el.id)
            if res is not None:
                out[el.id] = res
        return out

    def result_of(self, element: Any, previous: tuple[Any, ElementResult | None] | None = None,
                  keep: bool = True) -> ElementResult | None:
        """The result of ``element`` (in the scene or not: a candidate an edit would create),
        cached by value (unless ``keep`` is False). ``previous`` (element, result) of the same id
        lets a linkage whose joints moved be re-swept from the groups the move touched."""
        samples = self._samples_for(element)
        key = (element, samples)
        try:
            if key in self._by_value:
                self._by_value.move_to_end(key)
                return self._by_value[key]
        except TypeError:  # an unhashable element (not one of ours): solve it uncached
            return solve_element(element, samples)
        res = None
        if isinstance(element, Linkage):
            res = self._incremental(element, samples, previous, keep)
            if res is None:
                plan = self._plan(element)
                res = solve_linkage(element, samples, plan) if plan is not None else solve_linkage(element, samples)
        else:   # a drag preview (not kept) skips the slow extras (a rolling lever's slip report)
            res = solve_element(element, samples, measures=keep)
        if res is not None:
            self.stats[f"solve:{res.kind}"] += 1
        if keep:
            self._store(self._by_value, key, res)
        return res

    def _incremental(self, element: Linkage, samples: int | None,
                     previous: tuple[Any, ElementResult | None] | None, keep: bool = True
                     ) -> LinkageResult | None:
        """Re-sweep from ``previous`` when only drawn positions changed; None otherwise."""
        if previous is None or not isinstance(previous[1], LinkageResult):
            return None
        old = previous[1]
        if old.solution is None or old.element.id != element.id:
            return None
        moved = moved_joints(old.element, element)
        if moved is None or len(old.solution) != (samples or element.samples):
            return None
        try:
            plan = self._compile(element)
        except MechsketchError:
            return None  # the full solve reports the message
        sol = resweep(old.solution, plan, moved)
        if sol is None:
            return None
        self.stats["incremental"] += 1
        if keep:
            self._store(self._plans, element, plan)
        return LinkageResult(element, plan, sol, seconds=sol.elapsed, incremental=True)

    def _plan(self, element: Linkage) -> Plan | None:
        """The compiled plan of ``element`` (cached by value); None when it does not compile."""
        if element in self._plans:
            self._plans.move_to_end(element)
            return self._plans[element]
        try:
            plan = self._compile(element)
        except MechsketchError:
            return None
        self._store(self._plans, element, plan)
        return plan

    def _compile(self, element: Linkage) -> Plan:
        """``compile_plan`` with the structural decomposition cached by topology: a drag or a
        dimension edit recompiles the kernels' drawn geometry, never the Assur groups."""
        key = topology_key(element)
        groups = self._structures.get(key)
        if groups is not None:
            self._structures.move_to_end(key)
            return compile_plan(element, groups)
        plan = compile_plan(element)
        self.stats["decompose"] += 1
        self._store(self._structures, key, plan.groups)
        return plan

    def plan(self, element_id: str) -> Plan:
        """The compiled plan of a linkage (raises StructureError / GeometryError with the reason)."""
        el = self.element(element_id)
        plan = self._plan(el)
        return plan if plan is not None else self._compile(el)

    def solve(self, element_id: str, samples: int | None = None, order: int = 2,
              joints: Iterable[str] | None = None) -> Solution:
        """One driver revolution of a linkage for a specific request (cached by element value and
        request): ``samples`` N (default the workspace's override, else the element's), ``order``
        0 positions, 1 + velocities, 2 + accelerations, ``joints`` only what these depend on.
        Raises the core's error when the linkage cannot be solved."""
        el = self.element(element_id)
        n = samples or self._samples or el.samples
        jkey = None if joints is None else tuple(joints)
        if jkey is None and order == 2:
            res = self.result(element_id) if n == (self._samples or el.samples) else None
            if res is not None and res.solution is not None:
                return res.solution
        key = (el, n, order, jkey)
        if key in self._requests:
            self._requests.move_to_end(key)
            return self._requests[key]
        check_request(el, n)
        sol = self.plan(element_id).sweep(samples=n, order=order, joints=jkey)
        self.stats["solve:request"] += 1
        self._store(self._requests, key, sol)
        return sol

    def forces(self, element_id: str, samples: int | None = None) -> ForceResult:
        """The kinetostatics of a linkage over one driver revolution (computed when first asked,
        then cached by element value and N): driving torque, joint reactions, shaking force and
        moment, the power balance, and the result with joint friction when the scene has any
        (see :mod:`mechsketch.core.analyses.forces.kinetostatics`; SI units). ``samples`` as for :meth:`solve`.
        Raises the core's error when the linkage cannot be solved."""
        el = self.element(element_id)
        if not isinstance(el, Linkage):
            raise RequestError(f"element {element_id!r} is a {el.type}: forces apply to linkages")
        n = samples or self._samples or el.samples
        key = (el, n)
        if key in self._forces:
            self._forces.move_to_end(key)
            return self._forces[key]
        sol = self.solve(element_id, samples=n, order=2)
        from ..analyses.forces.kinetostatics import linkage_forces

        res = linkage_forces(sol.plan, sol)
        self.stats["forces"] += 1
        self._store(self._forces, key, res)
        return res

    def samples_for(self, element: Any) -> int | None:
        """The samples a result of ``element`` is solved at here (the override for a linkage or
        a Geneva drive, else None: the element's own)."""
        return self._samples_for(element)

    def has_result(self, element: Any) -> bool:
        """Whether the result of ``element`` (in the scene or a candidate) is cached by value."""
        try:
            return (element, self._samples_for(element)) in self._by_value
        except TypeError:   # an unhashable element is never cached
            return False

    def keep_result(self, element: Any, result: ElementResult | None) -> None:
        """Cache ``result``, computed elsewhere as :func:`solve_element` ``(element,
        samples_for(element))`` (a worker thread), so that the next request of ``element`` finds it."""
        self._store(self._by_value, (element, self._samples_for(element)), result)

    def check_element(self, element: Any) -> str | None:
        """Solve ``element`` (a candidate, not yet in the scene) as the workspace would; the
        core's message if it fails, else None. The result is kept for when the edit lands."""
        res = self.result_of(element)
        return None if res is None else res.error

    def _store(self, cache: OrderedDict, key: Hashable, value: Any) -> None:
        cache[key] = value
        while len(cache) > CACHE_SIZE + len(self._scene.elements):
            cache.popitem(last=False)
