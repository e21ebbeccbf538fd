"""The figures read one record per kind of run: a LIP run and an ALIP run are drawn through it."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.plots import path_following as pf_plots
from lipmpcc.plots import stepping_stones as st_plots
from lipmpcc.plots.logs import PathFollowingLog, SteppingStonesLog
from lipmpcc.push import Push
from lipmpcc.studies.path_scenarios import paper_a_pushes
from lipmpcc.studies.path_following import simulate_lip
from lipmpcc.studies.stone_course import paper_pushes, push_stones
from lipmpcc.studies.stepping_stones import run_case


def test_a_lip_run_is_drawn_from_its_path_following_log() -> None:
    pushes = paper_a_pushes(4.0, seed=1)
    assert pushes and all(isinstance(p, Push) and len(p.force) == 2 for p in pushes)
    run = simulate_lip("circle-push", pushes=pushes, n_steps=10)
    log = run.log
    assert isinstance(log, PathFollowingLog) and log.steps == 10 == run.summary["steps"]
    assert log.e_contouring_c is None and log.theta_c is None  # the LIP's errors are per step
    assert log.step_offsets.shape == (10, 2) and len(log.v_avg_t) == len(log.v_avg)
    assert log.pushes == tuple(pushes)
    fig = pf_plots.figure_circle(log, run.path, "circle")
    assert len(fig.axes) == 2
    plt.close(fig)
    with pytest.raises(InvalidInputError, match="lip_path_log"):
        pf_plots.figure_circle(run.lip_log, run.path)  # a loop's own log is not drawn directly
    over = simulate_lip("overtake", planner="cartesian", n_steps=8)
    fig = pf_plots.figure_overtake(over.log, over.path, over.obstacles, cartesian=True)
    assert len(fig.axes) == 4
    plt.close(fig)


def test_an_alip_log_is_a_stepping_stones_log_and_other_objects_are_not() -> None:
    log, m = run_case("alip-mpc", push_stones(10), pushes=paper_pushes())
    assert isinstance(log, SteppingStonesLog) and not m["fell"]
    assert len(log.push_windows) == 2  # towards stones 5 and 10; the others are beyond the course
    fig = st_plots.plot_push_response(log, title="push")
    plt.close(fig)
    with pytest.raises(InvalidInputError, match="log"):
        st_plots.plot_footprints(np.zeros(3))
