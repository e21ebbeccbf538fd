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


def test_an_obstacle_along_the_path_walks_on_past_its_ends():
    """Issue 31: it does not stand on the path's end for good (an ``ahead`` obstacle made the goal unreachable)."""
    from lipmpcc.paths import SplinePath

    path = SplinePath(np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 2.0]]))
    L, end, tan = path.length, path.position(path.length), path.tangent(path.length)
    a = Obstacle.circle(0.3, path=path, s0=L - 1.0, speed=0.5)
    assert np.allclose(a.center(2.0), end)
    assert np.allclose(a.center(6.0), end + 2.0 * tan)  # 2 m past the end, straight along its tangent
    assert np.allclose(a.center(np.array([1.0, 6.0])), [path.position(L - 0.5), end + 2.0 * tan])
    assert a.heading(6.0) == pytest.approx(path.slope(L))
    back = Obstacle.circle(0.3, path=path, s0=1.0, speed=-0.5)  # an oncoming one walks on past the start
    assert np.allclose(back.center(4.0), path.position(0.0) - 1.0 * path.tangent(0.0))


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


def test_json_comment_lines_are_skipped_and_errors_keep_their_line(tmp_path):
    # issue 15: every reader accepts '#' comment lines (the path and stone CSVs did, the JSON did not)
    f = tmp_path / "obs.json"
    f.write_text('# my obstacles; world frame [m]\n[\n  # one moving along the path\n'
                 '  {"shape": "circle", "radius": 0.25, "s0": 2.0, "speed": 0.6, "name": "#1"}\n]\n')
    (ob,) = obstacles_from_json(f, LinePath((0, 0), (10, 0)))
    assert ob.is_circle and ob.speed == 0.6
    f.write_text('# a comment\n[\n  # another\n  {"shape": "circle",, }\n]\n')
    with pytest.raises(InvalidInputError, match="line 4"):
        obstacles_from_json(f, LinePath((0, 0), (10, 0)))


@pytest.mark.parametrize(
    "content, match",
    [
        ("{not json", "valid JSON"),
        ('{"shape": "circle"}', "JSON list"),
        ('[{"shape": "square", "radius": 1, "s0": 0}]', "'circle' or 'ellipse'"),
        ('[{"shape": "circle", "radius": -1, "s0": 0}]', "radius > 0"),
        ('[{"shape": "ellipse", "axes": [1], "s0": 0}]', "two"),
        ('[{"shape": "circle", "radius": 0.2}]', "either"),
        ('[{"shape": "circle", "radius": 0.2, "s0": 99}]', "arc length >= 0 and <= 10"),
        ('[{"shape": "circle", "radius": 0.2, "position": [0, "a"]}]', "two finite numbers"),
        ('[{"shape": "circle", "radius": "big", "s0": 1}]', r"radius = 'big': expected a radius > 0"),
        ('[{"shape": "circle", "radius": 1e6, "s0": 1}]', r"radius = 1000000.0: expected a radius > 0 and <= 50 \[m\]"),
        ('[{"shape": "circle", "radius": true, "s0": 1}]', r"radius = True"),
        ('[{"shape": "circle", "radius": 0.3, "s0": 1, "speed": 1e308}]', r"obstacles\[0\].speed = 1e\+308: expected a speed >= -10 and <= 10 \[m/s\]"),
        ('[{"shape": "circle", "radius": 0.3, "position": [0, 0], "velocity": [1e308, 0]}]', r"velocity.*norm <= 10 m/s"),
        ('[{"shape": "circle", "radius": 0.3, "position": [1e300, 0]}]', r"position.*within"),
        ('[{"shape": "ellipse", "axes": [0.3, 1e6], "position": [0, 0]}]', r"axes\[1\] = 1000000.0"),
        ('[{"shape": "circle", "radius": 0.3, "position": [0, 0], "orientation": "x"}]', r"orientation = 'x'"),
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


# ---- issue 14: one validation layer -------------------------------------------------------------
@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Obstacle(axes=(1,)), r"axes = \(1,\): expected a list of two finite numbers \[m\] \(got shape \(1,\)\)"),
        (lambda: Obstacle(axes=1.0), r"axes = 1.0"),
        (lambda: Obstacle.circle(radius="big"), r"radius = 'big': expected a radius > 0 and <= 50 \[m\]"),
        (lambda: Obstacle.circle(1e6, position=(3, 0)), r"radius = 1000000.0: expected a radius > 0 and <= 50 \[m\]"),
        (lambda: Obstacle.circle(0.3, path=LinePath((0, 0), (9, 0)), speed=1e308), r"speed = 1e\+308: expected a speed"),
        (lambda: Obstacle.circle(0.3, velocity=(np.nan, 0)), r"velocity.*NaN or inf"),
        (lambda: Obstacle.circle(0.3, position="here"), r"position = 'here'"),
        (lambda: Obstacle.circle(0.3, path="line"), r"path = 'line': expected a lipmpcc.paths.Path or None"),
        (lambda: Obstacle(axes=(0.5, -1.0)), r"axes\[1\] = -1.0"),
        (lambda: Obstacle.circle(True), r"radius = True"),
    ],
)
def test_bad_obstacles_are_named(make, match):
    from lipmpcc.exceptions import ObstacleError

    with pytest.raises(ObstacleError, match=match):
        make()


