"""Paper B's course and ALIP planners scaled to a robot whose layout states its sizes (CourseScale); Digit's
layouts state none and keep paper B's numbers. The G1 run uses the Menagerie model with the layout
``robot init`` writes (skipped when ../shared is absent)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from lipmpcc.exceptions import ParameterError
from lipmpcc.planners.alip_mpc import AlipMpcParams
from lipmpcc.planners.alip_qp import AlipQpParams
from lipmpcc.studies import RunOptions
from lipmpcc.studies.stepping_stones import _stones_course
from lipmpcc.studies.stone_course import CourseScale, planner_params, scaled_profile

from ..conftest import SHARED_HUMANOIDS


def test_scaled_step_params_scale_reach_width_and_durations() -> None:
    p = AlipMpcParams.paper()
    s = p.scaled(length=0.5, width=0.8, time=0.9)
    assert s.limits.x_max == pytest.approx(0.3) and s.w == pytest.approx(0.8 * p.w)
    assert s.limits.y_min == pytest.approx(0.08)
    assert s.limits.y_max == pytest.approx(0.8 * p.w + 0.5 * (p.limits.y_max - p.w))  # the legs' lateral reach
    assert (s.T_min, s.T_nom, s.T_max) == pytest.approx((0.9 * p.T_min, 0.9 * p.T_nom, 0.9 * p.T_max))
    assert s.horizon == p.horizon and s.alpha_u == p.alpha_u and s.stone_size == p.stone_size
    assert p.scaled() is p
    q = AlipQpParams.paper().scaled(0.5, 1.0, 1.0)
    assert q.limits.x_max == pytest.approx(0.3) and q.T_nom == AlipQpParams.paper().T_nom
    with pytest.raises(ParameterError):
        p.scaled(length=0.0)


def test_a_layout_without_sizes_keeps_paper_b() -> None:
    digit = SimpleNamespace(max_step_length=None, step_width=None, step_duration=0.4)
    assert CourseScale.for_robot(digit) is None  # type: ignore[arg-type]
    assert planner_params("alip-mpc", scale=None) == AlipMpcParams.paper()
    small = CourseScale.for_robot(SimpleNamespace(max_step_length=0.275, step_width=0.13, step_duration=0.3))  # type: ignore[arg-type]
    assert (small.length, small.width, small.time) == pytest.approx((0.5, 0.5, 0.75))
    assert planner_params("alip-mpc", scale=small).limits.x_max == pytest.approx(0.3)


def test_the_scaled_profiles_stay_within_the_scaled_reach() -> None:
    scale = CourseScale(length=0.6, width=0.9, time=0.8)
    limits = AlipMpcParams.paper().scaled(0.6, 0.9, 0.8).limits
    for profile in ("I", "II", "III", "IV"):
        seq = scaled_profile(profile, scale, seed=3)  # raises TerrainError when a stone is out of reach
        steps = np.abs(np.diff(seq.centers, axis=0))
        assert np.all(steps[:, 0] <= limits.x_max) and np.all(steps[:, 1] <= limits.y_max)
    given = scaled_profile("I", scale, L=0.2, W=-0.05)  # --L / --W given: used as given
    assert given.meta["L"][0] == 0.2 and given.meta["W"][0] == -0.05


def test_g1_stones_course_is_scaled_to_its_layout(tmp_path: Path) -> None:
    """`lipmpcc run stones --robot g1.xml` with the layout `robot init` writes: profile I's L, W scaled by G1's
    reach (0.333 m of Digit's 0.55 m), stated in the summary's fields; the paper's case (L = 0.4) kept."""
    from lipmpcc.robots.autolayout import write_layout

    g1 = SHARED_HUMANOIDS["g1"]
    if not g1.exists():
        pytest.skip(f"reference model not found at {g1}")
    for item in g1.parent.iterdir():  # the model beside its layout, as a student's folder (../shared is read-only)
        (tmp_path / item.name).symlink_to(item)
    write_layout(tmp_path / "g1.xml", tmp_path / "g1.lipmpcc.toml")
    course = _stones_course(RunOptions("stones", robot=str(tmp_path / "g1.xml"), profile="I"))
    robot = course.description
    scale = CourseScale.for_robot(robot)
    assert scale is not None and scale.length == pytest.approx(robot.max_step_length / 0.55)
    assert course.extra["L"] == 0.4 and course.extra["L_used_m"] == pytest.approx(0.4 * scale.length)
    assert course.extra["L_used_m"] < robot.max_step_length and course.extra["W_used_m"] == pytest.approx(0.15 * scale.length)
    assert course.extra["course_scale"]["length"] == pytest.approx(scale.length)
    given = _stones_course(RunOptions("stones", robot=str(tmp_path / "g1.xml"), profile="I", L=0.2, W=0.0))
    assert given.extra["L_used_m"] == 0.2 and given.extra["W_used_m"] == 0.0


@pytest.mark.parametrize(("name", "n_stones", "crossed"), [("t1", 6, 6), ("g1", 6, 6)])
def test_menagerie_humanoids_cross_scaled_stones(name: str, n_stones: int, crossed: int, request) -> None:
    """The first stones of profile I scaled to G1 / T1 (layouts from `robot init`, unedited) on the full body:
    both cross 6 stones (no fall, no failed solve). Before the layouts' ``alip_wbc_overrides`` (session 40)
    G1 stepped onto 3 and fell on the back edge of the 3rd; before the scaling both fell on the approach."""
    from lipmpcc.studies.stepping_stones import simulate_full_body
    from lipmpcc.studies.stone_metrics import stones_reached

    robot = request.getfixturevalue(f"shared_{name}")
    run = simulate_full_body(robot, "alip-mpc", scaled_profile("I", CourseScale.for_robot(robot)).head(n_stones))
    assert stones_reached(run.log) >= crossed, run.metrics["fall_reason"]
    assert run.source.approach_failures == 0
    if crossed == n_stones:
        assert not run.result.fell, run.result.fall_reason
        assert run.metrics["step_rmse_m"] < 0.05 and run.metrics["solver_failures"] == 0  # measured: T1 0.010, G1 0.041 m
