"""lipmpcc.studies.stone_course: paper B's courses — the approach and the stones moved onto the robot's standing
feet, the push test's stones and footstep-timed pushes, the planners under test and the row labels."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.studies.stone_course import (PLANNERS, case_label, make_course, make_planner, paper_pushes, planner_params,
                                          push_stones)
from lipmpcc.terrain import N_APPROACH, approach_footholds, initial_feet, make_profile


def test_the_course_is_the_approach_then_the_stones_moved_onto_the_standing_feet() -> None:
    stones = make_profile("I", None, 0.4, 0.15).head(4)
    seq, shift = make_course(stones)
    assert len(seq) == N_APPROACH + 4 and np.all(shift == 0.0)
    np.testing.assert_array_equal(seq.centers[:N_APPROACH], approach_footholds().centers)
    feet = np.vstack(initial_feet()) + np.array([1.0, -0.5])
    moved, shift = make_course(stones, feet)
    np.testing.assert_allclose(shift, (1.0, -0.5))
    np.testing.assert_allclose(moved.centers, seq.centers + shift)
    with pytest.raises(InvalidInputError, match="stones"):
        make_course("stones")


def test_the_push_test_pushes_count_the_approach_and_scale() -> None:
    pushes = paper_pushes()
    assert [p.step for p in pushes] == [N_APPROACH + s - 1 for s in (5, 10, 15, 20)]
    assert pushes[0].force == (150.0, 0.0) and paper_pushes(0.5)[0].force == (75.0, 0.0)
    assert all(p.t_start == pytest.approx(0.1) and p.t_end == pytest.approx(0.2) for p in pushes)
    assert len(push_stones()) == 24 and len(push_stones(5)) == 5
    with pytest.raises(InvalidInputError, match="scale"):
        paper_pushes(-1.0)


def test_the_planners_under_test_and_the_row_labels() -> None:
    assert PLANNERS == ("alip-mpc", "alip-qp")
    assert type(make_planner("alip-qp")).__name__ == "AlipQp" and type(make_planner("alip-mpc")).__name__ == "AlipMpc"
    assert planner_params("alip-mpc", cop_range=(0.02, 0.01)).cop_range == (0.02, 0.01)
    with pytest.raises(InvalidInputError, match="--planner"):
        planner_params("capture-point")
    assert case_label("I", 0.4, 0.15) == "I L=0.4 W=+0.15" and case_label("II", seed=3) == "II seed 3"
