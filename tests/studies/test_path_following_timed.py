"""``--step-duration-range`` on a full body: the timed MPCC re-planned at 25 Hz within each step
(lipmpcc.planners.sources.mpcc.TimedMpccFootstepSource) walks digit_like in MuJoCo; the summary gains the range and the
planned and executed durations (a fixed-T run's summary is unchanged: no such fields)."""

from __future__ import annotations

import json

import pytest

from lipmpcc.cli import main

pytestmark = pytest.mark.slow


def test_digit_like_runs_the_timed_mpcc_and_reports_the_durations(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("LIPMPCC_FAST", "1")
    out = tmp_path / "o"
    assert main(["run", "overtake", "--robot", "digit_like", "--step-duration-range", "0.3", "0.5", "--duration", "4",
                 "--obstacle-speed", "0.8", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["step_duration_range"] == [0.3, 0.5] and s["params"]["rate_hz"] == 25.0
    assert not s["fell"] and s["solver_failures"] == 0 and s["outcome"] == "completed"
    planned, executed = s["planned_durations_s"], s["executed_durations_s"]
    assert 0.3 - 1e-9 <= planned["min"] and planned["max"] <= 0.5 + 1e-9 and planned["median"] < 0.4
    # executed between touch-downs: a foot may meet the ground a tick or two before its clock ends
    assert executed["n"] >= 8 and 0.25 <= executed["min"] and executed["max"] <= 0.5 + 1e-9


def test_digit_like_timed_mpcc_overtakes_the_08_m_per_s_obstacle_without_contact(tmp_path) -> None:
    """Issue 18's full-body criterion: with T in [0.3, 0.5] s, digit_like passes the 0.8 m/s obstacle on the
    line (fixed T = 0.4 s cannot: 0.75 m/s at most) without a fall and with the whole body clear of it. Before
    the full-body parameters of the timed MPCC (a heading weight, a body disk holding the standing robot) it
    touched the obstacle (−0.051 m) and fell at 22.1 s (2026-12-02); it passes it at about 20.6 s."""
    out = tmp_path / "o"
    assert main(["run", "overtake", "--robot", "digit_like", "--step-duration-range", "0.3", "0.5", "--duration", "24",
                 "--obstacle-speed", "0.8", "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert not s["fell"] and s["overtook"] and not s["collided"]
    assert s["min_body_clearance_m"] > 0.0 and s["min_clearance_m"] > 0.0
    assert s["planner_params"]["robot_radius"] > 0.4 and s["planner_params"]["heading_weight"] == 200.0 and s["planner_params"]["R"][2] == 50.0
