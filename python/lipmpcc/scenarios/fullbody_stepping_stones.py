"""Deprecated: merged into :mod:`lipmpcc.studies.stepping_stones` (the robot is an option) in lipmpcc 0.2
(see CHANGELOG.md); removed in 0.3."""

from typing import TYPE_CHECKING, Any

from .._deprecated import forward

if TYPE_CHECKING:
    from ..studies.stepping_stones import FullBodyStonesRun

__getattr__, __dir__ = forward(
    __name__,
    "lipmpcc.studies.stepping_stones",
    {
        "simulate": "simulate_full_body",
        "study_table": "study_table_full_body",
        "to_alip_log": "lipmpcc.studies.stone_metrics:full_body_stones_log",
        "paper_cases_fullbody": "table_ii_cases",
        "summarize": "lipmpcc.scenarios.fullbody_stepping_stones:_summarize",
    },
)


def _summarize(run: "FullBodyStonesRun", scenario: str, robot_name: str, extra: dict[str, Any]) -> dict[str, Any]:
    """The 0.1 summary of a full-body stones run (now built by the stones study itself)."""
    from ..studies import stepping_stones as study

    course = study._Course(planner=run.planner, robot=robot_name, stones=run.stones,
                           pushes=(), cop_range=None, extra=dict(extra))
    return study._summary(scenario, course, robot_name, run.metrics, run.alip, run)
