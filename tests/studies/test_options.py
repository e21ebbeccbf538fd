"""RunResult.save: summary.json (numpy values as JSON, non-finite as null) and the figures."""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np
import pytest

from lipmpcc.studies import RunOptions, RunResult, get, names


def test_save_writes_the_summary_and_the_figures_and_closes_them(tmp_path) -> None:
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    res = RunResult(
        summary={"a": np.float64(1.5), "n": np.int64(3), "ok": np.bool_(True), "x": np.array([1.0, np.nan]),
                 "t": (1, 2), "inf": float("inf")},
        figures={"line": fig},
    )
    path = res.save(tmp_path / "out")
    assert path == tmp_path / "out" / "summary.json"
    assert json.loads(path.read_text()) == {"a": 1.5, "n": 3, "ok": True, "x": [1.0, None], "t": [1, 2], "inf": None}
    assert (tmp_path / "out" / "line.png").stat().st_size > 0
    assert not plt.fignum_exists(fig.number)


def test_registry_names_every_study() -> None:
    assert names() == ["circle", "circle-push", "overtake", "follow-path", "stones", "push", "walk", "stand", "stone-field"]
    assert get("stones").__module__ == "lipmpcc.studies.stepping_stones"
    assert RunOptions("walk").seed is None and RunOptions("walk").rng_seed == 0


def test_a_figure_that_cannot_be_written_leaves_no_new_summary(tmp_path, monkeypatch) -> None:
    """save writes the figures first and summary.json last, through a renamed file: a figure that fails
    leaves no summary.json (and no temporary file), and the figures are closed all the same."""
    fig, _ = plt.subplots()

    def broken(*args, **kwargs):
        raise OSError("No space left on device")

    monkeypatch.setattr(fig, "savefig", broken)
    with pytest.raises(OSError, match="No space left"):
        RunResult(summary={"fell": False}, figures={"f": fig}).save(tmp_path)
    assert list(tmp_path.iterdir()) == [] and not plt.fignum_exists(fig.number)


def test_run_outcome_reads_outcome_or_the_flags_in_their_precedence() -> None:
    from lipmpcc.studies import OUTCOMES, run_outcome

    assert set(OUTCOMES) == {"completed", "fell", "collided", "stopped_early", "stalled", "incomplete", "trailing"}
    assert run_outcome({"outcome": "stalled"}) == "stalled"  # issue 31: the new outcomes are read as they are
    assert run_outcome({}) == "completed"  # a summary without the fields: missing = False/None
    assert run_outcome({"fell": False, "collided": False, "stopped_early": None}) == "completed"
    assert run_outcome({"fell": True}) == "fell"
    assert run_outcome({"fell": np.bool_(True)}) == "fell"
    assert run_outcome({"stopped_early": "first solve failed"}) == "stopped_early"
    assert run_outcome({"fell": True, "stopped_early": "fell"}) == "fell"
    assert run_outcome({"collided": True, "fell": True, "stopped_early": "x"}) == "collided"
    assert run_outcome({"outcome": "collided"}) == "collided"  # the summary's own word first
    assert run_outcome({"outcome": "completed", "fell": True}) == "completed"
    assert run_outcome({"outcome": "exploded", "fell": True}) == "fell"  # not an outcome: the flags


