"""Typed solver results and vocabulary: the kernels' assembly mode and slides, the group kinds as
string enums, the project's errors for unknown ids and bad requests, and no import hidden inside a
function anywhere in the solver package.

References are independent of the kernels: modes from the builders' construction and from the
drawn triangle's orientation; slides from closed-form mechanism geometry differentiated by mpmath.
"""
from __future__ import annotations

import ast
import cmath
import json
import math
from pathlib import Path

import mpmath
import numpy as np
import pytest

import linkage_builders as LB
from mechsketch.core import Linkage, load_scene
from mechsketch.core.errors import MechsketchError, RequestError, UnknownIdError
from mechsketch.core.model.geneva import ContactModel, HalfWidth, NormalForce, SlipRadius
from mechsketch.core.solver import plan as plan_module
from mechsketch.core.solver.diagnostics import DeadPoint, DeadPointKind, diagnose
from mechsketch.core.solver.flip import FLIPPABLE
from mechsketch.core.solver.kernels import DyadOut, Slide
from mechsketch.core.solver.plan import TOGGLE_COND, TOUCH_REL, Plan, Solution, compile_plan, unwrap_finite
from mechsketch.core.solver.structure import DYAD_KINDS, Group, GroupKind, decompose
from mechsketch.resources import example_path

SOLVER_DIR = Path(plan_module.__file__).resolve().parent


def _c(xy) -> complex:
    return complex(float(xy[0]), float(xy[1]))


def _at(lk: Linkage, jid: str) -> complex:
    return _c(lk.joint(jid).at)


def _drawn(lk: Linkage):
    """(plan, order-0 solution at the drawn driver angle)."""
    plan = compile_plan(lk)
    return plan, plan.evaluate(np.array([plan.theta0]), order=0)


def _sign(x: float) -> int:
    return 1 if x >= 0.0 else -1


def _cross(a: complex, b: complex) -> float:
    return a.real * b.imag - a.imag * b.real


def _axis(lk: Linkage, jid: str) -> complex:
    return cmath.exp(1j * math.radians(lk.joint(jid).axis_deg or 0.0))


# -- the assembly mode -----------------------------------------------------------------------------
def _mode_from_drawing(lk: Linkage, g: Group) -> int | None:
    """The assembly mode the drawn pose gives, read off the drawn joints (not the kernels)."""
    if g.kind == "RRR":  # which side of M→H the inner joint L lies on
        m, h, l_ = _at(lk, g.outer_i), _at(lk, g.outer_j), _at(lk, g.inner)
        return _sign(_cross(h - m, l_ - m))
    if g.kind == "RRP":  # the rod M→L projected on the guide direction
        m, l_ = _at(lk, g.outer_i), _at(lk, g.inner)
        u = _axis(lk, g.outer_j)
        return _sign((u.conjugate() * (l_ - m)).real)
    if g.kind == "RPR":  # H→M projected on the slide axis
        m, h = _at(lk, g.outer_i), _at(lk, g.outer_j)
        u = _axis(lk, g.inner)
        return _sign((u.conjugate() * (m - h)).real)
    return None


BUILT_WITH_MODE = [
    ("fourbar+", lambda: LB.fourbar(mode=1), 1),
    ("fourbar-", lambda: LB.fourbar(mode=-1), -1),
    ("fourbar- q3", lambda: LB.fourbar(theta0=225.0, mode=-1, rot=200.0, origin=-300 - 90j), -1),
    ("slider_crank+", lambda: LB.slider_crank(mode=1, xi=150.0), 1),
    ("slider_crank-", lambda: LB.slider_crank(mode=-1, xi=200.0, offset=-10.0), -1),
    ("inverted+", lambda: LB.inverted_slider_crank(mode=1, offset=15.0), 1),
    ("inverted-", lambda: LB.inverted_slider_crank(mode=-1, offset=15.0), -1),
    ("crank_guided+", lambda: LB.crank_guided(mode=1), 1),
    ("crank_guided-", lambda: LB.crank_guided(mode=-1), -1),
]