def test_numpy_numbers_are_accepted_and_stored_as_floats():
    ob = Obstacle.circle(np.float32(0.25), position=np.array([3, 1]), velocity=(np.int64(0), 0.5))
    assert ob.axes == (0.25, 0.25) and ob.position == (3.0, 1.0) and ob.velocity == (0.0, 0.5)
    assert type(ob.axes[0]) is float
    assert np.allclose(ob.center(2.0), [3.0, 2.0])


def test_binary_obstacle_file_is_refused_clearly(tmp_path):
    f = tmp_path / "obs.json"
    f.write_bytes(b"\x00\x01\xff\xfe\x89PNG")
    with pytest.raises(InvalidInputError, match=r"obs.json.*UTF-8 text.*the file is binary"):
        obstacles_from_json(f, None)


def test_barrier_params_names_bad_arguments():
    ob = Obstacle.circle(0.3, position=(3, 0))
    for kw, match in (({"obstacles": "x"}, r"obstacles = 'x'"), ({"obstacles": [1]}, r"obstacles\[0\] = 1"),
                      ({"times": None}, r"times = None"), ({"inflate": -0.1}, r"inflate = -0.1")):
        args = {"obstacles": [ob], "times": np.zeros(3), "inflate": 0.1, "inflate_foot": 0.1, **kw}
        with pytest.raises(InvalidInputError, match=match):
            barrier_params(**args)


def test_reader_arguments_of_the_wrong_type_are_named(tmp_path):
    f = tmp_path / "obs.json"
    f.write_text("[]")
    with pytest.raises(InvalidInputError, match=r"reference_path = 'circle'"):
        obstacles_from_json(f, "circle")
    with pytest.raises(InvalidInputError, match=r"obstacles = 5: expected the path of a JSON file"):
        obstacles_from_json(5, None)


@pytest.mark.parametrize("kind", ["on a path", "past the path's end", "free", "ellipse on a path"])
def test_barrier_params_unchecked_is_the_checked_bit_for_bit(kind):
    """``check=False`` (the planners' loop: one path evaluation per obstacle, issue 28) gives the same numbers."""
    line = LinePath((0.0, 0.0), (3.0, 1.0))
    ob = {"on a path": Obstacle.circle(0.3, path=line, s0=0.5, speed=0.4),
          "past the path's end": Obstacle.circle(0.3, path=line, s0=2.9, speed=0.6),
          "free": Obstacle.circle(0.2, position=(1.0, -0.5), velocity=(0.3, 0.1), orientation=0.4),
          "ellipse on a path": Obstacle(axes=(0.5, 0.2), path=line, s0=-0.2, speed=0.7)}[kind]
    times = 1.3 + 0.4 * np.arange(6)
    assert np.array_equal(barrier_params([ob], times, 0.25, 0.15, check=False), barrier_params([ob], times, 0.25, 0.15))
