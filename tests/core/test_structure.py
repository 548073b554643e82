"""Structural analysis: mobility, decomposition into the driver plus class-II groups, and the
diagnosis (with the joints at fault) of under-/over-constrained and higher-class linkages."""
from __future__ import annotations

import itertools
from dataclasses import replace

import pytest

import linkage_builders as LB
import solution_checks as CK
from mechsketch.core import StructureError, load_scene
from mechsketch.core.solver.plan import compile_plan
from mechsketch.core.solver.structure import decompose, joint_count, mobility
from mechsketch.resources import example_path


def example(name):
    return load_scene(example_path(name)).elements[0]


@pytest.mark.parametrize("name,groups", [
    ("fourbar_crank_rocker", [("RRR", "coupler", "rocker", "C", "B", "D", "crank", "ground")]),
    ("slider_crank_offset", [("RRP", "rod", "slider", "C", "B", "S", "crank", "ground")]),
    ("inverted_slider_crank", [("RPR", "block", "rocker", "Q", "B", "C", "crank", "ground")]),
    ("sixbar_moving_guide", [("RRR", "coupler", "rocker", "C", "B", "D", "crank", "ground"),
                             ("RRP", "rod2", "block", "E", "B", "Q", "crank", "rocker")]),
    ("double_rocker", [("RRR", "coupler", "output", "C", "B", "D", "input", "ground")]),
])
def test_examples_decompose(name, groups):
    lk = example(name)
    assert mobility(lk) == 1
    got = [(g.kind, g.link_i, g.link_j, g.inner, g.outer_i, g.outer_j, g.known_i, g.known_j)
           for g in decompose(lk)]
    assert got == groups


def test_joint_count_counts_a_compound_hinge_once_per_extra_link():
    lk = LB.two_dyads()          # B on crank, coupler and rod
    assert joint_count(lk) == 1 + 2 + 1 + 1 + 1 + 1   # A, B(×2), C, D, E, S
    assert mobility(lk) == 3 * (6 - 1) - 2 * 7 == 1
    coupler_point = lk.with_joint(lk.joint("A").__class__("P1", lk.joint("A").kind, (50.0, 50.0)))
    coupler_point = coupler_point.with_link(lk.link("coupler").__class__("coupler", ("B", "C", "P1")))
    assert joint_count(coupler_point) == 7      # a joint on one link is a traced point, no pair


@pytest.mark.parametrize("builder,kinds", [
    (LB.prp_linkage, ["PRP"]), (LB.scotch_yoke, ["RPP"]), (LB.crank_guided, ["RRP"]),
    (lambda: LB.sixbar_stephenson(on_rocker=True, f=(150.0, 60.0)), ["RRR", "RRR"]),
    (LB.two_dyads, ["RRR", "RRP"]),
])
def test_kinds_of_the_test_linkages(builder, kinds):
    assert [g.kind for g in decompose(builder())] == kinds


def test_dyad_hanging_on_a_compound_inner_joint():
    """Regression: the slider rod pinned at C (on coupler, rocker and rod) used to be reported
    as a higher-class group."""
    lk = LB.sixbar_compound()
    gs = decompose(lk)
    assert [(g.kind, g.link_i, g.link_j, g.inner) for g in gs] == [
        ("RRR", "coupler", "rocker", "C"), ("RRP", "rod", "slider", "E")]
    assert gs[1].outer_i == "C" and gs[1].known_i in ("coupler", "rocker")


@pytest.mark.parametrize("builder", [LB.slider_crank, LB.scotch_yoke, LB.inverted_slider_crank, LB.prp_linkage,
                                     lambda: LB.sixbar_guide(-1), LB.sixbar_compound])
def test_decomposition_does_not_depend_on_the_file_order_of_links(builder):
    lk = builder()
    ref = {(g.kind, frozenset((g.link_i, g.link_j)), g.inner) for g in decompose(lk)}
    for perm in itertools.islice(itertools.permutations(lk.links), 0, 720, 7):
        other = replace(lk, links=tuple(perm))
        got = decompose(other)
        assert {(g.kind, frozenset((g.link_i, g.link_j)), g.inner) for g in got} == ref
        # the canonical orientation: the slider (P outer joint) is always link j
        for g in got:
            assert g.kind in ("RRR", "RRP", "RPR", "PRP", "RPP")


