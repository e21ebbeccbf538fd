"""The stone choice as a MILP (issue 29, notebook 13): big-M and hull rows pick one stone per foot; the plain
branch-and-bound finds HiGHS's optimum and explores fewer nodes on the hull; the MILP planner crosses a field."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.planners.stone_field import StoneFieldParams
from lipmpcc.planners.stone_milp import (MilpStoneFieldPlanner, branch_and_bound, footstep_milp, hull_rows,
                                         one_stone_rows, relax, solve_milp)
from lipmpcc.stone_field import make_stone_field
from lipmpcc.studies.stone_field import run_field
from lipmpcc.terrain import entry_foothold

C = np.array([[0.3, -0.1], [0.35, 0.2], [0.7, 0.0]])
H = np.array([[0.1, 0.05], [0.1, 0.05], [0.06, 0.04]])


def test_big_m_rows_hold_exactly_on_the_chosen_stone() -> None:
    A, b = one_stone_rows(C, H, 2.0)
    holds = lambda u, z: bool(np.all(A @ np.r_[u, z] <= b + 1e-9))  # noqa: E731
    e = np.eye(3)
    assert holds([0.35, 0.2], e[1]) and holds([0.45, 0.25], e[1]) and holds([0.64, -0.04], e[2])
    assert not holds([0.35, 0.2], e[0]) and not holds([0.46, 0.2], e[1])
    assert not holds([0.35, 0.2], np.zeros(3)) and not holds([0.35, 0.2], e[0] + e[1])


def test_hull_rows_hold_on_the_union_and_relax_to_its_hull() -> None:
    A, b, E, e = hull_rows(C, H)
    # the foothold on stone 1: v_1 = u, z_1 = 1, the other copies 0
    x = np.zeros(2 + 9)
    x[:2], x[3], x[2 + 3 + 2:2 + 3 + 4] = [0.4, 0.22], 1.0, [0.4, 0.22]
    assert np.all(A @ x <= b + 1e-12) and np.allclose(E @ x, e)
    x[3] = 0.0  # z_1 = 0 forces v_1 = 0: u = v_1 breaks
    assert not (np.all(A @ x <= b + 1e-12) and np.allclose(E @ x, e))


def _small_problem(form: str):  # noqa: ANN202
    fld = make_stone_field(4, length=1.6, density=5.0)
    return MilpStoneFieldPlanner(fld).problem(entry_foothold(), +1, horizon=4, formulation=form)


def test_branch_and_bound_finds_highs_optimum_and_the_hull_explores_less() -> None:
    big, hull = _small_problem("big-m"), _small_problem("hull")
    x, cost, _ = solve_milp(big)
    rb, rh = branch_and_bound(big), branch_and_bound(hull)
    assert rb.cost == pytest.approx(cost, abs=1e-6) and rh.cost == pytest.approx(cost, abs=1e-6)
    assert rh.n_nodes < rb.n_nodes and rb.nodes[0].status == "branched"
    assert relax(big)[0] == pytest.approx(rb.root_bound) and rb.root_bound <= cost + 1e-9
    nodes, feet = big.decode(rb.x)
    fld = make_stone_field(4, length=1.6, density=5.0)
    for j, u in zip(nodes, feet):  # every foothold on the stone its binary picked
        on = fld.in_goal(u) if j == fld.n_stones else fld.stone_at(u) == j
        assert on, (j, u)


def test_the_milp_planner_crosses_a_field_with_a_foot() -> None:
    fld = make_stone_field(0)
    prm = StoneFieldParams(mpc=StoneFieldParams().mpc.__class__.paper(cop_range=(0.06, 0.025)))
    pl = MilpStoneFieldPlanner(fld, prm)
    r = run_field(fld, planner=pl)
    assert r.outcome == "completed" and pl.name == "stone-field-milp" and len(pl.milp_times) >= r.field_steps - 1


def test_bad_inputs_are_named() -> None:
    with pytest.raises(InvalidInputError, match="formulation"):
        footstep_milp(C, H, (0, 0), 1, [np.ones(3)], [np.arange(3)], formulation="sos1")
    with pytest.raises(InvalidInputError, match="limits"):
        footstep_milp(C, H, (0, 0), 1, [np.ones(3)], [np.arange(3)], limits=(0.5, 0.4, 0.2))
    with pytest.raises(InvalidInputError, match="rows"):
        MilpStoneFieldPlanner(make_stone_field(0), rows=42)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"\(rows, 5\)"):
        footstep_milp(C, H, (0, 0), 1, [np.ones(3)], [np.arange(3)], rows=lambda c, h, m: (np.zeros((2, 3)), np.zeros(2)))
