"""lipmpcc.plots.stepping_stones: paper B's figures from a short ALIP run (3 stones) and hand-made records."""

from __future__ import annotations

from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.loops.alip import run_alip_loop
from lipmpcc.planners.alip_mpc import AlipMpc
from lipmpcc.plots import stepping_stones as st
from lipmpcc.plots.logs import SteppingStonesLog
from lipmpcc.terrain import approach_footholds, make_profile


@pytest.fixture(scope="module")
def log():
    run = run_alip_loop(AlipMpc(), approach_footholds() + make_profile("I", L=0.4, W=0.15).head(3))
    assert run.completed and not run.fell
    return run


def test_footprints_show_the_stones_the_feet_and_the_paths(log) -> None:
    assert isinstance(log, SteppingStonesLog)
    fig = st.plot_footprints(log, title="three stones")
    try:
        (ax,) = fig.axes
        n_stones = int(np.sum(log.sequence.is_stone))
        assert n_stones == 3 and len(ax.patches) == 2 * n_stones + len(log.footholds)  # stone, bounds, feet
        lines = {ln.get_label(): ln for ln in ax.get_lines()}
        np.testing.assert_array_equal(lines["footholds"].get_xdata(), log.footholds[:, 0])
        np.testing.assert_array_equal(lines["COM"].get_ydata(), log.com[:, 1])
        assert "DCM" in lines and "failed footstep" not in lines
        assert ax.get_title() == "three stones: completes the course"
    finally:
        plt.close(fig)


def test_durations_and_initial_dcm_per_step(log) -> None:
    fig = st.plot_durations_and_dcm(log, title="timing")
    try:
        ax_T, ax_x, ax_y = fig.axes
        planned = [ln for ln in ax_T.get_lines() if ln.get_label() == "planned (each tick)"][0]
        np.testing.assert_array_equal(planned.get_ydata(), log.plan_T)
        dcm_x = [ln for ln in ax_x.get_lines() if ln.get_marker() == "o"][0]
        n = min(len(log.td_times) + 1, len(log.z_initial))
        np.testing.assert_array_equal(dcm_x.get_ydata(), log.z_initial[:n, 0])
        dashed = [ln for ln in ax_x.get_lines() if ln.get_linestyle() == "--"]
        assert sorted(ln.get_ydata()[0] for ln in dashed) == pytest.approx(sorted(log.dcm_bounds.x))
    finally:
        plt.close(fig)
    fig = st.plot_push_response(log, title="no push")
    try:
        assert len(fig.axes) == 4 and fig._suptitle.get_text() == "no push: survives"
    finally:
        plt.close(fig)


def test_table_bars_mark_falls() -> None:
    rows = [
        {"case": "I-0.4", "planner": "alip-mpc", "fell": False, "step_rmse_m": 0.02},
        {"case": "I-0.4", "planner": "alip-qp", "fell": True, "step_rmse_m": float("nan")},
        {"case": "II-0", "planner": "alip-mpc", "fell": False, "step_rmse_m": 0.03},
    ]
    fig = st.plot_table_bars(rows, title="table")
    try:
        (ax,) = fig.axes
        assert sorted(round(p.get_height(), 3) for p in ax.patches) == [0.02, 0.03]
        falls = [ln for ln in ax.get_lines() if ln.get_marker() == "x" and len(ln.get_xdata())]
        assert len(falls) == 1 and [t.get_text() for t in ax.get_xticklabels()] == ["I-0.4", "II-0"]
    finally:
        plt.close(fig)


def _source() -> SimpleNamespace:
    """What the full-body figures read of an ALIP footstep source: records, contact phases, the planner's box."""
    recs = [SimpleNamespace(t=0.1 * k, step_index=k // 2, planned_duration=0.5,
                            result=SimpleNamespace(cop_offset=np.array([0.01 * (k % 3), -0.005]))) for k in range(6)]
    return SimpleNamespace(records=recs, contact_phases=[0.9, 0.88, 0.91],
                           planner=SimpleNamespace(params=SimpleNamespace(cop_range=(0.04, 0.015))))


def test_cop_offsets_and_timing_errors(log) -> None:
    fig = st.plot_cop_offsets(_source(), [(0.2, 0.3, (100.0, 0.0))], title="ankle")
    try:
        ax_x, ax_y = fig.axes
        np.testing.assert_allclose(ax_x.get_lines()[0].get_ydata(), [0.0, 1.0, 2.0, 0.0, 1.0, 2.0])  # [cm]
        assert len(ax_x.patches) == 1  # the push
        assert sorted(ln.get_ydata()[0] for ln in ax_y.get_lines() if ln.get_linestyle() == "--") == pytest.approx([-1.5, 1.5])
    finally:
        plt.close(fig)
    with pytest.raises(InvalidInputError, match="source"):
        st.plot_cop_offsets(SimpleNamespace(records=[]))
    fig = st.plot_timing_errors(log, _source())
    try:
        a, b = fig.axes
        np.testing.assert_allclose(b.get_lines()[0].get_ydata(), [0.9, 0.88, 0.91])
        assert len(a.get_lines()[0].get_ydata()) == len(log.durations)
    finally:
        plt.close(fig)


def test_frames_check_their_configurations_before_rendering() -> None:
    import mujoco

    model = mujoco.MjModel.from_xml_string("<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>")
    with pytest.raises(InvalidInputError, match="frames"):
        st.plot_frames(model, np.zeros((3, model.nq + 1)), np.zeros(3))
    with pytest.raises(InvalidInputError, match="n"):
        st.plot_frames(model, np.zeros((3, model.nq)), np.zeros(3), n=0)
    with pytest.raises(InvalidInputError, match="log"):
        st.plot_durations_and_dcm({"t": []})
