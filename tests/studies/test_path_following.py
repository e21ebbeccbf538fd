"""lipmpcc.studies.path_following: paper A on the full-body robot (digit_like), the MPCC driving the
full-body loop at 15 Hz.

The issue's done-criteria, on CI-sized runs: the circle of radius 2 m (half a lap) with max |contouring
error| ≤ 0.10 m after 3 s and no fall, the same under paper A's random pushes without a fall, the MPCC
overtaking the 0.6 m/s obstacle with non-negative clearance, the Cartesian MPC trailing the 0.1 m/s one
with Cartesian error ≤ 0.06 m; planner failures are survived and counted. (The study's full-body MPCC
parameters: test_path_params.py; the footstep source alone: tests/planners/sources/test_mpcc.py; the CLI:
test_path_following_cli.py, test_path_following_full_body_cli.py.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest


# ---- closed loop on digit_like ------------------------------------------------------------------


@pytest.fixture(scope="module")
def robot():
    from lipmpcc.robots import load_robot

    return load_robot("digit_like")


@pytest.fixture(scope="module")
def probe(robot):
    """One simulator + whole-body controller shared by the closed-loop tests (each run resets them)."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    return FullBodyLoop(robot, planner=None)


def _step_widths(touchdowns) -> np.ndarray:
    out = []
    for a, b in zip(touchdowns[:-1], touchdowns[1:]):
        d = b.pos[:2] - a.pos[:2]
        out.append(abs(-math.sin(b.yaw) * d[0] + math.cos(b.yaw) * d[1]))
    return np.asarray(out)


@pytest.mark.slow
def test_circle_half_lap_within_ten_centimetres(robot, probe) -> None:
    from lipmpcc.studies.path_following import simulate_full_body as simulate

    fb = simulate(robot, "circle", "mpcc", duration=20.0, loop=probe)
    s, log, res = fb.summary, fb.log, fb.result
    assert not s["fell"], f"fell at {res.fall_time:.2f} s"
    assert s["contouring_error_max_m"] <= 0.10  # at the touch-downs, after 3 s
    assert s["contouring_error_continuous_max_m"] <= 0.10  # every WBC tick after 3 s
    assert s["progress_m"] > 0.4 * 2 * math.pi * 2.0 * 20.0 / 48.0  # a steady walk along the circle
    assert s["solver_failures"] == 0
    # heading follows the path: the torso turned by about progress / R
    yaw = np.unwrap(res.log.torso_yaw)
    assert yaw[-1] - yaw[0] == pytest.approx(s["progress_m"] / 2.0, abs=0.35)
    # touch-downs are detected from contact and the steps last ≈ T once the offset is learnt
    assert s["touchdowns_by_contact"] >= 0.9 * s["steps"]
    durations = np.diff(log.t)[5:]
    assert np.all(np.abs(durations - 0.4) < 0.02), durations
    # Digit-class footholds: the feet stay apart and land where the MPCC put them
    assert np.min(_step_widths(res.touchdowns)) >= 0.14
    err = [np.linalg.norm(td.pos[:2] - td.planned) for td in res.touchdowns]
    assert np.sqrt(np.mean(np.square(err))) < 0.02
    # 15 Hz re-planning within each swing
    assert res.planner_rate_hz == 15.0
    per_step = np.bincount([r.step_index for r in fb.source.records])
    assert np.median(per_step) >= 5


@pytest.mark.slow
def test_circle_under_random_pushes_does_not_fall(robot, probe) -> None:
    from lipmpcc.studies.path_scenarios import paper_a_pushes
    from lipmpcc.studies.path_following import simulate_full_body as simulate

    pushes = paper_a_pushes(20.0, seed=3)
    assert len(pushes) >= 8 and all(abs(np.hypot(*p.force)) <= 50.0 and p.duration == 0.1 for p in pushes)
    assert np.all(np.diff([p.t_start for p in pushes]) <= 2.0)
    fb = simulate(robot, "circle-push", "mpcc", pushes=pushes, duration=20.0, loop=probe)
    s = fb.summary
    assert not s["fell"], f"fell at {fb.result.fall_time:.2f} s"
    assert fb.result.sim_time == pytest.approx(20.0, abs=0.01)
    # pushed, yet still following the path
    assert s["contouring_error_max_m"] <= 0.25
    assert s["progress_m"] > 4.0
    recovered = [r for r in s["push_recovery_s"] if np.isfinite(r)]
    assert len(recovered) >= 0.8 * len(s["push_recovery_s"])


