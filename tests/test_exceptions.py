"""lipmpcc.exceptions: every error carries its data, reads as one line and keeps the builtin base classes."""

from __future__ import annotations

import pytest

from lipmpcc import exceptions as ex


@pytest.mark.parametrize("cls", [ex.InvalidInputError, ex.PathError, ex.ParameterError, ex.StateError, ex.TerrainError])
def test_input_errors_carry_name_value_expected_and_are_value_errors(cls) -> None:
    err = cls("T", -0.4, "a positive step duration [s]", detail="paper A uses 0.4 s")
    assert isinstance(err, ValueError) and isinstance(err, ex.LipmpccError) and isinstance(err, ex.InvalidInputError)
    assert (err.name, err.value, err.expected, err.detail) == ("T", -0.4, "a positive step duration [s]", "paper A uses 0.4 s")
    assert str(err) == "T = -0.4: expected a positive step duration [s] (paper A uses 0.4 s)"
    with pytest.raises(ValueError):
        raise err


def test_long_values_are_shortened_in_the_message_only() -> None:
    value = list(range(100))
    err = ex.InvalidInputError("xs", value, "a short list")
    shown = str(err).split(": expected")[0]
    assert shown.endswith("...") and len(shown) == len("xs = ") + 120
    assert err.value is value


def test_file_description_solver_and_render_errors() -> None:
    f = ex.ModelFileError("robot.xml", "file not found")
    assert isinstance(f, FileNotFoundError) and f.path == "robot.xml" and f.reason == "file not found"
    assert str(f) == "robot model robot.xml: file not found"
    d = ex.RobotDescriptionError("robot.xml", ["left_foot body", "torso"])
    assert isinstance(d, ValueError) and d.missing == ["left_foot body", "torso"]
    assert str(d) == "robot model robot.xml: missing left_foot body, torso"
    s = ex.NoFallbackPlanError("mpcc/sqp", "infeasible", 3, "first solve")
    assert isinstance(s, ex.SolverError) and isinstance(s, RuntimeError)
    assert (s.solver, s.status, s.iterations) == ("mpcc/sqp", "infeasible", 3)
    assert str(s) == "mpcc/sqp failed with status 'infeasible' after 3 iterations: first solve"
    r = ex.RenderUnavailableError("MP4 video", "needs imageio-ffmpeg")
    assert isinstance(r, RuntimeError) and (r.what, r.reason) == ("MP4 video", "needs imageio-ffmpeg")
    assert str(r) == "MP4 video unavailable: needs imageio-ffmpeg"


def test_every_public_error_derives_from_the_base() -> None:
    for name in ex.__all__:
        assert issubclass(getattr(ex, name), ex.LipmpccError), name


def test_concurrent_use_error_names_the_object_and_the_remedy() -> None:
    err = ex.ConcurrentUseError("WholeBodyController(robot='digit_like')", "solve", "controller")
    assert isinstance(err, RuntimeError) and isinstance(err, ex.LipmpccError)
    assert (err.obj, err.method) == ("WholeBodyController(robot='digit_like')", "solve")
    assert str(err).startswith("WholeBodyController(robot='digit_like').solve() called while another thread")
    assert str(err).endswith("use one controller per thread") and "\n" not in str(err)
    assert "ConcurrentUseError" in ex.__all__
def test_obstacle_and_layout_errors() -> None:
    o = ex.ObstacleError("radius", 1e6, "a radius > 0 and <= 50 [m]")
    assert isinstance(o, ex.InvalidInputError) and isinstance(o, ValueError)
    assert str(o) == "radius = 1000000.0: expected a radius > 0 and <= 50 [m]"
    lay = ex.LayoutError("my.toml", ["leg_joints as a list of joint names (got 5)"])
    assert isinstance(lay, ex.RobotDescriptionError) and lay.path == "my.toml"
    assert lay.missing == ["leg_joints as a list of joint names (got 5)"]
    assert str(lay) == "robot layout my.toml: expected leg_joints as a list of joint names (got 5)"
    assert lay.args == (str(lay),)
