"""lipmpcc.sim.decorations: the path, obstacles, footholds and push drawn into a MuJoCo scene from plain
arrays (one function for the live viewer, the replay and the videos)."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.sim.decorations import NEAR_RADIUS, SceneDecorations, draw_decorations

SCENE = "<mujoco><worldbody><geom type='plane' size='5 5 0.1'/></worldbody></mujoco>"


def _scene(maxgeom: int = 1000):
    import mujoco

    return mujoco.MjvScene(mujoco.MjModel.from_xml_string(SCENE), maxgeom=maxgeom)


def _geoms(scn):
    return [scn.geoms[i] for i in range(scn.ngeom)]


def test_each_part_adds_its_geoms_with_its_shape_and_place() -> None:
    import mujoco

    path = np.column_stack([np.linspace(0.0, 2.0, 21), np.zeros(21)])
    deco = SceneDecorations(
        path_xy=path,
        obstacles=[(1.0, 0.5, 0.3, 0.3, 0.0, 1.0), (2.0, -0.5, 0.4, 0.2, 0.5, 0.0)],
        landed=[(0.1, 0.1, 0.0), (0.3, -0.1, 1.0)],
        planned=[(0.5, 0.1), (0.7, -0.1)],
        push=(0.0, 0.0, 1.0, 50.0, 0.0, 0.0),
    )
    scn = _scene()
    assert draw_decorations(scn, deco) == 20 + 2 + 2 + 2 + 1
    g = _geoms(scn)
    caps, obs, feet, arrow = g[:20], g[20:22], g[22:26], g[26]
    assert all(x.type == mujoco.mjtGeom.mjGEOM_CAPSULE for x in caps)
    np.testing.assert_allclose(caps[0].pos[:2], [0.05, 0.0], atol=1e-9)  # the segment's middle
    assert obs[0].type == mujoco.mjtGeom.mjGEOM_CYLINDER and obs[1].type == mujoco.mjtGeom.mjGEOM_ELLIPSOID
    np.testing.assert_allclose(obs[0].size, [0.3, 0.3, 0.5], rtol=1e-6)  # radius 0.3 m, 1 m tall
    np.testing.assert_allclose(obs[1].size, [0.4, 0.2, 0.5], rtol=1e-6)
    np.testing.assert_allclose(obs[1].pos, [2.0, -0.5, 0.5])
    assert [tuple(np.round(x.pos[:2], 6)) for x in feet] == [(0.1, 0.1), (0.3, -0.1), (0.5, 0.1), (0.7, -0.1)]
    assert not np.allclose(feet[0].rgba, feet[1].rgba)  # left and right in their colours
    assert feet[2].size[0] > feet[3].size[0]  # the current plan bigger than its preview
    assert arrow.type == mujoco.mjtGeom.mjGEOM_ARROW


def test_only_the_path_near_the_robot_is_drawn_and_the_scene_never_overflows() -> None:
    path = np.column_stack([np.linspace(0.0, 20.0, 201), np.zeros(201)])
    scn = _scene()
    n = draw_decorations(scn, SceneDecorations(path_xy=path, near_xy=(0.0, 0.0)))
    assert n == int(round(NEAR_RADIUS / 0.1)) - 1 or n == int(round(NEAR_RADIUS / 0.1))
    small = _scene(maxgeom=5)
    assert draw_decorations(small, SceneDecorations(path_xy=path, planned=[(1.0, 1.0)])) == 5
    assert small.ngeom == 5


def test_nothing_to_draw_adds_nothing_and_a_zero_push_no_arrow() -> None:
    scn = _scene()
    assert draw_decorations(scn, SceneDecorations()) == 0
    assert draw_decorations(scn, SceneDecorations(push=(0, 0, 1, 0, 0, 0))) == 0


@pytest.mark.parametrize("kw", [{"path_xy": [[0.0, np.nan]]}, {"obstacles": [[1.0, 2.0]]}, {"landed": [[0.0, 0.0]]},
                                {"push": [1.0, 2.0]}])
def test_bad_arrays_are_named(kw) -> None:
    name = next(iter(kw))
    with pytest.raises(InvalidInputError, match=name):
        SceneDecorations(**kw)
    with pytest.raises(InvalidInputError, match="deco"):
        draw_decorations(_scene(), {"path_xy": []})
