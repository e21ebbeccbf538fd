"""lipmpcc.plots.walking: the walk/stand figures drawn from a small hand-made full-body result."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pytest

from lipmpcc.plots import walking
from lipmpcc.push import Push


def _result() -> SimpleNamespace:
    """The fields of a :class:`~lipmpcc.plots.logs.FullBodyRunResult`: 2 s of walking along x at 0.25 m/s, 400 Hz ticks, a touch-down every 0.4 s alternating feet."""
    t = np.arange(0.0, 2.0, 0.0025)
    n = len(t)
    com = np.column_stack([0.25 * t, 0.03 * np.sin(np.pi * t / 0.4), np.full(n, 0.9)])
    com_vel = np.column_stack([np.full(n, 0.25), np.zeros(n), np.zeros(n)])
    log = SimpleNamespace(
        t=t, com=com, com_ref=com + 0.001, com_vel=com_vel, dcm=com[:, :2] + com_vel[:, :2] / 3.3,
        base_height=np.full(n, 1.0), torso_tilt=np.full(n, 0.01), swing_err=np.full(n, 0.002),
        wbc_time=np.full(n, 2e-4), left_foot=np.tile([0.0, 0.13, 0.0], (n, 1)), right_foot=np.tile([0.0, -0.13, 0.0], (n, 1)),
    )
    tds = [SimpleNamespace(t=0.4 * k, side="left" if k % 2 else "right", pos=np.array([0.1 * k, 0.13 if k % 2 else -0.13, 0.0]),
                           planned=np.array([0.1 * k + 0.01, 0.13 if k % 2 else -0.13])) for k in range(1, 5)]
    return SimpleNamespace(log=log, touchdowns=tds, wbc_rate_hz=400.0,
                           wbc_ms={"median": 0.2, "p90": 0.25, "max": 0.4}, real_time_factor=3.0)


def test_top_view_draws_paths_and_footholds() -> None:
    res = _result()
    fig = walking.top_view(res, "walk")
    try:
        (ax,) = fig.axes
        labels = {h.get_label() for h in ax.get_lines()} | {c.get_label() for c in ax.collections}
        assert {"COM", "DCM", "start", "left foot", "right foot", "left planned", "right planned", "initial feet"} <= labels
        left = [c for c in ax.collections if c.get_label() == "left foot"][0]
        np.testing.assert_allclose(left.get_offsets()[:, 0], [0.1, 0.3])
        assert ax.get_title() == "walk" and ax.get_legend() is not None
    finally:
        plt.close(fig)


def test_tracking_marks_the_fall() -> None:
    res = _result()
    res.fell, res.fall_time, res.fall_reason = True, 1.5, "torso tilted 1.01 rad (> 1.0 rad)"
    fig = walking.tracking(res)
    try:
        assert "fell at t = 1.50 s: torso tilted" in fig.axes[0].get_title()
        assert any(np.allclose(ln.get_xdata(), 1.5) for ln in fig.axes[3].get_lines())
    finally:
        plt.close(fig)
    fig = walking.tracking(_result())  # no fall, no mark
    try:
        assert fig.axes[0].get_title() == ""
    finally:
        plt.close(fig)


def test_tracking_has_four_panels_with_the_pushes() -> None:
    res = _result()
    push = Push((50.0, 0.0), 1.0, 0.1)
    fig = walking.tracking(res, [push])
    try:
        assert len(fig.axes) == 5  # four panels and the tilt's twin axis
        com_x = [ln for ln in fig.axes[0].get_lines() if ln.get_label() == "COM x"][0]
        np.testing.assert_array_equal(com_x.get_ydata(), res.log.com[:, 0])
        assert any(ln.get_label() == "stride speed" for ln in fig.axes[1].get_lines())
        err = fig.axes[3].get_lines()[0]
        np.testing.assert_allclose(err.get_ydata(), 2.0)  # [mm]
        assert all(len(fig.axes[i].patches) == 1 for i in range(4))  # the push window on every panel
        assert "pushes" in [t.get_text() for t in fig.axes[0].get_legend().get_texts()]  # and in a legend
    finally:
        plt.close(fig)


def test_timing_histogram_and_stand_view() -> None:
    res = _result()
    fig = walking.timing(res)
    try:
        ax = fig.axes[0]
        budget = [ln for ln in ax.get_lines() if ln.get_label().startswith("tick period")][0]
        assert budget.get_xdata()[0] == pytest.approx(2.5)  # 1 / 400 Hz [ms]
        assert "RTF 3.0" in ax.get_title() and ax.patches
    finally:
        plt.close(fig)
    fig = walking.stand_view(res, [Push((0.0, 50.0), 0.5, 0.1)])
    try:
        excursion, polygon = fig.axes
        y = [ln for ln in excursion.get_lines() if ln.get_label() == "COM y − y0"][0]
        np.testing.assert_allclose(y.get_ydata(), (res.log.com[:, 1] - res.log.com[0, 1]) * 1e3)
        assert len(excursion.texts) == 1 and {"COM", "DCM"} <= {ln.get_label() for ln in polygon.get_lines()}
        assert "push (force [N] beside it)" in [t.get_text() for t in excursion.get_legend().get_texts()]
    finally:
        plt.close(fig)