@pytest.mark.slow
def test_mpcc_overtakes_the_fast_obstacle(robot, probe) -> None:
    from lipmpcc.studies.path_following import simulate_full_body as simulate

    fb = simulate(robot, "overtake", "mpcc", obstacle_speed=0.6, duration=30.0, loop=probe)
    s, log = fb.summary, fb.log
    assert not s["fell"], f"fell at {fb.result.fall_time:.2f} s"
    assert s["overtook"]
    assert s["min_clearance_m"] >= 0.0
    # the whole body, not only the planner's disks: with the default 0.2 m disk the obstacle caught the trailing
    # right thigh from behind at 22.7 s, 6.7 cm deep; the swept-body disk (0.43 m) keeps it clear
    assert fb.params.robot_radius > 0.42 and s["min_body_clearance_m"] >= 0.03
    # it went around: a large temporary contouring error, while the lag stays small
    assert s["contouring_error_max_m"] > 0.3
    assert s["lag_error_rms_m"] < 0.05
    assert s["v_avg_mean"] > 0.9 * s["v_max"]
    assert abs(log.e_contouring[-1]) < s["contouring_error_max_m"] / 2  # coming back to the path
    assert s["real_time_factor"] > 0


@pytest.mark.slow
def test_cartesian_mpc_trails_the_slow_obstacle(robot, probe) -> None:
    from lipmpcc.studies.path_following import simulate_full_body as simulate

    fb = simulate(robot, "overtake", "cartesian", obstacle_speed=0.1, duration=15.0, loop=probe)
    s, log = fb.summary, fb.log
    ob = fb.obstacles[0]
    assert not s["fell"], f"fell at {fb.result.fall_time:.2f} s"
    assert not s["overtook"]
    assert s["min_clearance_m"] >= 0.0
    assert s["cartesian_error_max_m"] <= 0.06
    # it caught up with the obstacle and stays right behind it, on the path
    gap = ob.s0 + ob.speed * log.tc[-1] - log.theta_c[-1]
    r = fb.params.robot_radius  # the swept-body disk
    assert 0.25 + r <= gap < 0.25 + r + 0.4 and s["min_body_clearance_m"] > 0.0
    assert np.max(np.abs(log.e_contouring_c[log.tc > 3.0])) < 0.05
    # shorter steps once the obstacle constraint is active
    ux = log.step_offsets[:, 0]
    assert np.mean(np.abs(ux[-10:])) < 0.5 * np.max(np.abs(ux))


@pytest.mark.slow
def test_planner_failures_are_survived_and_counted(robot, probe, monkeypatch) -> None:
    """Every 4th MPCC solve is made to fail (all its attempts, warm and cold): the MPCC's fallback
    plan (the previous one, replayed from the new state) keeps the robot walking, and each is counted."""
    from lipmpcc.planners import mpcc as mpcc_module
    from lipmpcc.studies import path_following as study

    original = mpcc_module.MpccPlanner._attempt
    failed_solves: set[int] = set()

    def flaky(self, *args, **kw):
        if self.last is not None and self.solves % 4 == 0:
            failed_solves.add(self.solves)
            self._last_status = ("injected failure", 0)
            return None
        return original(self, *args, **kw)

    monkeypatch.setattr(mpcc_module.MpccPlanner, "_attempt", flaky)
    fb = study.simulate_full_body(robot, "circle", "mpcc", duration=8.0, loop=probe)
    s = fb.summary
    assert not s["fell"]
    assert len(failed_solves) >= 15
    assert s["solver_failures"] == len(failed_solves)
    assert sum(r.status == "fallback" for r in fb.source.records) == s["solver_failures"]
    assert s["progress_m"] > 1.0
    assert s["contouring_error_max_m"] <= 0.10