@pytest.mark.parametrize("name,build,mode", BUILT_WITH_MODE, ids=[c[0] for c in BUILT_WITH_MODE])
def test_typed_mode_is_the_mode_the_builder_drew(name, build, mode):
    lk = build()
    _, sol = _drawn(lk)
    (g,) = sol.groups
    out = sol.group_output(g.name)
    assert isinstance(out, DyadOut)
    assert out.mode == mode == _mode_from_drawing(lk, g)
    assert type(out.mode) is int


def test_typed_modes_of_chained_groups_are_the_modes_the_builders_drew():
    cases = [(LB.sixbar_stephenson(mode1=-1, mode2=-1, f=(60.0, -150.0), e_pt=(50.0, -30.0)), [-1, -1]),
             (LB.eight_bar(), [1, 1, -1]), (LB.prp_linkage(), [None]), (LB.scotch_yoke(), [None])]
    for lk, modes in cases:
        _, sol = _drawn(lk)
        assert [sol.group_output(g.name).mode for g in sol.groups] == modes, lk.id


ALL_LINKAGES = [
    LB.fourbar, LB.slider_crank, LB.inverted_slider_crank, LB.prp_linkage, LB.scotch_yoke,
    LB.crank_guided, LB.sixbar_compound, LB.two_dyads, LB.sixbar_guide, LB.rpr_on_moving_links,
    LB.rrp_guide_on_coupler, LB.eight_bar, lambda: LB.sixbar_stephenson(on_rocker=True, f=(150.0, 60.0)),
    lambda: LB.sixbar_stephenson(mode1=-1, mode2=-1, f=(60.0, -150.0), e_pt=(50.0, -30.0)),
]
EXAMPLES = ["fourbar_crank_rocker", "double_rocker", "fourbar_coupler_centrodes", "inverted_slider_crank",
            "sixbar_moving_guide", "slider_crank_offset"]


def _all_cases():
    for build in ALL_LINKAGES:
        yield build()
    for name in EXAMPLES:
        yield load_scene(example_path(name)).elements[0]


def test_every_groups_typed_mode_matches_the_drawn_pose_and_a_full_sweep_keeps_it():
    seen = set()
    for lk in _all_cases():
        plan, sol = _drawn(lk)
        sweep = plan.sweep(90, order=2)
        for g in plan.groups:
            want = _mode_from_drawing(lk, g)
            assert sol.group_output(g.name).mode == want, (lk.id, g.name)
            assert sweep.group_output(g.name).mode == want, (lk.id, g.name)  # the drawn mode, not per sample
            assert (want is None) == (g.kind not in FLIPPABLE)
            seen.add(g.kind)
    assert seen == set(GroupKind)


def test_diagnostics_list_each_group_with_its_kind_and_typed_mode():
    lk = LB.fourbar(mode=-1)
    sol = compile_plan(lk).sweep(360, order=2)
    d = diagnose(sol)
    assert d.groups == [("RRR(coupler,rocker)", GroupKind.RRR, -1)]
    assert "group RRR(coupler,rocker): kind RRR, mode -1" in d.lines()
    yoke = diagnose(compile_plan(LB.scotch_yoke()).sweep(90, order=0))
    assert "group RPP(block,yoke): kind RPP" in yoke.lines()


# -- slides against closed-form geometry -----------------------------------------------------------
mpmath.mp.dps = 40


def _ref(f, theta: float, omega: float) -> tuple[float, float, float]:
    """(f, df/dt, d²f/dt²) at driver angle ``theta`` turning at constant ``omega`` (mpmath)."""
    t = mpmath.mpf(theta)
    return (float(f(t) - 0), float(mpmath.diff(f, t, 1) * omega), float(mpmath.diff(f, t, 2) * omega ** 2))


