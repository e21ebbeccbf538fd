"""lipmpcc.studies.robot_check: `robot init`'s report and `robot check`'s verdict (short runs on the
Menagerie T1 with the layout `robot init` writes; skipped when ../shared is absent)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from lipmpcc.studies.robot_check import CheckResult, CheckStage, check_robot, init_robot

from ..conftest import SHARED_HUMANOIDS


def test_the_verdict_lists_each_stage_and_the_fixes() -> None:
    bad = CheckResult("r", ["a note"], [CheckStage("stand", True, "2 s without falling"),
                                        CheckStage("step in place", False, "fell at t = 1.00 s: ...")])
    text = bad.report()
    assert not bad.passed and "[ok] stand" in text and "[FAILED] step in place" in text and "not ready" in text


def test_t1_stands_and_steps_in_place_with_its_generated_layout(tmp_path: Path) -> None:
    t1 = SHARED_HUMANOIDS["t1"]
    if not t1.exists():
        pytest.skip(f"reference model not found at {t1}")
    # the model beside its layout, as a student's folder (../shared is read-only)
    for item in t1.parent.iterdir():
        (tmp_path / item.name).symlink_to(item)
    report = init_robot(tmp_path / "t1.xml")
    assert "wrote" in report and tomllib.loads((tmp_path / "t1.lipmpcc.toml").read_text())["torso_body"] == "Trunk"
    result = check_robot(tmp_path / "t1.xml", stand_s=0.5, step_s=1.5)  # 0.6 s shift + 2 clock-timed 0.3 s steps
    text = result.report()
    assert result.stages[0].passed, text
    assert [s.name for s in result.stages] == ["stand", "step in place"]
    assert result.stages[1].numbers["steps"] >= 2, text


@pytest.mark.parametrize("name", ["g1", "t1"])
def test_menagerie_humanoids_stand_with_their_generated_layouts(name: str, request) -> None:
    """G1 and T1 as shipped (<position> servos), with the layout `robot init` writes, unedited: 1 s of
    standing, no fall, no QP failure, the posture task on every non-leg joint."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    robot = request.getfixturevalue(f"shared_{name}")
    result = FullBodyLoop(robot, planner=None).run(duration=1.0)
    assert not result.fell, result.fall_reason
    assert result.qp_failures == 0 and result.summary()["fall_reason"] is None
    assert abs(result.log.com[-1, 2] - result.log.com[0, 2]) < 0.01


