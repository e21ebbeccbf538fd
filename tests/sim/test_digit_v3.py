"""Bring your own Digit: the whole stack on the reference Digit v3 MJCF, unedited.

osudrl/roadrunner's ``digit-v3.xml`` (../shared, MIT): a slide+ball base, six closed loops (achilles,
toe-A and toe-B rods, ``<equality connect>``), passive shin and heel springs, 20 geared motors. The
runs of the digit_like walking tests, with the same criteria, through the same loop (MuJoCo 2 kHz,
C++ whole-body QP 400 Hz, capture-point steps): standing under four 50 N pushes, 10 m straight at
≥ 0.5 m/s, a full circle of radius 2 m, 20 steps in place. None may fall, and MuJoCo's loop
constraints (soft) must stay closed to 1 mm throughout.

Skipped when ../shared is absent (``shared_digit_xml``). About 50 s of simulated time in all.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ..conftest import SHARED_DIGIT
from .walking_checks import check_full_circle, check_steps_in_place, check_walked_10m_straight

pytestmark = [pytest.mark.slow, pytest.mark.shared_model]

LOOP_TOLERANCE = 1e-3  # [m] anchor distance of any <equality connect>, over every run


class LoopWatch:
    """Wraps ``sim.step`` to record the largest loop-closure error (MuJoCo's anchor distance) [m]
    after every controller tick."""

    def __init__(self, sim) -> None:
        from lipmpcc.robots import loop_closure_errors

        self.max = 0.0
        step = sim.step

        def watched(ctrl, n=1, **kw):
            step(ctrl, n, **kw)
            self.max = max(self.max, float(np.max(loop_closure_errors(sim.model, sim.data))))

        sim.step = watched


@pytest.fixture(scope="module")
def digit() -> object:
    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT}")
    from lipmpcc.robots import load_robot

    return load_robot(SHARED_DIGIT)


def _loop(robot, speed: float | None, yaw_rate: float = 0.0):
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    planner = None if speed is None else CapturePointPlanner(speed=speed, yaw_rate=yaw_rate)
    loop = FullBodyLoop(robot, planner=planner)
    return loop, LoopWatch(loop.sim)


def test_the_file_is_taken_as_is(digit, shared_digit_xml: Path) -> None:
    """The description and the controller read the unedited file: slide+ball base, 6 loops, 4 passive
    springs, 20 geared motors bounded by gear × ctrlrange."""
    from lipmpcc.control.wbc import WholeBodyController

    assert digit.mjcf_path == shared_digit_xml and digit.closed_loops and digit.base_joint is None
    wbc = WholeBodyController(digit)
    assert wbc.model.base_kind == "slide+ball" and wbc.n_loops == 6 and wbc.spring_model == "rigid"
    assert wbc.params.cop_safety_factor == pytest.approx(0.6)  # the Digit v3 layout's override


def test_stands_5s_under_four_50N_pushes(digit) -> None:
    from lipmpcc.studies.walking import stand_pushes

    loop, watch = _loop(digit, None)
    res = loop.run(duration=5.0, pushes=stand_pushes(t_first=1.0, spacing=1.0))
    log = res.log
    assert not res.fell, f"fell at t = {res.fall_time:.2f} s"
    assert res.min_base_height > log.base_height[0] - 0.05
    # both feet down (a lateral push may unload the far foot below 1 N for a tick or two)
    assert np.mean(np.all(log.contact, axis=1)) > 0.995
    feet_drift = (np.linalg.norm(log.left_foot[-1] - log.left_foot[0])
                  + np.linalg.norm(log.right_foot[-1] - log.right_foot[0]))
    assert feet_drift < 0.01
    c = log.com[:, :2] - log.com[0, :2]
    assert np.max(np.linalg.norm(c, axis=1)) > 1e-3  # the pushes move it
    assert np.linalg.norm(c[-1]) < 0.01  # and it comes back
    assert res.qp_failures == 0
    assert watch.max < LOOP_TOLERANCE


def test_walks_10m_straight_at_least_half_a_metre_per_second(digit) -> None:
    loop, watch = _loop(digit, 0.6)
    check_walked_10m_straight(loop.run(duration=19.0))
    assert watch.max < LOOP_TOLERANCE


def test_walks_a_full_circle_of_radius_2m(digit) -> None:
    v, R = 0.5, 2.0
    loop, watch = _loop(digit, v, yaw_rate=v / R)
    check_full_circle(loop.run(duration=28.0), R)
    assert watch.max < LOOP_TOLERANCE


def test_twenty_steps_in_place(digit) -> None:
    loop, watch = _loop(digit, 0.0)
    check_steps_in_place(loop.run(n_steps=20), 20)
    assert watch.max < LOOP_TOLERANCE


def test_cli_walks_the_users_file(shared_digit_xml: Path, tmp_path: Path) -> None:
    """``lipmpcc run walk --robot PATH.xml`` on the unedited file."""
    import json

    from lipmpcc.cli import main

    out = tmp_path / "walk"
    args = ["run", "walk", "--robot", str(shared_digit_xml), "--steps", "6", "--speed", "0.4", "--out", str(out)]
    assert main(args) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["robot"] == "digit_v3" and s["fell"] is False and s["steps"] == 6
    assert s["qp_failures"] == 0 and s["distance_walked_m"] > 0.3


def test_mpcc_overtakes_the_fast_obstacle_without_contact(digit) -> None:
    """Paper A's overtaking study on the user's file: the MPCC at 15 Hz passes the 0.6 m/s obstacle
    without contact or fall. Digit v3's layout asks for a 0.16 m minimum lateral step (its tarsi touch
    below that) and a 0.35 s step (0.86 m/s at v_max = 0.3 m per step: at 0.4 s it walked beside the
    obstacle for 15 s, gaining only 0.02–0.05 m/s on it)."""
    from lipmpcc.studies.path_following import simulate_full_body as simulate
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    assert digit.min_lateral_step == pytest.approx(0.16) and digit.step_duration == pytest.approx(0.35)
    probe = FullBodyLoop(digit, planner=None)
    watch = LoopWatch(probe.sim)
    fb = simulate(digit, "overtake", "mpcc", obstacle_speed=0.6, duration=30.0, loop=probe)
    s, log = fb.summary, fb.log
    ob = fb.obstacles[0]
    assert not s["fell"], f"fell at {fb.result.fall_time:.2f} s"
    assert s["min_clearance_m"] >= 0.0
    assert s["overtook"]
    assert s["contouring_error_max_m"] > 0.3  # it went around, beside the obstacle
    lead = log.theta_c[-1] - (ob.s0 + ob.speed * log.tc[-1])
    assert lead > 1.0  # at the end it is well ahead of the obstacle, back on the line
    assert abs(log.e_contouring_c[-1]) < 0.2
    assert s["lag_error_rms_m"] < 0.05
    assert s["solver_failures"] <= 0.02 * len(log.v_avg_t)
    assert watch.max < LOOP_TOLERANCE


def test_cartesian_mpc_trails_the_slow_obstacle_without_contact(digit) -> None:
    """The other half of paper A's overtaking pair on the user's file: the Cartesian MPC behind the
    0.1 m/s obstacle. With paper A's cost it turned step after step (its 0.16 m lateral bound is met
    more cheaply by turning) and fell; with the full body's heading weight it trails. Its Cartesian
    error (≈ 0.16 m) is the sway of 0.16 m side steps at 0.1 m/s, above digit_like's 0.013 m."""
    from lipmpcc.studies.path_following import simulate_full_body as simulate

    fb = simulate(digit, "overtake", "cartesian", obstacle_speed=0.1, duration=25.0)
    s, log = fb.summary, fb.log
    ob = fb.obstacles[0]
    assert not s["fell"], f"fell at {fb.result.fall_time:.2f} s"
    assert s["min_clearance_m"] >= 0.0 and not s["overtook"]
    assert s["cartesian_error_max_m"] < 0.25
    assert s["progress_m"] > 2.5  # it walked up to the obstacle ...
    assert ob.s0 + ob.speed * log.tc[-1] - log.theta_c[-1] < 1.0  # ... and stays behind it, close
    assert np.max(np.abs(log.footholds[:, 2])) < 0.5  # no turning away from the line