def _check_slides(lk: Linkage, inputs: np.ndarray, refs) -> None:
    """``refs``: per slide of the only group, f(θ) (mpmath) with f(θ0) = 0."""
    plan = compile_plan(lk)
    omega = plan.omega
    sol = plan.evaluate(inputs, order=2)
    (g,) = sol.groups
    out = sol.group_output(g.name)
    assert out.ok.all()
    assert len(out.slides) == len(refs)
    for k, (slide, f) in enumerate(zip(out.slides, refs)):
        assert isinstance(slide, Slide)
        want = np.array([_ref(f, th, omega) for th in inputs])
        got = np.stack([np.broadcast_to(a, inputs.shape) for a in (slide.s, slide.sd, slide.sdd)], axis=1)
        scale = np.max(np.abs(want), axis=0) + 1.0
        assert np.all(np.abs(got - want) <= 1e-10 * scale), (g.name, k, np.max(np.abs(got - want), axis=0))
    # derivatives are there only up to the requested order
    s0 = plan.evaluate(inputs, order=0).group_output(g.name).slides
    s1 = plan.evaluate(inputs, order=1).group_output(g.name).slides
    assert all(s.sd is None and s.sdd is None for s in s0)
    assert all(s.sd is not None and s.sdd is None for s in s1)
    for a, b in zip(s0, out.slides):
        assert np.array_equal(np.broadcast_to(a.s, inputs.shape), np.broadcast_to(b.s, inputs.shape))


INPUTS = np.linspace(0.0, 2.0 * math.pi, 13)[:-1] + 0.1


def test_rrp_slide_is_the_slider_stroke_of_the_offset_slider_crank():
    r, rod, e, th0 = 40.0, 160.0, 20.0, 0.3
    for mode in (1, -1):
        lk = LB.slider_crank(crank=r, rod=rod, offset=e, theta0=math.degrees(th0), mode=mode)

        def x(t, mode=mode):  # slider pin on the guide y = e (guide along +x through the frame)
            return r * mpmath.cos(t) + mode * mpmath.sqrt(rod ** 2 - (e - r * mpmath.sin(t)) ** 2)

        _check_slides(lk, INPUTS, [lambda t, x=x: x(t) - x(mpmath.mpf(th0))])


def test_rrp_slide_on_a_guide_turning_with_the_crank():
    pin, rod, o2, a_deg = 8j, 80.0, -60.0 + 20.0j, 50.0  # rod > |O2| + 8: assembles all round
    for mode in (1, -1):
        lk = LB.crank_guided(crank_dir=a_deg, o2=(o2.real, o2.imag), rod=rod, pin=(0.0, 8.0), mode=mode)
        th0 = cmath.phase(_at(lk, "Q"))   # the crank A→Q, A at the origin

        def t_along(t, mode=mode, th0=th0):
            """Along-guide coordinate of the slide point: the block pin E = u·(t + pin) on the guide
            u = e^{i(a + θ − θ0)} lies at distance ``rod`` from O2 (in the guide's frame: w)."""
            w = mpmath.conj(mpmath.expjpi((math.radians(a_deg) + t - th0) / mpmath.pi)) * o2
            return mpmath.re(w) - pin.real + mode * mpmath.sqrt(rod ** 2 - (pin.imag - mpmath.im(w)) ** 2)

        _check_slides(lk, INPUTS, [lambda t, f=t_along, th0=th0: f(t) - f(mpmath.mpf(th0))])