@pytest.mark.parametrize("name", ["g1", "t1"])
def test_menagerie_humanoids_walk_with_their_generated_layouts(name: str, request) -> None:
    """G1 and T1 walk at 0.5 m/s for 2.5 s (the full 20 s: benchmarks/bench_humanoids.py) with the
    capture-point walker sized by their layouts: steps forward, no fall, no QP failure."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.studies.walking import capture_point_params

    robot = request.getfixturevalue(f"shared_{name}")
    planner = CapturePointPlanner(capture_point_params(robot), speed=0.5, yaw_rate=0.0)
    result = FullBodyLoop(robot, planner=planner).run(duration=2.5)
    assert not result.fell, result.fall_reason
    assert result.n_steps >= 5 and result.displacement > 0.3 and result.qp_failures == 0


def test_g1_follows_the_circle_with_its_generated_layout(shared_g1) -> None:
    """Unitree G1 on paper A's circle (MPCC, fixed T) for 12 s with the layout ``robot init`` writes, unedited:
    the loop times the touch-downs (``touchdown_timing = "loop"`` in the layout). With the contact ending the
    swing ("planner") G1 touched down 27 ms early on average and fell at 8.5 s; with it, the 45 s run completes
    (contouring RMS 0.021 m; benchmarks/bench_humanoids.py)."""
    from lipmpcc.studies.path_following import simulate_full_body

    assert shared_g1.touchdown_timing == "loop"
    run = simulate_full_body(shared_g1, "circle", duration=12.0)
    res = run.result
    assert not res.fell, res.fall_reason
    assert res.n_steps >= 30 and res.qp_failures <= 5
    durations = [t.duration for t in res.touchdowns[3:]]
    assert max(abs(d - shared_g1.step_duration) for d in durations) < 0.01  # the loop's clock, to a WBC tick
    e = run.log.e_contouring
    assert max(abs(x) for x in e) < 0.10


def test_t1_mpcc_parameters_follow_the_circle_on_the_lip(shared_t1) -> None:
    """Paper A's MPCC with the parameters a full-body run gives Booster T1 (its generated layout's LIP height, step
    duration, smallest lateral step and reach rectangle) follows the circle on the LIP: the planner alone is not
    why T1's full-body ``circle`` falls (docs/add_a_robot.md, "Why T1's MPCC runs fall")."""
    import numpy as np

    from lipmpcc.loops import lip as lip_loop
    from lipmpcc.planners.mpcc import MpccPlanner
    from lipmpcc.studies.path_params import fullbody_params, robot_rectangle
    from lipmpcc.studies.path_scenarios import study_path

    t1 = shared_t1
    prm = fullbody_params("circle", "mpcc", t1.lip_height, t1.min_lateral_step, t1.step_duration, robot_rectangle(t1))
    assert prm.model.T == pytest.approx(t1.step_duration) and prm.rectangle.lateral[0] == t1.min_lateral_step
    path = study_path("circle")
    p0 = path.position(0.0)
    log = lip_loop.simulate(MpccPlanner(path, prm), np.array([p0[0], 0.0, p0[1], 0.0, path.slope(0.0)]), 40, [], [])
    assert not log.fell
    e = np.asarray(log.e_contouring)[10:]  # after the start-up
    assert float(np.sqrt(np.mean(e**2))) < 0.03 and float(np.max(np.abs(e))) < 0.08
    assert log.theta_final > 3.0  # [m] of the 15.7 m path in 40 steps of 0.303 s


def test_t1_follows_the_circle_with_its_generated_layout(shared_t1) -> None:
    """Booster T1 on paper A's circle for 6 s with the layout ``robot init`` writes, unedited. Until session 41 it
    fell at 4.78 s with 81 QP failures: the stance ankle alone paid for the swing leg's angular momentum, the CoP
    sat at its rectangle's corner and the stance foot rolled onto it and spun. The layout's ``[wbc_overrides]``
    now damp the centroidal angular momentum with a yielding upper body (``angular_momentum_weight`` 1.0,
    ``arm_posture`` weight 0.01; paper B's runs only before), and the 45 s run completes (146 steps, contouring
    RMS 0.030 m, 0 QP failures; docs/add_a_robot.md, Appendix B)."""
    from lipmpcc.studies.path_following import simulate_full_body

    overrides = dict(shared_t1.wbc_overrides)
    assert overrides["angular_momentum_weight"] == 1.0 and overrides["arm_posture"]["weight"] == 0.01
    assert shared_t1.landing_depth == 0.0 and not shared_t1.steady_heading  # nothing else added
    run = simulate_full_body(shared_t1, "circle", duration=6.0)
    res = run.result
    assert not res.fell, res.fall_reason
    assert res.n_steps >= 17 and res.qp_failures == 0
    assert max(abs(x) for x in run.log.e_contouring) < 0.10


