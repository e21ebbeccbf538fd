"""lipmpcc.studies.clearance: the whole robot's clearance from its MuJoCo geometry (digit_like standing)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.obstacles import Obstacle
from lipmpcc.studies.clearance import BodyClearance


@pytest.fixture(scope="module")
def standing():
    import mujoco

    from lipmpcc.robots import load_robot
    from lipmpcc.robots.description import reset_data

    robot = load_robot("digit_like")
    m = robot.scene_model
    d = mujoco.MjData(m)
    reset_data(m, d, robot.standing_reset, robot.standing_keyframe, robot.standing_qpos)
    mujoco.mj_kinematics(m, d)
    return robot, d.qpos.copy()[None, :], _y_reach(m, d)


def _y_reach(m, d) -> float:
    """How far the robot's geoms reach sideways, max |y| [m], from their shapes (boxes: corners; capsules
    and cylinders: axis ends and radius), independently of MuJoCo's distance code."""
    out = 0.0
    for g in range(m.ngeom):
        if m.geom_bodyid[g] == 0:
            continue
        R = d.geom_xmat[g].reshape(3, 3)
        c, size, kind = d.geom_xpos[g], m.geom_size[g], int(m.geom_type[g])
        if kind == 6:  # box
            corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * size
            out = max(out, float(np.max(np.abs(c[1] + corners @ R[1]))))
        elif kind in (3, 5):  # capsule, cylinder
            a = R[:, 2]
            r = size[0] if kind == 3 else size[0] * math.sqrt(max(0.0, 1.0 - a[1] ** 2))
            out = max(out, max(abs(c[1] + s * size[1] * a[1]) for s in (-1, 1)) + r)
    return out


def test_an_obstacle_the_body_disk_clears_but_the_arm_touches(standing):
    """0.6 m beside the COM with r = 0.25 m: the planner's 0.2 m body disk clears it by 0.15 m, the arm
    (a capsule reaching ~0.35 m out) does not by much; 0.1 m nearer, the arm is inside it."""
    robot, q, _ = standing
    t = np.zeros(1)
    near = BodyClearance(robot, [Obstacle.circle(0.25, position=(0.0, 0.6))]).measure(q, t)
    disk = Obstacle.circle(0.25, position=(0.0, 0.6)).clearance(np.zeros((1, 2)), 0.0, 0.2)[0]
    assert near.min_clearance < disk - 0.1
    assert "arm" in near.geom and near.obstacle == 0 and near.queries >= 1
    hit = BodyClearance(robot, [Obstacle.circle(0.25, position=(0.0, 0.5))]).measure(q, t)
    assert hit.min_clearance < 0.0 and "arm" in hit.geom


def test_distances_match_the_geometry(standing):
    """A far circle: its distance is the centre's distance minus the radius minus the robot's reach;
    an ellipse (a circumscribed prism) is never farther than the ellipse itself."""
    robot, q, y_max = standing
    r = BodyClearance(robot, [Obstacle.circle(0.25, position=(0.0, -3.0))]).measure(q, np.zeros(1))
    assert r.min_clearance == pytest.approx(3.0 - 0.25 - y_max, abs=6e-3)
    wall = Obstacle(axes=(2.0, 0.3), position=(0.0, 1.0))  # it holds the circle of radius 0.3 m
    e = BodyClearance(robot, [wall]).measure(q, np.zeros(1))
    inner = BodyClearance(robot, [Obstacle.circle(0.3, position=(0.0, 1.0))]).measure(q, np.zeros(1))
    assert 1.0 - 0.3 - y_max - 6e-3 <= e.min_clearance < inner.min_clearance


def test_moving_obstacles_and_the_least_over_time(standing):
    """An obstacle moving towards the robot: the least clearance is at the last sample, when it is nearest;
    with many samples only a few pairs are handed to MuJoCo."""
    robot, q, y_max = standing
    ob = Obstacle.circle(0.2, position=(0.0, 3.0), velocity=(0.0, -1.0))
    times = np.linspace(0.0, 2.0, 41)
    res = BodyClearance(robot, [ob, Obstacle.circle(0.3, position=(50.0, 0.0))]).measure(np.repeat(q, 41, axis=0), times)
    assert res.time == pytest.approx(2.0) and res.obstacle == 0
    assert res.min_clearance == pytest.approx(1.0 - 0.2 - y_max, abs=6e-3)
    assert res.queries < 20 and res.samples == 41 and res.cost < 1.0