def test_rpr_slide_is_the_change_of_the_along_axis_distance_of_the_inverted_slider_crank():
    r, ground, th0 = 40.0, 100.0, math.radians(30.0)
    for offset in (0.0, 25.0):
        for mode in (1, -1):
            lk = LB.inverted_slider_crank(crank=r, ground=ground, offset=offset, theta0=math.degrees(th0),
                                          mode=mode)
            (g,) = compile_plan(lk).groups
            assert (g.outer_i, g.outer_j) == ("B", "C")  # the block (pin B) slides on the rocker (pivot C)

            def along(t, mode=mode, offset=offset):
                """Signed distance along the axis from C to B: |B − C|² − offset², B = r·e^{it},
                C = (ground, 0), the axis at a fixed offset from C."""
                return mode * mpmath.sqrt(r * r + ground * ground - 2 * r * ground * mpmath.cos(t) - offset ** 2)

            _check_slides(lk, INPUTS, [lambda t, along=along: along(t) - along(mpmath.mpf(th0))])


def test_rpp_slides_are_the_scotch_yoke_displacements():
    r, th0 = 30.0, math.radians(35.0)
    lk = LB.scotch_yoke(crank=r, theta0=math.degrees(th0), slot=90.0, guide=0.0)
    (g,) = compile_plan(lk).groups
    assert (g.inner, g.outer_j) == ("Qs", "Qg")
    # the block climbs the vertical slot by Δ(r sin θ); the yoke slides along x by Δ(r cos θ)
    _check_slides(lk, INPUTS, [lambda t: r * (mpmath.sin(t) - mpmath.sin(th0)),
                               lambda t: r * (mpmath.cos(t) - mpmath.cos(th0))])


def test_prp_slides_follow_the_intersection_of_the_turning_and_the_fixed_guide():
    lk = LB.prp_linkage(crank_dir=40.0, xi=100.0, g=(60.0, 10.0))
    th0 = cmath.phase(_at(lk, "Q1"))   # the crank's drawn angle (pivot at the origin)
    a1 = math.radians(40.0)            # drawn direction of the guide on the crank (through A)
    u2 = cmath.exp(1j * math.radians(100.0))
    G = 60.0 + 10.0j

    def cross(a, b):
        return mpmath.re(a) * mpmath.im(b) - mpmath.im(a) * mpmath.re(b)

    def t1(t):  # L = t1·u1 on the crank's guide, u1 = e^{i(a1 + t − θ0)}, and on the line G + t2·u2
        u1 = mpmath.expjpi((a1 + t - th0) / mpmath.pi)
        return cross(G, u2) / cross(u1, u2)

    def L(t):
        return t1(t) * mpmath.expjpi((a1 + t - th0) / mpmath.pi)

    L0 = L(mpmath.mpf(th0))
    # the guides cross as drawn from −80° to 100° (parallel there; the far side is not reached)
    inputs = th0 + np.array([-1.0, -0.5, -0.2, 0.1, 0.4, 0.8, 0.9])
    _check_slides(lk, inputs, [lambda t: t1(t) - t1(mpmath.mpf(th0)),
                               lambda t: mpmath.re(mpmath.conj(u2) * (L(t) - L0))])


def test_rrr_has_no_slides():
    _, sol = _drawn(LB.fourbar())
    (g,) = sol.groups
    assert sol.group_output(g.name).slides == ()


# -- group kinds (and the other string kinds) are string enums ------------------------------------
def test_group_kind_compares_and_serialises_as_todays_strings():
    for text in ("RRR", "RRP", "RPR", "PRP", "RPP"):
        kind = GroupKind(text)
        assert kind == text and text == kind and isinstance(kind, str)
        assert str(kind) == text and f"{kind}" == text and format(kind, ">5") == f"{text:>5}"
        assert "%s" % kind == text and json.dumps({"k": kind}) == json.dumps({"k": text})
        assert {text: 1}[kind] == 1 and hash(kind) == hash(text)
        assert text in DYAD_KINDS
    assert DYAD_KINDS == tuple(GroupKind) and len(DYAD_KINDS) == 5
    assert set(FLIPPABLE) == {"RRR", "RRP", "RPR"}
    with pytest.raises(ValueError):
        GroupKind("PPP")