@pytest.mark.parametrize("profile, L, W", [("I", 0.2, 0.15), ("III", None, None)])
def test_alip_mpc_crosses_stones(digit, profile, L, W) -> None:
    """Paper B on the user's file: ALIP-MPC at 25 Hz with Digit v3's ankle (``alip_cop_range``) over
    Profile I (L, W) = (0.2, +0.15) and Profile III seed 0, 32 stones each, on a MuJoCo course whose
    stones collide like Digit v3's own floor (conaffinity 127: its right leg has contype 4). With the
    point foot it fell on Profile III."""
    from lipmpcc.studies.stepping_stones import simulate_full_body as simulate
    from lipmpcc.terrain import make_profile

    assert digit.alip_cop_range == (0.04, 0.015)
    run = simulate(digit, "alip-mpc", make_profile(profile, 0, L, W))
    m = run.metrics
    assert not m["fell"], f"fell at stone {m['fall_step']}"
    assert m["steps_completed"] == 32
    assert m["step_rmse_m"] <= 0.05 and m["stones_violated"] == 0
    assert m["solver_failures"] == 0


def test_stones_collide_like_the_models_own_floor(digit) -> None:
    import mujoco

    from lipmpcc.studies.stepping_stones import make_course
    from lipmpcc.sim.stones_scene import StonesRobotSim
    from lipmpcc.terrain import make_profile

    course, _ = make_course(make_profile("I", L=0.4, W=0.15).head(3))
    sim = StonesRobotSim(digit, course)
    m = sim.model
    for b in sim.scene_boxes:
        g = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, b.name)
        assert m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 127
    right_foot = [g for g in range(m.ngeom) if m.geom_bodyid[g] == mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, digit.right_foot_body)
                  and m.geom_contype[g]]
    assert right_foot and all(m.geom_contype[g] & 127 for g in right_foot)
