"""lipmpcc.sim.stones_scene: the stepping-stone course as MuJoCo terrain (boxes, pit, platforms)."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.sim.stones_scene import SceneBox, StonesSceneParams, scene_boxes
from lipmpcc.terrain import approach_footholds, make_profile


@pytest.fixture(scope="module")
def robot():
    from lipmpcc.robots import load_robot

    return load_robot("digit_like")


def test_scene_boxes_of_a_small_course() -> None:
    """An approach platform under the free footholds, one box per stone (the foot-centre rectangle grown
    by the foot, top at z = 0, ``depth`` deep), an exit platform from the last stone's far edge."""
    course = approach_footholds() + make_profile("I", L=0.4, W=0.15).head(3)
    p = StonesSceneParams()
    boxes = scene_boxes(course, p, foot_size=(0.2, 0.1))
    assert [b.kind for b in boxes] == ["approach", "stone", "stone", "stone", "exit"]
    stones = boxes[1:4]
    assert [b.index for b in stones] == [6, 7, 8] and [b.name for b in stones] == [f"lipmpcc_stone_{i}" for i in (6, 7, 8)]
    for b in stones:
        i = b.index
        np.testing.assert_array_equal(b.center[:2], course.centers[i])
        np.testing.assert_allclose(2 * np.asarray(b.half_size[:2]), course.sizes[i] + [0.2, 0.1])
        assert b.center[2] + b.half_size[2] == pytest.approx(p.top) and 2 * b.half_size[2] == pytest.approx(p.depth)
        assert b.contains_xy(course.centers[i]) and not b.contains_xy(course.centers[i] + [0.0, b.half_size[1] + 0.01])
    free = course.centers[:6]
    app = boxes[0]
    assert app.center[0] - app.half_size[0] == pytest.approx(free[:, 0].min() - p.approach_back)
    assert app.center[0] + app.half_size[0] == pytest.approx(free[:, 0].max() + p.approach_margin)
    ex = boxes[-1]
    assert ex.center[0] - ex.half_size[0] == pytest.approx(course.centers[8][0] + stones[-1].half_size[0])
    assert 2 * ex.half_size[0] == pytest.approx(p.exit_length)
    # a foot margin of the parameters wins over the robot's foot
    wide = scene_boxes(course, StonesSceneParams(foot_margin=(0.3, 0.3)), foot_size=(0.2, 0.1))
    np.testing.assert_allclose(2 * np.asarray(wide[1].half_size[:2]), course.sizes[6] + 0.3)


def test_the_exit_reaches_back_to_the_last_stone_when_a_free_step_would_hang_over_the_pit() -> None:
    """A free step after the course as long as the last one (the planner's) lands with its whole sole on the exit:
    on a short-step course (G1's scaled profile I, L = 0.242 m, sole 0.17 m) the exit starts at the last stone's
    centre; on paper B's L = 0.4 m with Digit's sole it starts at the last stone box's far edge, as before."""
    for L, foot, reaches_back in ((0.242, (0.17, 0.06), True), (0.4, (0.235, 0.08), False)):
        course = approach_footholds() + make_profile("I", L=L, W=0.09).head(4)
        boxes = scene_boxes(course, StonesSceneParams(), foot_size=foot)
        last, ex = boxes[-2], boxes[-1]
        start = ex.center[0] - ex.half_size[0]
        c = course.centers[last.index]
        if reaches_back:
            assert start == pytest.approx(c[0])
        else:
            assert start == pytest.approx(c[0] + last.half_size[0])
        step = c[0] - course.centers[last.index - 1][0]
        assert c[0] + step - 0.5 * foot[0] >= start  # the free step's heel is on the exit


def test_scene_boxes_and_parameters_reject_bad_input() -> None:
    with pytest.raises(InvalidInputError, match="sequence"):
        scene_boxes("stones")
    with pytest.raises(InvalidInputError, match="at least one stone"):
        scene_boxes(approach_footholds())
    with pytest.raises(ParameterError, match="pit_depth"):
        StonesSceneParams(depth=0.5, pit_depth=0.4)
    with pytest.raises(ParameterError, match="foot_margin"):
        StonesSceneParams(foot_margin=(-0.1, 0.0))
    with pytest.raises(ParameterError, match="exit_length"):
        StonesSceneParams(exit_length=0.0)
    assert SceneBox("b", "stone", (0, 0, 0), (0.1, 0.1, 0.1)).contains_xy(np.array([0.1, -0.1]))


@pytest.mark.slow
def test_stone_scene_puts_the_stones_over_a_pit_and_a_foot_off_them_falls(robot) -> None:
    import mujoco

    from lipmpcc.studies.stone_course import make_course
    from lipmpcc.sim.stones_scene import StonesRobotSim, StonesSceneParams

    p = StonesSceneParams()
    course, _ = make_course(make_profile("I", 0, 0.4, 0.15).head(4))
    sim = StonesRobotSim(robot, course)
    m = sim.model
    floor = [g for g in range(m.ngeom) if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE]
    assert floor and all(m.geom_pos[g][2] == pytest.approx(-p.pit_depth) for g in floor)
    stones = [b for b in sim.scene_boxes if b.kind == "stone"]
    assert len(stones) == 4
    for b in stones:  # top at z = 0, 0.3 m deep, the foot-centre bounds grown by the foot
        g = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, b.name)
        assert m.geom_pos[g][2] + m.geom_size[g][2] == pytest.approx(0.0)
        assert 2 * m.geom_size[g][2] == pytest.approx(p.depth)
        assert 2 * m.geom_size[g][0] == pytest.approx(0.2 + robot.foot_length)
        assert m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 1
    # the standing robot is on the approach platform ...
    assert all(sim.contact_state()) and not sim.fallen()
    # ... and a robot standing where there is no stone drops into the pit
    far, _ = make_course(make_profile("I", 0, 0.4, 0.15).head(4), standing_feet=np.array([[3.0, 0.13], [3.0, -0.13]]))
    pit = StonesRobotSim(robot, far, standing_feet=np.array([[3.0, 0.13], [3.0, -0.13]]))
    assert not any(pit.contact_state())
    pit.run(0.5, progress=False)
    assert pit.fallen() and "pit" in pit.fall_reason()


@pytest.mark.slow
@pytest.mark.shared_model
def test_stones_collide_like_the_models_own_floor(shared_digit) -> None:
    import mujoco

    from lipmpcc.studies.stone_course import make_course
    from lipmpcc.sim.stones_scene import StonesRobotSim
    from lipmpcc.terrain import make_profile

    digit = shared_digit
    course, _ = make_course(make_profile("I", L=0.4, W=0.15).head(3))
    sim = StonesRobotSim(digit, course)
    m = sim.model
    for b in sim.scene_boxes:
        g = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, b.name)
        assert m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 127
    right_foot = [g for g in range(m.ngeom) if m.geom_bodyid[g] == mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, digit.right_foot_body)
                  and m.geom_contype[g]]
    assert right_foot and all(m.geom_contype[g] & 127 for g in right_foot)