@pytest.mark.parametrize("kw, message", [
    (dict(steps="3"), r"--steps = '3': expected an integer >= 1"),
    (dict(seed=-1), r"--seed = -1: expected an integer >= 0"),
    (dict(obstacle_speed="fast"), r"--obstacle-speed = 'fast': expected a finite number \[m/s\]"),
    (dict(duration=float("nan")), r"--duration = nan"),
    (dict(video=1), r"--video = 1: expected True or False"),
    (dict(cop_range=(0.1,)), r"--cop-range"),
    (dict(robot=5), r"--robot = 5: expected text"),
    (dict(step_duration_range=(0.3,)), r"--step-duration-range = \(0.3,\): expected a list of two finite numbers \[s\]"),
    (dict(step_duration_range="0.3 0.5"), r"--step-duration-range = '0.3 0.5'"),
])
def test_run_options_name_an_option_of_the_wrong_type(kw, message) -> None:
    """The Python API refuses what the CLI's parser would (a study would fail deep inside otherwise)."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions

    with pytest.raises(InvalidInputError, match=message):
        RunOptions("circle", **kw)


def test_run_options_accept_numpy_numbers() -> None:
    from lipmpcc.studies import RunOptions

    o = RunOptions("circle", steps=np.int64(3), seed=np.int32(2), obstacle_speed=np.float32(0.5), cop_range=[0, 0])
    assert (o.steps, o.seed, o.obstacle_speed, o.cop_range) == (3, 2, 0.5, (0.0, 0.0))
    assert type(o.steps) is int and type(o.obstacle_speed) is float


@pytest.mark.parametrize("value, message", [
    ((0.5, 0.3), r"--step-duration-range = \(0.5, 0.3\): expected TMIN <= TMAX \[s\]"),
    ((0.0, 0.4), r"--step-duration-range = \(0.0, 0.4\): expected step durations TMIN, TMAX > 0 \[s\]"),
    ((-0.4, -0.3), r"expected step durations TMIN, TMAX > 0"),
    ((float("nan"), 0.5), r"--step-duration-range = \(nan, 0.5\): expected a list of two finite numbers"),
    ((0.3, float("inf")), r"--step-duration-range = \(0.3, inf\)"),
    ((0.15, 0.5), r"expected a range within \[0.2, 1\] s \(the step durations a robot walks\)"),
    ((0.3, 1.01), r"expected a range within \[0.2, 1\] s"),
    ((0.25, 0.35), r"expected a range that contains the MPCC's nominal step duration T = 0.4 s"),
])
def test_run_options_refuse_a_bad_step_duration_range_naming_it(value, message) -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions

    with pytest.raises(InvalidInputError, match=message):
        RunOptions("circle", step_duration_range=value)


def test_run_options_take_a_step_duration_range() -> None:
    from lipmpcc.studies import RunOptions
    from lipmpcc.studies.options import check_step_duration_range

    assert RunOptions("circle").step_duration_range is None
    o = RunOptions("overtake", step_duration_range=[np.float32(0.25), np.int64(1)])
    assert o.step_duration_range == (0.25, 1.0) and all(type(v) is float for v in o.step_duration_range)
    assert RunOptions("circle", step_duration_range=(0.4, 0.4)).step_duration_range == (0.4, 0.4)
    assert RunOptions("circle", step_duration_range=(0.2, 1.0)).step_duration_range == (0.2, 1.0)
    assert check_step_duration_range((0.6, 0.8), nominal=0.7) == (0.6, 0.8)  # a robot's own nominal T


@pytest.mark.parametrize("value, expected", [
    (["q_c=50", "rho = 0.1"], {"q_c": 50.0, "rho": 0.1}),
    (["rho=1", "rho=2"], {"rho": 2.0}),  # given twice: the last
    ({"N": np.int64(7), "gamma": np.float32(0.5)}, {"N": 7.0, "gamma": 0.5}),
    ([("q_l", "3")], {"q_l": 3.0}),
])
def test_run_options_parse_set_values(value, expected) -> None:
    from lipmpcc.studies import RunOptions

    o = RunOptions("circle", set=value)
    assert o.set == expected and all(type(v) is float for v in o.set.values())
    assert o.planner_settings.values == expected and o.planner_settings.preset is None


@pytest.mark.parametrize("value, message", [
    (["q_c"], r"--set = 'q_c': expected KEY=VALUE"),
    (["=3"], r"--set = '=3': expected KEY=VALUE"),
    (["rho=nan"], r"--set rho = 'nan': expected a finite number"),
    (["rho=inf"], r"--set rho = 'inf'"),
    ({"rho": "fast"}, r"--set rho = 'fast'"),
    ({"rho": True}, r"--set rho = True"),
    ("rho=1", r"--set = 'rho=1': expected KEY=VALUE texts"),
    ({3: 1.0}, r"--set = 3: expected a parameter name"),
])
def test_run_options_refuse_bad_set_values_naming_them(value, message) -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions

    with pytest.raises(InvalidInputError, match=message):
        RunOptions("circle", set=value)


def test_run_options_refuse_an_unknown_preset_listing_the_names() -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions

    with pytest.raises(InvalidInputError, match=r"--preset = 'fast': expected one of circle, overtake, cartesian, "
                                                r"paper-b, paper-b-qp"):
        RunOptions("circle", preset="fast")
    assert RunOptions("circle", preset="overtake").planner_settings.preset == "overtake"


def test_run_options_check_replan_hz() -> None:
    """``replan_hz``: None (at the exchanges), or a finite rate in [1, 1000] Hz kept as a float."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions
    from lipmpcc.studies.options import REPLAN_HZ_RANGE, check_replan_hz

    assert RunOptions("circle").replan_hz is None
    o = RunOptions("circle", step_duration_range=(0.3, 0.5), replan_hz=np.int64(25))
    assert o.replan_hz == 25.0 and type(o.replan_hz) is float
    assert check_replan_hz(REPLAN_HZ_RANGE[1]) == 1000.0
    for bad in (0, 0.5, 1001, float("nan"), "25", True):
        with pytest.raises(InvalidInputError, match=r"--replan-hz"):
            RunOptions("circle", step_duration_range=(0.3, 0.5), replan_hz=bad)


def test_a_fixed_step_duration_needs_not_contain_the_nominal() -> None:
    """TMIN = TMAX is a fixed duration anywhere in [0.2, 1] s; a range must still contain T = 0.4 s."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies.options import check_step_duration_range

    assert check_step_duration_range((0.3, 0.3)) == (0.3, 0.3)
    with pytest.raises(InvalidInputError, match=r"\(or TMIN = TMAX: a fixed duration\)"):
        check_step_duration_range((0.3, 0.35))


def test_a_step_duration_range_is_judged_against_the_robots_own_nominal_step_duration(tmp_path) -> None:
    """A robot whose layout sets step_duration = 0.6: 0.5-0.7 is its range (it does not hold 0.4 s), 0.3-0.5
    is not (it does not hold 0.6 s)."""
    import shutil

    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.robots.layouts import shipped_layout
    from lipmpcc.robots.loading import digit_like_paths
    from lipmpcc.studies import RunOptions, check_options
    from lipmpcc.studies.options import robot_step_duration

    mjcf = tmp_path / "slow.xml"
    shutil.copy(digit_like_paths()[0], mjcf)
    lay = shipped_layout("digit_like")
    (tmp_path / "slow.lipmpcc.toml").write_text("".join(f'{k} = "{lay[k]}"\n' for k in ("left_foot_body", "right_foot_body",
                                                                                         "torso_body")) + "step_duration = 0.6\n")
    assert robot_step_duration(str(mjcf)) == 0.6 and robot_step_duration("lip") == 0.4
    check_options(RunOptions("circle", robot=str(mjcf), step_duration_range=(0.5, 0.7)))
    with pytest.raises(InvalidInputError, match=r"\(0.3, 0.5\).*nominal step duration T = 0.6 s"):
        check_options(RunOptions("circle", robot=str(mjcf), step_duration_range=(0.3, 0.5)))
    with pytest.raises(InvalidInputError, match=r"T = 0.4 s"):  # the LIP's own
        RunOptions("circle", robot="lip", step_duration_range=(0.5, 0.7))
