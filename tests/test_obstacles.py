"""lipmpcc.obstacles: motion, clearance, JSON loading and its errors."""

import json

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.obstacles import Obstacle, barrier_params, obstacles_from_json
from lipmpcc.paths import LinePath


def test_motion_along_path_and_with_velocity():
    path = LinePath((0, 0), (10, 0))
    a = Obstacle.circle(0.25, path=path, s0=1.0, speed=0.5)
    assert np.allclose(a.center(2.0), [2.0, 0.0])
    b = Obstacle.circle(0.3, position=(1, 1), velocity=(0.1, -0.2))
    assert np.allclose(b.center(np.array([0.0, 10.0])), [[1, 1], [2, -1]])


def test_clearance_circle_and_ellipse():
    c = Obstacle.circle(0.5, position=(0, 0))
    assert c.clearance([[2.0, 0.0]], 0.0, robot_radius=0.5)[0] == pytest.approx(1.0)
    assert c.clearance([[0.1, 0.0]], 0.0)[0] < 0
    e = Obstacle(axes=(1.0, 0.5), position=(0, 0), orientation=0.0)
    assert e.clearance([[2.0, 0.0]], 0.0)[0] == pytest.approx(1.0, abs=1e-6)
    assert e.clearance([[0.0, 1.5]], 0.0)[0] == pytest.approx(1.0, abs=1e-6)
    assert e.clearance([[0.0, 0.2]], 0.0)[0] < 0
    er = Obstacle(axes=(1.0, 0.5), position=(0, 0), orientation=np.pi / 2)
    assert er.clearance([[0.0, 2.0]], 0.0)[0] == pytest.approx(1.0, abs=1e-6)


def test_barrier_matrix_is_the_inflated_ellipse():
    e = Obstacle(axes=(1.0, 0.5), position=(0, 0), orientation=0.3)
    bp = barrier_params([e], np.array([0.0]), 0.2, 0.1)[0, 0]
    M = np.array([[bp[2], bp[3]], [bp[3], bp[4]]])
    R = np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
    p = R @ np.array([1.2, 0.0])  # on the inflated boundary along the major axis
    assert p @ M @ p == pytest.approx(1.0)


def test_json_loading(tmp_path):
    path = LinePath((0, 0), (10, 0))
    f = tmp_path / "obs.json"
    f.write_text(json.dumps([
        {"shape": "circle", "radius": 0.25, "s0": 2.0, "speed": 0.6},
        {"shape": "ellipse", "axes": [0.5, 0.2], "position": [3, 1], "velocity": [0, -0.1]},
    ]))
    obs = obstacles_from_json(f, path)
    assert len(obs) == 2 and obs[0].is_circle and not obs[1].is_circle
    assert np.allclose(obs[1].center(10.0), [3, 0])


@pytest.mark.parametrize(
    "content, match",
    [
        ("{not json", "valid JSON"),
        ('{"shape": "circle"}', "JSON list"),
        ('[{"shape": "square", "radius": 1, "s0": 0}]', "'circle' or 'ellipse'"),
        ('[{"shape": "circle", "radius": -1, "s0": 0}]', "radius > 0"),
        ('[{"shape": "ellipse", "axes": [1], "s0": 0}]', "two"),
        ('[{"shape": "circle", "radius": 0.2}]', "either"),
        ('[{"shape": "circle", "radius": 0.2, "s0": 99}]', "arc length in"),
        ('[{"shape": "circle", "radius": 0.2, "position": [0, "a"]}]', "two numbers"),
        ('[{"shape": "circle", "radius": "big", "s0": 1}]', "a number"),
    ],
)
def test_json_errors(tmp_path, content, match):
    f = tmp_path / "bad.json"
    f.write_text(content)
    with pytest.raises(InvalidInputError, match=match):
        obstacles_from_json(f, LinePath((0, 0), (10, 0)))


def test_missing_json(tmp_path):
    with pytest.raises(InvalidInputError, match="existing JSON"):
        obstacles_from_json(tmp_path / "none.json", None)
