"""Deprecated: moved to :mod:`lipmpcc.robots` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

``RobotDescription`` → :mod:`lipmpcc.robots.description`; ``load_robot``, ``describe_model``,
``digit_like_paths`` → :mod:`lipmpcc.robots.loading`; layout files → :mod:`lipmpcc.robots.layouts`;
``compile_mjcf``, ``loop_closure_errors`` → :mod:`lipmpcc.robots.mjcf`; ``LEFT``/``RIGHT`` →
:mod:`lipmpcc.conventions`; ``DIGIT_MASS`` → :data:`lipmpcc.robots.description.DIGIT_PUBLISHED_MASS`.
"""

from ._deprecated import forward

__getattr__, __dir__ = forward(__name__, "lipmpcc.robots.loading", renames={
    "RobotDescription": "lipmpcc.robots.description:RobotDescription",
    "DIGIT_MASS": "lipmpcc.robots.description:DIGIT_PUBLISHED_MASS",
    "LEFT": "lipmpcc.conventions:LEFT",
    "RIGHT": "lipmpcc.conventions:RIGHT",
    "MAX_ALIP_COP_RANGE": "lipmpcc.robots.layouts:MAX_ALIP_COP_RANGE",
    "DIGIT_V3_STANDING_QPOS": "lipmpcc.robots.layouts:DIGIT_V3_STANDING_QPOS",
    "LAYOUT_KEYS": "lipmpcc.robots.layouts:LAYOUT_KEYS",
    "read_layout_file": "lipmpcc.robots.layouts:read_layout_file",
    "compile_mjcf": "lipmpcc.robots.mjcf:compile_mjcf",
    "loop_closure_errors": "lipmpcc.robots.mjcf:loop_closure_errors",
})
