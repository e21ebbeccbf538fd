"""lipmpcc.plots.path_following: paper A's figures drawn from a small hand-made PathFollowingLog."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.plots import path_following as pf
from lipmpcc.plots.logs import PathFollowingLog
from lipmpcc.push import Push

PATH = LinePath((0, 0), (10, 0))


def _log(continuous: bool = False) -> PathFollowingLog:
    """Eight steps of 0.2 m along x, feet 0.13 m either side, a push at 1 s; the COM sampled every 0.1 s."""
    n, m = 8, 33
    t = 0.4 * np.arange(1, n + 1)
    sides = np.array([1, -1] * 4)
    footholds = np.column_stack([0.2 * np.arange(1, n + 1), 0.13 * sides, np.zeros(n)])
    tc = np.linspace(0.0, 3.2, m)
    com = np.column_stack([0.25 * tc, np.full(m, 0.25), 0.02 * np.sin(4 * tc), np.zeros(m)])
    err = 0.02 * np.sin(t)
    return PathFollowingLog(
        t=t, e_contouring=err, e_lag=0.5 * err, e_cartesian=np.abs(err), footholds=footholds, sides=sides,
        step_offsets=np.column_stack([np.full(n, 0.1), 0.13 * sides]), v_avg_t=t, v_avg=np.full(n, 0.1), v_max=0.3,
        tc=tc, com=com, obstacles=np.stack([np.column_stack([1.5 + 0.1 * tc, np.zeros(m)])]),
        clearance=np.full(m, 0.5), pushes=(Push((40.0, 10.0), 1.0, 0.1),), progress=0.8,
        theta_c=0.25 * tc if continuous else None, e_contouring_c=0.02 * np.sin(tc) if continuous else None,
    )


def test_figure_circle_draws_the_path_the_com_the_feet_and_the_errors() -> None:
    log = _log()
    fig = pf.figure_circle(log, PATH, "hand-made")
    try:
        ax_path, ax_err = fig.axes
        lines = {ln.get_label(): ln for ln in ax_path.get_lines()}
        assert {"reference path", "COM", "left foot", "right foot"} <= set(lines)
        np.testing.assert_array_equal(lines["COM"].get_xdata(), log.com[:, 0])
        np.testing.assert_array_equal(lines["left foot"].get_xdata(), log.footholds[log.sides == 1, 0])
        assert ax_path.get_legend() is not None and len(ax_path.texts) == 1  # the push arrow
        err = {ln.get_label(): ln for ln in ax_err.get_lines()}
        np.testing.assert_array_equal(err["ē_c contouring"].get_ydata(), log.e_contouring)
        assert len(ax_err.patches) == 1  # the push window
        assert "pushes" in [t.get_text() for t in ax_err.get_legend().get_texts()]  # named in the legend
        assert fig._suptitle.get_text() == "hand-made"
    finally:
        plt.close(fig)


def test_a_full_body_log_shows_the_continuous_error_and_the_settle_time() -> None:
    log = _log(continuous=True)
    fig = pf.figure_circle_fullbody(log, PATH)
    try:
        labels = [ln.get_label() for ln in fig.axes[1].get_lines()]
        assert "ē_c of the COM (400 Hz)" in labels and "ē_c at touch-downs" in labels and "settle time" in labels
        settle = [ln for ln in fig.axes[1].get_lines() if ln.get_label() == "settle time"][0]
        assert settle.get_xdata()[0] == pytest.approx(3.0)
    finally:
        plt.close(fig)


def test_figure_overtake_has_four_panels_and_the_obstacles() -> None:
    log = _log()
    ob = Obstacle.circle(0.25, path=PATH, s0=1.5, speed=0.1)
    fig = pf.figure_overtake(log, PATH, [ob], cartesian=True)
    try:
        assert len(fig.axes) == 4
        assert len(fig.axes[0].patches) == 4  # the obstacle at four instants
        assert [ln.get_label() for ln in fig.axes[1].get_lines()][0] == "‖e‖ Cartesian"
        assert fig.axes[3].get_ylim()[1] == pytest.approx(1.15 * log.v_max)
    finally:
        plt.close(fig)
    fig = pf.figure_overtake(log, PATH, [ob], cartesian=False)
    try:
        assert {"ē_c contouring", "ē_l lag"} <= {ln.get_label() for ln in fig.axes[1].get_lines()}
    finally:
        plt.close(fig)


def test_frames_and_bad_logs() -> None:
    images = [np.zeros((8, 8, 3), np.uint8)] * 5
    fig = pf.figure_frames(images, [0.0, 0.5, 1.0, 1.5, 2.0], title="frames", ncols=3)
    try:
        assert len(fig.axes) == 6 and sum(bool(ax.images) for ax in fig.axes) == 5
        assert fig.axes[1].get_title() == "t = 0.5 s"
    finally:
        plt.close(fig)
    with pytest.raises(InvalidInputError, match="PathFollowingLog"):
        pf.figure_circle({"t": []}, PATH)