def test_no_obstacles_and_bad_input(standing):
    robot, q, _ = standing
    none = BodyClearance(robot, []).measure(q, np.zeros(1))
    assert math.isinf(none.min_clearance) and none.geom == ""
    with pytest.raises(InvalidInputError, match="qpos"):
        BodyClearance(robot, [Obstacle.circle(0.2, position=(1.0, 0.0))]).measure(q[:, :5], np.zeros(1))
    with pytest.raises(InvalidInputError, match="obstacles"):
        BodyClearance(robot, ["not an obstacle"])


def test_the_pruned_search_finds_the_exhaustive_minimum(standing):
    """Bounds prune the pairs handed to MuJoCo; the least distance is the one every pair gives."""
    robot, q, _ = standing
    rng = np.random.default_rng(3)
    frames = np.repeat(q, 6, axis=0)
    frames[:, 0] += rng.uniform(-0.3, 0.3, 6)
    frames[:, 1] += rng.uniform(-0.3, 0.3, 6)
    times = np.linspace(0.0, 1.0, 6)
    obs = [Obstacle.circle(0.2, position=(0.9, 0.2), velocity=(-0.3, 0.0)),
           Obstacle(axes=(0.6, 0.15), position=(-0.2, -0.9), orientation=0.7),
           Obstacle.circle(0.3, position=(6.0, 6.0))]
    bc = BodyClearance(robot, obs)
    res = bc.measure(frames, times)
    every = min((bc.distance(frames[i], times[i], int(g), j), i, j)
                for i in range(6) for g in bc.robot_geoms for j in range(3))
    assert res.min_clearance == pytest.approx(every[0], abs=1e-9)
    assert res.time == pytest.approx(times[every[1]]) and res.obstacle == every[2]
    assert res.queries < 6 * len(bc.robot_geoms) * 3 / 4


def test_non_finite_configurations_are_left_out(standing):
    robot, q, _ = standing
    frames = np.repeat(q, 3, axis=0)
    frames[2, :] = np.nan  # a diverged simulation's last state
    ob = Obstacle.circle(0.25, position=(0.0, 1.0))
    res = BodyClearance(robot, [ob]).measure(frames, np.array([0.0, 0.1, 0.2]))
    assert math.isfinite(res.min_clearance) and res.samples == 2 and res.time in (0.0, 0.1)


# ---- the swept body (what the geometry covers about the COM during a step) ---------------------------------


def test_the_swept_body_of_digit_like_from_its_geometry() -> None:
    """Standing, the forearms set the radius (0.415 m: 0.27 m ahead, 0.34 m beside the COM) and the thighs reach
    0.29 m behind; swept, the legs (not the arms) reach further ahead and behind, the trailing thigh behind."""
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.clearance import standing_body_radius, swept_body

    robot = load_robot("digit_like")
    still = swept_body(robot)
    assert still.radius == standing_body_radius(robot) and 0.40 < still.radius < 0.43 and still.part.endswith("forearm")
    assert 0.25 < still.front < 0.29 and 0.27 < still.back < 0.31 and 0.33 < still.half_width < 0.37
    assert still.stride == 0.0
    swept = [swept_body(robot, s) for s in (0.1, 0.2, 0.3)]
    backs = [b.back for b in swept]
    assert backs == sorted(backs) and backs[0] > still.back + 0.04  # the thigh moves back with the foot
    assert all(b.half_width == still.half_width for b in swept)  # the arms do not swing
    assert all(b.radius >= still.radius for b in swept) and swept[1].part.endswith("thigh")
    assert 0.40 < swept[1].back < 0.43 and 0.42 < swept[1].radius < 0.45  # measured on a run: back ≤ 0.42 m


def test_a_bigger_robot_sweeps_a_bigger_body(shared_digit) -> None:
    """Digit v3 (wider arms, longer legs) covers more than digit_like, standing and swept; bad strides refused."""
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.clearance import swept_body

    small, big = load_robot("digit_like"), shared_digit
    for stride in (0.0, 0.2):
        a, b = swept_body(small, stride), swept_body(big, stride)
        assert b.radius > a.radius + 0.05 and b.half_width > a.half_width and b.back > a.back
    for bad in (-0.1, float("nan"), True, "0.2"):
        with pytest.raises(InvalidInputError, match="stride"):
            swept_body(small, bad)  # type: ignore[arg-type]