def test_t1_overtake_holds_its_heading_within_its_per_step_bounds(shared_t1) -> None:
    """Booster T1 in paper A's overtake (0.4 m/s obstacle) for 7.5 s with its generated layout, unedited. Until
    session 41 (second part) it fell at 6.6 s (0.3 m/s: 5.7 s): paper A's near-free heading turned the plan by its
    ±0.3 rad bound from step to step and the MPCC asked up to 0.3 m per 0.303 s step (1.0 m/s). A layout that
    states its sizes now gets paper A's per-step bounds as Digit's speed and turn rate (× step_duration / 0.4 s) and
    the steady heading every robot has on a user's scene with obstacles, and its body disk covers the arms that
    swing freely (``clearance.arm_reach``); the 30 s runs at 0.2, 0.3 and 0.4 m/s end with no fall and no contact
    (docs/add_a_robot.md, Appendix B)."""
    from lipmpcc.studies.path_following import simulate_full_body

    from lipmpcc.studies.clearance import arm_reach

    run = simulate_full_body(shared_t1, "overtake", obstacle_speed=0.4, duration=7.5)
    assert run.params.robot_radius == pytest.approx(arm_reach(shared_t1))  # the swinging arms inside the disk
    scale = shared_t1.step_duration / 0.4
    assert run.params.v_max == pytest.approx(0.3 * scale)
    assert run.params.rectangle.heading[1] == pytest.approx(0.3 * scale)
    assert run.params.R[2] >= 50.0  # the steady heading
    res = run.result
    assert not res.fell, res.fall_reason
    assert res.qp_failures <= 2 and run.summary["min_body_clearance_m"] > 0.05  # [m] no part of the body near it


def test_t1_follows_the_circle_when_its_feet_aim_below_the_ground(shared_t1) -> None:
    """Booster T1 on paper A's circle for 5.5 s with its generated layout plus ``landing_depth = 0.02`` and
    ``steady_heading = true``: with the layout as ``robot init`` wrote it before session 41 T1 landed 7 of its
    first 13 feet up to 1.4 cm in the air at the planned time, the stance foot then spun by up to 0.3 rad and the
    robot fell at 4.8 s (the generated layout alone completes since: the test above); aiming the swing foot 2 cm below the ground, every foot is on the ground at its touch-down and the 45 s
    run completes (and with the heading held to the path, at contouring RMS 0.005 m; docs/add_a_robot.md)."""
    from dataclasses import replace

    from lipmpcc.studies.path_following import simulate_full_body

    assert shared_t1.landing_depth == 0.0 and shared_t1.touchdown_timing == "loop"
    run = simulate_full_body(replace(shared_t1, landing_depth=0.02, steady_heading=True), "circle", duration=5.5)
    res = run.result
    assert run.params.heading_weight == pytest.approx(60.0) and run.params.R[2] == pytest.approx(50.0)
    assert run.loop.params.landing_depth == pytest.approx(0.02)  # the layout's, through the loop
    assert not res.fell, res.fall_reason
    assert res.n_steps >= 15 and res.qp_failures == 0
    assert all(td.by_contact for td in res.touchdowns)  # on the ground at the planned time
    assert max(abs(td.pos[2]) for td in res.touchdowns) < 0.01


def test_the_verdict_states_the_layout_values_in_use() -> None:
    """`robot check` prints the values the runs use, with units, and says which the layout leaves to a default
    (digit_like's layout states no step_width / max_step_length / lip_height: Digit's are used)."""
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.robot_check import layout_in_use

    lines = layout_in_use(load_robot("digit_like"))
    text = "\n".join(lines)
    assert lines[0].startswith("mass 47.9 kg") and "pushes x 1.00" in lines[0]
    assert "step_width 0.26 m (Digit's, not in the layout)" in text and "step_duration 0.4 s" in text
    assert "sole 0.235 x 0.08 m" in text and "within 0.9 of it (cop_safety_factor)" in text
    assert "fall_height 0.55 m" in text and lines[-1].startswith("posture: 0 waist, 8 arm, 0 head joints")
    report = CheckResult("digit_like", lines, [CheckStage("stand", True, "2 s without falling")]).report()
    assert all(f"  note: {line}" in report for line in lines)


def test_a_sunk_robot_is_told_the_crouch_option() -> None:
    """The fix for a fall by height names the command that changes the knee bend (no source edit)."""
    from lipmpcc.studies.robot_check import _fixes

    tip = _fixes("torso 0.33 m above the lower sole (< 0.34 m)", 0)
    assert "robot init MODEL.xml --crouch RATIO --force" in tip and "fall_height [m]" in tip
