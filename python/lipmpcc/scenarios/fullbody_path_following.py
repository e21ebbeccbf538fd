"""Deprecated: merged into :mod:`lipmpcc.studies.path_following` (the robot is an option) in lipmpcc 0.2
(see CHANGELOG.md); removed in 0.3."""

from typing import TYPE_CHECKING, Sequence

from .._deprecated import forward

if TYPE_CHECKING:
    from ..push import Push
    from ..studies import RunOptions, RunResult

__getattr__, __dir__ = forward(
    __name__,
    "lipmpcc.studies.path_following",
    {
        "simulate": "simulate_full_body",
        "summarize": "lipmpcc.studies.path_metrics:summarize_full_body",
        "build_log": "lipmpcc.studies.path_metrics:full_body_path_log",
        "FullBodyPathLog": "PathFollowingLog",
        "loop_pushes": "lipmpcc.scenarios.fullbody_path_following:_loop_pushes",
        "run": "lipmpcc.scenarios.fullbody_path_following:_run",
        "SETTLE_TIME": "lipmpcc.studies.path_scenarios:FULLBODY_SETTLE_TIME",
        "OBSTACLE_START": "lipmpcc.studies.path_scenarios:FULLBODY_OBSTACLE_START",
    },
)


def _loop_pushes(pushes: "Sequence[Push]") -> "list[Push]":
    """The 0.1 conversion of planar pushes into torso pushes (F_x, F_y, 0) [N]; the full-body loop now
    takes planar pushes as they are."""
    from ..push import Push

    return [Push((float(p.force[0]), float(p.force[1]), 0.0), p.t_start, p.duration) for p in pushes]


def _run(opts: "RunOptions", scenario: str, planner: str, pushes_fn: object = None) -> "RunResult":
    """The 0.1 entry of a full-body paper A study: :func:`lipmpcc.studies.run` with the scenario and
    planner set (the study draws paper A's pushes itself)."""
    from dataclasses import replace

    from ..exceptions import InvalidInputError
    from ..studies import run

    if pushes_fn is not None:
        raise InvalidInputError("pushes_fn", pushes_fn, "None (the circle-push study draws paper A's pushes itself)")
    return run(replace(opts, scenario=scenario, planner=planner))