def test_decompose_gives_group_kinds_and_a_group_built_from_a_string_converts():
    for lk in _all_cases():
        for g in decompose(lk):
            assert type(g.kind) is GroupKind
            assert g.name.startswith(f"{g.kind}(")
    g = Group("RRR(a,b)", "RRR", "a", "b", "C", "B", "D", "crank", "ground")
    assert g.kind is GroupKind.RRR


def test_dead_point_kind_is_a_string_enum():
    d = DeadPoint(0.5, "RRR(a,b)", "toggle", 1e-4)
    assert d.kind is DeadPointKind.TOGGLE and d.kind == "toggle" and f"{d.kind}" == "toggle"
    assert "near toggle" in str(d)
    assert "assembly limit" in str(DeadPoint(0.5, "RRR(a,b)", DeadPointKind.LIMIT, 0.0))
    assert str(DeadPointKind.CHANGE_POINT) == "change point"
    lk = LB.fourbar(crank=40.0, coupler=60.0, rocker=60.0, ground=80.0)  # a Grashof double-rocker range
    for p in diagnose(compile_plan(lk).sweep(360, order=2)).dead_points:
        assert type(p.kind) is DeadPointKind


def test_contact_model_choices_are_string_enums_that_serialise_as_strings():
    m = ContactModel(normal_force="paper", half_width="hertz", slip_radius="undeformed")
    assert m.normal_force is NormalForce.PAPER and m.half_width is HalfWidth.HERTZ
    assert m.slip_radius is SlipRadius.UNDEFORMED
    assert m == ContactModel(NormalForce.PAPER, HalfWidth.HERTZ, SlipRadius.UNDEFORMED)
    d = m.to_dict()
    assert d == {"normal_force": "paper", "half_width": "hertz", "slip_radius": "undeformed"}
    assert all(type(v) is str for v in d.values())
    assert ContactModel(**json.loads(json.dumps(d))) == m
    default = ContactModel()
    assert (default.normal_force, default.half_width, default.slip_radius) == ("derived", "paper_half", "deformed")
    assert f"{default.half_width}" == "paper_half"
    with pytest.raises(ValueError, match="normal_force must be one of 'derived', 'paper'; got 'guess'"):
        ContactModel(normal_force="guess")


# -- errors: the project's, which are also the builtins --------------------------------------------
def test_unknown_ids_raise_unknown_id_error_which_is_a_key_error():
    lk = LB.sixbar_guide()
    plan = compile_plan(lk)
    full = plan.sweep(36, order=2)
    part = plan.evaluate([0.3], order=0, joints=["C"])       # only the four-bar
    unsolved = next(g for g in full.groups if g.name not in {h.name for h in part.groups})
    calls = [
        (lambda: plan.evaluate([0.3], joints=["nope"]), "no joint 'nope'"),
        (lambda: full.position("nope"), "no joint 'nope'"),
        (lambda: full.velocity("nope"), "no joint 'nope'"),
        (lambda: full.angle("nope"), "no link 'nope'"),
        (lambda: full.omega("nope"), "no link 'nope'"),
        (lambda: full.point("nope", (0.0, 0.0)), "no link 'nope'"),
        (lambda: part.angle(unsolved.link_j), "not solved"),
        (lambda: part.position(unsolved.inner), "not solved"),
        (lambda: full.group_output("nope"), "no group 'nope'"),
        (lambda: full.conditioning("nope"), "no group 'nope'"),
        (lambda: full.feasible("nope"), "no group 'nope'"),
        (lambda: full.transmission_angle("nope"), "no group 'nope'"),
        (lambda: part.group_output(unsolved.name), "not solved"),
    ]
    for call, fragment in calls:
        with pytest.raises(UnknownIdError) as exc:
            call()
        assert isinstance(exc.value, KeyError) and isinstance(exc.value, MechsketchError)
        assert fragment in str(exc.value)
        assert not str(exc.value).startswith(("'", '"'))  # printed as the message, not quoted