def test_reversed_slider_listing_is_mirrored_to_rrp():
    lk = LB.slider_crank()
    lk = replace(lk, links=tuple(lk.link(k) for k in ("ground", "crank", "slider", "rod")))
    (g,) = decompose(lk)
    assert (g.kind, g.link_i, g.link_j, g.outer_i, g.outer_j) == ("RRP", "rod", "slider", "B", "S")
    sol = compile_plan(lk).sweep(samples=36)
    assert CK.closure_error(lk, sol) < 1e-12


def test_ppp_group_is_refused_naming_its_joints():
    lk = LB.build("ppp", [("A", "R", (0, 0)), ("Q1", "P", (30, 10), 20.0), ("Q3", "P", (40, 30), 80.0),
                         ("Q2", "P", (60, 40), 150.0)],
                 {"ground": ["A", "Q2"], "crank": ["A", "Q1"], "b1": ["Q1", "Q3"], "b2": ["Q3", "Q2"]},
                 "ground", "crank", "A")
    assert mobility(lk) == 1
    with pytest.raises(StructureError, match="PPP") as info:
        decompose(lk)
    assert set(info.value.joints) == {"Q1", "Q3", "Q2"}
    assert set(info.value.links) == {"b1", "b2"}


def test_under_constrained_five_bar():
    lk = LB.build("fivebar", [("A", "R", (0, 0)), ("B", "R", (20, 30)), ("C", "R", (70, 60)), ("D", "R", (120, 40)),
                             ("E", "R", (140, 0))],
                 {"ground": ["A", "E"], "crank": ["A", "B"], "l2": ["B", "C"], "l3": ["C", "D"], "l4": ["D", "E"]},
                 "ground", "crank", "A")
    assert mobility(lk) == 2
    with pytest.raises(StructureError, match="under-constrained") as info:
        decompose(lk)
    assert "mobility 2" in str(info.value)
    assert set(info.value.joints) == set("ABCDE")


def test_over_constrained_four_bar_with_a_diagonal():
    lk = LB.fourbar()
    lk = lk.with_link(lk.link("coupler").__class__("diag", ("B", "D")))
    assert mobility(lk) == 0
    with pytest.raises(StructureError, match="over-constrained") as info:
        decompose(lk)
    assert "mobility 0" in str(info.value)
    assert set(info.value.joints) == {"A", "B", "C", "D"}


def test_class_three_group_is_reported_with_its_joints_and_links():
    lk = LB.class3()
    assert mobility(lk) == 1
    with pytest.raises(StructureError, match="class-II") as info:
        decompose(lk)
    err = info.value
    assert set(err.links) == {"b1", "b2", "b3", "tri"}
    assert set(err.joints) == {"B", "X1", "X2", "X3", "G2", "G3"}
    for j in ("X1", "X2", "X3", "G2", "G3"):
        assert j in str(err)
    with pytest.raises(StructureError):
        compile_plan(lk)


def test_class_three_after_a_dyad_names_only_the_rest():
    """A four-bar whose rocker drives a triad: the dyad is solved, the triad reported."""
    fb = LB.fourbar()
    X1, X2, X3, G2, G3 = (170, 150), (230, 170), (210, 110), (260, 240), (280, 60)
    joints = [(j.id, "R", j.at) for j in fb.joints] + [("X1", "R", X1), ("X2", "R", X2), ("X3", "R", X3),
                                                      ("G2", "R", G2), ("G3", "R", G3)]
    links = {k.id: list(k.joints) for k in fb.links}
    links["ground"] += ["G2", "G3"]
    links.update(b1=["C", "X1"], b2=["G2", "X2"], b3=["G3", "X3"], tri=["X1", "X2", "X3"])
    lk = LB.build("fb3", joints, links, "ground", "crank", "A")
    assert mobility(lk) == 1
    with pytest.raises(StructureError) as info:
        decompose(lk)
    assert set(info.value.links) == {"b1", "b2", "b3", "tri"}
    assert "A" not in info.value.joints and "B" not in info.value.joints


@pytest.mark.parametrize("mutate,match", [
    (lambda lk: lk.with_link(lk.link("crank").__class__("crank", ("A",))), "at least one other joint"),
    (lambda lk: lk.with_driver(lk.driver.__class__("ground", "A", 60.0)), "driver"),
    (lambda lk: lk.with_driver(lk.driver.__class__("crank", "B", 60.0)), "pivot"),
    (lambda lk: lk.with_driver(lk.driver.__class__("nolink", "A", 60.0)), "driver"),
])
def test_bad_drivers_built_in_code_are_structure_errors(mutate, match):
    with pytest.raises(StructureError, match=match):
        decompose(mutate(LB.fourbar()))
