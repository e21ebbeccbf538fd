"""lipmpcc.studies.path_scenarios: paper A's scenarios — the paths, the obstacles, the pushes, the presets and the
run lengths, and the checks of a user's path and obstacles against the robot's start."""

from __future__ import annotations

import math

import numpy as np
import pytest


def test_follow_path_bounds_its_steps_by_the_path_length() -> None:
    from lipmpcc.studies.path_scenarios import FOLLOW_PATH_MAX_STEPS, follow_path_duration, follow_path_steps

    assert follow_path_steps(12.0) == 150 + 20 and follow_path_steps(1e6) == FOLLOW_PATH_MAX_STEPS
    # the LIP's bound in time at T = 0.4 s: 12.5 m / 0.2 m/s + 20 steps of 0.4 s, after the 3 s settle
    assert follow_path_duration(12.5) == pytest.approx(3.0 + 8.0 + 62.5) and follow_path_duration(1e6) == 600.0


def test_the_study_paths_start_where_the_robot_stands_along_its_heading():
    from lipmpcc.studies.path_scenarios import CIRCLE_RADIUS, LINE_LENGTH, study_path

    circle = study_path("circle", (1.0, 2.0), 0.5)
    np.testing.assert_allclose(circle.position(0.0), (1.0, 2.0), atol=1e-12)
    assert circle.slope(0.0) == pytest.approx(0.5) and circle.length == pytest.approx(1.25 * 2 * math.pi * CIRCLE_RADIUS)
    line = study_path("overtake", (0.0, 0.0), 0.0)
    assert line.length == pytest.approx(LINE_LENGTH) and line.slope(3.0) == pytest.approx(0.0)


def test_only_overtake_has_the_papers_obstacle_at_the_planners_speed():
    from lipmpcc.studies.path_scenarios import OBSTACLE_START, PAPER_SPEED, study_obstacles, study_path

    path = study_path("overtake")
    assert study_obstacles("circle", "mpcc", path, OBSTACLE_START) == []
    (ob,) = study_obstacles("overtake", "cartesian", path, OBSTACLE_START)
    assert ob.speed == PAPER_SPEED["cartesian"] and ob.s0 == OBSTACLE_START
    assert study_obstacles("overtake", "mpcc", path, OBSTACLE_START, speed=0.8)[0].speed == 0.8


def test_paper_a_pushes_are_seeded_and_bounded():
    from lipmpcc.studies.path_scenarios import paper_a_pushes

    a, b = paper_a_pushes(20.0, 3), paper_a_pushes(20.0, 3)
    assert a == b and a != paper_a_pushes(20.0, 4) and len(a) >= 5
    assert all(np.hypot(*p.force) <= 50.0 + 1e-9 and p.duration == pytest.approx(0.1) and p.t_start < 20.0 for p in a)


def test_a_start_off_the_path_or_on_an_obstacle_is_refused():
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.obstacles import Obstacle
    from lipmpcc.studies.path_scenarios import check_obstacles_clear, check_path_start, study_path

    path = study_path("overtake")
    check_path_start(path, (0.1, 0.0), 0.2)  # near enough
    with pytest.raises(InvalidInputError, match="shift its waypoints"):
        check_path_start(path, (1.0, 0.0), 0.0)
    with pytest.raises(InvalidInputError, match="obstacle 0 starts on the robot"):
        check_obstacles_clear([Obstacle.circle(0.25, position=(0.1, 0.0))], (0.0, 0.0), 0.2)
    check_obstacles_clear([Obstacle.circle(0.25, position=(2.0, 0.0))], (0.0, 0.0), 0.2)


def test_the_line_is_longer_than_the_run_can_walk() -> None:
    """Paper A's line studies run on a path the run cannot reach the end of: 40 m, or the MPCC's most progress
    (v_max per shortest step) plus its plan's reach (the timed 0.8 m/s overtaking's 60 s run reached the 40 m end)."""
    from lipmpcc.studies.path_scenarios import LINE_LENGTH, study_line_length, study_path

    assert study_line_length(0.3, 0.4, 1.5, 30.0) == LINE_LENGTH == study_line_length(0.3, 0.3, 1.5, 30.0)
    assert study_line_length(0.3, 0.3, 1.5, 60.0) == pytest.approx(61.5)
    assert study_line_length(0.3, 0.4, 1.5, None, 200) == pytest.approx(61.5)
    assert study_line_length(0.3, 0.4, 1.5) == LINE_LENGTH
    assert study_path("overtake", (1.0, 2.0), 0.0, 61.5).length == pytest.approx(61.5)
    assert study_path("circle", (0.0, 0.0), 0.0, 61.5).length == pytest.approx(study_path("circle").length)
