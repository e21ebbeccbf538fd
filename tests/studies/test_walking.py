"""lipmpcc.studies.walking: the stand study's pushes and the walk/stand options checked before any
simulation (the runs themselves: tests/loops/fullbody/test_loop.py, the CLI: test_walking_cli.py)."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.push import Push
from lipmpcc.studies import walking
from lipmpcc.studies.options import RunOptions


def test_stand_pushes_are_four_50N_torso_pushes_front_back_left_right() -> None:
    pushes = walking.stand_pushes(t_first=0.5, spacing=0.25)
    assert all(isinstance(p, Push) for p in pushes)
    assert [p.t_start for p in pushes] == [0.5, 0.75, 1.0, 1.25]
    assert [tuple(np.sign(p.force)) for p in pushes] == [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0)]
    assert all(np.linalg.norm(p.force) == 50.0 and p.duration == 0.1 and p.step is None for p in pushes)
    assert [p.t_start for p in walking.stand_pushes()] == [1.0, 2.0, 3.0, 4.0]


def test_defaults() -> None:
    assert (walking.PLANNER, walking.DEFAULT_ROBOT, walking.DEFAULT_SPEED) == ("capture-point", "digit_like", 0.6)


@pytest.mark.parametrize("run", [walking.run_walk, walking.run_stand])
@pytest.mark.parametrize(
    "kw, option",
    [({"robot": "lip"}, "--robot"), ({"robot": "alip"}, "--robot"), ({"planner": "mpcc"}, "--planner"),
     ({"duration": -1.0}, "--duration"), ({"duration": float("nan")}, "--duration")],
)
def test_bad_options_are_named_before_simulating(run, kw: dict, option: str, tmp_path) -> None:
    with pytest.raises(InvalidInputError) as err:  # RunOptions itself refuses a NaN
        run(RunOptions("walk" if run is walking.run_walk else "stand", out=str(tmp_path), **kw))
    assert err.value.name == option
    assert not any(tmp_path.iterdir())  # nothing written


def test_capture_point_params_scale_with_the_layout_sizes() -> None:
    import dataclasses

    from lipmpcc.planners.capture_point import CapturePointParams
    from lipmpcc.robots import load_robot
    from lipmpcc.studies.walking import capture_point_params

    digit = load_robot("digit_like")
    assert capture_point_params(digit) == CapturePointParams()  # Digit's layout states no sizes
    small = dataclasses.replace(digit, step_width=0.13, max_step_length=0.275, step_duration=0.3)
    p = capture_point_params(small)
    assert (p.step_width, p.max_step_forward, p.step_duration) == (0.13, 0.275, 0.3)
    assert p.min_step_width == pytest.approx(0.07) and p.max_step_backward == pytest.approx(0.175)
    assert p.min_duration == pytest.approx(0.225) and p.max_duration == pytest.approx(0.375)
    assert digit.push_scale == 1.0 and dataclasses.replace(digit, total_mass=24.0).push_scale == pytest.approx(24.0 / 47.9)
