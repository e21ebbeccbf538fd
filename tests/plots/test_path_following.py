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


@pytest.mark.parametrize("continuous", [False, True])
def test_figure_follow_path_draws_the_path_the_plan_the_obstacles_and_the_error(continuous) -> None:
    log = _log(continuous=continuous)
    ob = Obstacle.circle(0.25, position=(1.5, 0.0))
    fig = pf.figure_follow_path(log, PATH, [ob], "Path following: test", settle_time=1.0)
    try:
        ax_path, ax_err, ax_v = fig.axes
        lines = {ln.get_label(): ln for ln in ax_path.get_lines()}
        assert {"reference path", "COM", "left foot", "right foot"} <= set(lines)
        np.testing.assert_array_equal(lines["right foot"].get_xdata(), log.footholds[log.sides == -1, 0])
        np.testing.assert_allclose(lines["reference path"].get_xdata()[[0, -1]], [0.0, 10.0])
        assert len(ax_path.patches) == 4  # the obstacle at four instants
        labels = [ln.get_label() for ln in ax_err.get_lines()]
        assert ("ē_c of the COM (400 Hz)" in labels) == continuous
        judged = np.abs(log.e_contouring[log.t - log.tc[0] >= 1.0]).max()
        assert ax_err.get_title() == f"max |contouring error| after 1 s: {judged:.3f} m"
        assert "v_avg" in [ln.get_label() for ln in ax_v.get_lines()]
        assert fig._suptitle.get_text() == "Path following: test"
    finally:
        plt.close(fig)
    fig = pf.figure_follow_path(log, PATH)  # no obstacles: none drawn
    try:
        assert len(fig.axes[0].patches) == 0 and fig._suptitle.get_text() == "Path following"
    finally:
        plt.close(fig)


def _plans(log: PathFollowingLog, N: int = 3) -> list:
    """One hand-made plan per step: the COM 0.2 m further per predicted step, the feet beside it."""
    from types import SimpleNamespace

    plans = []
    for k in range(len(log.footholds)):
        x = 0.2 * k + 0.2 * np.arange(N + 1)
        states = np.column_stack([x, np.full(N + 1, 0.5), np.zeros(N + 1), np.zeros(N + 1), np.zeros(N + 1)])
        feet = np.column_stack([x[:N] + 0.2, 0.13 * np.array([1, -1, 1])[:N], np.zeros(N)])
        plans.append(SimpleNamespace(states=states, footsteps=feet))
    return plans


def test_the_receding_horizon_at_a_step_shows_the_past_solid_and_that_solve_s_plan_dashed() -> None:
    log, obstacle = _log(), Obstacle.circle(0.25, position=(1.5, 0.0), velocity=(0.1, 0.0))
    plans = _plans(log)
    fig, ax = plt.subplots()
    try:
        pf.plot_receding_horizon(ax, log, plans, PATH, 5, [obstacle])
        lines = {ln.get_label(): ln for ln in ax.get_lines()}
        np.testing.assert_array_equal(lines["plan of step 5: COM"].get_xdata(), plans[5].states[:, 0])
        assert lines["plan of step 5: COM"].get_linestyle() == "--"
        np.testing.assert_array_equal(lines["plan: footholds"].get_ydata(), plans[5].footsteps[:, 1])
        placed = len(lines["left feet placed"].get_xdata()) + len(lines["right feet placed"].get_xdata())
        assert placed == 5  # the feet of steps 0..4
        assert lines["COM walked"].get_xdata().max() <= 0.25 * log.t[5] + 1e-12
        assert len(ax.patches) == 1 and ax.get_legend() is not None
        np.testing.assert_allclose(ax.patches[0].center, obstacle.center(log.t[5]))
    finally:
        plt.close(fig)


def test_the_animation_has_at_most_the_frames_asked_and_ends_at_the_last_step() -> None:
    log = _log()
    plans = _plans(log)
    anim = pf.animate_receding_horizon(log, plans, PATH, frames=3, dpi=30)
    try:
        html = anim.to_jshtml()
        assert html.count("frames[") >= 3 and "<img" in html
        ax = anim._fig.axes[0]
        assert ax.get_title().endswith(f"step {len(plans) - 1}")  # the last frame drawn is the last step
    finally:
        plt.close(anim._fig)


def test_the_receding_horizon_names_a_bad_step_or_a_missing_plan() -> None:
    log = _log()
    fig, ax = plt.subplots()
    try:
        with pytest.raises(InvalidInputError, match="plans"):
            pf.plot_receding_horizon(ax, log, _plans(log)[:-1], PATH, 0)
        with pytest.raises(InvalidInputError, match=r"k = 8: expected a step index"):
            pf.plot_receding_horizon(ax, log, _plans(log), PATH, 8)
        with pytest.raises(InvalidInputError, match="frames"):
            pf.animate_receding_horizon(log, _plans(log), PATH, frames=0)
    finally:
        plt.close("all")


def test_the_path_figure_is_framed_on_the_robot_not_on_a_far_moving_obstacle() -> None:
    """issue 31: a pedestrian crossing the path and walking on to y = 40 m does not stretch the axes: they
    hold the path, the COM and the feet with the margin; its track is clipped with an arrow where it goes;
    the stall point is marked; no two labels overlap."""
    base = _log()
    m = len(base.tc)
    far = np.column_stack([np.full(m, 5.0), np.linspace(-4.0, 40.0, m)])
    log = PathFollowingLog(**{**base.__dict__, "obstacles": far[None]})
    ob = Obstacle.circle(0.3, position=(5.0, -4.0), velocity=(0.0, 9.0))  # its drawn track: the log's
    fig = pf.figure_follow_path(log, PATH, [ob], events=[("stalled from 1 s", (0.5, 0.0))])
    try:
        ax = fig.axes[0]
        x0, x1, y0, y1 = pf.path_region(log, PATH, None, [ob])
        assert ax.get_xlim() == pytest.approx((x0, x1))
        assert x0 >= -pf.REGION_MARGIN - 1e-9 and x1 <= 10.0 + pf.REGION_MARGIN + 1e-9
        lo, hi = ax.get_ylim()
        assert -3.0 < lo < 0.0 < hi < 3.0  # not the obstacle's 40 m
        arrows = [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None and t.get_text() == ""]
        assert len(arrows) >= 2  # the push and the obstacle's heading
        assert "stalled from 1 s (0.50, 0.00) m" in [t.get_text() for t in ax.get_legend().get_texts()]
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        boxes = [t.get_window_extent(r) for t in ax.texts if t.get_text()]
        assert len(boxes) >= 2 and not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    finally:
        plt.close(fig)