def test_circle_push_takes_the_sweeps_pushes_or_scales_the_papers() -> None:
    """The hook of ``lipmpcc sweep``: ``RunOptions.extra["pushes"]`` replaces paper A's pushes,
    ``extra["push_scale"]`` scales their forces; without them, paper A's pushes unchanged."""
    from lipmpcc.push import Push
    from lipmpcc.studies import RunOptions
    from lipmpcc.studies.path_following import _study_pushes
    from lipmpcc.studies.path_scenarios import paper_a_pushes

    paper = paper_a_pushes(20.0, 3)
    assert _study_pushes(RunOptions("circle-push", seed=3), "circle-push", 20.0) == paper
    scaled = _study_pushes(RunOptions("circle-push", seed=3, extra={"push_scale": 2.0}), "circle-push", 20.0)
    assert [p.force for p in scaled] == [tuple(2.0 * f for f in p.force) for p in paper]
    assert [p.t_start for p in scaled] == [p.t_start for p in paper]
    mine = [Push((30.0, 0.0), 0.1, 0.1, step=4)]
    assert _study_pushes(RunOptions("circle-push", extra={"pushes": mine}), "circle-push", 20.0) == mine
    assert _study_pushes(RunOptions("circle", extra={"pushes": mine}), "circle", 20.0) == []


# ---- the LIP with --step-duration-range (issue 18: the timed MPCC) -------------------------------
def _old_fields(summary: dict) -> dict:
    """A summary without the fields issue 18 added and the machine's timings."""
    new = ("step_duration_range", "planned_durations_s", "executed_durations_s", "solve_ms")
    return {k: v for k, v in summary.items() if k not in new}


def test_lip_without_a_step_duration_range_is_the_fixed_T_run() -> None:
    """The option absent: the old path (MpccPlanner through lipmpcc.loops.lip.simulate), every earlier
    field the same to the bit; the new fields say fixed T (every duration 0.4 s, no range)."""
    from lipmpcc.loops import lip as lip_loop
    from lipmpcc.planners.mpcc import MpccPlanner
    from lipmpcc.studies import RunOptions, run
    from lipmpcc.studies.path_scenarios import SETTLE_TIME, _initial_state, lip_params, study_path

    res = run(RunOptions("circle", robot="lip", steps=20))
    s = res.summary
    path, prm = study_path("circle"), lip_params("circle", "mpcc")
    log = lip_loop.simulate(MpccPlanner(path, prm), _initial_state(path), 20)
    direct = lip_loop.summarize(log, [], settle_time=SETTLE_TIME)
    assert {k: s[k] for k in _old_fields(direct)} == _old_fields(direct)
    np.testing.assert_array_equal(res.log.lip_log.footholds, log.footholds)
    assert s["step_duration_range"] is None
    for key in ("planned_durations_s", "executed_durations_s"):
        d = s[key]
        assert d["n"] == 20 and d["min"] == pytest.approx(0.4, abs=1e-12) and d["max"] == pytest.approx(0.4, abs=1e-12)
    assert len(s["executed_durations_s"]["values"]) == 20


def test_lip_with_a_fixed_range_gives_the_fixed_T_footsteps() -> None:
    """--step-duration-range 0.4 0.4: the timed MPCC reduces to paper A's (footsteps within 1e-6 m)."""
    from lipmpcc.studies import RunOptions, run

    fixed = run(RunOptions("circle", robot="lip", steps=20))
    timed = run(RunOptions("circle", robot="lip", steps=20, step_duration_range=(0.4, 0.4)))
    assert type(timed.log.lip_log.plans[0]).__name__ == "TimedMpccResult"
    np.testing.assert_allclose(timed.log.lip_log.footholds, fixed.log.lip_log.footholds, atol=1e-6, rtol=0)
    np.testing.assert_allclose(timed.log.lip_log.t, fixed.log.lip_log.t, atol=1e-12, rtol=0)
    assert timed.summary["step_duration_range"] == [0.4, 0.4]
    assert timed.summary["contouring_error_max_m"] == pytest.approx(fixed.summary["contouring_error_max_m"], abs=1e-6)


