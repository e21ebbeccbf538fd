"""The papers' numbers: one file, one key scheme, read by the studies and the report."""

from __future__ import annotations

import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.push import Push
from lipmpcc.studies import paper
from lipmpcc.studies.stone_course import PLANNERS, paper_pushes, push_stones
from lipmpcc.terrain import N_APPROACH


def test_every_table_ii_course_has_both_planners_under_the_cli_spelling() -> None:
    cases = paper.table_ii_cases()
    assert [paper.case_key(c["profile"], c["L"], c["W"]) for c in cases] == [
        "I L=0.2 W=+0.15", "I L=0.4 W=+0.15", "I L=0.55 W=+0.15",
        "I L=0.2 W=-0.15", "I L=0.4 W=-0.15", "I L=0.55 W=-0.15", "II", "III", "IV",
    ]
    table = paper.reference()["paper_b"]["table_ii_step_rmse_m"]
    assert list(table) == [paper.case_key(c["profile"], c["L"], c["W"]) for c in cases]
    assert all(set(row) == set(PLANNERS) for row in table.values())


def test_rmse_is_a_number_or_none_where_the_paper_reports_a_failure() -> None:
    assert paper.table_ii_rmse("I L=0.55 W=-0.15", "alip-mpc") == 0.022
    assert paper.table_ii_claim("II", "alip-qp") == "falls at step 14"
    assert paper.table_ii_rmse("II", "alip-qp") is None
    assert paper.table_ii_rmse("I L=0.3 W=+0.15", "alip-mpc") is None  # a course of one's own
    assert paper.table_ii_rmse(None, "alip-mpc") is None
    with pytest.raises(InvalidInputError, match="case"):
        paper.table_ii_claim("V", "alip-mpc")


def test_the_push_test_is_read_from_the_reference_file() -> None:
    test = paper.push_test()
    assert (test.n_stones, test.L, test.W, test.window) == (24, 0.4, 0.0, (0.1, 0.2))
    assert [(p.stone, p.force) for p in test.pushes] == [(5, (150.0, 0.0)), (10, (-150.0, 0.0)), (15, (0.0, 75.0)), (20, (0.0, -75.0))]
    assert paper.push_test_claim("alip-mpc") == "survives"
    assert len(push_stones()) == 24 and len(push_stones(7)) == 7


def test_paper_pushes_are_pushes_of_the_swings_towards_the_stones() -> None:
    pushes = paper_pushes()
    assert all(isinstance(p, Push) for p in pushes)
    assert [p.step for p in pushes] == [N_APPROACH + s - 1 for s in (5, 10, 15, 20)]
    assert all(p.t_start == 0.1 and p.t_end == 0.2 for p in pushes)  # the window's end is kept exactly
    assert paper_pushes(0.5)[1].force == (-75.0, 0.0)
    with pytest.raises(InvalidInputError, match="scale"):
        paper_pushes(-1.0)


def test_paper_a_and_the_reference_are_copies() -> None:
    ref = paper.reference()
    ref["paper_a"]["circle"]["claim"] = "edited"
    assert paper.paper_a("circle")["claim"].startswith("followed")
    assert paper.paper_a("overtake_cartesian")["cartesian_error_max_m"] == 0.06
    with pytest.raises(InvalidInputError, match="study"):
        paper.paper_a("stairs")
