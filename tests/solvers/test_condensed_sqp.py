"""lipmpcc.solvers.condensed_sqp: the generic SQP on small problems with known solutions."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from lipmpcc.solvers.condensed_sqp import CondensedSqp


def _problem(lbg: float = 0.5, ubg: float = np.inf, jit: bool = False) -> CondensedSqp:
    """min (u0 − a)² + (u1 + 2)²  s.t.  lbg ≤ u0 + u1 ≤ ubg,  −3 ≤ u ≤ 3, with a parameter a."""
    u = ca.SX.sym("u", 2)
    a = ca.SX.sym("a", 1)
    cost = (u[0] - a) ** 2 + (u[1] + 2) ** 2
    return CondensedSqp("test_sqp", u, [a], cost, u[0] + u[1], [lbg], [ubg], [-3.0, -3.0], [3.0, 3.0], jit=jit)


def test_active_constraint_solution_and_parameter():
    sqp = _problem()
    sol = sqp.solve(np.zeros(2), (np.array([1.0]),))
    # unconstrained optimum (1, -2) violates u0 + u1 >= 0.5: projected onto the line -> (1.75, -1.25)
    assert sol.found and sol.status == "converged"
    np.testing.assert_allclose(sol.u, [1.75, -1.25], atol=1e-4)
    assert sol.cost == pytest.approx(2 * 0.75**2, abs=1e-6)
    assert sqp.lam.shape == (1,) and sqp.lam[0] < 0  # the constraint is active: its multiplier is kept
    # the parameter moves the optimum: a = 4 makes the constraint inactive, u0 hits its bound 3
    far = sqp.solve(np.zeros(2), (np.array([4.0]),))
    assert far.found
    np.testing.assert_allclose(far.u, [3.0, -2.0], atol=1e-4)


def test_non_convex_cost_is_convexified():
    """A concave term (−u1²) is handled by the eigenvalue floor: the solver still converges to a
    feasible local minimum on the bounds."""
    u = ca.SX.sym("u", 2)
    p = ca.SX.sym("p", 1)
    sqp = CondensedSqp("test_sqp_nc", u, [p], (u[0] - p) ** 2 - 0.5 * u[1] ** 2, u[0] - u[1], [-1.0], [1.0],
                       [-2.0, -2.0], [2.0, 2.0])
    sol = sqp.solve(np.array([0.0, 0.1]), (np.array([0.0]),))
    assert sol.found
    # from u1 > 0 the concave term drives u1 to its bound 2, and u0 − u1 >= −1 holds u0 at 1: cost 1 − 2
    np.testing.assert_allclose(sol.u, [1.0, 2.0], atol=1e-3)  # linear convergence: the step tolerance is 1e-4
    assert sol.cost == pytest.approx(-1.0, abs=1e-6)


def test_infeasible_problem_is_reported():
    sqp = _problem(lbg=7.0)  # u0 + u1 <= 6 with the bounds
    sol = sqp.solve(np.zeros(2), (np.array([1.0]),))
    assert not sol.found and ("infeasible" in sol.status or "qp_failed" in sol.status)
    assert np.all(sqp.lam == 0.0)  # no warm start from a failed solve


def test_trace_records_iterations():
    sqp = _problem()
    sqp.trace = []
    sol = sqp.solve(np.zeros(2), (np.array([1.0]),))
    assert len(sqp.trace) == sol.iterations and sqp.qp_iters >= sol.iterations


@pytest.mark.parametrize("offset", [0.0, 1e3, 1e6, 1e9])
def test_a_constraint_far_from_its_infinite_bound_stays_free(offset):
    """g = offset + u0 + u1 >= 0.5 with no upper bound: far from active whatever its value. The finite
    stand-in for the infinite upper bound bounds the QP step, not g (with ``_BIG − g`` as the step's
    upper bound, g above 1e4 made every QP infeasible: an obstacle 100 m away failed every MPCC solve)."""
    u = ca.SX.sym("u", 2)
    a = ca.SX.sym("a", 1)
    cost = (u[0] - a) ** 2 + (u[1] + 2) ** 2
    sqp = CondensedSqp("test_sqp_far", u, [a], cost, u[0] + u[1] + offset, [0.5], [np.inf], [-3.0, -3.0], [3.0, 3.0])
    sol = sqp.solve(np.zeros(2), (np.array([1.0]),))
    expected = [1.75, -1.25] if offset == 0.0 else [1.0, -2.0]
    assert sol.found and sol.status == "converged"
    np.testing.assert_allclose(sol.u, expected, atol=1e-4)
    # and the same below: a lower-unbounded row far below its upper bound
    sqp2 = CondensedSqp("test_sqp_far_lo", u, [a], cost, u[0] + u[1] - offset, [-np.inf], [10.0], [-3.0, -3.0], [3.0, 3.0])
    sol2 = sqp2.solve(np.zeros(2), (np.array([1.0]),))
    assert sol2.found
    np.testing.assert_allclose(sol2.u, [1.0, -2.0], atol=1e-4)


def _maratos(soc: float, max_iter: int = 30) -> CondensedSqp:
    """min 2(u0² + u1² − 1) − u0  s.t.  u0² + u1² = 1 (Nocedal & Wright, example 15.4): solution (1, 0), λ = −3/2;
    from a point of the circle the full SQP step raises the violation more than it lowers the cost."""
    u = ca.SX.sym("u", 2)
    p = ca.SX.sym("p", 1)
    circle = u[0] ** 2 + u[1] ** 2 - 1
    return CondensedSqp("test_sqp_maratos", u, [p], 2 * circle - u[0] + 0 * p[0], circle, [0.0], [0.0], [-3.0, -3.0],
                        [3.0, 3.0], max_iter=max_iter, second_order_correction=soc)


def test_second_order_correction_overcomes_the_maratos_effect():
    start = np.array([np.cos(0.05), np.sin(0.05)])
    plain, corrected = _maratos(0.0), _maratos(0.1)  # the first step is 0.05 long
    for sqp in (plain, corrected):
        sqp.lam = np.array([-1.5])
        sqp.trace = []
    slow = plain.solve(start, (np.zeros(1),))
    assert not slow.found and max(a for _, a, _, _ in plain.trace) < 0.1  # the merit function cuts every step
    fast = corrected.solve(start, (np.zeros(1),))
    assert fast.found and fast.iterations <= 3 and all(a == 1.0 for _, a, _, _ in corrected.trace)
    np.testing.assert_allclose(fast.u, [1.0, 0.0], atol=1e-8)
    short = _maratos(0.01)  # corrects only steps shorter than 0.01: the first is cut as without the correction
    short.lam, short.trace = np.array([-1.5]), []
    short.solve(start, (np.zeros(1),))
    assert short.trace[0][1] < 0.1


@pytest.mark.parametrize("start, saved", [(1.44, 1), (1.5, 0)])
def test_rate_stop_ends_when_the_steps_left_are_below_tol(start, saved):
    """min (u0² − 2)² + u1²: Newton steps shrink quadratically. From 1.44 (steps 2.5e-2, 6.8e-4, 4.8e-7) the second
    step's contraction puts the solution within 1e-4: one iteration less; from 1.5 (7.9e-2, 6.8e-3, 4.9e-5) not."""
    u = ca.SX.sym("u", 2)
    p = ca.SX.sym("p", 1)
    sols = []
    for rate_stop in (0.0, 1.0):
        sqp = CondensedSqp("test_sqp_rate", u, [p], (u[0] ** 2 - p[0]) ** 2 + u[1] ** 2, u[0] + u[1], [-10.0], [10.0],
                           [-3.0, -3.0], [3.0, 3.0], rate_stop=rate_stop)
        sols.append(sqp.solve(np.array([start, 0.0]), (np.array([2.0]),)))
    assert all(s.found for s in sols)
    assert sols[1].iterations == sols[0].iterations - saved
    assert abs(sols[1].u[0] - np.sqrt(2.0)) < 1e-4