def test_bad_requests_raise_request_error_which_is_a_value_error():
    plan = compile_plan(LB.sixbar_guide())
    s0 = plan.sweep(36, order=0)
    s1 = plan.sweep(36, order=1)
    rrp = next(g.name for g in s0.groups if g.kind == "RRP")
    calls = [
        (lambda: plan.evaluate([0.3], order=3), "order must be 0, 1 or 2, got 3"),
        (lambda: plan.evaluate([0.3], order=-1), "order must be 0, 1 or 2"),
        (lambda: plan.sweep(1), "samples must be at least 2, got 1"),
        (lambda: s0.velocity("C"), "velocity needs a solve with order >= 1"),
        (lambda: s0.point_velocity("coupler", (0.0, 0.0)), "order >= 1"),
        (lambda: s0.omega("coupler"), "omega needs a solve with order >= 1"),
        (lambda: s1.acceleration("C"), "acceleration needs a solve with order >= 2"),
        (lambda: s1.alpha("coupler"), "alpha needs a solve with order >= 2"),
        (lambda: s0.transmission_angle(rrp), "defined here for RRR groups; RRP(rod2,block) is RRP"),
    ]
    for call, fragment in calls:
        with pytest.raises(RequestError) as exc:
            call()
        assert isinstance(exc.value, ValueError) and isinstance(exc.value, MechsketchError)
        assert fragment in str(exc.value)


# -- imports: none inside a function, no cycle between the solver's modules ------------------------
def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _imports(tree: ast.AST):
    """(import node, inside a function?) for every import not guarded by ``if TYPE_CHECKING:``."""
    def walk(node, in_function):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child.test):
                for sub in child.orelse:  # only the body is exempt
                    yield from walk_one(sub, in_function)
                continue
            yield from walk_one(child, in_function)

    def walk_one(node, in_function):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node, in_function
        yield from walk(node, in_function or isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)))

    yield from walk(tree, False)


def _solver_files() -> list[Path]:
    files = sorted(SOLVER_DIR.glob("*.py"))
    assert {"plan.py", "branches.py", "kernels.py", "structure.py"} <= {f.name for f in files}
    return files


def test_no_module_of_the_solver_imports_inside_a_function():
    bad = []
    for path in _solver_files():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node, in_function in _imports(tree):
            if in_function:
                bad.append(f"{path.name}:{node.lineno}: {ast.unparse(node)}")
    assert not bad, "imports inside functions:\n" + "\n".join(bad)


def test_the_finder_sees_a_function_level_import_and_spares_type_checking():
    src = ("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .plan import Plan\n"
           "def f():\n    if TYPE_CHECKING:\n        import os\n    from .branches import x\n    return x\n")
    found = [(ast.unparse(n), inside) for n, inside in _imports(ast.parse(src))]
    assert found == [("from typing import TYPE_CHECKING", False), ("from .branches import x", True)]


def test_the_solver_modules_import_each_other_without_a_cycle_at_run_time():
    names = {p.stem for p in _solver_files()}
    graph: dict[str, set[str]] = {}
    for path in _solver_files():
        deps = set()
        for node, _ in _imports(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                if node.module:
                    deps.add(node.module.split(".")[0])
                else:
                    deps.update(a.name for a in node.names)
        graph[path.stem] = deps & names
    assert "plan" not in graph["branches"]  # only under TYPE_CHECKING
    state: dict[str, int] = {}

    def visit(n, path):
        state[n] = 1
        for m in graph[n]:
            assert state.get(m) != 1, f"import cycle: {' -> '.join(path + [m])}"
            if m not in state:
                visit(m, path + [m])
        state[n] = 2

    for n in graph:
        if n not in state:
            visit(n, [n])


def test_the_plan_module_still_exports_its_public_names():
    assert TOGGLE_COND == 1e-3 and TOUCH_REL == 64 * np.finfo(float).eps
    assert all(callable(x) for x in (Plan, Solution, compile_plan, unwrap_finite))
