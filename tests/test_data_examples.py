"""The sample files of data/examples/ (docs/formats.md) load through the public readers, and a
short LIP / ALIP run with them succeeds through the CLI."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from lipmpcc.cli import main
from lipmpcc.obstacles import obstacles_from_json
from lipmpcc.paths import SplinePath, load_path_csv, load_waypoints_csv
from lipmpcc.resources import data_path
from lipmpcc.robots import load_robot, read_layout_file
from lipmpcc.robots.layouts import LAYOUT_KEYS, shipped_layout
from lipmpcc.terrain import entry_foothold, load_stones

from .conftest import REPO

EXAMPLES = data_path("examples")
WAYPOINTS = EXAMPLES / "my_waypoints.csv"
OBSTACLES = EXAMPLES / "my_obstacles.json"
STONES = EXAMPLES / "my_stones.csv"
LAYOUT = EXAMPLES / "my_layout.toml"


def test_the_samples_ship_with_the_package_data() -> None:
    assert sorted(p.name for p in EXAMPLES.iterdir()) == [
        "my_layout.toml", "my_obstacles.json", "my_stones.csv", "my_waypoints.csv",
    ]
    for f in (WAYPOINTS, OBSTACLES, STONES, LAYOUT):
        assert f.read_text().startswith("#"), f"{f.name} opens with a comment header"


def test_waypoints_are_an_s_curve_from_the_robots_start() -> None:
    w = load_waypoints_csv(WAYPOINTS)
    assert w.shape[0] >= 5 and np.array_equal(w[0], [0.0, 0.0])
    path = load_path_csv(WAYPOINTS)
    assert isinstance(path, SplinePath)
    assert path.slope(0.0) == pytest.approx(0.0, abs=0.05)  # leaves the origin along +x
    k = path.curvature(np.linspace(0.0, path.length, 400))
    assert k.max() > 0.2 and k.min() < -0.2  # a left bend and a right bend
    assert np.max(np.abs(k)) < 1.0  # no bend sharper than 1 m radius


def test_obstacles_one_moving_along_the_path_and_one_static() -> None:
    path = load_path_csv(WAYPOINTS)
    obs = obstacles_from_json(OBSTACLES, path)
    assert len(obs) == 2
    moving, static = obs
    assert moving.path is path and moving.is_circle and moving.speed > 0
    assert not np.allclose(moving.center(0.0), moving.center(5.0))
    assert static.path is None and not static.is_circle and static.velocity == (0.0, 0.0)
    assert np.array_equal(static.center(0.0), static.center(10.0))
    # the static one stands beside the path, not on it
    assert np.min(np.linalg.norm(path.sample(500) - static.center(0.0), axis=1)) > max(static.axes)


def test_stones_are_a_reachable_course_for_the_right_foot_first() -> None:
    seq = load_stones(STONES)
    assert len(seq) == 8 and seq.centers[0, 0] > entry_foothold()[0]
    assert seq.centers[0, 1] < 0 < seq.centers[1, 1]  # right foot, then left
    assert np.allclose(seq.sizes, [0.2, 0.1])


def test_the_layout_is_digit_likes_with_every_key_explained() -> None:
    layout = read_layout_file(LAYOUT)
    assert layout == shipped_layout("digit_like")
    text = LAYOUT.read_text()
    for key in LAYOUT_KEYS:
        assert key in text, f"{key} is explained in the sample"
    robot = load_robot(data_path("models", "digit_like", "digit_like.xml"), layout=LAYOUT)
    assert robot.layout_file == LAYOUT and robot.left_foot_body == "left_foot"


def _summary(out: Path) -> dict:
    """The run's summary.json, after checking that docs/formats.md documents each of its fields."""
    s = json.loads((out / "summary.json").read_text())
    documented = set(re.findall(r"`([A-Za-z_0-9]+)`", (REPO / "docs" / "formats.md").read_text()))
    fields = list(s) + [f"{k}.{sub}" for k, v in s.items() if isinstance(v, dict) for sub in v]
    missing = [f for f in fields if f.rsplit(".", 1)[-1] not in documented | {"median", "p90", "max", "n"}]
    assert not missing, f"summary.json fields not in docs/formats.md: {missing}"
    return s


def test_lip_follows_the_sample_path(tmp_path: Path) -> None:
    out = tmp_path / "circle"
    assert main(["run", "circle", "--robot", "lip", "--path", str(WAYPOINTS), "--steps", "30", "--out", str(out)]) == 0
    s = _summary(out)
    assert s["fell"] is False and s["solver_failures"] == 0 and s["steps"] == 30
    assert s["contouring_error_max_m"] < 0.05 and s["progress_m"] > 2.0


def test_lip_overtakes_among_the_sample_obstacles(tmp_path: Path) -> None:
    out = tmp_path / "overtake"
    args = ["run", "overtake", "--robot", "lip", "--path", str(WAYPOINTS), "--obstacles", str(OBSTACLES),
            "--steps", "40", "--out", str(out)]
    assert main(args) == 0
    s = _summary(out)
    assert s["fell"] is False and s["obstacle_speeds_mps"] == [0.15, 0.0]
    assert s["min_clearance_m"] > 0.0 and math.isfinite(s["progress_m"])


def test_alip_crosses_the_sample_stones(tmp_path: Path) -> None:
    out = tmp_path / "stones"
    assert main(["run", "stones", "--robot", "alip", "--stones", str(STONES), "--out", str(out)]) == 0
    s = _summary(out)
    assert s["fell"] is False and s["n_stones"] == 8 and s["steps_completed"] == 8
    assert s["stones_violated"] == 0 and s["stones_file"] == str(STONES)
