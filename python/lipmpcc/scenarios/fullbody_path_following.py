"""Deprecated: merged into :mod:`lipmpcc.studies.path_following` (the robot is an option) in lipmpcc 0.2
(see CHANGELOG.md); removed in 0.3."""

from .._deprecated import forward

__getattr__, __dir__ = forward(
    __name__,
    "lipmpcc.studies.path_following",
    {
        "simulate": "simulate_full_body",
        "summarize": "summarize_full_body",
        "build_log": "full_body_path_log",
        "FullBodyPathLog": "PathFollowingLog",
        "loop_pushes": "_full_body_loop_pushes",
        "SETTLE_TIME": "FULLBODY_SETTLE_TIME",
        "OBSTACLE_START": "FULLBODY_OBSTACLE_START",
    },
)
