"""Deprecated: merged into :mod:`lipmpcc.studies.stepping_stones` (the robot is an option) in lipmpcc 0.2
(see CHANGELOG.md); removed in 0.3."""

from .._deprecated import forward

__getattr__, __dir__ = forward(
    __name__,
    "lipmpcc.studies.stepping_stones",
    {
        "simulate": "simulate_full_body",
        "study_table": "study_table_full_body",
        "to_alip_log": "full_body_stones_log",
        "paper_cases_fullbody": "table_ii_cases",
    },
)