def test_lip_with_a_step_duration_range_overtakes_the_08_m_per_s_obstacle() -> None:
    """overtake --obstacle-speed 0.8 (40 steps): fixed T = 0.4 s tops out at v_max / T = 0.75 m/s and trails
    it; with T in [0.3, 0.5] s the MPCC shortens its steps and passes it without contact (measured: past it
    by 40 steps, clearance 0.059 m, durations 0.30-0.43 s)."""
    from lipmpcc.studies import RunOptions, run

    fixed = run(RunOptions("overtake", robot="lip", obstacle_speed=0.8, steps=40)).summary
    timed = run(RunOptions("overtake", robot="lip", obstacle_speed=0.8, steps=40, step_duration_range=(0.3, 0.5))).summary
    assert not fixed["overtook"] and not fixed["fell"]
    assert timed["overtook"] and not timed["collided"] and not timed["fell"] and timed["min_clearance_m"] > 0.0
    assert timed["outcome"] == "completed" and timed["solver_failures"] == 0
    d = timed["executed_durations_s"]
    assert 0.3 - 1e-9 <= d["min"] and d["max"] <= 0.5 + 1e-9 and d["median"] < 0.35  # shorter steps
    assert timed["planned_durations_s"]["median"] == pytest.approx(d["median"], abs=1e-12)  # the LIP executes the plan


def test_timed_lip_planner_checks_the_range_against_the_presets_T() -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.planners.mpcc import MpccParams
    from lipmpcc.paths import LinePath
    from lipmpcc.studies.path_params import timed_lip_planner

    pl = timed_lip_planner(LinePath((0, 0), (5, 0)), MpccParams.circle(), (0.3, 0.5))
    assert (pl.params.T_min, pl.params.T_max, pl.params.mpcc) == (0.3, 0.5, MpccParams.circle())
    with pytest.raises(InvalidInputError, match=r"--step-duration-range = \(0.45, 0.5\).*nominal step duration T = 0.4 s"):
        timed_lip_planner(LinePath((0, 0), (5, 0)), MpccParams.circle(), (0.45, 0.5))


# ---- follow-path, --preset and --set (issue 15) ------------------------------------------------------
WAYPOINTS = __import__("pathlib").Path(__file__).resolve().parents[2] / "data" / "examples" / "my_waypoints.csv"


def _bends_max(run) -> float:
    """Max |contouring error| [m] at the support exchanges after the settle time and before the last metre of
    the path (its bends: a run that reaches the end of its path then steps about its end point)."""
    log = run.lip_log
    n = len(log.theta_init)
    judged = (log.theta_init < run.path.length - 1.0) & (log.t[:n] >= run.settle_time)  # as the summary: after 2 s
    return float(np.max(np.abs(log.e_contouring[:n][judged])))


def test_follow_path_keeps_to_the_s_curve_where_the_overtaking_weights_cut_its_bends(tmp_path) -> None:
    """follow-path on the sample S-curve (data/examples/my_waypoints.csv) with the contouring-accurate
    preset walks to its end within 3 cm; the overtaking weights (overtake --path, no obstacle; and
    follow-path --preset overtake) cut its bends by over 8 cm (measured: 0.013 m against 0.12 m on the
    bends; over the whole run 0.013 m against 0.43 m, the overtaking weights wander about the path's end)."""
    from lipmpcc.studies import RunOptions, run

    empty = tmp_path / "none.json"
    empty.write_text("[]")
    fp = run(RunOptions("follow-path", path=str(WAYPOINTS)))
    ov = run(RunOptions("overtake", path=str(WAYPOINTS), obstacles=str(empty), steps=45))
    fo = run(RunOptions("follow-path", path=str(WAYPOINTS), preset="overtake", steps=45))
    s = fp.summary
    assert s["scenario"] == "follow-path" and s["preset"] == "circle" and s["planner_set"] == {}
    assert s["planner_params"]["Q_bar"] == [300.0, 3.0] and s["stopped_reason"] == "end of path"
    assert s["outcome"] == "completed" and s["contouring_error_max_m"] < 0.03 and _bends_max(fp.log) < 0.03
    assert ov.summary["preset"] == "overtake" and fo.summary["planner_params"]["Q_bar"] == [1.0, 1000.0]
    for other in (ov, fo):
        assert _bends_max(other.log) > 0.08 and _bends_max(other.log) > 4 * _bends_max(fp.log)
        assert other.summary["contouring_error_max_m"] > 5 * s["contouring_error_max_m"]
    assert _bends_max(fo.log) == pytest.approx(_bends_max(ov.log), abs=1e-9)  # the same weights, the same run
    assert list(fp.figures) == ["follow-path"]
    assert fp.figures["follow-path"]._suptitle.get_text() == "Path following: MPCC (circle preset) on the LIP"


