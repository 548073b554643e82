"""A plan keeps the input grid of its sweeps (the inputs, and the crank's cos and sin) between
sweeps of one size: the results are those of a fresh plan bit for bit, and a solution handed out
never shares a writable array with a later one."""
from __future__ import annotations

import numpy as np
import pytest

from mechsketch.core.io.scene_file import load_scene
from mechsketch.core.solver import kernels as K
from mechsketch.core.solver.plan import compile_plan
from mechsketch.resources import example_path


def _four():
    return load_scene(example_path("fourbar_crank_rocker")).elements[0]


def test_repeated_sweeps_equal_a_fresh_plan_and_the_closed_form():
    lk = _four()
    plan = compile_plan(lk)
    for n in (360, 3600, 360):      # a size again after another one: from the kept grid
        sol = plan.sweep(n, order=2)
        fresh = compile_plan(lk).sweep(n, order=2)
        for j in lk.joint_ids:
            for get in ("position", "velocity", "acceleration"):
                assert np.array_equal(getattr(sol, get)(j), getattr(fresh, get)(j))
        # the crank's rotation: cos and sin of the offset from the drawn angle, an independent form
        c, s = sol.link_state(lk.driver.link).cs
        th = np.sign(plan.omega) * 2.0 * np.pi * np.arange(n) / n
        assert np.allclose(c, np.cos(th), atol=1e-12) and np.allclose(s, np.sin(th), atol=1e-12)


def test_a_solution_is_not_changed_by_later_sweeps_or_by_its_reader():
    plan = compile_plan(_four())
    a = plan.sweep(360, order=2)
    keep = a.input.copy(), a.position("E").copy()
    a.input[:] = 0.0                 # the user's own copy of the inputs: writable, not shared
    b = plan.sweep(360, order=2)
    assert b.input is not a.input and np.array_equal(b.input, keep[0])
    assert np.array_equal(a.position("E"), keep[1])
    c, s = b.link_state(plan.linkage.driver.link).cs
    with pytest.raises(ValueError):  # shared between sweeps: read-only
        c[0] = 2.0
    assert np.array_equal(b.position("E"), keep[1])


def test_grid_cos_sin_bit_for_bit_with_the_kernel():
    plan = compile_plan(_four())
    sol = plan.sweep(1000, order=0)
    c, s = K.crank_cs(sol.input, plan.theta0)
    c1, s1 = sol.link_state(plan.linkage.driver.link).cs
    assert np.array_equal(c, c1) and np.array_equal(s, s1)


def test_crank_motion_kept_with_the_grid_is_the_states_own_bit_for_bit():
    """The crank's points and rates kept with the grid equal what a solve at other inputs (no
    grid: :meth:`Plan.evaluate`) computes at the same inputs, to the bit (signed zeros too), and
    what a user gets of them is a writable copy."""
    lk = _four()
    plan = compile_plan(lk)
    crank = lk.driver.link
    for order in (0, 1, 2):
        for _ in range(2):
            sol = plan.sweep(360, order=order)
            ref = plan.evaluate(sol.input.copy(), order=order)     # no grid: computed afresh
            for j in lk.link(crank).joints:
                for get in ("position", "velocity", "acceleration")[:order + 1]:
                    a, b = getattr(sol, get)(j), getattr(ref, get)(j)
                    assert a.tobytes() == b.tobytes()
                    a[:] = 7.0                                     # the user's own copy
    again = plan.sweep(360, order=2)
    assert again.position("B").tobytes() == ref.position("B").tobytes()
    assert again.velocity("B").tobytes() == ref.velocity("B").tobytes()
    st = again.link_state(crank)
    for v in st._points.values():
        for pair in v:
            for a in pair:
                assert not (isinstance(a, np.ndarray) and a.flags.writeable)


@pytest.mark.parametrize("name", ["fourbar_crank_rocker", "slider_crank_offset", "sixbar_moving_guide",
                                  "fourbar_loaded"])
def test_sweep_from_the_grid_equals_a_solve_without_it(name):
    """Everything a sweep gives (kept crank motion, a probe proved from the crank's finiteness)
    is what a solve at the same inputs without the grid gives, to the bit."""
    lk = load_scene(example_path(name)).elements[0]
    plan = compile_plan(lk)
    for n in (8, 360):
        for _ in range(2):
            sol = plan.sweep(n, order=2)
            ref = plan.evaluate(sol.input.copy(), order=2)
            assert sol.valid.tobytes() == ref.valid.tobytes()
            assert sol.rates_valid.tobytes() == ref.rates_valid.tobytes()
            for j in lk.joint_ids:
                for get in ("position", "velocity", "acceleration"):
                    assert getattr(sol, get)(j).tobytes() == getattr(ref, get)(j).tobytes(), (j, get)
            for k in lk.moving_links:
                assert sol.alpha(k).tobytes() == ref.alpha(k).tobytes()


def test_sweeps_of_one_plan_in_threads_equal_a_serial_sweep():
    """What solves share (the grid, the crank's kept motion, the frame's template) is complete
    before it is shared: solves of one plan in several threads give the serial result."""
    from concurrent.futures import ThreadPoolExecutor

    lk = load_scene(example_path("sixbar_moving_guide")).elements[0]
    ref = compile_plan(lk).evaluate(compile_plan(lk).sweep(360).input.copy(), order=2)
    plan = compile_plan(lk)

    def one(_):
        sol = plan.sweep(360, order=2)
        return all(getattr(sol, get)(j).tobytes() == getattr(ref, get)(j).tobytes()
                   for j in lk.joint_ids for get in ("position", "velocity", "acceleration"))

    with ThreadPoolExecutor(4) as ex:
        assert all(ex.map(one, range(40)))