def test_follow_path_draws_its_obstacles_and_needs_a_path(tmp_path) -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions, run
    from lipmpcc.studies.path_following import simulate_lip

    obstacles = WAYPOINTS.parent / "my_obstacles.json"
    res = run(RunOptions("follow-path", path=str(WAYPOINTS), obstacles=str(obstacles), steps=6))
    s = res.summary
    assert s["min_clearance_m"] is not None and len(s["obstacle_speeds_mps"]) == len(res.log.obstacles) > 0
    fig = res.figures["follow-path"]
    # 6 steps do not reach the end: the title says how the run ended (issue 31)
    assert s["outcome"] == "incomplete" and fig._suptitle.get_text().endswith("with obstacles (incomplete)")
    assert len(fig.axes[0].patches) > 0
    with pytest.raises(InvalidInputError, match="--path"):
        run(RunOptions("follow-path", steps=3))
    with pytest.raises(InvalidInputError, match="path"):
        simulate_lip("follow-path", n_steps=3)


def test_circle_on_a_path_file_names_it_and_draws_its_obstacles() -> None:
    # issue 15's friction: `circle --path FILE --obstacles FILE` drew a figure titled "circle" without the obstacles
    from lipmpcc.studies import RunOptions, run

    obstacles = WAYPOINTS.parent / "my_obstacles.json"
    res = run(RunOptions("circle", path=str(WAYPOINTS), obstacles=str(obstacles), steps=6))
    fig = res.figures["circle"]
    assert fig._suptitle.get_text() == "MPCC on the LIP, circle on my_waypoints.csv, with obstacles"
    assert len(fig.axes[0].patches) > 0
    plain = run(RunOptions("circle", steps=4)).figures["circle"]
    assert plain._suptitle.get_text() == "MPCC on the LIP, circle" and len(plain.axes[0].patches) == 0


def test_set_and_preset_reach_the_planner_and_the_summary() -> None:
    from lipmpcc.studies import RunOptions, run

    res = run(RunOptions("circle", steps=4, preset="overtake", set={"q_c": 50.0, "v_max": 0.2, "N": 4}))
    s = res.summary
    assert s["preset"] == "overtake" and s["planner_set"] == {"q_c": 50.0, "v_max": 0.2, "N": 4.0}
    p = s["planner_params"]
    assert (p["Q_bar"], p["W_bar"], p["rho"], p["v_max"], p["N"]) == ([50.0, 1000.0], [1.0, 1000.0], 50.0, 0.2, 4)
    assert res.log.params.Q_bar == (50.0, 1000.0) and res.log.lip_log.plans[0].theta.shape == (5,)  # N = 4
    assert s["params"]["Q_bar"] == (50.0, 1000.0) or s["params"]["Q_bar"] == [50.0, 1000.0]
    assert s["v_max"] == 0.2


def test_without_preset_or_set_the_study_parameters_are_unchanged() -> None:
    from lipmpcc.planners.presets import PlannerSettings, params_dict
    from lipmpcc.studies import RunOptions, run
    from lipmpcc.studies.path_scenarios import lip_params, study_preset

    assert [study_preset(s, p) for s, p in (("circle", "mpcc"), ("circle-push", "mpcc"), ("overtake", "mpcc"),
                                            ("follow-path", "mpcc"), ("overtake", "cartesian"))] == \
        ["circle", "circle", "overtake", "circle", "cartesian"]
    res = run(RunOptions("overtake", steps=3))
    assert res.log.params == lip_params("overtake", "mpcc") == PlannerSettings().apply(lip_params("overtake", "mpcc"), "mpcc")
    assert res.summary["preset"] == "overtake" and res.summary["planner_params"] == params_dict(lip_params("overtake", "mpcc"))


